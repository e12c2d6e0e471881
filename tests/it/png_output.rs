//! `output::write_png` read back with the image crate: size, colour type, the code values of
//! both display transforms (sRGB curve, plain clamp) and exposure.

use crate::common;

use lumis_core::film::DisplayTransform;
use lumis_core::film::{Film, PixelAov};
use lumis_core::math::Vec4;
use lumis_io::output::{OutputError, write_png};

#[test]
fn png_srgb_encoding_and_exposure() {
    let dir = tempfile::tempdir().unwrap();
    let mut film = Film::new(5, 2);
    // Premultiplied: (0.25, .., 0.5) is 0.25 over black, not un-premultiplied to 0.5.
    let linear = [0.5, 1.0, 0.0, 0.25, 4.0];
    for (x, v) in linear.into_iter().enumerate() {
        let alpha = if x == 3 { 0.5 } else { 1.0 };
        film.set(x as u32, 0, Vec4::new(v, v, v, alpha), PixelAov::MISS);
    }
    film.set(0, 1, Vec4::new(0.5, 0.0, 1.0, 1.0), PixelAov::MISS);

    let path = dir.path().join("out.png");
    let read_back = |stops: f32| {
        write_png(&path, &film, stops, DisplayTransform::Srgb).unwrap();
        let img = image::open(&path).unwrap();
        assert_eq!(img.color(), image::ColorType::Rgb8, "RGB8, no alpha");
        assert_eq!((img.width(), img.height()), (5, 2));
        img.to_rgb8()
    };

    let img = read_back(0.0);
    let row0: Vec<u8> = (0..5).map(|x| img.get_pixel(x, 0)[0]).collect();
    assert_eq!(row0, [188, 255, 0, 137, 255]);
    assert_eq!(img.get_pixel(0, 1).0, [188, 0, 255]);
    assert_eq!(img.get_pixel(1, 1).0, [0, 0, 0]);

    // +1 stop doubles linear values: 0.25 -> 0.5 -> 188.
    let img = read_back(1.0);
    let row0: Vec<u8> = (0..5).map(|x| img.get_pixel(x, 0)[0]).collect();
    assert_eq!(row0, [255, 255, 0, 188, 255]);
    // -1 stop halves them: 1.0 -> 0.5 -> 188.
    assert_eq!(read_back(-1.0).get_pixel(1, 0).0, [188, 188, 188]);
    assert_eq!(common::files::dir_entries(dir.path()), ["out.png"]);

    let err = write_png(&path, &film, f32::NAN, DisplayTransform::Clamp).unwrap_err();
    assert!(matches!(err, OutputError::BadExposure { .. }), "{err:?}");
}

#[test]
fn png_clamp_encoding_has_no_transfer_curve() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("clamp.png");
    let mut film = Film::new(6, 1);
    // Known linear values and their codes: round(clamp(v) * 255), no curve (sRGB would give
    // 0, 124, 188, 137 for the first four).
    let linear = [0.0, 0.2, 0.5, 0.25, 1.5, -0.5];
    for (x, v) in linear.into_iter().enumerate() {
        let alpha = if x == 3 { 0.5 } else { 1.0 };
        film.set(x as u32, 0, Vec4::new(v, v, v, alpha), PixelAov::MISS);
    }
    let row = |stops: f32| -> Vec<u8> {
        write_png(&path, &film, stops, DisplayTransform::Clamp).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        (0..6).map(|x| img.get_pixel(x, 0)[1]).collect()
    };
    assert_eq!(row(0.0), [0, 51, 128, 64, 255, 0]);
    // Exposure applies before the clamp: +1 stop doubles 0.2 to 0.4 -> 102.
    assert_eq!(row(1.0), [0, 102, 255, 128, 255, 0]);
    write_png(&path, &film, 0.0, DisplayTransform::Srgb).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.get_pixel(1, 0).0, [124, 124, 124]);
}

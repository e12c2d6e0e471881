//! Round trip of `output::write_exr` through an independent reader (the exr crate), extension
//! dispatch, and the atomic-write guarantees on failure. PNG encoding: `png_output.rs`.

use exr::prelude::{AttributeValue, Blocks, Compression, FlatSamples, Text};
use lumis_core::accel::RayFrame;
use lumis_core::camera::Camera;
use lumis_core::film::DisplayTransform;
use lumis_core::film::{Film, PixelAov};
use lumis_core::math::{Vec2, Vec3, Vec4};
use lumis_io::output::{
    ATTR_RENDER_SECONDS, ATTR_RENDERER, ATTR_SPP, ATTR_SPP_PER_AXIS, Develop, ExrCamera,
    ExrMetadata, OutputError, StagedOutputs, develop, write_exr, write_png,
};
use std::path::Path;

use crate::common;
use common::exr::{FlatImage, read_exr};

const W: u32 = 7;
const H: u32 = 5;

/// What the header records of [`scene_camera`].
fn camera() -> ExrCamera {
    ExrCamera::new(&scene_camera(), W, H)
}

fn scene_camera() -> Camera {
    Camera::look_at(
        Vec3::new(1.0, 2.0, 5.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        50.0,
        0.0,
        None,
    )
    .unwrap()
}

fn is_hit(x: u32, y: u32) -> bool {
    !(x + y).is_multiple_of(3)
}

/// A 7x5 film with known values: hits with distinct ids, misses with the miss AOV.
fn film() -> Film {
    let mut film = Film::new(W, H);
    for y in 0..H {
        for x in 0..W {
            let (fx, fy) = (x as f32, y as f32);
            if is_hit(x, y) {
                let alpha = if x % 2 == 0 { 1.0 } else { 0.5 };
                let rgba = Vec4::new(0.1 + 0.1 * fx, 0.05 + 0.2 * fy, 3.0 + fx * fy, alpha);
                let aov = PixelAov {
                    depth: 1.5 + fx + 0.25 * fy,
                    normal: Vec3::new(fx - 3.0, fy - 2.0, 1.0).normalize(),
                    prim_id: 100 + (x + W * y) as i32,
                    object_id: (x % 3) as i32,
                    ..PixelAov::MISS
                };
                film.set(x, y, rgba, aov);
            } else {
                film.set(x, y, Vec4::ZERO, PixelAov::MISS);
            }
        }
    }
    film
}

fn meta(float_rgba: bool) -> ExrMetadata {
    ExrMetadata {
        float_rgba,
        spp_per_axis: 4,
        render_seconds: Some(2.75),
        ..ExrMetadata::default()
    }
}

fn samples<'a>(image: &'a FlatImage, name: &str) -> &'a FlatSamples {
    let layer = &image.layer_data[0];
    let channel = layer.channel_data.list.iter().find(|c| c.name == *name);
    &channel
        .unwrap_or_else(|| panic!("no channel {name}"))
        .sample_data
}

fn f32s(image: &FlatImage, name: &str) -> Vec<f32> {
    match samples(image, name) {
        FlatSamples::F32(v) => v.clone(),
        other => panic!("{name} is not FLOAT: {other:?}"),
    }
}

/// Row vector times an Imath row-major M44f, as a compositor applies `worldToNDC`.
fn row_times_m44f(p: [f32; 4], m: &[f32; 16]) -> [f32; 4] {
    let mut out = [0.0; 4];
    for (j, o) in out.iter_mut().enumerate() {
        *o = (0..4).map(|i| p[i] * m[i * 4 + j]).sum();
    }
    out
}

fn write_and_read(float_rgba: bool) -> (Film, FlatImage) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.exr");
    let film = film();
    write_exr(&path, &film, &camera(), &meta(float_rgba)).unwrap();
    assert_eq!(
        common::files::dir_entries(dir.path()),
        ["out.exr"],
        "temp file left behind"
    );
    (film, read_exr(&path))
}

#[test]
fn exr_layout_channels_and_compression() {
    for float_rgba in [false, true] {
        let (_, image) = write_and_read(float_rgba);
        assert_eq!(image.layer_data.len(), 1, "single part");
        let layer = &image.layer_data[0];
        assert_eq!(layer.size.0, W as usize);
        assert_eq!(layer.size.1, H as usize);
        assert_eq!(layer.encoding.compression, Compression::ZIP16);
        assert_eq!(layer.encoding.blocks, Blocks::ScanLines);

        let names: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        // Stored in the byte order EXR requires.
        let expected = [
            "A",
            "B",
            "G",
            "N.X",
            "N.Y",
            "N.Z",
            "R",
            "Z",
            "id.object",
            "id.prim",
        ];
        assert_eq!(names, expected);

        for name in ["R", "G", "B", "A"] {
            let is_half = matches!(samples(&image, name), FlatSamples::F16(_));
            let is_float = matches!(samples(&image, name), FlatSamples::F32(_));
            assert!(if float_rgba { is_float } else { is_half }, "{name}");
        }
        for name in ["Z", "N.X", "N.Y", "N.Z", "id.prim", "id.object"] {
            assert!(
                matches!(samples(&image, name), FlatSamples::F32(_)),
                "{name}"
            );
        }
    }
}

#[test]
fn exr_pixels_round_trip() {
    for float_rgba in [false, true] {
        let (film, image) = write_and_read(float_rgba);
        let z = f32s(&image, "Z");
        let n = [
            f32s(&image, "N.X"),
            f32s(&image, "N.Y"),
            f32s(&image, "N.Z"),
        ];
        let prim = f32s(&image, "id.prim");
        let object = f32s(&image, "id.object");
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                let want = film.pixel(x, y);
                for (c, name) in ["R", "G", "B", "A"].into_iter().enumerate() {
                    let got = samples(&image, name).value_by_flat_index(i).to_f32();
                    if float_rgba {
                        assert_eq!(got, want[c], "{name} at ({x},{y})");
                    } else {
                        // Half: 11-bit mantissa, relative error <= 2^-11.
                        let tol = 1e-3 * want[c].abs();
                        assert!((got - want[c]).abs() <= tol, "{name} ({x},{y}): {got}");
                    }
                }
                let aov = film.pixel_aov(x, y);
                assert_eq!(z[i], aov.depth, "Z at ({x},{y})");
                assert_eq!([n[0][i], n[1][i], n[2][i]], aov.normal.to_array());
                assert_eq!(prim[i], aov.prim_id as f32);
                assert_eq!(object[i], aov.object_id as f32);
                if !is_hit(x, y) {
                    assert_eq!(z[i], f32::INFINITY);
                    assert_eq!((prim[i], object[i]), (-1.0, -1.0));
                }
            }
        }
        // The fixture really has distinct ids on hits.
        assert_eq!(prim[1], 101.0);
        assert_eq!(object[2], 2.0);
    }
}

#[test]
fn exr_attributes() {
    let (_, image) = write_and_read(false);
    let attrs = &image.layer_data[0].attributes;
    let cam = scene_camera();

    // Imath row-major M44f of the transposed (row-vector) matrix.
    let w2c = attrs.world_to_camera.expect("worldToCamera");
    let w2ndc = attrs.world_to_normalized_device.expect("worldToNDC");
    let imath = |m: lumis_core::math::Mat4| {
        // Imath's row-vector matrix is glam's transpose, stored row by row.
        let row_vector_form = m.transpose();
        std::array::from_fn::<f32, 16, _>(|k| row_vector_form.row(k / 4)[k % 4])
    };
    assert_eq!(w2c, imath(cam.world_to_camera()));
    assert_eq!(w2ndc, imath(cam.world_to_ndc(W, H)));

    // worldToCamera as a compositor applies it: the eye goes to the origin, +z is forward.
    let ahead = cam.position() + cam.forward() * 3.0;
    let p = row_times_m44f(ahead.extend(1.0).to_array(), &w2c);
    let eye = row_times_m44f(cam.position().extend(1.0).to_array(), &w2c);
    for (got, want) in p.iter().zip([0.0, 0.0, 3.0, 1.0]) {
        assert!((got - want).abs() < 1e-5, "{p:?}");
    }
    assert!(eye[..3].iter().all(|c| c.abs() < 1e-5), "{eye:?}");

    // worldToNDC maps a point seen through a film position back to that position.
    for film_pos in [
        Vec2::new(1.5, 0.5),
        Vec2::new(6.25, 4.75),
        Vec2::new(3.5, 2.5),
    ] {
        let world = cam
            .ray(&RayFrame::unbounded(), film_pos, W, H, Vec2::ZERO)
            .at(5.0);
        let q = row_times_m44f(world.extend(1.0).to_array(), &w2ndc);
        let (nx, ny) = (q[0] / q[3], q[1] / q[3]);
        assert!(
            (nx * W as f32 - film_pos.x).abs() < 1e-3,
            "{q:?} vs {film_pos}"
        );
        assert!(
            (ny * H as f32 - film_pos.y).abs() < 1e-3,
            "{q:?} vs {film_pos}"
        );
    }

    let software = attrs.software_name.as_ref().expect("software").to_string();
    assert_eq!(software, format!("lumis {}", env!("CARGO_PKG_VERSION")));
    assert_eq!(software, "lumis 0.1.0");
    let other = |name: &str| attrs.other.get(&Text::from(name)).cloned();
    assert_eq!(
        other(ATTR_RENDERER),
        Some(AttributeValue::Text(Text::from("lumis 0.1.0")))
    );
    assert_eq!(other(ATTR_SPP), Some(AttributeValue::I32(16)));
    assert_eq!(other(ATTR_SPP_PER_AXIS), Some(AttributeValue::I32(4)));
    assert_eq!(other(ATTR_RENDER_SECONDS), Some(AttributeValue::F32(2.75)));
}

#[test]
fn missing_directory_fails_without_leftovers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing").join("out.exr");
    let err = write_exr(&path, &film(), &camera(), &meta(false)).unwrap_err();
    assert!(matches!(err, OutputError::CreateTemp { .. }), "{err:?}");
    assert!(err.to_string().contains(&*path.to_string_lossy()), "{err}");
    assert!(common::files::dir_entries(dir.path()).is_empty());
}

#[test]
fn directory_target_fails_without_leftovers() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("sub");
    std::fs::create_dir(&target).unwrap();
    for result in [
        write_exr(&target, &film(), &camera(), &meta(false)),
        write_png(&target, &film(), 0.0, DisplayTransform::Srgb),
    ] {
        // Refused before a temporary file is made: a directory is not a regular file.
        let err = result.unwrap_err();
        assert!(matches!(err, OutputError::NotRegular { .. }), "{err:?}");
        assert!(err.to_string().contains("(a directory)"), "{err}");
        assert_eq!(common::files::dir_entries(dir.path()), ["sub"]);
        assert!(common::files::dir_entries(&target).is_empty());
    }
}

/// Develops `film` without exposure into the image `path` names by extension and writes it,
/// as `lumis render` does.
fn write_by_extension(
    path: &Path,
    film: &Film,
    camera: &ExrCamera,
    meta: &ExrMetadata,
) -> Result<(), OutputError> {
    let (mut film, mut meta) = (film.clone(), meta.clone());
    let how = Develop {
        exposure: Some(0.0),
        tonemap: lumis_core::film::Tonemap::None,
        display: DisplayTransform::Srgb,
    };
    let developed = develop(&mut film, camera, &[path], &how, &mut meta)?;
    let mut staged = StagedOutputs::new();
    for (path, bytes) in &developed.images {
        staged.stage_bytes(path, bytes)?;
    }
    staged.commit()
}

#[test]
fn failed_encoding_leaves_existing_file_intact() {
    let dir = tempfile::tempdir().unwrap();
    for (name, film) in [
        ("old.exr", Film::new(0, 0)),
        ("old.png", Film::new(0, 0)),
        ("wide.exr", Film::new(7, 0)),
        ("tall.png", Film::new(0, 5)),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, b"previous render").unwrap();
        let err = write_by_extension(&path, &film, &camera(), &meta(false)).unwrap_err();
        assert!(matches!(err, OutputError::EmptyFilm { .. }), "{err:?}");
        assert!(err.to_string().contains(name), "{err}");
        assert_eq!(std::fs::read(&path).unwrap(), b"previous render");
    }
    assert_eq!(
        common::files::dir_entries(dir.path()),
        ["old.exr", "old.png", "tall.png", "wide.exr"]
    );
}

#[test]
fn overwrite_replaces_existing_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.exr");
    std::fs::write(&path, b"previous render").unwrap();
    write_exr(&path, &film(), &camera(), &meta(true)).unwrap();
    assert_eq!(read_exr(&path).layer_data[0].size.0, W as usize);
    assert_eq!(common::files::dir_entries(dir.path()), ["out.exr"]);
}

#[test]
fn extension_dispatch() {
    let dir = tempfile::tempdir().unwrap();
    let (film, cam, meta) = (film(), camera(), meta(false));
    for name in ["a.EXR", "b.Exr"] {
        write_by_extension(&dir.path().join(name), &film, &cam, &meta).unwrap();
        read_exr(&dir.path().join(name));
    }
    write_by_extension(&dir.path().join("c.PNG"), &film, &cam, &meta).unwrap();
    let png = image::open(dir.path().join("c.PNG")).unwrap();
    assert_eq!((png.width(), png.height()), (W, H));

    for name in ["d.jpg", "noext", "e.exr.tmp"] {
        let path = dir.path().join(name);
        let err = write_by_extension(&path, &film, &cam, &meta).unwrap_err();
        assert!(matches!(err, OutputError::UnsupportedExtension { .. }));
        assert!(err.to_string().contains(name), "{err}");
    }
    assert_eq!(
        common::files::dir_entries(dir.path()),
        ["a.EXR", "b.Exr", "c.PNG"]
    );
}

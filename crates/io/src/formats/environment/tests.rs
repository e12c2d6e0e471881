//! Known answers for both formats, the channel choice, the clamps, and damaged or oversized
//! files refused with their name.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use ::exr::prelude::{
    AnyChannel, AnyChannels, Blocks, Compression, Encoding, FlatSamples, Image, Layer,
    LayerAttributes, LineOrder, SmallVec, Vec2, WritableImage, f16,
};
use ::image::Rgb;
use ::image::codecs::hdr::HdrEncoder;
use lumis_core::scene::limits::MAX_RADIANCE;

use super::*;

/// A scratch folder and `bytes` written in it as `name`.
fn file(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Writes `bytes` as `name` in a fresh folder and reads it back.
fn read_bytes(name: &str, bytes: &[u8]) -> Result<EnvironmentImage, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    read_environment_image(&file(&dir, name, bytes))
}

/// A run-length encoded `.hdr` (the `image` crate's encoder) of `texels`, `w` across.
fn hdr_rle(w: usize, texels: &[[f32; 3]]) -> Vec<u8> {
    let rgb: Vec<Rgb<f32>> = texels.iter().map(|&t| Rgb(t)).collect();
    let mut out = Vec::new();
    HdrEncoder::new(&mut out)
        .encode(&rgb, w, texels.len() / w)
        .unwrap();
    out
}

/// A flat (not run-length encoded) `.hdr` of RGBE `texels`, `w` across, in the exact form
/// tools/make_sky.py writes.
fn hdr_flat(w: usize, rgbe: &[[u8; 4]]) -> Vec<u8> {
    let h = rgbe.len() / w;
    let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    out.extend(rgbe.iter().flatten());
    out
}

/// An uncompressed single-part EXR of the named channels, `w x h`.
fn exr(w: usize, h: usize, channels: Vec<(&str, FlatSamples)>) -> Vec<u8> {
    let list: SmallVec<_> = channels
        .into_iter()
        .map(|(name, samples)| AnyChannel::new(name, samples))
        .collect();
    let image =
        Image::from_encoded_channels((w, h), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
    let mut out = Cursor::new(Vec::new());
    image.write().to_buffered(&mut out).unwrap();
    out.into_inner()
}

/// `F32` samples of one channel of `texels`.
fn channel(texels: &[[f32; 3]], c: usize) -> FlatSamples {
    FlatSamples::F32(texels.iter().map(|t| t[c]).collect())
}

/// R, G and B channels of `texels`, their names prefixed by `layer`.
fn rgb_channels(layer: &str, texels: &[[f32; 3]]) -> Vec<(String, FlatSamples)> {
    ["R", "G", "B"]
        .iter()
        .enumerate()
        .map(|(c, n)| (format!("{layer}{n}"), channel(texels, c)))
        .collect()
}

fn exr_named(w: usize, h: usize, channels: &[(String, FlatSamples)]) -> Vec<u8> {
    exr(
        w,
        h,
        channels
            .iter()
            .map(|(n, s)| (n.as_str(), s.clone()))
            .collect(),
    )
}

/// Four texels of a 2x2 map: red and green on the top row, blue and grey below.
const QUAD: [[f32; 3]; 4] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.5, 0.5],
];

#[test]
fn radiance_values_round_trip_within_rgbe_precision() {
    // 16 across: the encoder run-length encodes scanlines of 8 or more texels.
    let texels: Vec<[f32; 3]> = (0..16 * 4)
        .map(|i| {
            let v = 10f32.powf(i as f32 / 8.0 - 3.0);
            [v, 0.5 * v, 0.01 * v]
        })
        .collect();
    let img = read_bytes("sky.hdr", &hdr_rle(16, &texels)).unwrap();
    assert_eq!((img.width, img.height, img.clamped), (16, 4, 0));
    for (got, want) in img.texels.iter().zip(&texels) {
        // RGBE keeps 8 bits of mantissa under the largest component's exponent.
        let step = want[0] / 64.0;
        for c in 0..3 {
            assert!((got[c] - want[c]).abs() <= step, "{got:?} vs {want:?}");
        }
    }
}

#[test]
fn flat_rgbe_as_make_sky_writes_it_is_read_exactly() {
    // 8 across (a width run-length encoding could use) and flat: mantissa x 2^(e - 136).
    let mut rgbe = vec![[128, 64, 32, 129]; 16]; // (1, 0.5, 0.25)
    rgbe[0] = [200, 100, 0, 136]; // (200, 100, 0)
    rgbe[15] = [0, 0, 0, 0];
    let img = read_bytes("sky.hdr", &hdr_flat(8, &rgbe)).unwrap();
    assert_eq!((img.width, img.height), (8, 2));
    assert_eq!(img.texels[0], [200.0, 100.0, 0.0]);
    assert_eq!(img.texels[1], [1.0, 0.5, 0.25]);
    assert_eq!(img.texels[15], [0.0; 3]);
}

#[test]
fn row_zero_is_the_top_of_the_image() {
    let hdr = read_bytes("quad.hdr", &hdr_rle(2, &QUAD)).unwrap();
    let exr = read_bytes("quad.exr", &exr_named(2, 2, &rgb_channels("", &QUAD))).unwrap();
    for img in [hdr, exr] {
        assert_eq!(img.texels, QUAD);
    }
}

#[test]
fn the_extension_is_case_insensitive_and_pic_is_radiance() {
    for name in ["SKY.HDR", "sky.Pic"] {
        assert_eq!(read_bytes(name, &hdr_rle(2, &QUAD)).unwrap().texels, QUAD);
    }
    let path = Path::new("SKY.EXR");
    let bytes = exr_named(2, 2, &rgb_channels("", &QUAD));
    assert_eq!(decode_environment_image(&bytes, path).unwrap().texels, QUAD);
}

#[test]
fn unknown_extensions_are_refused_naming_the_supported_ones() {
    for name in ["sky.png", "sky"] {
        let e = decode_environment_image(b"", Path::new(name))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(name) && e.contains(".hdr") && e.contains(".exr"),
            "{e}"
        );
    }
}

#[test]
fn blender_multilayer_exr_reads_its_combined_pass() {
    let mut channels = rgb_channels("ViewLayer.Combined.", &QUAD);
    channels.push(("ViewLayer.Combined.A".into(), channel(&QUAD, 0)));
    channels.push(("ViewLayer.Depth.Z".into(), channel(&QUAD, 1)));
    let img = read_bytes("blender.exr", &exr_named(2, 2, &channels)).unwrap();
    assert_eq!(img.texels, QUAD);
    // Another RGB pass beside it: the Combined one is still the colour.
    channels.extend(rgb_channels("ViewLayer.DiffCol.", &[[9.0; 3]; 4]));
    let img = read_bytes("blender.exr", &exr_named(2, 2, &channels)).unwrap();
    assert_eq!(img.texels, QUAD);
}

#[test]
fn several_rgb_layers_without_a_combined_pass_are_refused() {
    let mut channels = rgb_channels("left.", &QUAD);
    channels.extend(rgb_channels("right.", &QUAD));
    let e = read_bytes("stereo.exr", &exr_named(2, 2, &channels))
        .unwrap_err()
        .to_string();
    assert!(e.contains("stereo.exr") && e.contains("left, right"), "{e}");
}

#[test]
fn a_tiled_compressed_exr_off_the_origin_is_read() {
    // 10x6 in 4x4 tiles (partial ones at the right and bottom), its data window at (5, 3).
    let texels: Vec<[f32; 3]> = (0..60).map(|i| [i as f32, 0.5, 0.25]).collect();
    let list: SmallVec<_> = rgb_channels("", &texels)
        .into_iter()
        .map(|(name, samples)| AnyChannel::new(name.as_str(), samples))
        .collect();
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::Tiles(Vec2(4, 4)),
        line_order: LineOrder::Unspecified,
    };
    let attributes = LayerAttributes {
        layer_position: Vec2(5, 3),
        ..LayerAttributes::default()
    };
    let layer = Layer::new((10, 6), attributes, encoding, AnyChannels::sort(list));
    let mut out = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut out)
        .unwrap();
    let img = read_bytes("tiled.exr", &out.into_inner()).unwrap();
    assert_eq!((img.width, img.height), (10, 6));
    assert_eq!(img.texels, texels);
}

#[test]
fn half_float_exr_is_read() {
    let half = |c: usize| FlatSamples::F16(QUAD.iter().map(|t| f16::from_f32(t[c])).collect());
    let bytes = exr(2, 2, vec![("R", half(0)), ("G", half(1)), ("B", half(2))]);
    assert_eq!(read_bytes("half.exr", &bytes).unwrap().texels, QUAD);
}

#[test]
fn a_luminance_only_exr_is_grey() {
    let bytes = exr(2, 1, vec![("Y", FlatSamples::F32(vec![0.25, 4.0]))]);
    let img = read_bytes("grey.exr", &bytes).unwrap();
    assert_eq!(img.texels, [[0.25; 3], [4.0; 3]]);
}

#[test]
fn an_exr_without_colour_channels_is_refused_listing_its_channels() {
    let zeros = || FlatSamples::F32(vec![0.0; 4]);
    let bytes = exr(2, 2, vec![("Z", zeros()), ("A", zeros()), ("N.X", zeros())]);
    let e = read_bytes("depth.exr", &bytes).unwrap_err().to_string();
    assert!(
        e.contains("depth.exr") && e.contains("channels A, N.X, Z"),
        "{e}"
    );
}

#[test]
fn integer_colour_is_refused() {
    let ints = || FlatSamples::U32(vec![1; 4]);
    let bytes = exr(2, 2, vec![("R", ints()), ("G", ints()), ("B", ints())]);
    let e = read_bytes("ids.exr", &bytes).unwrap_err().to_string();
    assert!(e.contains("u32"), "{e}");
}

#[test]
fn non_finite_negative_and_excessive_texels_are_clamped_and_counted() {
    let texels = [
        [1.0, 2.0, 3.0],
        [f32::NAN, 0.0, 0.0],
        [f32::INFINITY, 1.0, 1.0],
        [-1.0, 0.5, 0.5],
        [2e6, 0.0, 0.0],
        [f32::NEG_INFINITY, f32::NAN, 1e7],
    ];
    let img = read_bytes("bad.exr", &exr_named(6, 1, &rgb_channels("", &texels))).unwrap();
    assert_eq!(img.clamped, 5);
    let m = MAX_RADIANCE;
    let want = [
        [1.0, 2.0, 3.0],
        [0.0, 0.0, 0.0],
        [m, 1.0, 1.0],
        [0.0, 0.5, 0.5],
        [m, 0.0, 0.0],
        [0.0, 0.0, m],
    ];
    assert_eq!(img.texels, want);
    // Half floats' infinity too; RGBE cannot be negative but can exceed the limit.
    let inf = || FlatSamples::F16(vec![f16::INFINITY, f16::ONE]);
    let img = read_bytes(
        "inf.exr",
        &exr(2, 1, vec![("R", inf()), ("G", inf()), ("B", inf())]),
    );
    assert_eq!(img.unwrap().clamped, 1);
    let img = read_bytes(
        "sun.hdr",
        &hdr_flat(2, &[[128, 0, 0, 128 + 40], [128, 0, 0, 129]]),
    );
    let img = img.unwrap();
    assert_eq!(
        (img.clamped, img.texels[0], img.texels[1]),
        (1, [m, 0.0, 0.0], [1.0, 0.0, 0.0])
    );
}

#[test]
fn a_truncated_radiance_file_says_which_row_it_ends_in() {
    let flat = hdr_flat(8, &[[128, 64, 32, 129]; 64]);
    let header = flat.len() - 64 * 4;
    // Three rows of eight texels and half of the fourth.
    let cut = &flat[..header + 3 * 8 * 4 + 16];
    let e = read_bytes("cut.hdr", cut).unwrap_err().to_string();
    assert!(e.contains("cut.hdr") && e.contains("truncated"), "{e}");
    assert!(
        e.contains("8x8") && e.contains("after 3 of the 8 rows"),
        "{e}"
    );
    // Run-length encoded, cut in half.
    let rle = hdr_rle(16, &[[0.3, 0.2, 0.1]; 16 * 16]);
    let e = read_bytes("half.hdr", &rle[..rle.len() / 2])
        .unwrap_err()
        .to_string();
    assert!(e.contains("half.hdr") && e.contains("truncated"), "{e}");
}

#[test]
fn a_truncated_exr_is_an_error_naming_the_file() {
    let texels = vec![[0.25, 0.5, 1.0]; 32 * 16];
    let bytes = exr_named(32, 16, &rgb_channels("", &texels));
    let e = read_bytes("cut.exr", &bytes[..bytes.len() / 2])
        .unwrap_err()
        .to_string();
    assert!(e.contains("cut.exr") && e.contains("truncated"), "{e}");
}

#[test]
fn every_truncation_of_a_small_file_is_an_error_not_a_panic() {
    let texels: Vec<[f32; 3]> = (0..8 * 4).map(|i| [i as f32, 1.0, 2.0]).collect();
    let files = [
        ("t.hdr", hdr_rle(8, &texels)),
        ("t.exr", exr_named(8, 4, &rgb_channels("", &texels))),
    ];
    for (name, bytes) in files {
        for len in 0..bytes.len() {
            let path = Path::new(name);
            let e = decode_environment_image(&bytes[..len], path).unwrap_err();
            // A panic caught by the guard would say "internal error".
            let e = e.to_string();
            assert!(e.contains(name) && !e.contains("internal error"), "{e}");
        }
        assert!(decode_environment_image(&bytes, Path::new(name)).is_ok());
    }
}

#[test]
fn a_header_claiming_100000_squared_texels_is_refused_before_decoding() {
    let hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n";
    let e = read_bytes("huge.hdr", hdr).unwrap_err().to_string();
    assert!(
        e.contains("huge.hdr") && e.contains("100000x100000") && e.contains("32768"),
        "{e}"
    );
    // The same lie in an EXR header: its data window made 100000 x 100000.
    let mut bytes = exr_named(2, 2, &rgb_channels("", &QUAD));
    let tag = b"dataWindow\0box2i\0";
    let at = bytes.windows(tag.len()).position(|w| w == tag).unwrap() + tag.len() + 4;
    bytes[at + 8..at + 16]
        .copy_from_slice(&[99_999i32.to_le_bytes(), 99_999i32.to_le_bytes()].concat());
    let e = read_bytes("huge.exr", &bytes).unwrap_err().to_string();
    assert!(e.contains("huge.exr") && e.contains("100000x100000"), "{e}");
}

#[test]
fn too_small_and_foreign_files_are_refused() {
    let e = read_bytes("dot.hdr", &hdr_flat(1, &[[128, 128, 128, 129]])).unwrap_err();
    assert!(e.to_string().contains("at least 2x1"), "{e}");
    let e = read_bytes("text.hdr", b"hello").unwrap_err();
    assert!(e.to_string().contains("signature"), "{e}");
    let e = read_bytes("text.exr", b"hello").unwrap_err();
    assert!(e.to_string().contains("not an OpenEXR file"), "{e}");
    let missing = Path::new("/nonexistent/sky.hdr");
    assert!(matches!(
        read_environment_image(missing),
        Err(SceneError::Read { .. })
    ));
}

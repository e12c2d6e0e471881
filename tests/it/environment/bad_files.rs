//! Bad environment files through the command line: a clear error naming the file, exit code
//! 1, no panic; texels that are not finite are clamped (and said so), never a NaN pixel.

use super::write_hdr;
use crate::common::exr::{channel, read_exr};
use crate::exr_passes::lumis;

fn refused(dir: &std::path::Path, file: &str, expect: &[&str]) {
    let out = lumis(dir)
        .args([
            "-o", "o.png", "--quiet", "--width", "8", "--height", "6", "--env", file,
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{file}: {err}");
    assert!(!err.contains("panicked"), "{file}: {err}");
    assert!(
        err.contains(file),
        "{file}: the error does not name the file: {err}"
    );
    for e in expect {
        assert!(err.contains(e), "{file}: expected {e:?} in {err}");
    }
    assert!(!dir.join("o.png").exists(), "{file}: an image was written");
}

#[test]
fn truncated_huge_foreign_and_missing_files_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_hdr(&d.join("sky.hdr"), 16, 8, |_, _| [1.0, 1.0, 1.0]);
    let full = std::fs::read(d.join("sky.hdr")).unwrap();
    std::fs::write(d.join("cut.hdr"), &full[..full.len() / 2]).unwrap();
    std::fs::write(
        d.join("huge.hdr"),
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 200000\n\x01\x02",
    )
    .unwrap();
    std::fs::write(d.join("sky.png"), b"not an environment").unwrap();
    std::fs::write(d.join("noise.exr"), b"v/1\x01 not really an exr").unwrap();
    refused(d, "cut.hdr", &["truncated"]);
    refused(d, "huge.hdr", &["100000"]);
    refused(d, "sky.png", &[".hdr"]);
    refused(d, "noise.exr", &[]);
    refused(d, "missing.hdr", &[]);
}

#[test]
fn non_finite_texels_are_clamped_and_the_image_stays_finite() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An EXR map with NaN, +inf, -inf and a huge value among ordinary texels.
    let (w, h) = (8usize, 4usize);
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30];
    let texel = |x: usize, y: usize, c: usize| {
        let k = y * w + x;
        if k < 4 && c == 0 { bad[k] } else { 0.25 }
    };
    let channels = ["B", "G", "R"].iter().map(|name| {
        let c = match *name {
            "R" => 0,
            "G" => 1,
            _ => 2,
        };
        let values: Vec<f32> = (0..w * h).map(|k| texel(k % w, k / w, c)).collect();
        exr::prelude::AnyChannel::new(*name, exr::prelude::FlatSamples::F32(values))
    });
    let layer = exr::prelude::Layer::new(
        (w, h),
        exr::prelude::LayerAttributes::default(),
        exr::prelude::Encoding::UNCOMPRESSED,
        exr::prelude::AnyChannels::sort(channels.collect()),
    );
    use exr::prelude::WritableImage;
    exr::prelude::Image::from_layer(layer)
        .write()
        .to_file(d.join("bad.exr"))
        .unwrap();
    let out = lumis(d)
        .args(["-o", "o.exr", "--float", "--width", "16", "--height", "9"])
        .args(["--env", "bad.exr", "--aov", "lightpaths"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("4 texel(s)") && err.contains("clamped"),
        "{err}"
    );
    let image = read_exr(&d.join("o.exr"));
    for c in [
        "R",
        "G",
        "B",
        "A",
        "background.R",
        "ambient.G",
        "reflection.B",
    ] {
        assert!(channel(&image, c).iter().all(|v| v.is_finite()), "{c}");
    }
}

//! `output::exr`'s reader is the writer's inverse: an EXR `lumis render` wrote, read back
//! with `read_exr` and written again with `encode_exr`, is the same file byte for byte, for
//! every layer kind (RGBA half and float, depth with `+inf` and a finite miss value, normals,
//! ids, albedo, position, uv, Cryptomatte of even and odd levels), both channel layouts, depth
//! of field (disk and square lens), a crop window, a farm tile, a frame of an animation, the
//! timing attribute and an automatic exposure. `lumis merge` writes its file through this
//! reader and this writer.

use std::path::Path;
use std::process::Command;

use lumis_core::camera::Lens;
use lumis_io::output::{ChannelLayout, ExrImage, encode_exr, read_exr};

use crate::common;
use common::cli::assert_ok;
use common::files::{files_under, root};

/// Renders `args` to `NAME.exr` in `dir`, reads it back, writes it again, and returns what
/// was read after checking the bytes are the same.
fn rewrites_identically(dir: &Path, name: &str, args: &[&str]) -> ExrImage {
    let file = format!("{name}.exr");
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .args(["render", "-q", "--threads", "2", "-o", &file])
        .args(args)
        .output()
        .unwrap();
    assert_ok(&out);
    let path = dir.join(&file);
    let written = std::fs::read(&path).unwrap();
    let image = read_exr(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let again = encode_exr(&path, &image.film, &image.camera, &image.meta).unwrap();
    assert!(
        again == written,
        "{name}: written again, the file differs ({} against {} bytes)",
        again.len(),
        written.len()
    );
    image
}

const SIZE: [&str; 4] = ["--width", "24", "--height", "20"];

#[test]
fn the_default_render_with_every_layer_in_lumis_layout() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plain = rewrites_identically(d, "plain", &SIZE);
    assert!(!plain.meta.float_rgba && plain.meta.identity.is_some());
    // The built-in scene has depth of field.
    assert!(plain.camera.focus.is_some() && matches!(plain.camera.lens, Lens::Disk(_)));
    let mut args = SIZE.to_vec();
    args.extend([
        "--cryptomatte",
        "--aov",
        "albedo,position,uv,lightpaths,lights",
        "--transparent",
    ]);
    let all = rewrites_identically(d, "all", &args);
    let aov = all.meta.aov_layers;
    assert!(aov.albedo && aov.position && aov.uv);
    // 7 light paths and the default scene's 2 lights.
    assert_eq!(all.film.passes().len(), 9);
    assert_eq!(all.film.crypto().len(), 2);
    // Misses read back as the film's miss depth, the value written as the metadata's.
    assert!(all.film.aov().iter().any(|a| a.prim_id < 0));
    assert!(
        all.film
            .aov()
            .iter()
            .all(|a| (a.prim_id < 0) == (a.depth == f32::INFINITY))
    );
    assert_eq!(all.meta.z_miss, f32::INFINITY);
}

#[test]
fn blender_layout_float_odd_levels_and_a_finite_miss_depth() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = SIZE.to_vec();
    args.extend([
        "--layout",
        "blender",
        "--float",
        "--cryptomatte",
        "--cryptomatte-levels",
        "3",
        "--aov",
        "albedo,position,uv,lightpaths,lights",
        "--z-miss",
        "1e10",
        "--exposure",
        "1.5",
        "--seed",
        "7",
        "--timing-metadata",
    ]);
    let image = rewrites_identically(dir.path(), "blender", &args);
    let meta = &image.meta;
    assert_eq!(meta.layout, ChannelLayout::Blender);
    assert!(meta.float_rgba && meta.render_seconds.is_some());
    assert_eq!((meta.z_miss, meta.exposure), (1e10, 1.5));
    assert_eq!(
        image.film.crypto()[0].levels(),
        4,
        "3 levels read back as 4"
    );
}

#[test]
fn a_tile_a_crop_and_a_frame() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = SIZE.to_vec();
    args.extend(["--tile", "1/3", "--cryptomatte", "--layout", "blender"]);
    args.extend(["--aov", "lightpaths,lights"]);
    let tile = rewrites_identically(d, "tile", &args);
    let header = tile.meta.tile.expect("a tile");
    assert_eq!(header.spec.to_string(), "1/3");
    assert_eq!(tile.film.full_size(), (24, 20));
    assert!(tile.film.height() < 20);

    let mut args = SIZE.to_vec();
    args.extend(["--crop", "0.2,0.7,0.1,0.9", "--aov", "uv"]);
    let crop = rewrites_identically(d, "crop", &args);
    assert_ne!(crop.film.origin(), (0, 0));

    let orbit = root().join("scenes/orbit.toml");
    let args = [
        "--width",
        "20",
        "--height",
        "12",
        "--frame",
        "7",
        orbit.to_str().unwrap(),
    ];
    let frame = rewrites_identically(d, "frame", &args);
    assert_eq!(frame.meta.frame.map(|f| f.number()), Some(7));
}

#[test]
fn a_scn_scene_and_a_model_with_automatic_exposure() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scn = files_under(&root().join("tests/fixtures/scn"), &["scn"]).remove(0);
    let mut args = SIZE.to_vec();
    args.push(scn.to_str().unwrap());
    rewrites_identically(d, "scn", &args);
    let knot = root().join("assets/knot.obj");
    let mut args = SIZE.to_vec();
    args.extend(["--cryptomatte", knot.to_str().unwrap()]);
    rewrites_identically(d, "knot", &args);
}

#[test]
fn files_lumis_did_not_write_are_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("junk.exr");
    std::fs::write(&path, b"not an exr").unwrap();
    let err = read_exr(&path).unwrap_err().to_string();
    assert!(err.contains("junk.exr") && err.contains("OpenEXR"), "{err}");
    // A well-formed EXR of another program: no lumis channels.
    let other = dir.path().join("other.exr");
    exr::prelude::write_rgba_file(&other, 2, 2, |_, _| (0.5f32, 0.5f32, 0.5f32, 1.0f32)).unwrap();
    let err = read_exr(&other).unwrap_err().to_string();
    assert!(err.contains("other.exr"), "{err}");
}

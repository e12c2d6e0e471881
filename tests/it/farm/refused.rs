//! Tiles that do not make one render's image are refused, naming the tile at fault, and the
//! merge's output is left as it was; bad `--tile` values are refused before any work.

use std::path::{Path, PathBuf};

use super::common::cli::assert_ok;
use super::{lumis, merge, refused, render_tiles};

const SIZE: [&str; 4] = ["--width", "24", "--height", "40"];

/// Three tiles of the default scene, and a tile 1/3 rendered with `extra` flags (which replace
/// the image size when they give a width).
fn tiles_and_a_foreign_one(dir: &Path, extra: &[&str]) -> (Vec<PathBuf>, PathBuf) {
    let mut tiles = render_tiles(dir, "t", 3, &SIZE);
    tiles.sort();
    let mut args = vec!["render", "-q", "--tile", "1/3", "-o", "foreign.exr"];
    if !extra.contains(&"--width") {
        args.extend_from_slice(&SIZE);
    }
    args.extend_from_slice(extra);
    assert_ok(&lumis(dir, &args));
    (tiles, dir.join("foreign.exr"))
}

#[test]
fn a_tile_of_another_render_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sky = super::common::files::root().join("assets/sky.hdr");
    std::fs::copy(sky, d.join("sky.hdr")).unwrap();
    for (extra, what) in [
        (&["--env", "sky.hdr"][..], "the scene"),
        (&["--aov", "lightpaths"][..], "settings"),
        (&["--seed", "3"][..], "the seed"),
        (&["--spp", "3"][..], "spp: 3"),
        (&["-D", "materials.glass.ior=1.4"][..], "the scene"),
        (&["--cryptomatte"][..], "settings"),
        (&["--width", "25", "--height", "40"][..], "display window"),
    ] {
        let (tiles, foreign) = tiles_and_a_foreign_one(d, extra);
        let err = refused(&merge(
            d,
            &[tiles[0].clone(), foreign, tiles[2].clone()],
            "m.exr",
        ));
        assert!(
            err.contains("foreign.exr") && err.contains(what),
            "{extra:?}: {err}"
        );
        assert!(!d.join("m.exr").exists());
    }
}

#[test]
fn missing_duplicate_and_miscounted_tiles_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut tiles = render_tiles(d, "t", 3, &SIZE);
    tiles.sort();
    let err = refused(&merge(d, &[tiles[0].clone(), tiles[2].clone()], "m.exr"));
    assert!(err.contains("tile 1 of 3 missing"), "{err}");
    let err = refused(&merge(
        d,
        &[tiles[0].clone(), tiles[1].clone(), tiles[1].clone()],
        "m.exr",
    ));
    assert!(err.contains("1/3 was given twice"), "{err}");
    let mut args = vec!["render", "-q", "--tile", "1/2", "-o", "half.exr"];
    args.extend_from_slice(&SIZE);
    assert_ok(&lumis(d, &args));
    let err = refused(&merge(
        d,
        &[tiles[0].clone(), d.join("half.exr"), tiles[2].clone()],
        "m.exr",
    ));
    assert!(
        err.contains("half.exr") && err.contains("tile count"),
        "{err}"
    );
}

#[test]
fn files_that_are_no_tiles_are_refused_without_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tiles = render_tiles(d, "t", 2, &SIZE);
    let mut args = vec!["render", "-q", "-o", "whole.exr"];
    args.extend_from_slice(&SIZE);
    assert_ok(&lumis(d, &args));
    let err = refused(&merge(d, &[d.join("whole.exr")], "m.exr"));
    assert!(
        err.contains("whole.exr") && err.contains("lumis/tile"),
        "{err}"
    );
    std::fs::write(d.join("junk.exr"), b"not an exr at all").unwrap();
    let err = refused(&merge(d, &[tiles[0].clone(), d.join("junk.exr")], "m.exr"));
    assert!(err.contains("junk.exr") && err.contains("OpenEXR"), "{err}");
    // Every truncation of a real tile: a clean error, never a panic or a half-written output.
    let bytes = std::fs::read(&tiles[0]).unwrap();
    for cut in (0..bytes.len()).step_by(97) {
        std::fs::write(d.join("cut.exr"), &bytes[..cut]).unwrap();
        let err = refused(&merge(d, &[d.join("cut.exr"), tiles[1].clone()], "m.exr"));
        assert!(err.contains("cut.exr"), "cut at {cut}: {err}");
    }
    let err = refused(&merge(d, &[d.join("nowhere.exr")], "m.exr"));
    assert!(err.contains("nowhere.exr"), "{err}");
    assert!(!d.join("m.exr").exists());
}

#[test]
fn the_output_is_never_a_tile_and_a_failed_merge_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut tiles = render_tiles(d, "t", 2, &SIZE);
    tiles.sort();
    let before = std::fs::read(&tiles[1]).unwrap();
    let err = refused(&merge(d, &tiles, tiles[1].to_str().unwrap()));
    assert!(err.contains("t_1.exr"), "{err}");
    assert_eq!(std::fs::read(&tiles[1]).unwrap(), before);
    std::fs::write(d.join("keep.exr"), b"previous").unwrap();
    refused(&merge(d, &tiles[..1], "keep.exr"));
    assert_eq!(std::fs::read(d.join("keep.exr")).unwrap(), b"previous");
    let err = refused(&merge(d, &tiles, "m.png"));
    assert!(err.contains(".exr"), "{err}");
}

#[test]
fn bad_tile_flags_are_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = |extra: &[&str]| {
        let mut args = vec!["render", "-q"];
        args.extend_from_slice(&SIZE);
        args.extend_from_slice(extra);
        lumis(d, &args)
    };
    for bad in ["3/3", "1/0", "x/4", "-1/3"] {
        let out = run(&[&format!("--tile={bad}")]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains("I/N"), "{bad}: {err}");
    }
    let err = refused(&run(&["--tile", "0/41"]));
    assert!(err.contains("at most 40 tiles"), "{err}");
    let err = refused(&run(&["--tile", "0/2", "-o", "t.png"]));
    assert!(err.contains("-o NAME.exr"), "{err}");
    let err = refused(&run(&["--tile", "0/2", "--png", "t.png"]));
    assert!(err.contains("no --png"), "{err}");
    let out = run(&["--tile", "0/2", "--crop", "0,1,0,0.5"]);
    assert_eq!(out.status.code(), Some(2));
    // Without -o a tile goes to tile_I.exr, and nothing else is written.
    assert_ok(&run(&["--tile", "1/2"]));
    let mut names: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["tile_1.exr"]);
}

#[test]
fn tiles_of_different_frames_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let orbit = super::common::files::root().join("scenes/orbit.toml");
    let scene = orbit.to_str().unwrap();
    for (i, frame) in [(0, "3"), (1, "4")] {
        let (spec, out) = (format!("{i}/2"), format!("f{i}.exr"));
        let args = [
            "render", "-q", "--width", "16", "--height", "20", "--frame", frame, "--tile", &spec,
            "-o", &out, scene,
        ];
        assert_ok(&lumis(d, &args));
    }
    let err = refused(&merge(d, &[d.join("f0.exr"), d.join("f1.exr")], "m.exr"));
    assert!(err.contains("f1.exr") && err.contains("the frame"), "{err}");
}

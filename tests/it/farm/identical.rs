//! The merge of every split equals the render made in one go, byte for byte.

use std::path::Path;

use super::common::cli::assert_ok;
use super::common::exr::read_exr;
use super::common::files::{paper_scenes, root};
use super::{merge, render_full, render_tiles};

/// Splits `scene_args` into each of `counts` tiles and checks every merge against the single
/// render's bytes.
fn assert_identical(dir: &Path, name: &str, counts: &[u32], scene_args: &[&str]) {
    let single = std::fs::read(render_full(dir, name, scene_args)).unwrap();
    for &n in counts {
        let tiles = render_tiles(dir, name, n, scene_args);
        let out = format!("{name}_merged_{n}.exr");
        assert_ok(&merge(dir, &tiles, &out));
        let merged = std::fs::read(dir.join(&out)).unwrap();
        assert!(
            merged == single,
            "{name}, {n} tiles: the merge differs from the single render ({} against {} bytes)",
            merged.len(),
            single.len()
        );
    }
}

/// The built-in scene (depth of field, glass, mirror, 2x2 samples): 40 rows are 3 bands of 16,
/// so 1, 2 and 3 tiles cut on bands and 7 and 16 on rows.
#[test]
fn default_scene_for_every_tile_count() {
    let dir = tempfile::tempdir().unwrap();
    assert_identical(
        dir.path(),
        "default",
        &[1, 2, 3, 7, 16],
        &["--width", "48", "--height", "40"],
    );
}

/// A taller image, so that several tiles share the 16-row bands unevenly.
#[test]
fn band_aligned_split_with_every_pass() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--width",
        "24",
        "--height",
        "150",
        "--cryptomatte",
        "--aov",
        "albedo,position,uv,lightpaths,lights",
        "--transparent",
    ];
    assert_identical(dir.path(), "passes", &[3, 7], &args);
}

/// An environment with its sun taken out as a light, and the light-path passes.
#[test]
fn an_environment_its_sun_and_the_passes() {
    let dir = tempfile::tempdir().unwrap();
    let sky = super::common::files::root().join("assets/sky.hdr");
    std::fs::copy(sky, dir.path().join("sky.hdr")).unwrap();
    let args = [
        "--width",
        "24",
        "--height",
        "40",
        "--env",
        "sky.hdr",
        "--env-sun",
        "--aov",
        "lightpaths,lights",
    ];
    assert_identical(dir.path(), "env", &[3], &args);
}

/// Float RGBA, Blender's channel names, a finite miss depth and a fixed exposure.
#[test]
fn float_blender_layout_and_fixed_exposure() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--width",
        "40",
        "--height",
        "32",
        "--float",
        "--layout",
        "blender",
        "--cryptomatte",
        "--z-miss",
        "1e10",
        "--exposure",
        "1.5",
        "--seed",
        "7",
        "--aov",
        "lightpaths,lights",
    ];
    assert_identical(dir.path(), "blender", &[2, 16], &args);
}

/// A model file: its automatic exposure is a function of the whole image, which only the merge
/// sees; the tiles leave it to the merge.
#[test]
fn automatic_exposure_of_a_model_is_the_whole_images() {
    let dir = tempfile::tempdir().unwrap();
    let knot = root().join("assets/knot.obj");
    let args = ["--width", "48", "--height", "36", knot.to_str().unwrap()];
    assert_identical(dir.path(), "knot", &[3], &args);
    let gltf = root().join("assets/gltf/cube.gltf");
    let args = [
        "--width",
        "32",
        "--height",
        "32",
        "--cryptomatte",
        gltf.to_str().unwrap(),
    ];
    assert_identical(dir.path(), "cube", &[2, 7], &args);
}

/// The paper's scenes (beside the checkout), each split in 3 and 7.
#[test]
fn paper_scenes_split_and_merged() {
    let dir = tempfile::tempdir().unwrap();
    for scene in paper_scenes() {
        let name = scene.file_stem().unwrap().to_str().unwrap().to_string();
        let args = [
            "--width",
            "48",
            "--height",
            "36",
            "--spp",
            "1",
            scene.to_str().unwrap(),
        ];
        assert_identical(dir.path(), &name, &[3, 7], &args);
    }
}

/// With `--timing-metadata` the render time differs from run to run; everything else still
/// matches, and the merge records the tiles' total.
#[test]
fn timing_is_the_only_difference_with_timing_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--width",
        "32",
        "--height",
        "24",
        "--timing-metadata",
        "--cryptomatte",
    ];
    render_full(dir.path(), "timed", &args);
    let tiles = render_tiles(dir.path(), "timed", 3, &args);
    assert_ok(&merge(dir.path(), &tiles, "timed.exr"));
    let (single, merged) = (
        read_exr(&dir.path().join("timed_full.exr")),
        read_exr(&dir.path().join("timed.exr")),
    );
    let seconds = lumis_io::output::ATTR_RENDER_SECONDS;
    let without_timing = |image: &super::common::exr::FlatImage| {
        let mut layer = image.layer_data[0].clone();
        let t = layer
            .attributes
            .other
            .remove(&exr::prelude::Text::from(seconds));
        assert!(matches!(t, Some(exr::prelude::AttributeValue::F32(s)) if s >= 0.0));
        (image.attributes.clone(), layer)
    };
    assert_eq!(without_timing(&single), without_timing(&merged));
}

/// A frame of an animation, split: the tiles carry the frame, the merge keeps it.
#[test]
fn a_frame_of_an_animation() {
    let dir = tempfile::tempdir().unwrap();
    let orbit = root().join("scenes/orbit.toml");
    let args = [
        "--width",
        "40",
        "--height",
        "24",
        "--frame",
        "7",
        orbit.to_str().unwrap(),
    ];
    assert_identical(dir.path(), "orbit", &[3], &args);
}

/// `lumis merge --png` writes the PNG `lumis render --png` writes: the display transform
/// recorded in the tiles (clamp for a `.scn` scene), the same --tonemap, automatic exposure.
#[test]
fn the_png_preview_is_the_single_renders() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scn = root().join("tests/fixtures/scn");
    let scn = super::common::files::files_under(&scn, &["scn"]).remove(0);
    let knot = root().join("assets/knot.obj");
    for (name, scene, tonemap) in [
        ("scn", scn.to_str().unwrap(), "none"),
        ("knot", knot.to_str().unwrap(), "filmic"),
        ("default", "", "filmic"),
    ] {
        let mut args = vec!["--width", "32", "--height", "40", "--tonemap", tonemap];
        if !scene.is_empty() {
            args.push(scene);
        }
        let mut single = vec!["render", "-q", "-o", "s.exr", "--png", "s.png"];
        single.extend_from_slice(&args);
        assert_ok(&super::lumis(d, &single));
        let tiles = render_tiles(d, name, 3, &args);
        let mut merge_args = vec![
            "merge",
            "-q",
            "-o",
            "m.exr",
            "--png",
            "m.png",
            "--tonemap",
            tonemap,
        ];
        merge_args.extend(tiles.iter().map(|p| p.to_str().unwrap()));
        assert_ok(&super::lumis(d, &merge_args));
        for (a, b) in [("s.exr", "m.exr"), ("s.png", "m.png")] {
            let same = std::fs::read(d.join(a)).unwrap() == std::fs::read(d.join(b)).unwrap();
            assert!(same, "{name}: {b} differs from the single render's {a}");
        }
    }
}

/// Instances (issue 28): the instancing example with its id layers (`id.instance` among them)
/// and Cryptomatte, the glTF `EXT_mesh_gpu_instancing` asset, and a frame of an animation that
/// moves an instance: every merge is the single render's bytes.
#[test]
fn instances_tiles_and_a_frame_that_moves_one() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/instances.toml");
    let args = [
        "--width",
        "64",
        "--height",
        "36",
        "--cryptomatte",
        scene.to_str().unwrap(),
    ];
    assert_identical(dir.path(), "instances", &[2, 5], &args);
    let gltf = root().join("assets/gltf/gpu_instancing.gltf");
    let args = ["--width", "48", "--height", "24", gltf.to_str().unwrap()];
    assert_identical(dir.path(), "gpu_instancing", &[3], &args);
    let moving = dir.path().join("moving.toml");
    std::fs::write(
        &moving,
        r#"
[camera]
position = [0.0, 1.0, 6.0]
look_at = [0.0, 0.5, 0.0]
fov = 40.0

[[light]]
type = "point"
position = [2.0, 5.0, 4.0]
intensity = 60.0

[[sphere]]
name = "ball"
center = [0.0, 0.0, 0.0]
radius = 0.5

[[instance]]
of = "ball"
name = "mover"
translate = [-1.5, 0.5, 0.0]
scale = [1.0, 0.5, 1.0]

[animation]
frames = 10

[[animation.instance]]
name = "mover"
frame = 0
translate = [-1.5, 0.5, 0.0]

[[animation.instance]]
name = "mover"
frame = 9
translate = [1.5, 0.5, 0.0]
"#,
    )
    .unwrap();
    let args = [
        "--width",
        "40",
        "--height",
        "24",
        "--frame",
        "4",
        moving.to_str().unwrap(),
    ];
    assert_identical(dir.path(), "moving", &[3], &args);
}

//! `lumis render --from IMAGE.exr` (issue 41): an image's header is enough to make it again,
//! byte for byte, for a TOML scene, a glTF model, a `.scn` scene, a farm tile and an animation
//! frame; a changed or missing input, another lumis version, an older text settings record
//! and extra pixel flags are refused with the image's name and the reason.

mod refused;

use crate::common::cli::{assert_ok, binary};
use std::path::Path;
use std::process::{Command, Output};

pub fn lumis(dir: &Path, args: &[&str]) -> Output {
    Command::new(binary())
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// Renders `args` to `a.exr` in `dir`, replays it to `b.exr`, and requires the same bytes.
fn replays_to_the_same_bytes(dir: &Path, args: &[&str]) {
    let mut first = vec!["render", "-q", "-o", "a.exr"];
    first.extend_from_slice(args);
    assert_ok(&lumis(dir, &first));
    assert_ok(&lumis(
        dir,
        &["render", "--from", "a.exr", "-o", "b.exr", "-q"],
    ));
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    assert!(
        std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
        "--from gave other bytes for {args:?}"
    );
}

fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(path)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn a_toml_scene_with_flags_and_defines() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("scenes/default.toml");
    replays_to_the_same_bytes(
        dir.path(),
        &[
            &scene,
            "--width",
            "48",
            "--height",
            "27",
            "--spp",
            "2",
            "-D",
            "render.max_depth=3",
            "--exposure",
            "-0.5",
            "--aov",
            "albedo,uv",
            "--seed",
            "9",
            "--cryptomatte",
        ],
    );
}

#[test]
fn the_built_in_scene_with_a_crop() {
    let dir = tempfile::tempdir().unwrap();
    replays_to_the_same_bytes(
        dir.path(),
        &[
            "--width",
            "40",
            "--height",
            "30",
            "--pixel-bounds",
            "5,30,2,20",
            "--float",
        ],
    );
}

#[test]
fn a_gltf_model_with_automatic_exposure() {
    let dir = tempfile::tempdir().unwrap();
    let model = repo("assets/gltf/lights_camera.gltf");
    replays_to_the_same_bytes(
        dir.path(),
        &[
            &model, "--camera", "0", "--width", "40", "--height", "30", "--layout", "blender",
        ],
    );
}

#[test]
fn a_paper_scene() {
    let scn = repo("../shared/paper-scenes/scenes/allMaterials.scn");
    if !Path::new(&scn).exists() {
        eprintln!("skipped: no {scn}");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    replays_to_the_same_bytes(dir.path(), &[&scn, "--width", "64", "--height", "36"]);
}

#[test]
fn a_farm_tile_and_an_animation_frame() {
    let dir = tempfile::tempdir().unwrap();
    replays_to_the_same_bytes(
        dir.path(),
        &["--width", "40", "--height", "30", "--tile", "1/3"],
    );
    let orbit = repo("scenes/orbit.toml");
    replays_to_the_same_bytes(
        dir.path(),
        &[
            &orbit, "--frame", "2", "--width", "40", "--height", "24", "--spp", "1",
        ],
    );
}

//! What a user reads says things in the command line's words, never in Rust's debug syntax
//! (issue 41): `lumis info` and the render summary with `--stats`, over every kind of light,
//! lens and format, hold no `{ `, `Vec3(` or `Some(`.

use crate::common::cli::{assert_ok, binary};
use std::path::Path;
use std::process::Command;

const DEBUG_MARKS: [&str; 5] = ["{ ", "Vec3(", "Some(", "Square(", "Disk("];

fn scenes() -> Vec<String> {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out: Vec<String> = [
        "scenes/default.toml",
        "scenes/environment.toml",
        "scenes/instances.toml",
        "assets/knot.obj",
        "assets/gltf/lights_camera.gltf",
    ]
    .iter()
    .map(|p| repo.join(p).to_string_lossy().into_owned())
    .collect();
    // A .scn scene has the paper's unattenuated lights and square lens.
    let scn = repo.join("../shared/paper-scenes/scenes/allMaterials.scn");
    if scn.exists() {
        out.push(scn.to_string_lossy().into_owned());
    }
    out
}

fn assert_plain(what: &str, text: &str) {
    for mark in DEBUG_MARKS {
        assert!(!text.contains(mark), "{what} prints `{mark}`:\n{text}");
    }
}

#[test]
fn info_and_the_summary_read_as_words() {
    let dir = tempfile::tempdir().unwrap();
    for scene in scenes() {
        let out = Command::new(binary())
            .args(["info", &scene])
            .output()
            .unwrap();
        assert_ok(&out);
        assert_plain(
            &format!("lumis info {scene}"),
            &String::from_utf8_lossy(&out.stdout),
        );
        for extra in [&[][..], &["--adaptive", "0.1", "--effects", "all"][..]] {
            let out = Command::new(binary())
                .args([
                    "render", &scene, "--stats", "--width", "24", "--height", "16",
                ])
                .args(["-o", "x.exr"])
                .args(extra)
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert_ok(&out);
            assert_plain(
                &format!("lumis render {scene} --stats {extra:?}"),
                &String::from_utf8_lossy(&out.stderr),
            );
        }
    }
}

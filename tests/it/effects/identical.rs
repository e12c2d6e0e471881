//! §3: for every paper scene, every shipped asset and the default scene, the default render is
//! bit-identical to `--effects all` at cutoff 0, in RGBA and every AOV layer.

use super::auto_and_all;
use super::common::files::{files_under, paper_scenes, root};
use std::path::Path;

/// Loads `file`, shrinks the image to `w x h` with one sample per pixel, and checks both modes.
fn check(file: &Path, w: u32, h: u32) -> (u64, u64) {
    let mut scene =
        lumis_io::formats::load(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let st = scene.settings_mut();
    (st.width, st.height, st.spp) = (w, h, 1);
    let (auto, all) = auto_and_all(&file.display().to_string(), &mut scene);
    (auto.counts.total(), all.counts.total())
}

#[test]
fn paper_scenes_render_the_same_bits_as_effects_all() {
    for file in &paper_scenes() {
        // The scene's own depth, lens rays and (zero) cutoff; a small image keeps the
        // everything-traced reference affordable.
        let (auto, all) = check(file, 24, 14);
        eprintln!("{}: {auto} rays, all {all}", file.display());
    }
}

#[test]
fn assets_render_the_same_bits_as_effects_all() {
    let mut models = files_under(&root().join("assets"), &["obj", "gltf", "glb"]);
    models.extend(files_under(&root().join("scenes"), &["toml"]));
    models.extend(files_under(
        &root().join("tests/fixtures"),
        &["toml", "scn"],
    ));
    assert!(
        models.len() >= 15,
        "expected the project's assets, found {models:?}"
    );
    for file in &models {
        check(file, 24, 16);
    }
}

#[test]
fn default_scene_renders_the_same_bits_as_effects_all() {
    let mut scene = lumis_io::formats::default_scene().expect("default scene");
    let st = scene.settings_mut();
    // Full samples and depth of the default; a smaller image.
    (st.width, st.height) = (64, 36);
    let (auto, all) = auto_and_all("default scene", &mut scene);
    // The default scene has every effect, and the decisions save rays of each skippable kind.
    let (a, r) = (&auto.counts, &all.counts);
    assert!(a.shadow > 0 && a.reflection > 0 && a.refraction > 0 && a.aov > 0);
    assert!(a.shadow < r.shadow && a.reflection < r.reflection && a.refraction < r.refraction);
    assert_eq!(a.camera, r.camera);
    assert_eq!(a.aov, r.aov);
}

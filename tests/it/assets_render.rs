//! Every model the project ships in `assets/` (except the deliberately broken ones in
//! `assets/gltf/bad/`) loads and renders, with geometry in view.

use crate::common;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::World;

#[test]
fn every_asset_loads_and_renders() {
    let files = common::files::files_under(
        &common::files::root().join("assets"),
        &["obj", "gltf", "glb", "m"],
    );
    assert!(
        files.len() >= 15,
        "expected the project's assets, found {files:?}"
    );
    for file in files {
        let mut scene =
            lumis_io::formats::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let st = scene.settings_mut();
        (st.width, st.height, st.spp) = (24, 16, 1);
        let world = World::build(scene.clone(), AccelKind::Sah, &BuildOptions::default());
        let film = render(&world, &RenderOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
            .film;
        let seen = film.aov().iter().filter(|a| a.object_id >= 0).count();
        // An empty scene (assets/gltf/empty_scene.gltf) is valid glTF and shows no geometry.
        let empty = scene.geometry().prims().is_empty();
        assert!(seen > 0 || empty, "{}: nothing in view", file.display());
    }
}

//! Every model the project ships in `assets/` (except the deliberately broken ones in
//! `assets/gltf/bad/`) loads and renders, with geometry in view.

use lumis::accel::{Accel, AccelKind, BuildOptions};
use lumis::render::{RenderOptions, render};
use std::path::{Path, PathBuf};

fn models(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let p = entry.path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n != "bad") {
                models(&p, out);
            }
        } else if p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| ["obj", "gltf", "glb", "m"].contains(&e))
        {
            out.push(p);
        }
    }
}

#[test]
fn every_asset_loads_and_renders() {
    let mut files = Vec::new();
    models(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"),
        &mut files,
    );
    files.sort();
    assert!(
        files.len() >= 15,
        "expected the project's assets, found {files:?}"
    );
    for file in files {
        let mut scene =
            lumis::scene::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let st = scene.settings_mut();
        (st.width, st.height, st.spp) = (24, 16, 1);
        let accel = Accel::build(
            AccelKind::Sah,
            &scene.geometry().prim_bounds(),
            &BuildOptions::default(),
        );
        let film = render(&scene, &accel, &RenderOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
            .film;
        let seen = film.aov().iter().filter(|a| a.object_id >= 0).count();
        assert!(seen > 0, "{}: nothing in view", file.display());
    }
}

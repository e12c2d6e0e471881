//! What each fuzz target does with one input, shared by the fuzz targets (fuzz/src/lib.rs)
//! and the stable regression test that replays their crash inputs (tests/fuzz_regressions.rs,
//! which includes this file by path, with queries/). It depends only on lumis, and the
//! `queries` target on the modules of queries/ (whose dependencies the main crate has as
//! dev-dependencies).
//!
//! Every target calls the entry point the CLI uses: `load_with_overrides` for scenes and
//! models (as `lumis render` does), `rays::read_rays` for `.npy` (as `lumis hits --rays`).
//! Path-based entry points get the input as a file with the right extension in `dir`, and
//! some targets get a fixed, valid companion file beside it.

use std::path::Path;

/// The fuzz targets, by name (also the folders of tests/fuzz_regressions/).
pub const TARGETS: [&str; 11] = [
    "toml", "obj", "mtl", "gltf", "glb", "scn", "m", "npy", "queries", "hdr", "exr",
];

/// Feeds `data` to `target` inside `dir`. Any `Ok` or `Err` of the loader is fine; only a
/// panic, a hang or runaway memory is a finding.
pub fn run_in(dir: &Path, target: &str, data: &[u8]) {
    let put = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("scratch file");
        path
    };
    let load = |path: &Path| {
        let options = lumis_io::formats::LoadOptions::default();
        let _ = lumis_io::formats::load_with_overrides(path, &options, &[]);
    };
    match target {
        "toml" => {
            // For `[[mesh]] file = "tri.obj"`.
            put("tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
            load(&put("scene.toml", data));
        }
        "obj" => {
            put(
                "m.mtl",
                b"newmtl red\nKd 1 0 0\nnewmtl glass\nKs 1 1 1\nNi 1.5\nillum 7\n",
            );
            load(&put("model.obj", data));
        }
        "mtl" => {
            put("m.mtl", data);
            let obj = b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl red\n\
                        f 1/1 2/1 3/1\nusemtl glass\nf 3 2 1\n";
            load(&put("model.obj", obj));
        }
        "gltf" => {
            // For buffers and images with `"uri": "buf.bin"`.
            put("buf.bin", &[0u8; 64]);
            load(&put("scene.gltf", data));
        }
        "glb" => load(&put("scene.glb", data)),
        "scn" => {
            // For `model tri.m ...`.
            put(
                "tri.m",
                b"Vertex 1 0 0 0\nVertex 2 1 0 0\nVertex 3 0 1 0\nFace 1 1 2 3\n",
            );
            load(&put("scene.scn", data));
        }
        "m" => {
            put("mesh.m", data);
            let scn = b"model mesh.m 1 0 0 -5 FlatColor 0.6 0.2 0.9 null\n";
            load(&put("scene.scn", scn));
        }
        "npy" => {
            let _ = lumis_io::rays::read_rays(&put("rays.npy", data));
        }
        // Environment maps, through the scene table that names them (as `--env` does).
        "hdr" | "exr" => {
            put(&format!("sky.{target}"), data);
            let scene = format!(
                "[environment]\nfile = \"sky.{target}\"\n[[sphere]]\ncenter = [0, 0, 0]\n\
                 radius = 1\n"
            );
            load(&put("scene.toml", scene.as_bytes()));
        }
        // Ray queries on a decoded scene (fuzz/src/queries/): no files, `dir` unused.
        "queries" => super::queries::run(data),
        other => panic!("no fuzz target {other}"),
    }
}

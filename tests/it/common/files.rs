//! The scene and model files the tests run over: the paper's `.scn` scenes beside the checkout
//! and the project's own assets.

use std::path::{Path, PathBuf};

/// The crate root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `name` in the project's glTF assets, `assets/gltf/`.
pub fn gltf_asset(name: &str) -> PathBuf {
    root().join("assets/gltf").join(name)
}

/// The paper's `.scn` scenes in `../shared/paper-scenes/scenes`, sorted. Empty (with a note on
/// stderr) when the folder is missing, unless `LUMIS_REQUIRE_PAPER_SCENES` is set (CI): then a
/// missing folder fails the test instead of silently skipping it.
pub fn paper_scenes() -> Vec<PathBuf> {
    let dir = root().join("../shared/paper-scenes/scenes");
    let files = files_under(&dir, &["scn"]);
    if files.is_empty() {
        assert!(
            std::env::var_os("LUMIS_REQUIRE_PAPER_SCENES").is_none(),
            "no paper scenes in {}",
            dir.display()
        );
        eprintln!("skipping: {} not found", dir.display());
    }
    files
}

/// Every file under `dir` (recursively) whose extension is one of `exts`, sorted, leaving out
/// the deliberately broken inputs kept in folders named `bad`.
pub fn files_under(dir: &Path, exts: &[&str]) -> Vec<PathBuf> {
    fn walk(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for p in entries.flatten().map(|e| e.path()) {
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "bad") {
                    walk(&p, exts, out);
                }
            } else if p
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| exts.contains(&e))
            {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, exts, &mut out);
    out.sort();
    out
}

/// The names of the entries of `dir`, sorted (what a run left behind there).
pub fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

//! What every fuzz target shares: a scratch folder per process for the path-based entry
//! points, and a panic hook that turns every panic into a crash, including those lumis's own
//! guard would otherwise catch quietly (a caught panic is still a bug to fix at the root).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// This process's scratch folder (created once; libFuzzer's fork mode runs one per child).
pub fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        lumis::formats::guard::install();
        std::panic::set_hook(Box::new(|info| {
            eprintln!("{info}");
            std::process::abort();
        }));
        let dir = std::env::temp_dir().join(format!("lumis-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    })
}

/// Writes `bytes` to `name` in the scratch folder and returns its path.
pub fn put(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, bytes).expect("scratch file");
    path
}

/// Loads `path` as `lumis render` does (default options, no overrides). Any `Ok` or `Err` is
/// fine; only a panic, a hang or runaway memory is a finding.
pub fn load(path: &Path) {
    let _ = lumis::formats::load_with_overrides(path, &lumis::formats::LoadOptions::default(), &[]);
}

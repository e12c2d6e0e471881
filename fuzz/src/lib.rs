//! What every fuzz target shares: a scratch folder per process for the path-based entry
//! points, and a panic hook that turns every panic into a crash, including those lumis's own
//! guard would otherwise catch quietly (a caught panic is still a bug to fix at the root).

mod harness;
pub mod queries;

pub use harness::TARGETS;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// This process's scratch folder (created once; libFuzzer's fork mode runs one per child).
fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        // lumis's quiet hook goes in first, so this one replaces it for every panic.
        lumis_io::files::guard::install();
        std::panic::set_hook(Box::new(|info| {
            eprintln!("{info}");
            // A panic inside lumis during a ray query: the scene and ray it happened on.
            if let Some(context) = queries::context() {
                eprintln!("{context}");
            }
            std::process::abort();
        }));
        let dir = std::env::temp_dir().join(format!("lumis-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    })
}

/// Runs fuzz target `target` on `data` (see [`harness::run_in`]).
pub fn run(target: &str, data: &[u8]) {
    harness::run_in(scratch(), target, data);
}

//! Walking every SIMD path the CPU supports: the tests that compare the accelerators with
//! brute force run once per path (scalar, AVX2, AVX-512), forcing it for the process, and
//! print which ran (`cargo test -- --nocapture` shows it).

use std::sync::{Mutex, MutexGuard};

use lumis_core::accel::SimdPath;

/// Held while a test walks the paths, so two such tests do not switch the path under each
/// other (other tests' walks may take the forced path meanwhile: every path gives the same
/// answers).
static SWITCHING: Mutex<()> = Mutex::new(());

/// The paths to walk; on drop the path in force before is restored.
pub struct SimdPaths {
    paths: Vec<SimdPath>,
    before: SimdPath,
    _lock: MutexGuard<'static, ()>,
}

/// Every path this CPU supports, narrowest first, for the test `what`.
pub fn simd_paths(what: &str) -> SimdPaths {
    let lock = SWITCHING.lock().unwrap_or_else(|e| e.into_inner());
    let paths = SimdPath::all_supported();
    let names: Vec<_> = paths.iter().map(|p| p.name()).collect();
    eprintln!("{what}: SIMD paths {}", names.join(", "));
    SimdPaths {
        paths,
        before: SimdPath::active(),
        _lock: lock,
    }
}

impl SimdPaths {
    /// Each path, forced in turn for as long as the iteration is on it.
    pub fn each(&self) -> impl Iterator<Item = SimdPath> + '_ {
        self.paths.iter().map(|&p| {
            p.force().expect("a supported path can be forced");
            p
        })
    }
}

impl Drop for SimdPaths {
    fn drop(&mut self) {
        let _ = self.before.force();
    }
}

//! Replays every input under tests/fuzz_regressions/<target>/ through the same harness as the
//! fuzz targets (fuzz/src/harness.rs, included by path), on the stable toolchain, so a crash
//! the fuzzer once found stays fixed even where the nightly fuzzing cannot run. A panic
//! anywhere fails, including one lumis's guard would catch quietly: this test's hook sees it.

#[path = "../../fuzz/src/harness.rs"]
mod harness;
use crate::queries;

use std::path::Path;
use std::sync::Mutex;

/// Where the panics seen so far happened.
static PANICS: Mutex<Vec<String>> = Mutex::new(Vec::new());

#[test]
fn every_recorded_fuzz_input_loads_or_fails_without_a_panic() {
    lumis_io::files::guard::install();
    std::panic::set_hook(Box::new(|info| {
        // A ray query's panic inside lumis also names the scene and ray (fuzz/src/queries/).
        let context = queries::context().unwrap_or_default();
        PANICS.lock().unwrap().push(format!("{info}\n{context}"));
    }));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut replayed = 0;
    let mut failures = Vec::new();
    for target in harness::TARGETS {
        let Ok(entries) = std::fs::read_dir(root.join(target)) else {
            continue;
        };
        let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
        files.sort();
        for file in files {
            let data = std::fs::read(&file).unwrap();
            let dir = tempfile::tempdir().unwrap();
            let outcome = std::panic::catch_unwind(|| harness::run_in(dir.path(), target, &data));
            let panics = std::mem::take(&mut *PANICS.lock().unwrap());
            if outcome.is_err() || !panics.is_empty() {
                failures.push(format!("{target} {}: {panics:?}", file.display()));
            }
            replayed += 1;
        }
    }
    let _ = std::panic::take_hook();
    assert!(replayed > 0, "no inputs under {}", root.display());
    assert!(failures.is_empty(), "{failures:#?}");
}

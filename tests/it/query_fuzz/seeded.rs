//! The fuzz target's checker over pseudo-random inputs from a fixed seed: every `cargo test`
//! runs it, nightly or not. Failures are grouped by their first line, each class reported
//! once with its first reproduction (the scene and ray as Rust).
//!
//! `QUERY_FUZZ_ONLY=i` runs seeded input `i` alone; `QUERY_FUZZ_REPLAY=DIR` replays the files
//! of a folder instead (a fuzz run's `fuzz/artifacts/queries/`), grouped the same way:
//! `QUERY_FUZZ_REPLAY=fuzz/artifacts/queries cargo test --test query_fuzz replay`.

use super::queries;
use std::collections::BTreeMap;
use std::sync::atomic::Ordering::Relaxed;

/// Inputs per run: a few seconds at the test profile's opt-level.
const INPUTS: usize = 20_000;

#[test]
fn seeded_queries_agree_with_brute_force_and_the_oracle() {
    let only = std::env::var("QUERY_FUZZ_ONLY").ok();
    let inputs = inputs(INPUTS).enumerate().filter_map(|(i, data)| {
        let wanted = only.as_ref().is_none_or(|o| *o == i.to_string());
        wanted.then(|| (format!("input {i}"), data))
    });
    let classes = run_all(inputs);
    let counts: Vec<String> = queries::COUNTS
        .iter()
        .zip(queries::COUNT_NAMES)
        .map(|(c, name)| format!("{name} {}", c.load(Relaxed)))
        .collect();
    println!("{INPUTS} inputs: {}", counts.join(", "));
    assert!(classes.is_empty(), "{}", report(&classes));
}

/// The first `n` seeded inputs (48 to 247 pseudo-random bytes each, splitmix64 from a fixed
/// seed): input `i` is the same in every run and for every test that uses them.
pub fn inputs(n: usize) -> impl Iterator<Item = Vec<u8>> {
    let mut state = 0x5eed_u64;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    (0..n).map(move |_| {
        let len = 48 + (next() % 200) as usize;
        (0..len).map(|_| next() as u8).collect()
    })
}

#[test]
fn replay() {
    let Ok(dir) = std::env::var("QUERY_FUZZ_REPLAY") else {
        return;
    };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let n = files.len();
    let classes = run_all(
        files
            .into_iter()
            .map(|f| (f.display().to_string(), std::fs::read(&f).unwrap())),
    );
    println!("{n} files replayed");
    assert!(classes.is_empty(), "{}", report(&classes));
}

/// Failure classes: (count, first reproduction) by class.
type Classes = BTreeMap<String, (usize, String)>;

/// Runs every `(name, bytes)` input, catching failures.
fn run_all(inputs: impl Iterator<Item = (String, Vec<u8>)>) -> Classes {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut classes = Classes::new();
    for (name, data) in inputs {
        let Err(e) = std::panic::catch_unwind(|| queries::run(&data)) else {
            continue;
        };
        let msg = e
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        // A panic inside lumis carries no report: the checker's context says where it was.
        let msg = match queries::context() {
            Some(c) => format!("panic inside lumis: {msg}\n{c}"),
            None => msg,
        };
        let entry = classes
            .entry(queries::failure_class(&msg))
            .or_insert((0, format!("{name}: {msg}\ndata: {data:?}")));
        entry.0 += 1;
    }
    std::panic::set_hook(hook);
    classes
}

fn report(classes: &Classes) -> String {
    let list: Vec<String> = classes
        .iter()
        .map(|(k, (n, first))| format!("== {n} x {k}\n{first}\n"))
        .collect();
    format!("{} failure classes:\n{}", classes.len(), list.join("\n"))
}

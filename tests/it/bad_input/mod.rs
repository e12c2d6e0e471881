//! The malformed-input corpus (issue 14): every format lumis reads, damaged in generated ways
//! (truncations, byte flips, NaN/Inf and huge numbers, huge counts, missing files), run through
//! the binary (`render`, `hits`, `info`) with a timeout. Each run must be a clean error (exit
//! code not 0 and not 101, stderr naming the file, no "panicked", no output left behind, an
//! existing output unchanged) or a clean render whose EXR holds only finite colour and normals.
//!
//! Failures are collected and reported together with the case that reproduces them. Failures
//! of a class another branch fixes are marked with their issue item ([`KNOWN_ITEMS`]); once
//! that branch is merged, deleting the item from the list makes them count again.

mod mutate;
mod run;
mod seeds;
mod values;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use run::{Outcome, Run};

/// Issue-14 items whose failures are expected until their branch is merged: 1 (panics inside
/// tobj and gltf), 2 (memory bombs), 3 (FIFOs and devices). Remove an item to enforce it.
const KNOWN_ITEMS: &[u32] = &[];

/// A splitmix64 generator: the cases are the same on every run and machine.
pub struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// One run: the files of its directory (seeds with one damaged or removed) and the command.
pub struct Case {
    pub label: String,
    pub files: BTreeMap<&'static str, Vec<u8>>,
    /// The damaged file (what the error must name).
    pub target: &'static str,
    pub args: Vec<String>,
    /// A FIFO instead of the target (issue item 3).
    pub fifo: bool,
}

/// `lumis render scene` at the corpus's size, writing `out.exr` and `out.png`.
fn render(scene: &str) -> Vec<String> {
    [
        "render", scene, "--width", "16", "--height", "12", "--spp", "1", "-o", "out.exr", "--png",
        "out.png", "-q",
    ]
    .map(String::from)
    .to_vec()
}

/// The command that reads `file` (damaged), alternating between the scene that references it
/// and the file itself where it is a scene too; every third case also runs `lumis info`.
fn commands(file: &str, k: usize) -> Vec<Vec<String>> {
    let scene = match (file, k % 2) {
        ("rays.npy", _) => {
            return vec![
                [
                    "hits",
                    "scene.toml",
                    "--rays",
                    "rays.npy",
                    "--out",
                    "hits.npy",
                ]
                .map(String::from)
                .to_vec(),
            ];
        }
        ("model.obj" | "model.mtl" | "tex.png", 1) => "model.obj",
        ("cube.gltf" | "cube.bin", 1) => "cube.gltf",
        ("cube.glb", 1) => "cube.glb",
        ("scene.scn", _) | ("tetra.m", 1) => "scene.scn",
        _ => "scene.toml",
    };
    let mut out = vec![render(scene)];
    if k.is_multiple_of(3) {
        out.push(vec!["info".into(), scene.into()]);
    }
    out
}

fn cases(repo: &Path) -> Vec<Case> {
    let seeds = seeds::seeds(repo);
    let all: BTreeMap<&'static str, Vec<u8>> =
        seeds.iter().map(|s| (s.name, s.bytes.clone())).collect();
    // CI runs the default ~300 cases; a deeper search sets another seed and a scale, e.g.
    // `LUMIS_BAD_INPUT_SEED=7 LUMIS_BAD_INPUT_SCALE=7 cargo test --test bad_input` (~2,000).
    let env = |key: &str, default: u64| {
        std::env::var(key)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let mut rng = Rng(env("LUMIS_BAD_INPUT_SEED", 14));
    let scale = env("LUMIS_BAD_INPUT_SCALE", 1).clamp(1, 100) as usize;
    let mut out = Vec::new();
    let mut k = 0;
    for seed in &seeds {
        let counts = (5 * scale, 8 * scale, 14 * scale);
        let mut ms = mutate::mutations(&seed.bytes, seed.text, &mut rng, counts);
        if seed.name != "scene.toml" && seed.name != "scene.scn" {
            ms.push(mutate::missing());
        }
        for m in ms {
            for args in commands(seed.name, k) {
                let mut files = all.clone();
                match &m.bytes {
                    Some(b) => files.insert(seed.name, b.clone()),
                    None => files.remove(seed.name),
                };
                out.push(Case {
                    label: format!("{}: {}", seed.name, m.label),
                    files,
                    target: seed.name,
                    args,
                    fifo: false,
                });
            }
            k += 1;
        }
    }
    // Non-regular files where a mesh and a buffer are expected (item 3).
    for target in ["model.obj", "cube.bin"] {
        let mut files = all.clone();
        files.remove(target);
        out.push(Case {
            label: format!("{target}: a FIFO"),
            files,
            target,
            args: commands(target, 0).remove(0),
            fifo: true,
        });
    }
    // Flags that only mean something for glTF files, on other formats.
    for (scene, flag) in [
        ("scene.toml", "--camera"),
        ("scene.toml", "--gltf-scene"),
        ("scene.scn", "--camera"),
        ("model.obj", "--gltf-scene"),
    ] {
        let mut args = render(scene);
        args.extend([flag.to_string(), "0".into()]);
        out.push(Case {
            label: format!("{scene}: {flag} 0"),
            files: all.clone(),
            target: scene,
            args,
            fifo: false,
        });
    }
    out
}

#[test]
fn every_malformed_input_is_a_clean_error_or_a_finite_render() {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let cases = cases(&repo);
    assert!(cases.len() > 250, "{} cases", cases.len());
    let scratch = tempfile::tempdir().unwrap();
    let results: Vec<(usize, Outcome)> = std::thread::scope(|s| {
        let workers = 2;
        let handles: Vec<_> = (0..workers)
            .map(|w| {
                let (cases, scratch) = (&cases, scratch.path());
                s.spawn(move || {
                    (w..cases.len())
                        .step_by(workers)
                        .map(|i| (i, Run::new(&cases[i], &scratch.join(i.to_string())).check()))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    let (mut failures, mut known) = (Vec::new(), Vec::new());
    let (mut errors, mut renders) = (0, 0);
    for (i, outcome) in results {
        let c = &cases[i];
        match outcome {
            Outcome::CleanError => errors += 1,
            Outcome::Accepted => renders += 1,
            Outcome::Bad { item, why } => {
                let line = format!("[{}] {}: lumis {}: {why}", i, c.label, c.args.join(" "));
                match item.filter(|n| KNOWN_ITEMS.contains(n)) {
                    Some(n) => known.push(format!("(known, item {n}) {line}")),
                    None => failures.push(line),
                }
            }
        }
    }
    eprintln!(
        "{} cases: {errors} clean errors, {renders} accepted renders, {} known failures:\n{}",
        cases.len(),
        known.len(),
        known.join("\n")
    );
    assert!(
        failures.is_empty(),
        "{} of {} malformed inputs were not handled cleanly:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
    // The corpus must exercise both sides.
    assert!(
        errors > 50 && renders > 50,
        "{errors} errors, {renders} renders"
    );
}

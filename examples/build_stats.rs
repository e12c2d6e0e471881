//! Build time and tree quality of the SAH hierarchy for one scene, measured in-process:
//! `cargo run --release --example build_stats -- SCENE [RUNS]`.
//!
//! Prints the median wall time of `Accel::build_for` over RUNS builds on a pool of
//! `BUILD_THREADS` threads (default 1), and the SAH cost of
//! the binary tree in the builder's own cost model: a node visit costs
//! 1, a leaf `ceil(n / 4)`, each weighted by its box's area relative to the root's.

use lumis_core::accel::{Accel, AccelKind, BuildOptions, Bvh, LEAF_ALIGN};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).expect("usage: build_stats SCENE [RUNS]");
    let runs: usize = args.get(2).map_or(9, |r| r.parse().expect("RUNS"));
    let scene = lumis_io::formats::load(std::path::Path::new(path)).expect("scene");
    let geometry = scene.geometry();
    let opts = BuildOptions::default();
    let threads: usize =
        std::env::var("BUILD_THREADS").map_or(1, |t| t.parse().expect("BUILD_THREADS"));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let mut times = Vec::new();
    let mut accel = None;
    for _ in 0..runs {
        let start = Instant::now();
        let a = pool.install(|| Accel::build_for(AccelKind::Sah, geometry, &opts));
        times.push(start.elapsed().as_secs_f64());
        accel = Some(a);
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let prims = geometry.prims().len();
    let wide = accel
        .as_ref()
        .and_then(Accel::wide)
        .expect("a wide hierarchy");
    let binary = wide.to_binary();
    println!(
        "prims {prims} build_median_ms {:.3} min_ms {:.3} mtri_per_s {:.2}",
        median * 1e3,
        times[0] * 1e3,
        prims as f64 / median / 1e6
    );
    println!(
        "binary_nodes {} binary_sah {:.4} wide_nodes {}",
        binary.nodes().len(),
        binary_cost(&binary),
        wide.nodes().len(),
    );
    println!(
        "tree_fingerprint {:016x} wide_fingerprint {:016x}",
        fingerprint(&binary),
        wide_fingerprint(wide)
    );
}

/// A hash of the tree's nodes as a set of (bounds, sorted leaf primitives): equal for the same
/// tree in any node order and any order within leaves.
fn fingerprint(b: &Bvh) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut all: Vec<(Vec<u32>, Vec<u32>)> = b
        .nodes()
        .iter()
        .map(|n| {
            let bits = [n.bounds.min.to_array(), n.bounds.max.to_array()]
                .concat()
                .iter()
                .map(|f| f.to_bits())
                .collect();
            let mut prims = if n.is_leaf() {
                b.prim_order()[n.first as usize..(n.first + n.count) as usize].to_vec()
            } else {
                vec![]
            };
            prims.sort_unstable();
            (bits, prims)
        })
        .collect();
    all.sort_unstable();
    let mut h = std::collections::hash_map::DefaultHasher::new();
    all.hash(&mut h);
    h.finish()
}

fn area(b: &lumis_core::math::Aabb) -> f64 {
    let e = b.max - b.min;
    (e.x as f64 * e.y as f64 + e.y as f64 * e.z as f64 + e.z as f64 * e.x as f64).max(0.0)
}

fn leaf_cost(count: u32) -> f64 {
    count.div_ceil(LEAF_ALIGN as u32) as f64
}

/// Sum over nodes of relative area times (1 for an interior node, the group count for a leaf).
fn binary_cost(b: &Bvh) -> f64 {
    let root = area(&b.nodes()[0].bounds);
    b.nodes()
        .iter()
        .map(|n| {
            let c = if n.is_leaf() { leaf_cost(n.count) } else { 1.0 };
            c * area(&n.bounds) / root
        })
        .sum()
}

/// A hash of the wide nodes (their debug text) and the primitive order: equal for the same
/// wide tree in the same layout.
fn wide_fingerprint(w: &lumis_core::accel::Wide8) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!("{:?}", w.nodes()).hash(&mut h);
    w.prim_order().hash(&mut h);
    h.finish()
}

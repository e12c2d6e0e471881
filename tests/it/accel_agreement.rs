//! Every accelerator kind, at several leaf sizes, under every traversal (ordered, and the
//! scale-lights segments with short and long first segments), returns exactly the brute-force answer:
//! the same primitive and bit-identical `t`, `u`, `v` for `intersect`, the same verdict for
//! `occluded`. Hierarchies also pass their own invariant check (`Bvh::validate`).
//!
//! Every SIMD path the CPU supports is walked (`common::simd`).
//!
//! Scenes and rays are seeded; a failure names the scene, kind, leaf size, path and ray index.

use crate::common;

use common::{Rng, all_kinds, brute, closest, occluded, rays, same_hit, scenes, simd};
use lumis_core::accel::{
    Accel, AccelKind, BuildOptions, BuildQuality, Hit, SegmentParams, Traversal,
};
use lumis_core::geometry::{Geometry, WatertightRay};
use lumis_core::math::Ray;

/// Leaf sizes every hierarchy is built with: one primitive per leaf (deepest tree, most box
/// culling), the default, and large leaves (many primitives tested per leaf).
const LEAF_SIZES: [usize; 3] = [1, 4, 20];

/// The traversals every hierarchy is walked with: ordered, the paper's exhaustive walk, many short segments (the scenes
/// span ~10-100 units), and the paper's long first segment.
const TRAVERSALS: [Traversal; 4] = [
    Traversal::Ordered,
    Traversal::Exhaustive,
    Traversal::Segments(SegmentParams {
        init: 0.05,
        max: 100.0,
    }),
    Traversal::Segments(SegmentParams {
        init: 4096.0,
        max: 40_000.0,
    }),
];

/// Every kind with its builder, and the SAH hierarchy once more from the fast builder.
fn builds() -> Vec<(AccelKind, BuildQuality)> {
    let mut builds: Vec<_> = all_kinds()
        .into_iter()
        .map(|k| (k, BuildQuality::Full))
        .collect();
    builds.push((AccelKind::Sah, BuildQuality::Fast));
    builds
}

/// Checks every kind and leaf size against brute force on `rays`; returns the number of rays.
fn check(name: &str, g: &Geometry, rays: &[Ray]) -> usize {
    let bounds = g.prim_bounds();
    let reference = brute(g);
    let expected: Vec<(Option<Hit>, bool)> = rays
        .iter()
        .map(|r| (closest(&reference, g, r), occluded(&reference, g, r)))
        .collect();
    // A hit and "occluded" must agree within the reference itself, or the comparison means little.
    for (i, (h, o)) in expected.iter().enumerate() {
        assert_eq!(
            h.is_some(),
            *o,
            "{name}: brute intersect/occluded disagree on ray {i}"
        );
    }
    let paths = simd::simd_paths(&format!("accel agreement, {name}"));
    for (kind, quality) in builds() {
        for max_leaf_size in LEAF_SIZES {
            let opts = BuildOptions {
                max_leaf_size,
                quality,
            };
            let built = Accel::build_for(kind, g, &opts);
            // Without a hierarchy the leaf size means nothing: one run of brute force suffices.
            if built.kind() == AccelKind::Brute && max_leaf_size != LEAF_SIZES[0] {
                continue;
            }
            if let Some(b) = built.bvh()
                && let Err(e) = b.validate(&bounds)
            {
                panic!("{name} {kind:?} {quality:?} leaf {max_leaf_size}: invalid hierarchy: {e}");
            }
            if let Some(w) = built.wide()
                && let Err(e) = w.validate(&bounds)
            {
                panic!(
                    "{name} {kind:?} {quality:?} leaf {max_leaf_size}: invalid wide hierarchy: {e}"
                );
            }
            for (traversal, path) in TRAVERSALS
                .into_iter()
                .flat_map(|t| paths.each().map(move |p| (t, p)))
            {
                let accel = built.clone().with_traversal(traversal);
                let what = format!(
                    "{name} {kind:?} {quality:?} leaf {max_leaf_size} {traversal:?} {}",
                    path.name()
                );
                for (i, (r, (hit, occ))) in rays.iter().zip(&expected).enumerate() {
                    let got = closest(&accel, g, r);
                    assert!(
                        same_hit(&got, hit),
                        "{what} ray {i} {r:?}: got {got:?}, brute {hit:?}"
                    );
                    assert_eq!(
                        occluded(&accel, g, r),
                        *occ,
                        "{what} ray {i} {r:?}: occluded"
                    );
                }
            }
        }
    }
    rays.len()
}

/// Generates `n` mixed rays for `g` and checks them.
fn check_mixed(name: &str, g: &Geometry, seed: u64, n: usize) -> usize {
    let rays = rays::mixed(&mut Rng::new(seed), g, n);
    check(name, g, &rays)
}

#[test]
fn uniform_scenes_agree_with_brute_force() {
    let mut n = 0;
    n += check_mixed("uniform a", &scenes::uniform(1, 300, 700), 11, 25_000);
    n += check_mixed("uniform b", &scenes::uniform(2, 40, 1_200), 12, 20_000);
    n += check_mixed("uniform small", &scenes::uniform(3, 5, 12), 13, 5_000);
    assert_eq!(n, 50_000);
}

#[test]
fn clustered_scenes_agree_with_brute_force() {
    let mut n = 0;
    n += check_mixed("clustered a", &scenes::clustered(4, 300, 900), 21, 25_000);
    n += check_mixed("clustered b", &scenes::clustered(5, 800, 800), 22, 25_000);
    assert_eq!(n, 50_000);
}

#[test]
fn tessellated_scene_agrees_with_brute_force() {
    let n = check_mixed("tessellated", &scenes::tessellated(6), 31, 20_000);
    assert_eq!(n, 20_000);
}

#[test]
fn degenerate_scenes_agree_with_brute_force() {
    let mut n = 0;
    n += check_mixed("empty", &scenes::empty(), 41, 600);
    n += check_mixed("single sphere", &scenes::single_sphere(), 42, 1_200);
    n += check_mixed("single triangle", &scenes::single_triangle(), 43, 1_200);
    n += check_mixed("same centroid", &scenes::same_centroid(44), 44, 6_000);
    n += check_mixed(
        "flat axis-aligned",
        &scenes::flat_axis_aligned(45),
        45,
        6_000,
    );
    assert_eq!(n, 15_000);
}

/// Rays whose interval ends just at, before or after their brute-force hit, and rays leaving
/// each hit point (hits near `t = 0`, some behind): the ends of the interval, where the packed
/// group test's range filter may reject only what the exact test would (t = N / (D dir) bounded
/// from the edge functions' errors).
#[test]
fn interval_ends_at_the_hit_agree_with_brute_force() {
    for (name, g, seed) in [
        ("tessellated", scenes::tessellated(6), 61),
        ("uniform", scenes::uniform(7, 60, 400), 62),
        ("clustered", scenes::clustered(8, 200, 300), 63),
    ] {
        let mut rng = Rng::new(seed);
        let bounds = g.prim_bounds();
        let reference = brute(&g);
        let mut rays = Vec::new();
        let mut near_ends = 0;
        while rays.len() < 6_000 {
            let probe = rays::aimed(&mut rng, &g, &bounds);
            let Some(h) = closest(&reference, &g, &probe) else {
                continue;
            };
            let t = h.hit.t;
            for t_max in [
                t,
                t.next_down(),
                t.next_up(),
                t * (1.0 - 1e-6),
                t * (1.0 + 1e-6),
            ] {
                rays.push(Ray { t_max, ..probe });
            }
            // From the hit point, forwards and back: the same plane at t ~ 0 either side.
            let p = probe.at(t);
            rays.push(Ray::new(p, probe.dir));
            rays.push(Ray::new(p, -probe.dir));
            rays.push(Ray::new(p, rng.unit_vector()));
            near_ends += 1;
        }
        assert!(near_ends > 600, "{name}: only {near_ends} hits");
        check(name, &g, &rays);
    }
}

/// Coincident duplicates give bit-identical `t`; every kind must report the lowest index among
/// the primitives hit at the smallest `t`, whatever order its traversal visits them in.
#[test]
fn exact_t_ties_go_to_the_lowest_index() {
    let (g, groups) = scenes::duplicates(51);
    let rays = rays::mixed(&mut Rng::new(52), &g, 12_000);
    check("duplicates", &g, &rays);
    let mut ties = 0;
    for (kind, quality) in builds() {
        for max_leaf_size in LEAF_SIZES {
            let opts = BuildOptions {
                max_leaf_size,
                quality,
            };
            let accel = Accel::build_for(kind, &g, &opts);
            for (i, r) in rays.iter().enumerate() {
                let Some(h) = closest(&accel, &g, r) else {
                    continue;
                };
                // The rule, stated independently of any accelerator: scan all, keep the first minimum.
                let wr = WatertightRay::new(r.dir);
                let first_min = (0..g.prims().len() as u32)
                    .filter(|&p| g.intersect(p, r, &wr).is_some_and(|x| x.t == h.hit.t))
                    .min();
                assert_eq!(
                    Some(h.prim),
                    first_min,
                    "{kind:?} {quality:?} leaf {max_leaf_size} ray {i}"
                );
                if let Some(group) = groups.iter().find(|gr| gr.contains(&h.prim)) {
                    assert_eq!(h.prim, group[..].iter().copied().min().unwrap());
                    ties += 1;
                }
            }
        }
    }
    // Aimed rays hit the duplicate groups often; make sure the case was actually exercised.
    assert!(ties > 1_000, "only {ties} hits on duplicate groups");
}

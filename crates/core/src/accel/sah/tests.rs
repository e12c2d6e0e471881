use super::*;
use crate::accel::BuildQuality;
use crate::accel::test_boxes::scattered as boxes;
use crate::math::Vec3;

/// Four unit boxes in a row, two units apart.
fn row_of_four() -> Vec<Aabb> {
    (0..4)
        .map(|i| {
            let x = 3.0 * i as f32;
            Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0))
        })
        .collect()
}

#[test]
fn primitives_tested_alone_are_not_priced_as_sharing_a_group() {
    let bounds = row_of_four();
    let opts = BuildOptions {
        max_leaf_size: 4,
        ..Default::default()
    };
    // Four triangles cost one group test together: one leaf.
    let shared = build(&bounds, &[SHARED_SLOTS; 4], &opts);
    assert_eq!(shared.nodes().len(), 1);
    assert_eq!(build(&bounds, &[], &opts).nodes(), shared.nodes());
    // Four spheres cost four tests together: split until each stands alone.
    let alone = build(&bounds, &[ALONE_SLOTS; 4], &opts);
    let leaves: Vec<u32> = alone
        .nodes()
        .iter()
        .filter(|n| n.is_leaf())
        .map(|n| n.count)
        .collect();
    assert_eq!(leaves, [1, 1, 1, 1]);
}

/// Trees over scattered, coincident, flat and huge boxes, triangles and spheres mixed, with
/// small and large leaves: all valid, leaves within the size limit.
#[test]
fn trees_are_valid_for_assorted_inputs() {
    let same = vec![Aabb::new(Vec3::ONE, Vec3::splat(2.0)); 300];
    let flat: Vec<Aabb> = boxes(500, 3)
        .into_iter()
        .map(|b| Aabb::new(b.min.with_z(1.0), b.max.with_z(1.0)))
        .collect();
    let huge: Vec<Aabb> = boxes(400, 5)
        .into_iter()
        .map(|b| Aabb::new(b.min * 3e36, b.max * 3e36))
        .collect();
    let tiny: Vec<Aabb> = boxes(400, 7)
        .into_iter()
        .map(|b| Aabb::new(b.min * 1e-38, b.max * 1e-38))
        .collect();
    for bounds in [
        boxes(1, 1),
        boxes(5, 1),
        boxes(3000, 2),
        same,
        flat,
        huge,
        tiny,
    ] {
        let mixed: Vec<u8> = (0..bounds.len())
            .map(|i| {
                if i % 7 == 0 {
                    ALONE_SLOTS
                } else {
                    SHARED_SLOTS
                }
            })
            .collect();
        for (leaf, quality) in [1, 4, 20]
            .into_iter()
            .flat_map(|l| QUALITIES.map(|q| (l, q)))
        {
            let opts = BuildOptions {
                max_leaf_size: leaf,
                quality,
            };
            for slots in [&[][..], &mixed] {
                let bvh = build(&bounds, slots, &opts);
                let case = (bounds.len(), bounds[0], leaf, slots.len(), quality);
                bvh.validate(&bounds)
                    .unwrap_or_else(|e| panic!("{case:?}: {e}"));
                let biggest = bvh.nodes().iter().map(|n| n.count).max().unwrap();
                assert!(
                    biggest as usize <= leaf.max(1),
                    "leaf of {biggest} > {leaf}"
                );
            }
        }
    }
}

/// The parallel halves are built as separate subtrees whatever the pool, so one thread and
/// several give the same nodes in the same order.
#[test]
fn the_tree_does_not_depend_on_the_thread_count() {
    let bounds = boxes(3 * PARALLEL_MIN, 11);
    for quality in QUALITIES {
        let opts = BuildOptions {
            quality,
            ..Default::default()
        };
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| build(&bounds, &[], &opts))
        };
        let one = on(1);
        one.validate(&bounds).unwrap();
        let three = on(3);
        assert_eq!(one.nodes(), three.nodes());
        assert_eq!(one.prim_order(), three.prim_order());
    }
}

/// Both builders.
const QUALITIES: [BuildQuality; 2] = [BuildQuality::Full, BuildQuality::Fast];

/// The fast builder's tree over a tessellated surface (many clusters) costs, by the surface
/// area heuristic, at most a few percent more than the full builder's.
#[test]
fn the_fast_tree_costs_little_more_than_the_full_one() {
    // A wavy height field of 2 x 160 x 160 triangles' boxes.
    let n = 160;
    let h = |i: usize, j: usize| ((i as f32 * 0.21).sin() + (j as f32 * 0.13).cos()) * 4.0;
    let mut bounds = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let corners = [h(i, j), h(i + 1, j), h(i, j + 1), h(i + 1, j + 1)];
            let (lo, hi) = corners
                .iter()
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, u), &c| {
                    (l.min(c), u.max(c))
                });
            let b = Aabb::new(
                Vec3::new(i as f32, lo, j as f32),
                Vec3::new(i as f32 + 1.0, hi, j as f32 + 1.0),
            );
            bounds.extend([b, b]);
        }
    }
    let cost = |quality| {
        let opts = BuildOptions {
            quality,
            ..Default::default()
        };
        let bvh = build(&bounds, &[], &opts);
        bvh.validate(&bounds).unwrap();
        crate::accel::Wide8::collapse(&bvh).sah_cost()
    };
    let (full, fast) = (cost(BuildQuality::Full), cost(BuildQuality::Fast));
    assert!(fast < full * 1.03, "fast {fast} against full {full}");
}

/// The same bound on seeded random boxes (scattered, some long, overlapping), which no grid
/// of clusters fits: the groups' full builds must make up for the clusters.
#[test]
fn the_fast_tree_costs_little_more_on_random_boxes() {
    for seed in 0..3 {
        let bounds = crate::accel::test_boxes::scattered(20_000, seed);
        let cost = |quality| {
            let opts = BuildOptions {
                quality,
                ..Default::default()
            };
            let bvh = build(&bounds, &[], &opts);
            bvh.validate(&bounds).unwrap();
            crate::accel::Wide8::collapse(&bvh).sah_cost()
        };
        let (full, fast) = (cost(BuildQuality::Full), cost(BuildQuality::Fast));
        assert!(
            fast < full * 1.03,
            "seed {seed}: fast {fast} against full {full}"
        );
    }
}

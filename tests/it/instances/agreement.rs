//! Every accelerator, leaf size and traversal over instances gives brute force's answer bit for
//! bit (brute force over instances, brute force inside each): nearest hit with its primitive,
//! inner primitive, instance and object; any hit; every hit.

use super::fixtures::{instanced, placements};
use crate::common::{Rng, all_kinds};
use lumis_core::accel::{AccelKind, BuildOptions, SegmentParams, Traversal, TraversalStats};
use lumis_core::geometry::Precision;
use lumis_core::math::{Aabb, Ray, Vec3};
use lumis_core::scene::{Scene, World};

/// Seeded rays: from a box around the scene towards points in it, from inside the instances,
/// short segments, and a few from far away.
fn rays(seed: u64, n: usize) -> Vec<Ray> {
    let mut rng = Rng::new(seed);
    let outer = Aabb::new(Vec3::splat(-12.0), Vec3::splat(12.0));
    let inner = Aabb::new(Vec3::splat(-5.0), Vec3::splat(5.0));
    (0..n)
        .map(|i| {
            let o = match i % 5 {
                0 => rng.in_box(&inner),
                4 => rng.unit_vector() * 1e7,
                _ => rng.in_box(&outer),
            };
            let target = rng.in_box(&inner);
            let mut r = Ray::new(o, target - o);
            if i % 7 == 3 {
                r.t_max = rng.range(0.2, 1.2);
            }
            r
        })
        .collect()
}

fn worlds(scene: &Scene) -> Vec<(String, World)> {
    let traversals = [
        Traversal::Ordered,
        Traversal::Exhaustive,
        Traversal::Segments(SegmentParams {
            init: 0.05,
            max: 100.0,
        }),
    ];
    let mut out = Vec::new();
    for kind in all_kinds() {
        for leaf in [1, kind.default_leaf_size()] {
            let opts = BuildOptions {
                max_leaf_size: leaf,
                ..Default::default()
            };
            let built = World::build(scene.clone(), kind, &opts);
            for t in traversals {
                if kind == AccelKind::Sah && t != Traversal::Ordered || kind != AccelKind::Sah {
                    out.push((
                        format!("{kind:?} leaf {leaf} {t:?}"),
                        built.clone().with_traversal(t),
                    ));
                }
            }
        }
    }
    out
}

#[test]
fn every_accelerator_over_instances_answers_as_brute_force_over_instances() {
    for precision in [Precision::Watertight, Precision::Fast, Precision::Double] {
        let mut scene = instanced(&placements());
        scene.settings_mut().precision = precision;
        let brute = World::build(scene.clone(), AccelKind::Brute, &BuildOptions::default());
        let configs = worlds(&scene);
        let mut hits = 0;
        let mut instance_hits = 0;
        for (i, ray) in rays(7, 1500).iter().enumerate() {
            let mut s = TraversalStats::default();
            let want = brute.trace(ray, &mut s).map(|t| t.caller_hit());
            let want_any = brute.occluded(ray, &mut s);
            let want_all = brute.all_hits(ray, &mut s);
            let want_ix = brute.intersect(ray, &mut s);
            hits += want.is_some() as usize;
            instance_hits += want_ix.is_some_and(|h| h.instance.is_some()) as usize;
            assert_eq!(
                want.is_some(),
                want_any,
                "ray {i}: nearest and any disagree"
            );
            for (name, w) in &configs {
                let got = w.trace(ray, &mut s).map(|t| t.caller_hit());
                assert_eq!(got, want, "{precision:?} {name}: ray {i} {ray:?}");
                assert_eq!(
                    w.occluded(ray, &mut s),
                    want_any,
                    "{precision:?} {name}: ray {i}"
                );
                if precision != Precision::Fast {
                    assert_eq!(
                        w.all_hits(ray, &mut s),
                        want_all,
                        "{precision:?} {name}: ray {i}"
                    );
                }
                let ix = w.intersect(ray, &mut s);
                assert_eq!(
                    ix.map(|h| (h.object, h.instance, h.inner, h.surface.p, h.surface.ng)),
                    want_ix.map(|h| (h.object, h.instance, h.inner, h.surface.p, h.surface.ng)),
                    "{precision:?} {name}: ray {i}"
                );
            }
        }
        assert!(
            hits > 600 && instance_hits > 300,
            "{hits} hits, {instance_hits} on instances"
        );
    }
}

#[test]
fn ids_name_the_instance_and_its_part() {
    let scene = instanced(&placements());
    let world = World::build(scene, AccelKind::Sah, &BuildOptions::default());
    let mut s = TraversalStats::default();
    // Straight at instance 3 (translated to y = 4, a mirror): its ball, then the moon beside.
    let ray = Ray::new(Vec3::new(0.0, 4.0, 10.0), -Vec3::Z);
    let hit = world.intersect(&ray, &mut s).expect("hits instance 3");
    assert_eq!(hit.instance, Some(3));
    let objects = world.scene().objects();
    assert_eq!(objects[hit.object as usize].name, "copy3/ball");
    // The moon sits at x = 1.6 in object space; the mirror puts it at x = -1.6.
    let moon = Ray::new(Vec3::new(-1.6, 4.0, 10.0), -Vec3::Z);
    let hit = world
        .intersect(&moon, &mut s)
        .expect("hits the mirrored moon");
    assert_eq!(objects[hit.object as usize].name, "copy3/moon");
    assert!((hit.surface.p.z - 0.5).abs() < 1e-5, "{:?}", hit.surface.p);
    assert!(
        (hit.surface.ng - Vec3::Z).length() < 1e-5,
        "outward: {:?}",
        hit.surface.ng
    );
    let ground = Ray::new(Vec3::new(0.0, -20.0, 10.0), -Vec3::Z);
    let hit = world.intersect(&ground, &mut s).expect("hits the ground");
    assert_eq!((hit.instance, hit.object), (None, 0));
}

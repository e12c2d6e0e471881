//! The batch walk enters instances in place (their walks interleaved with the other rays in
//! flight) and gives every ray the record of its one-ray walk, which asks each instance as a
//! nested query, and of brute force over instances, bit for bit: the hit, its primitive,
//! instance, object and normal (which the batch walk reads from the prototype's packed
//! leaves), on crowds of overlapping instances, nested boxes, tiny and huge placements, rays
//! from inside, from far away and along the axes.

use super::fixtures::{instanced, placements};
use crate::common::Rng;
use glam::{DAffine3, DQuat, DVec3};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::batch::{HitRecord, IN_FLIGHT, RayRow, trace_nearest_into};
use lumis_core::math::{Aabb, Vec3};
use lumis_core::scene::World;

/// The fixture's placements plus a crowd: 60 overlapping placements in a small box (leaves
/// of several instances, instances inside others' boxes), some tiny, one huge.
fn crowd() -> Vec<DAffine3> {
    let mut rng = Rng::new(77);
    let mut out = placements();
    for i in 0..60 {
        let scale = match i % 10 {
            0 => 1e-4,
            1 => 30.0,
            _ => rng.range(0.2, 1.5) as f64,
        };
        let mirror = if i % 7 == 2 { -1.0 } else { 1.0 };
        let axis = rng.unit_vector().as_dvec3();
        out.push(DAffine3::from_scale_rotation_translation(
            DVec3::new(mirror * scale, scale, scale * rng.range(0.5, 1.5) as f64),
            DQuat::from_axis_angle(axis, rng.range(0.0, 6.0) as f64),
            rng.in_box(&Aabb::new(Vec3::splat(-3.0), Vec3::splat(3.0)))
                .as_dvec3(),
        ));
    }
    out
}

/// Seeded rows: from around the crowd, from inside it, short segments, from far away, and
/// rays aimed at the tiny placements.
fn rows(world: &World, n: usize) -> Vec<RayRow> {
    let mut rng = Rng::new(5);
    let outer = Aabb::new(Vec3::splat(-40.0), Vec3::splat(40.0));
    let inner = Aabb::new(Vec3::splat(-4.0), Vec3::splat(4.0));
    let tiny: Vec<Vec3> = world
        .scene()
        .geometry()
        .instances()
        .iter()
        .filter(|i| i.bounds.extent().max_element() < 1e-2)
        .map(|i| i.bounds.center())
        .collect();
    (0..n)
        .map(|i| {
            let o = match i % 6 {
                0 => rng.in_box(&inner),
                5 => rng.unit_vector() * 1e6,
                _ => rng.in_box(&outer),
            };
            let target = match i % 4 {
                3 => tiny[i % tiny.len()],
                _ => rng.in_box(&inner),
            };
            let mut d = target - o;
            // Rays the batch walk hands to the one-ray walk (a zero direction component
            // needs another child test), at the top level and inside the identity placement.
            match i % 11 {
                7 => d = Vec3::new(0.0, 0.0, -d.z.abs().max(1.0)),
                9 => d.y = 0.0,
                _ => {}
            }
            let t_max = if i % 9 == 4 {
                rng.range(0.3, 0.9)
            } else {
                f32::INFINITY
            };
            [o.x, o.y, o.z, d.x, d.y, d.z, 0.0, t_max]
        })
        .collect()
}

fn records<const K: usize>(world: &World, rows: &[RayRow]) -> Vec<HitRecord> {
    let mut out = Vec::new();
    trace_nearest_into::<K, _>(world, rows, &mut out);
    out
}

#[test]
fn the_batch_walk_enters_instances_as_the_one_ray_walk_and_brute_force() {
    let scene = instanced(&crowd());
    let world = World::build(scene.clone(), AccelKind::Sah, &BuildOptions::default());
    let brute = World::build(scene, AccelKind::Brute, &BuildOptions::default());
    let rows = rows(&world, 6000);
    let want = records::<1>(&brute, &rows);
    let paths = crate::common::simd::simd_paths("batch walk over instances");
    let mut one = Vec::new();
    for path in paths.each() {
        one = records::<1>(&world, &rows);
        for (name, got) in [
            ("in flight", records::<IN_FLIGHT>(&world, &rows)),
            ("3 in flight", records::<3>(&world, &rows)),
            ("one at a time", one.clone()),
        ] {
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(g, w, "{name} {}: ray {i} {:?}", path.name(), rows[i]);
            }
        }
    }
    let on_instances = one.iter().filter(|r| r.instance.is_some()).count();
    let tiny_hits = one
        .iter()
        .filter(|r| r.instance.is_some_and(|k| k >= 6 && (k - 6) % 10 == 0))
        .count();
    assert!(
        on_instances > 2500 && tiny_hits > 20,
        "{on_instances} hits on instances, {tiny_hits} on tiny ones"
    );
}

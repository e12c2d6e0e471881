//! A scene made of one instance asks its prototype at once instead of walking a top level of
//! one leaf (`accel::one_instance`): every query answers as brute force over instances does,
//! bit for bit: records one ray at a time, in flight and in packets of one origin, any-hit
//! verdicts, and whole renders (camera packets, shadows, reflections), under every transform
//! class, tiny and huge placements, and rays from far away and along the axes.

use super::fixtures::{add_prototype, placements};
use crate::common::Rng;
use glam::{DAffine3, DQuat, DVec3};
use lumis_core::accel::{AccelKind, BuildOptions, PACKET, SimdPath, Traced};
use lumis_core::batch::{HitRecord, IN_FLIGHT, RayRow, trace_nearest_into};
use lumis_core::geometry::Precision;
use lumis_core::material::Material;
use lumis_core::math::{Aabb, Ray, Vec3};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, SceneBuilder, World, default_rig, framing_camera};

/// The fixture's placements and the extremes: 1e-6 and 1e6 scales, one a million units away.
fn one_placements() -> Vec<DAffine3> {
    let mut out = placements();
    let rot = DQuat::from_euler(glam::EulerRot::YXZ, 0.4, 0.2, -0.9);
    for (scale, at) in [(1e-6, 0.0), (1e6, 0.0), (2.0, 1e6)] {
        out.push(DAffine3::from_scale_rotation_translation(
            DVec3::new(scale, -scale, scale * 1.5),
            rot,
            DVec3::new(at, 0.5 * at, -at),
        ));
    }
    out
}

/// One instance of the fixture's two-part prototype and nothing else.
fn one(placement: DAffine3, spp: u32) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material {
        reflectivity: 0.3,
        ..Material::default()
    });
    let proto = add_prototype(&mut b, m);
    b.add_instance(proto, "only", placement);
    // Framed and lit as `lumis` frames a model file without a camera.
    let camera = framing_camera(b.bounds(), 48, 32);
    for light in default_rig(b.bounds(), &camera) {
        b.add_light(light);
    }
    let mut scene = b.build(camera).expect("within the limits");
    let st = scene.settings_mut();
    (st.width, st.height, st.spp) = (48, 32, spp);
    scene
}

/// Seeded rays at the instance's box: from around it, inside it and far away, short
/// segments, and rays along the axes (which the batch walk hands to the one-ray walk).
fn rays(world: &World, n: usize) -> Vec<Ray> {
    let b = world.scene().geometry().bounds();
    let (c, r) = (b.center(), b.extent().max_element());
    let around = Aabb::new(c - Vec3::splat(2.0 * r), c + Vec3::splat(2.0 * r));
    let mut rng = Rng::new(41);
    (0..n)
        .map(|i| {
            let o = match i % 6 {
                0 => rng.in_box(&b),
                5 => c + rng.unit_vector() * (1e6 * r.max(1.0)),
                _ => rng.in_box(&around),
            };
            let mut d = rng.in_box(&b) - o;
            match i % 11 {
                7 => d = Vec3::new(0.0, 0.0, -d.z.abs().max(r)),
                9 => d.y = 0.0,
                _ => {}
            }
            let mut ray = Ray::new(o, d);
            if i % 9 == 4 {
                ray.t_max = rng.range(0.3, 0.9);
            }
            ray
        })
        .collect()
}

fn records<const K: usize>(world: &World, rows: &[RayRow]) -> Vec<HitRecord> {
    let mut out = Vec::new();
    trace_nearest_into::<K, _>(world, rows, &mut out);
    out
}

fn row(r: &Ray) -> RayRow {
    [
        r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.t_min, r.t_max,
    ]
}

#[test]
fn one_instance_answers_as_brute_force_over_instances() {
    for (k, placement) in one_placements().into_iter().enumerate() {
        let scene = one(placement, 1);
        let world = World::build(scene.clone(), AccelKind::Sah, &BuildOptions::default());
        let brute = World::build(scene, AccelKind::Brute, &BuildOptions::default());
        let rays = rays(&world, 3000);
        let rows: Vec<RayRow> = rays.iter().map(row).collect();
        let want = records::<1>(&brute, &rows);
        for (name, got) in [
            ("in flight", records::<IN_FLIGHT>(&world, &rows)),
            ("3 in flight", records::<3>(&world, &rows)),
            ("one at a time", records::<1>(&world, &rows)),
        ] {
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(g, w, "placement {k} {name}: ray {i} {:?}", rays[i]);
            }
        }
        // A batch whose first ray comes from far away (the top level frames it first).
        let from_far = records::<IN_FLIGHT>(&world, &rows[5..]);
        for ((g, w), ray) in from_far.iter().zip(&want[5..]).zip(&rays[5..]) {
            assert_eq!(g, w, "placement {k} from far: {ray:?}");
        }
        let hits = want.iter().filter(|r| r.instance == Some(0)).count();
        assert!(hits > 200, "placement {k}: only {hits} hits");
        for (i, ray) in rays.iter().enumerate() {
            let (got, wanted) = (
                world.occluded(ray, &mut Default::default()),
                brute.occluded(ray, &mut Default::default()),
            );
            assert_eq!(got, wanted, "placement {k}: any hit of ray {i} {ray:?}");
        }
    }
}

#[test]
fn packets_into_one_instance_answer_as_single_rays() {
    let paths = crate::common::simd::simd_paths("packets into one instance");
    for path in paths.each() {
        let walked = packets_into_one_instance(path.name());
        // Without SIMD only packets that miss the instance's box are answered together.
        if path != SimdPath::Scalar {
            assert!(
                walked > 1000,
                "{}: only {walked} packets walked together",
                path.name()
            );
        }
    }
}

/// Checks packets into every placement on the path in force (`path` names it); returns how
/// many were walked together.
fn packets_into_one_instance(path: &str) -> usize {
    let mut walked = 0;
    for (k, placement) in one_placements().into_iter().enumerate() {
        let world = World::build(one(placement, 1), AccelKind::Sah, &BuildOptions::default());
        let brute = World::build(
            one(placement, 1),
            AccelKind::Brute,
            &BuildOptions::default(),
        );
        let g = world.scene().geometry();
        let b = g.bounds();
        let wide = Aabb::new(b.center() - b.extent() * 0.8, b.center() + b.extent() * 0.8);
        let mut rng = Rng::new(90 + k as u64);
        for p in 0..300 {
            let origin = b.center() + rng.unit_vector() * (3.0 * b.extent().max_element());
            let n = 1 + p % PACKET;
            // Some rays of a packet miss the box, some hit: the packet is walked as one.
            let packet: Vec<Ray> = (0..n)
                .map(|_| Ray::new(origin, rng.in_box(&wide) - origin))
                .collect();
            let mut out: [Option<Traced>; PACKET] = [None; PACKET];
            let together = world.accel().trace_packet(
                g,
                Precision::Watertight,
                &packet,
                &mut Default::default(),
                &mut out,
            );
            walked += usize::from(together);
            for (i, ray) in packet.iter().enumerate() {
                let alone = world.trace(ray, &mut Default::default());
                let want = brute
                    .trace(ray, &mut Default::default())
                    .map(|t| t.caller_hit());
                assert_eq!(
                    alone.map(|t| t.caller_hit()),
                    want,
                    "placement {k}: ray {ray:?}"
                );
                if together {
                    assert_eq!(
                        out[i], alone,
                        "{path}: placement {k} packet {p}: ray {i} {ray:?}"
                    );
                }
            }
        }
    }
    walked
}

#[test]
fn renders_of_one_instance_equal_brute_force_bit_for_bit() {
    for placement in placements() {
        let scene = one(placement, 4);
        let opts = RenderOptions {
            seed: 1,
            threads: Some(2),
            ..RenderOptions::default()
        };
        let image = |kind| {
            let world = World::build(scene.clone(), kind, &BuildOptions::default());
            render(&world, &opts).unwrap().film
        };
        let (got, want) = (image(AccelKind::Sah), image(AccelKind::Brute));
        let bits = |f: &lumis_core::film::Film| {
            f.rgba()
                .iter()
                .flat_map(|p| p.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&got), bits(&want), "placement {placement:?}");
        let lit = got.rgba().iter().filter(|p| p.w > 0.0).count();
        assert!(
            lit > 80,
            "placement {placement:?}: {lit} pixels on the instance"
        );
    }
}

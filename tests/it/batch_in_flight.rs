//! The batch walk with several rays in flight per thread (`batch::trace_nearest_into`) gives
//! every ray the record of its one-ray walk, bit for bit: on seeded incoherent, camera, miss,
//! axis-parallel and far-origin rays, for several numbers of rays in flight, on batches
//! shorter than that number and across the parallel chunks.

use crate::common::{Rng, rays, scene_box, scenes};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::batch::{HitRecord, IN_FLIGHT, RayRow, trace_nearest_into, trace_rays};
use lumis_core::camera::Camera;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::material::Material;
use lumis_core::math::{Ray, Vec2, Vec3};
use lumis_core::scene::{SceneBuilder, World};

/// The world of `meshes` and `spheres`, seen by a camera at z = 20.
fn world_of(meshes: Vec<Mesh>, spheres: &[Sphere]) -> World {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    for (i, mesh) in meshes.into_iter().enumerate() {
        b.add_mesh(format!("mesh{i}"), mesh, m);
    }
    for (i, s) in spheres.iter().enumerate() {
        b.add_sphere(format!("sphere{i}"), *s, m);
    }
    let eye = Vec3::new(1.0, 2.0, 20.0);
    let cam = Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 50.0, 0.0, None).expect("valid camera");
    let scene = b.build(cam).expect("scene within the value limits");
    World::build(scene, AccelKind::Sah, &BuildOptions::default())
}

/// A bumpy sphere, a jittered icosphere, a soup of small random triangles (a deep hierarchy
/// with overlapping boxes) and two analytic spheres (lanes the packed leaves hand back to the
/// geometry's own test).
fn world() -> World {
    let mut rng = Rng::new(41);
    let bumpy = scenes::uv_sphere(Vec3::ZERO, 2.0, 24, 40, |d| {
        1.0 + 0.05 * (7.0 * d.x).sin() * (5.0 * d.z).cos()
    });
    let mut ico = scenes::icosphere(3, 0.02, &mut rng);
    ico = Mesh::new(
        ico.positions()
            .iter()
            .map(|p| *p + Vec3::new(4.0, 0.0, 0.0))
            .collect(),
        None,
        None,
        ico.indices().to_vec(),
    )
    .expect("valid mesh");
    let soup: Vec<[Vec3; 3]> = (0..3000)
        .map(|_| {
            let c = Vec3::new(
                rng.range(-6.0, 6.0),
                rng.range(-3.0, 3.0),
                rng.range(-6.0, 6.0),
            );
            scenes::random_triangle(&mut rng, c, 0.4)
        })
        .collect();
    let spheres = [
        Sphere {
            center: Vec3::new(-4.0, 1.0, 0.0),
            radius: 1.0,
        },
        Sphere {
            center: Vec3::new(0.0, -2.5, 3.0),
            radius: 0.5,
        },
    ];
    world_of(vec![bumpy, ico, scenes::soup(&soup)], &spheres)
}

fn row(r: &Ray) -> RayRow {
    let (o, d) = (r.origin, r.dir);
    [o.x, o.y, o.z, d.x, d.y, d.z, r.t_min, r.t_max]
}

/// Rays of every kind, interleaved so any slice mixes them: incoherent, camera, misses
/// (pointing away from the scene), axis-parallel and other zero-component directions (the
/// scalar child test), and origins far outside the scene (traced from near it).
fn ray_rows(world: &World, n: usize) -> Vec<RayRow> {
    let mut rng = Rng::new(7);
    let g = world.scene().geometry();
    let bounds = g.prim_bounds();
    let scene = scene_box(g);
    let (w, h) = (64, 48);
    let camera = world.scene().camera();
    (0..n)
        .map(|i| {
            let r = match i % 6 {
                0 => rays::incoherent(&mut rng, &scene),
                1 => {
                    let film = Vec2::new(rng.range(0.0, w as f32), rng.range(0.0, h as f32));
                    camera.ray(world.accel().frame(), film, w, h, Vec2::splat(0.5))
                }
                2 => {
                    let o = rays::grown(&scene, 0.5).max + Vec3::splat(rng.range(0.0, 2.0));
                    Ray::new(o, rng.unit_vector().abs() + Vec3::splat(0.01))
                }
                3 => rays::axis_parallel(&mut rng, g, &bounds),
                4 => {
                    // One or two zero components, through the scene.
                    let mut d = rng.unit_vector();
                    d[rng.below(3)] = 0.0;
                    if rng.chance(0.3) {
                        d[rng.below(3)] = 0.0;
                    }
                    let d = if d == Vec3::ZERO { Vec3::X } else { d };
                    Ray::new(rng.in_box(&scene) - d * 20.0, d)
                }
                _ => {
                    let d = rng.unit_vector();
                    Ray::new(rng.in_box(&scene) - d * 1e7, d)
                }
            };
            row(&r)
        })
        .collect()
}

fn bits(records: &[HitRecord]) -> Vec<[u32; 9]> {
    records.iter().map(|r| r.row().map(f32::to_bits)).collect()
}

fn traced<const K: usize>(world: &World, rows: &[RayRow]) -> Vec<[u32; 9]> {
    let mut records = vec![HitRecord::MISS; 3];
    trace_nearest_into::<K, _>(world, rows, &mut records);
    assert_eq!(records.len(), rows.len());
    bits(&records)
}

#[test]
fn rays_in_flight_get_the_records_of_the_one_ray_walk() {
    let world = world();
    // More than one parallel chunk of rays.
    let rows = ray_rows(&world, 2500);
    let want = traced::<1>(&world, &rows);
    let hits = want
        .iter()
        .filter(|r| r[0] != f32::INFINITY.to_bits())
        .count();
    assert!(
        hits > 500 && hits < 2300,
        "{hits} hits: the rays should both hit and miss"
    );
    assert_eq!(traced::<2>(&world, &rows), want, "2 in flight");
    assert_eq!(traced::<3>(&world, &rows), want, "3 in flight");
    assert_eq!(traced::<8>(&world, &rows), want, "8 in flight");
    assert_eq!(traced::<IN_FLIGHT>(&world, &rows), want, "IN_FLIGHT");
    assert_eq!(traced::<16>(&world, &rows), want, "16 in flight");
    assert_eq!(
        bits(&trace_rays(&world, &rows[..], false)),
        want,
        "trace_rays"
    );
}

#[test]
fn batches_shorter_than_the_rays_in_flight_are_answered_whole() {
    let world = world();
    let rows = ray_rows(&world, 40);
    for n in [0, 1, 2, 5, IN_FLIGHT - 1, IN_FLIGHT, IN_FLIGHT + 1, 40] {
        for start in [0, 3] {
            let batch = &rows[start..(start + n).min(rows.len())];
            let want = traced::<1>(&world, batch);
            assert_eq!(traced::<8>(&world, batch), want, "{n} rays from {start}");
            assert_eq!(
                traced::<IN_FLIGHT>(&world, batch),
                want,
                "{n} rays from {start}"
            );
        }
    }
}

#[test]
fn an_empty_scene_answers_every_ray_in_flight_with_a_miss() {
    let world = world_of(Vec::new(), &[]);
    let rows: Vec<RayRow> = (0..30)
        .map(|i| row(&Ray::new(Vec3::splat(i as f32), Vec3::new(1.0, 0.5, -0.25))))
        .collect();
    let want = bits(&vec![HitRecord::MISS; rows.len()]);
    assert_eq!(traced::<1>(&world, &rows), want);
    assert_eq!(traced::<IN_FLIGHT>(&world, &rows), want);
}

//! Rays from far away, 1e6 to 3e38 from a unit-sized scene (issue 24): every query moves them
//! to near the scene (`lumis_core::accel::RayFrame`); every accelerator and traversal must answer
//! as brute force does, and brute force as exact rational arithmetic on the `f32` ray as given
//! says: the front face, not the back; a miss where the exact line misses; `t` within 2 ulp.

use super::common::{Rng, scenes};
use super::exact::{Q, V, q, ray_triangle, sphere_value, ulps_from};
use super::harness::Everywhere;
use lumis_core::geometry::{Geometry, Mesh, Precision, Sphere};
use lumis_core::math::{Ray, Vec3};
use num_traits::Signed;

/// Distances of the origins from the scene.
const MAGNITUDES: [f32; 8] = [1e6, 1e8, 1e12, 1e19, 1e20, 1e24, 1e30, 3e38];

/// The exact precisions (`fast` is the textbook test: agreement only, see the fuzz target).
const EXACT: [Precision; 2] = [Precision::Watertight, Precision::Double];

/// Random origins at distance `m` (rounded to f32) in every octant.
fn origins(rng: &mut Rng, m: f32, n: usize) -> Vec<Vec3> {
    (0..n).map(|_| rng.unit_vector() * m).collect()
}

/// The exact nearest crossing of `ray` with `mesh` in `(0, inf)`, with every triangle that
/// crosses there (several when the crossing is on a shared edge or vertex).
fn exact_nearest(mesh: &Mesh, ray: &Ray) -> Option<(Q, Vec<u32>)> {
    let mut best: Option<(Q, Vec<u32>)> = None;
    for (i, tri) in (0..mesh.triangle_count() as u32).map(|i| (i, mesh.corners(i))) {
        let Some(h) = ray_triangle(ray.origin, ray.dir, tri) else {
            continue;
        };
        if !h.t.is_positive() {
            continue;
        }
        match &mut best {
            Some((t, ids)) if h.t == *t => ids.push(i),
            Some((t, _)) if h.t > *t => {}
            _ => best = Some((h.t, vec![i])),
        }
    }
    best
}

#[test]
fn a_closed_mesh_seen_from_1e6_to_3e38_is_hit_on_its_front_face() {
    // A unit icosphere; each ray's direction is exactly -origin, so its line passes through
    // the centre at t = 1 and the front face is at t = 1 - ~1/|o|: from 1e8 on, front and back
    // round to the same f32 t, and only the moved origin orders them.
    let mesh = scenes::icosphere(2, 0.0, &mut Rng::new(5));
    let mut g = Geometry::new();
    g.add_mesh(mesh.clone());
    let everywhere = Everywhere::new(&g);
    let mut rng = Rng::new(11);
    let mut checked = 0;
    for m in MAGNITUDES {
        for o in origins(&mut rng, m, 12) {
            let ray = Ray::new(o, -o);
            let (t, ids) = exact_nearest(&mesh, &ray).expect("a line through the centre hits");
            for precision in EXACT {
                let hit = everywhere
                    .closest_with(precision, &ray)
                    .unwrap_or_else(|| panic!("{precision:?} lost the hit of {ray:?}"));
                assert!(
                    ids.contains(&hit.prim),
                    "{precision:?}: triangle {} instead of the front {ids:?} from {o}",
                    hit.prim
                );
                let ulps = ulps_from(hit.hit.t, &t);
                assert!(
                    ulps <= 2.0,
                    "{precision:?}: t {} is {ulps} ulp off",
                    hit.hit.t
                );
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 12 * MAGNITUDES.len());
}

#[test]
fn rays_from_far_away_aimed_beside_a_mesh_miss_it() {
    // Aimed at points 1.5 to 3 from the centre of the unit icosphere, 1e-3 rad off at 1e3 and
    // far less beyond: the exact line misses every triangle. The f32 triangle test fed the raw
    // origin overflowed (inf - inf) from ~1e19 on and reported hits.
    let mesh = scenes::icosphere(2, 0.0, &mut Rng::new(5));
    let mut g = Geometry::new();
    g.add_mesh(mesh.clone());
    let everywhere = Everywhere::new(&g);
    let mut rng = Rng::new(12);
    for m in MAGNITUDES {
        for o in origins(&mut rng, m, 8) {
            let side = rng.unit_vector().cross(o).normalize() * rng.range(1.5, 3.0);
            let ray = Ray::new(o, side - o);
            let exact = exact_nearest(&mesh, &ray);
            for precision in [Precision::Fast, Precision::Watertight, Precision::Double] {
                let hit = everywhere.closest_with(precision, &ray);
                assert_eq!(exact.is_some(), hit.is_some(), "{precision:?} on {ray:?}");
                assert!(!everywhere.occluded_with(precision, &ray) || exact.is_some());
            }
        }
    }
}

/// Asserts that `t` is within 2 ulp of the sphere's entry root along `ray`: the exact value of
/// `|o + t d - c|^2 - r^2` is positive (outside) 2 ulp before, and not positive somewhere up to
/// 2 ulp after (from far away one ulp of `t` can span the whole sphere, so the sign 2 ulp after
/// is not enough: the value's minimum over the window is what counts).
fn assert_front_root(s: &Sphere, ray: &Ray, t: f32) {
    let value = |t: &Q| sphere_value(ray.origin, ray.dir, s.center, s.radius, t);
    let (before, after) = (q(t.next_down().next_down()), q(t.next_up().next_up()));
    // The quadratic's minimum lies at the closest approach to the centre.
    let (o, d, c) = (V::of(ray.origin), V::of(ray.dir), V::of(s.center));
    let closest = c.sub(&o).dot(&d) / d.dot(&d);
    let lowest = closest.clamp(before.clone(), after.clone());
    assert!(
        value(&before).is_positive() && !value(&lowest).is_positive(),
        "t = {t} is not the entry of {s:?} along {ray:?}"
    );
}

#[test]
fn spheres_seen_from_1e6_to_3e38_are_entered_at_the_exact_root() {
    // A unit sphere; two concentric ones, whose fronts round to the same f32 t from 1e8 on
    // (the outer must win, not the lower index); a tiny one. Each centred at the origin, so a
    // ray with direction exactly -origin passes through the centre: it must enter the outer
    // sphere within 2 ulp of the exact root.
    let unit = Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    };
    let outer = Sphere {
        center: Vec3::ZERO,
        radius: 1.5,
    };
    let tiny = Sphere {
        center: Vec3::ZERO,
        radius: 1e-3,
    };
    let mut rng = Rng::new(13);
    for spheres in [vec![unit], vec![unit, outer], vec![tiny]] {
        let mut g = Geometry::new();
        for s in &spheres {
            g.add_sphere(*s);
        }
        let everywhere = Everywhere::new(&g);
        let want = spheres.len() - 1;
        let target = spheres[want];
        for m in MAGNITUDES {
            for o in origins(&mut rng, m, 8) {
                let ray = Ray::new(o, -o);
                for precision in EXACT {
                    let hit = everywhere
                        .closest_with(precision, &ray)
                        .expect("aimed at it");
                    assert_eq!(hit.prim as usize, want, "{precision:?} from {o}");
                    assert_front_root(&target, &ray, hit.hit.t);
                }
            }
        }
    }
}

#[test]
fn hits_beyond_f32_max_either_way_along_a_far_ray_are_no_hits_for_every_query() {
    // A far origin and a tiny direction put the surfaces at |t| ~ 1e41, behind or ahead: no
    // f32 distance, so no hit, and no occlusion either (the survey of the query fuzz target
    // found occluded = true with intersect = None when t_min = -inf: only the upper end of the
    // moved ray's interval was capped at f32::MAX).
    let mesh = scenes::icosphere(2, 0.0, &mut Rng::new(5));
    let mut g = Geometry::new();
    g.add_mesh(mesh);
    g.add_sphere(Sphere {
        center: Vec3::new(0.0, 0.0, 0.25),
        radius: 0.5,
    });
    let everywhere = Everywhere::new(&g);
    for origin_z in [1e6, 1e12, 3e38] {
        for dir_z in [1e-35, -1e-35, 1.4e-42, -1.4e-42] {
            let ray = Ray {
                origin: Vec3::new(0.0, 0.0, origin_z),
                dir: Vec3::new(0.0, 0.0, dir_z),
                t_min: f32::NEG_INFINITY,
                t_max: f32::INFINITY,
            };
            for precision in [Precision::Fast, Precision::Watertight, Precision::Double] {
                let hit = everywhere.closest_with(precision, &ray);
                assert_eq!(hit, None, "{precision:?} on {ray:?}");
                assert!(
                    !everywhere.occluded_with(precision, &ray),
                    "{precision:?} on {ray:?}"
                );
            }
        }
    }
}

//! Directions of any magnitude: every finite, non-zero direction (components from 2^-149 to
//! 2^127, subnormal included, some exactly zero) must get brute force's answer from every
//! accelerator and traversal, and that answer must match the exact intersection.

use super::common::{Rng, scenes};
use super::exact::{self, q, ulps_from};
use super::harness::Everywhere;
use lumis_core::geometry::{Geometry, Mesh, Precision, Sphere};
use lumis_core::math::{Ray, Vec3};
use num_traits::Signed;

/// A random finite non-zero direction whose components have independent binary exponents in
/// `[-149, 127]`; about one component in six is exactly zero.
fn wild_direction(rng: &mut Rng) -> Vec3 {
    loop {
        let mut c = [0f32; 3];
        for x in &mut c {
            if rng.chance(0.17) {
                continue;
            }
            let e = rng.below(277) as i32 - 149;
            let mant = rng.range(1.0, 2.0);
            let v = (mant as f64 * 2f64.powi(e)) as f32;
            *x = if rng.chance(0.5) { -v } else { v };
        }
        let d = Vec3::from(c);
        if d != Vec3::ZERO && d.is_finite() {
            return d;
        }
    }
}

#[test]
fn subnormal_direction_component_keeps_the_far_hit() {
    // The reported case: 1 / 2e-39 overflows f32, and the boxes entered at ~5e37 were culled.
    let tri = [
        Vec3::new(1.0, 0.1, -1.0),
        Vec3::new(1.0, 0.1, 1.0),
        Vec3::new(1.0, 0.3, 0.0),
    ];
    let mut g = Geometry::new();
    g.add_mesh(scenes::soup(&[tri]));
    let ray = Ray::new(Vec3::ZERO, Vec3::new(1e-38, 2e-39, 0.0));
    let hit = Everywhere::new(&g).closest(&ray).expect("brute force hits");
    let exact = exact::ray_triangle(ray.origin, ray.dir, tri).expect("exact hit");
    assert!(
        ulps_from(hit.hit.t, &exact.t) <= 1.0,
        "t {} vs exact {}",
        hit.hit.t,
        exact::exact_to_f64(&exact.t)
    );
}

#[test]
fn every_accelerator_agrees_with_brute_force_for_directions_of_any_magnitude() {
    // Triangles and spheres in a unit-sized scene; rays from inside it in wild directions.
    let g = scenes::uniform(11, 24, 160);
    let everywhere = Everywhere::new(&g);
    let mut rng = Rng::new(5);
    let bounds = g.bounds();
    let prim_bounds = g.prim_bounds();
    let mut hits = 0;
    for i in 0..3000 {
        let o = rng.in_box(&bounds);
        // Odd rays: aimed at a primitive, the direction scaled by 2^k for k in -140..=100
        // (the magnitude alone wild); even rays: every component's exponent wild.
        let dir = if i % 2 == 1 {
            let target = prim_bounds[rng.below(prim_bounds.len())].center();
            let k = rng.below(241) as i32 - 140;
            ((target - o).as_dvec3() * 2f64.powi(k)).as_vec3()
        } else {
            wild_direction(&mut rng)
        };
        if dir == Vec3::ZERO || !dir.is_finite() {
            continue;
        }
        let ray = Ray::new(o, dir);
        hits += usize::from(everywhere.closest(&ray).is_some());
        everywhere.occluded(&ray);
    }
    assert!(
        hits > 1000,
        "only {hits} hits: the rays must exercise the scene"
    );
}

#[test]
fn hits_with_wild_directions_match_exact_arithmetic() {
    // Triangle soup only, so the exact oracle covers every primitive. Criterion: whenever the
    // exact nearest hit lies off the edges (every barycentric >= 1e-4) at a t that f32 can hold,
    // lumis reports that triangle with t within 2 ulp; whenever the exact line misses every
    // triangle by that margin, lumis misses too.
    let mut rng = Rng::new(17);
    let tris: Vec<[Vec3; 3]> = (0..12)
        .map(|_| scenes::random_triangle(&mut rng, Vec3::ZERO, 1.5))
        .collect();
    let mut g = Geometry::new();
    g.add_mesh(
        Mesh::new(
            tris.iter().flatten().copied().collect(),
            None,
            None,
            (0..tris.len() as u32)
                .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
                .collect(),
        )
        .unwrap(),
    );
    let everywhere = Everywhere::new(&g);
    let margin = q(1e-4);
    let (mut checked, mut checked_hits) = (0, 0);
    for _ in 0..400 {
        let origin = Vec3::new(
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
        );
        let dir = wild_direction(&mut rng);
        let ray = Ray::new(origin, dir);
        let got = everywhere.closest(&ray);
        // Exact nearest hit with t > 0, and whether any candidate sits within the margin band.
        let mut best: Option<(usize, exact::ExactHit)> = None;
        let mut ambiguous = false;
        for (i, t) in tris.iter().enumerate() {
            let Some(h) = exact::ray_triangle(origin, dir, *t) else {
                continue;
            };
            if !h.t.is_positive() {
                continue;
            }
            let w = q(1.0) - &h.u - &h.v;
            if h.u < margin || h.v < margin || w < margin {
                ambiguous = true;
            }
            if best.as_ref().is_none_or(|(_, b)| h.t < b.t) {
                best = Some((i, h));
            }
        }
        if ambiguous {
            continue;
        }
        match best {
            Some((i, h)) if exact::exact_to_f64(&h.t) < f32::MAX as f64 / 2.0 => {
                let got = got.unwrap_or_else(|| panic!("missed triangle {i} on {ray:?}"));
                assert_eq!(got.prim as usize, i, "wrong triangle on {ray:?}");
                let ulps = ulps_from(got.hit.t, &h.t);
                assert!(ulps <= 2.0, "t off by {ulps} ulp on {ray:?}");
                checked_hits += 1;
            }
            Some(_) => {} // exact t beyond f32: either answer is a rounding of infinity
            None => assert!(got.is_none(), "hit nothing real on {ray:?}: {got:?}"),
        }
        checked += 1;
    }
    assert!(
        checked > 300 && checked_hits > 20,
        "{checked} rays, {checked_hits} hits checked"
    );
}

/// `f32::from_bits`, for the fuzz target's exact inputs.
fn b(bits: u32) -> f32 {
    f32::from_bits(bits)
}

#[test]
fn components_2_to_the_126_apart_keep_every_accelerator_on_brute_force() {
    // Found by the query fuzz target. (1) A direction (1e17, 0, -2.4e-38): the f32 shear
    // ratio underflows to 0 (the true 2.4e-55 moves a sheared coordinate 2e17 away by 4.8e-38),
    // so the packed SIMD filter took a lane's edge sign as certain and dropped a hit the
    // scalar test found. (2) A ray from f32::MAX grazing a sphere of radius 5.5e-20, tangent
    // within the double-double discriminant's rounding: the sphere reported a hit on a line
    // that misses its box by 1e-57, which every hierarchy culled.
    let mut g = Geometry::new();
    let big = b(0x5c31_a2bc); // 2e17
    let quad = vec![
        Vec3::ZERO,
        Vec3::new(big, 0.0, 0.0),
        Vec3::new(0.0, big, 0.0),
        Vec3::new(-big, 0.0, 0.0),
    ];
    g.add_mesh(Mesh::new(quad, None, None, vec![[0, 1, 2], [0, 2, 3]]).unwrap());
    let ray = Ray {
        origin: Vec3::new(b(3), 0.0, b(0x0102_0000)),
        dir: Vec3::new(b(0x5bb1_a2bc), 0.0, b(0x8102_0000)),
        t_min: f32::NEG_INFINITY,
        t_max: f32::INFINITY,
    };
    let hit = Everywhere::new(&g)
        .closest(&ray)
        .expect("on the shared edge");
    assert_eq!((hit.prim, hit.hit.t), (0, 1.0));

    let mut g = Geometry::new();
    g.add_sphere(Sphere {
        center: Vec3::ZERO,
        radius: b(0x1f81_8000), // 5.48e-20
    });
    let ray = Ray {
        origin: Vec3::new(f32::MAX, 1e-30, b(0x9dc2_8000)),
        dir: Vec3::new(-f32::MAX, -1e-30, b(0x1f8d_a800)),
        t_min: 0.0,
        t_max: f32::INFINITY,
    };
    for precision in [Precision::Watertight, Precision::Double] {
        Everywhere::new(&g).closest_with(precision, &ray);
    }
}

#[test]
fn a_vertex_of_a_sliver_is_hit_at_its_exact_distance() {
    // Found by the query fuzz target: a ray along x with |d| = 7.4e-39 through the vertex
    // (0, 0, 0) of a sliver whose f64 normal cancels to 1% (its corners span 9 units and
    // 1.3e-14 across): t was 0.14% short. The plane distance now takes the compensated
    // normal whenever the plain one cancels.
    let sliver = vec![
        Vec3::new(1.0, 9.0, 0.5),
        Vec3::ZERO,
        Vec3::new(0.0, b(0x0015_00fc), b(0x286b_0000)),
    ];
    let mut g = Geometry::new();
    g.add_mesh(Mesh::new(sliver.clone(), None, None, vec![[0, 1, 2]]).unwrap());
    let ray = Ray::new(
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(b(0x0050_fc00), 0.0, 0.0),
    );
    let t = exact::plane_t(ray.origin, ray.dir, [sliver[0], sliver[1], sliver[2]]).unwrap();
    for precision in [Precision::Watertight, Precision::Double] {
        let hit = Everywhere::new(&g)
            .closest_with(precision, &ray)
            .expect("at a vertex");
        assert!(ulps_from(hit.hit.t, &t) <= 1.0, "t {} for {t}", hit.hit.t);
    }
}

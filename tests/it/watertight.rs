//! No leaks through closed meshes: every ray from inside a closed tessellated mesh hits it,
//! through the SAH hierarchy, including rays aimed exactly at vertices and edge midpoints (where
//! a non-watertight triangle test lets rays slip between neighbours), near the origin and
//! translated 1e5 away from it, where coordinates keep only a few fractional bits.

use crate::common;

use common::{Rng, closest, scenes};
use lumis_core::accel::{Accel, AccelKind, BuildOptions};
use lumis_core::geometry::{Geometry, Mesh};
use lumis_core::math::{Mat4, Ray, Vec3};

/// A jittered closed icosphere (5120 triangles) of `radius` around `center`.
fn closed_mesh(center: Vec3, radius: f32, seed: u64) -> Mesh {
    let m = scenes::icosphere(4, 0.02, &mut Rng::new(seed));
    m.transformed(&(Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(radius))))
}

/// Every vertex and every edge midpoint of `m`: the points a leak would show at.
fn targets(m: &Mesh) -> Vec<Vec3> {
    let p = m.positions();
    let mut t: Vec<Vec3> = p.to_vec();
    for &[a, b, c] in m.indices() {
        for (i, j) in [(a, b), (b, c), (c, a)] {
            // Each edge appears in two triangles; taking it once (i < j) halves the work.
            if i < j {
                t.push((p[i as usize] + p[j as usize]) * 0.5);
            }
        }
    }
    t
}

/// Casts rays from inside and from outside at `m`; panics on the first leak.
fn check_closed(name: &str, m: Mesh, center: Vec3, radius: f32, seed: u64) {
    let aims = targets(&m);
    let mut g = Geometry::new();
    g.add_mesh(m);
    let bounds = g.prim_bounds();
    let mut rng = Rng::new(seed);
    for max_leaf_size in [1, 4] {
        // Through the packed leaves too (`closest` checks both paths agree).
        let accel = Accel::build_for(
            AccelKind::Sah,
            &g,
            &BuildOptions {
                max_leaf_size,
                ..Default::default()
            },
        );
        accel
            .wide()
            .expect("a wide hierarchy")
            .validate(&bounds)
            .expect("valid hierarchy");
        let must_hit = |r: Ray, what: &str, i: usize| {
            assert!(
                closest(&accel, &g, &r).is_some(),
                "{name} leaf {max_leaf_size}: {what} ray {i} leaks: {r:?}"
            );
        };
        // Random directions from random points well inside.
        for i in 0..20_000 {
            let o = center + rng.unit_vector() * rng.range(0.0, 0.6 * radius);
            must_hit(Ray::new(o, rng.unit_vector()), "inside", i);
        }
        for (i, &p) in aims.iter().enumerate() {
            // From inside, straight at the vertex or edge midpoint.
            let o = center + rng.unit_vector() * rng.range(0.0, 0.3 * radius);
            must_hit(Ray::new(o, p - o), "inside-aimed", i);
            // From outside, within 30 degrees of the outward direction, so the ray enters
            // through `p` instead of grazing the silhouette; the hit can be no farther than `p`.
            let out = (p - center).normalize();
            let from = (out + rng.unit_vector() * 0.5).normalize();
            let o = p + from * 2.0 * radius;
            let r = Ray::new(o, p - o);
            let h = closest(&accel, &g, &r);
            let t = h.map_or(f32::INFINITY, |h| h.hit.t);
            // `p` itself is rounded (an edge midpoint moves up to half an ulp per axis off the
            // edge), so allow a few ulps of `p` along the ray; a leak would reach the far side.
            let tol = 4.0 * f32::EPSILON * p.abs().max_element().max(1.0) / (p - o).length();
            assert!(
                t <= 1.0 + 1e-5 + tol,
                "{name} leaf {max_leaf_size}: outside ray {i} at {p} leaks: t {t}"
            );
        }
    }
}

#[test]
fn icosphere_at_the_origin_has_no_leaks() {
    check_closed(
        "origin",
        closed_mesh(Vec3::ZERO, 1.0, 1),
        Vec3::ZERO,
        1.0,
        2,
    );
}

#[test]
fn icosphere_far_from_the_origin_has_no_leaks() {
    // At 1e5 the float spacing is 1/128, so vertices sit on a coarse grid and edges are long
    // in ulps; the watertight test must still close every seam.
    let c = Vec3::new(1e5, -1e5, 1e5);
    check_closed("far", closed_mesh(c, 4.0, 3), c, 4.0, 4);
}

#[test]
fn uv_sphere_poles_and_seam_have_no_leaks() {
    // Thin pole triangles and the wrapped seam are the other classic leak sites.
    let m = scenes::uv_sphere(Vec3::ZERO, 1.0, 32, 48, |_| 1.0);
    check_closed("uv sphere", m, Vec3::ZERO, 1.0, 5);
}

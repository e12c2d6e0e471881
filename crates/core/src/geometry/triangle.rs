//! Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013).
//!
//! The ray is sheared so it points down +z from the origin; the edge functions are then 2-D
//! cross products evaluated identically for both triangles sharing an edge, so a ray through a
//! shared edge or vertex hits at least one of them. An edge function that rounds to exactly 0
//! is recomputed in `f64`, as the paper prescribes.
//!
//! The distance of an accepted hit is recomputed in `f64` from the plane equation: the sheared
//! `f32` formula loses most of its digits for grazing rays (at 1e-6 rad from the plane, relative
//! t errors reach 1e-2, as Embree's do), which would misorder nearby surfaces and put the depth
//! AOV off; the plane form in `f64` keeps them near 1e-7 (measured with tools/crosscheck_hits.py
//! against a float64 reference).

use super::conditioning::{Shear64, plane_distance};
use super::edge_bound::{SHEAR_UNDERFLOW, edge_bound, magnitudes};
use super::exact::edge_sign;
use crate::math::{Ray, Vec3};
use std::cmp::Ordering;

/// Per-ray constants of the shear transform, computed once per ray and reused for every
/// triangle it is tested against.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    pub(crate) kx: usize,
    pub(crate) ky: usize,
    pub(crate) kz: usize,
    pub(crate) sx: f32,
    pub(crate) sy: f32,
    sz: f32,
    /// `|sx|`, `|sy|` widened for underflow: the weights of `|(p - o)[kz]|` in a vertex's
    /// sheared magnitudes ([`magnitudes`]).
    pub(crate) w: [f32; 2],
}

impl WatertightRay {
    /// Precomputes the shear for `dir` (must be non-zero).
    #[inline]
    pub fn new(dir: Vec3) -> Self {
        let [kx, ky, kz] = shear_axes(dir);
        // Arrays, not glam's `Index`, which matches on the index at every access.
        let d = dir.to_array();
        let (sx, sy) = (d[kx] / d[kz], d[ky] / d[kz]);
        Self {
            kx,
            ky,
            kz,
            sx,
            sy,
            sz: 1.0 / d[kz],
            w: [sx.abs() + SHEAR_UNDERFLOW, sy.abs() + SHEAR_UNDERFLOW],
        }
    }
}

/// The axes of the shear for direction `d`: `kz` the largest component's, `kx`, `ky` the
/// others, swapped when `d[kz] < 0` so the sheared triangle's winding does not depend on the
/// sign of the major axis. The same axes serve the `f32` and the `f64` tests.
#[inline(always)]
fn shear_axes(d: Vec3) -> [usize; 3] {
    let a = d.abs();
    let (kz, kx, ky, negative) = if a.x >= a.y && a.x >= a.z {
        (0, 1, 2, d.x < 0.0)
    } else if a.y >= a.z {
        (1, 2, 0, d.y < 0.0)
    } else {
        (2, 0, 1, d.z < 0.0)
    };
    if negative { [ky, kx, kz] } else { [kx, ky, kz] }
}

/// A triangle hit: distance and the barycentric weights of `v1` and `v2` (Embree's `u`, `v`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Weight of the second vertex.
    pub u: f32,
    /// Weight of the third vertex.
    pub v: f32,
}

/// Intersects `ray` (with its precomputed shear `wr`) with triangle `p0 p1 p2`, both faces.
#[inline]
pub fn intersect_triangle(
    ray: &Ray,
    wr: &WatertightRay,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<TriangleHit> {
    let (kx, ky, kz) = (wr.kx, wr.ky, wr.kz);
    let a = p0 - ray.origin;
    let b = p1 - ray.origin;
    let c = p2 - ray.origin;
    let (aa, ba, ca) = (a.to_array(), b.to_array(), c.to_array());
    let ax = aa[kx] - wr.sx * aa[kz];
    let ay = aa[ky] - wr.sy * aa[kz];
    let bx = ba[kx] - wr.sx * ba[kz];
    let by = ba[ky] - wr.sy * ba[kz];
    let cx = ca[kx] - wr.sx * ca[kz];
    let cy = ca[ky] - wr.sy * ca[kz];
    let (cx_by, cy_bx) = (cx * by, cy * bx);
    let (ax_cy, ay_cx) = (ax * cy, ay * cx);
    let (bx_ay, by_ax) = (bx * ay, by * ax);
    let e0 = cx_by - cy_bx;
    let e1 = ax_cy - ay_cx;
    let e2 = bx_ay - by_ax;
    // An edge function within its rounding error of 0 (the ray passes near that edge, or
    // grazes the plane) is re-evaluated from an f64 shear; the decision and the value depend
    // only on the ray and the edge, so neighbours agree and the test stays watertight.
    let k = [kx, ky, kz];
    let (ma, mb, mc) = (
        magnitudes(aa, k, wr.w),
        magnitudes(ba, k, wr.w),
        magnitudes(ca, k, wr.w),
    );
    // Written `!(|e| > bound)` so that a NaN (an overflowed product, `inf - inf`: only for
    // coordinates beyond the scene limits) is refined too, in f64, where no product of f32
    // inputs overflows; it would otherwise pass the sign test below as "not outside".
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN must compare as "within the bound"
    let refine = [
        !(e0.abs() > edge_bound([cx_by, cy_bx], [cx, cy], [bx, by], mc, mb)),
        !(e1.abs() > edge_bound([ax_cy, ay_cx], [ax, ay], [cx, cy], ma, mc)),
        !(e2.abs() > edge_bound([bx_ay, by_ax], [bx, by], [ax, ay], mb, ma)),
    ];
    if refine[0] | refine[1] | refine[2] {
        return rare_refined_hit(ray, [kx, ky, kz], [p0, p1, p2], [e0, e1, e2], refine);
    }
    // Every sign is certain from here on.
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if !(det.abs() >= f32::MIN_POSITIVE && det.is_finite()) {
        // A determinant below the normal range (a triangle of ~1e-19 seen from nearby: its
        // reciprocal overflows) or beyond f32: the decision stands, the numbers come from f64.
        return rare_refined_hit(ray, [kx, ky, kz], [p0, p1, p2], [e0, e1, e2], [true; 3]);
    }
    let inv_det = 1.0 / det;
    // No early range test on the sheared f32 distance: it can be off by 1e-2 at grazing angles,
    // and rejecting on it would make exact ties (duplicate triangles) depend on visit order.
    let t = plane_distance(ray, p0, p1, p2).unwrap_or_else(|| {
        let (az, bz, cz) = (wr.sz * aa[kz], wr.sz * ba[kz], wr.sz * ca[kz]);
        (e0 * az + e1 * bz + e2 * cz) * inv_det
    });
    if !in_range(t, ray) {
        return None;
    }
    Some(TriangleHit {
        t,
        u: e1 * inv_det,
        v: e2 * inv_det,
    })
}

/// The edges [`intersect_triangle`] could not decide in `f32` (`refine`), or all three: each
/// re-evaluated from the `f64` shear, and where that too lies within its rounding of 0, decided
/// exactly ([`edge_sign`]: a ray 1e-20 off the edge of a unit triangle has an `f64` edge
/// function of exactly 0). The other edges keep their `f32` values, whose signs were certain.
/// So every sign is the exact one: both triangles sharing an edge decide alike, a hit lies in
/// the closed triangle (and so inside every box around it), and a triangle without area,
/// whose exact edge functions sum to 0, is never hit.
fn refined_hit(
    ray: &Ray,
    k: [usize; 3],
    p: [Vec3; 3],
    f32_edges: [f32; 3],
    refine: [bool; 3],
) -> Option<TriangleHit> {
    let shear = Shear64::new(ray, k);
    // Edge i runs from corner i + 1 to corner i + 2.
    let edge = |i: usize| {
        if !refine[i] {
            return f32_edges[i] as f64;
        }
        let (a, b) = (p[(i + 1) % 3], p[(i + 2) % 3]);
        let (e, bound) = shear.edge(a, b);
        if e.abs() > bound {
            return e;
        }
        match edge_sign(ray.origin, ray.dir, a, b, k) {
            Ordering::Equal => 0.0,
            // The value only weighs the barycentrics: keep it unless its sign is wrong.
            s => f64::MIN_POSITIVE
                .max(e.abs())
                .copysign(if s.is_lt() { -1.0 } else { 1.0 }),
        }
    };
    let (e0, e1, e2) = (edge(0), edge(1), edge(2));
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    // `None` only for a ray parallel to the plane in compensated arithmetic, whose exact edge
    // functions all vanish: no hit.
    let t = plane_distance(ray, p[0], p[1], p[2])?;
    in_range(t, ray).then(|| TriangleHit {
        t,
        u: (e1 / det) as f32,
        v: (e2 / det) as f32,
    })
}

/// The end of [`intersect_triangle`] for a triangle whose three `f32` edge functions all lie
/// outside their bounds, agree in sign, and sum to a normal determinant, with `u`, `v` computed
/// from them as it does: the hit, `None` when its distance is out of range, or `Err(())` when
/// the plane form fails, where `intersect_triangle` itself must finish (rare: a plane whose
/// compensated denominator vanishes). Lets a SIMD pass over several triangles that has
/// already made every decision up to here skip repeating them.
#[inline(always)]
pub(crate) fn finish_decided_hit(
    ray: &Ray,
    [p0, p1, p2]: [Vec3; 3],
    u: f32,
    v: f32,
) -> Result<Option<TriangleHit>, ()> {
    let t = plane_distance(ray, p0, p1, p2).ok_or(())?;
    Ok(in_range(t, ray).then_some(TriangleHit { t, u, v }))
}

/// [`refined_hit`] where the `f32` test needs it, kept out of its way.
#[cold]
#[inline(never)]
fn rare_refined_hit(
    ray: &Ray,
    k: [usize; 3],
    p: [Vec3; 3],
    f32_edges: [f32; 3],
    refine: [bool; 3],
) -> Option<TriangleHit> {
    refined_hit(ray, k, p, f32_edges, refine)
}

/// `t` inside the ray's `(t_min, t_max]` and finite: a distance beyond `f32::MAX` rounds to
/// infinity, which is no hit (a ray with `t_max = inf` would otherwise accept it).
#[inline(always)]
fn in_range(t: f32, ray: &Ray) -> bool {
    t > ray.t_min && t <= ray.t_max && t < f32::INFINITY
}

/// `--precision fast`: the `f32` Moller-Trumbore test (JGT 1997) as most renderers ship it.
/// Not watertight: its edge tests are evaluated per triangle with different rounding, so a ray
/// through a shared edge can miss both neighbours, more often the farther the mesh lies from
/// the origin (`o - p0` loses the low bits of the coordinates).
#[inline]
pub fn intersect_triangle_fast(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<TriangleHit> {
    let (e1, e2) = (p1 - p0, p2 - p0);
    let pvec = ray.dir.cross(e2);
    let det = e1.dot(pvec);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - p0;
    let u = s.dot(pvec) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv_det;
    // Negated, so that a NaN (an overflowed product) is rejected, not accepted.
    if !(v >= 0.0 && u + v <= 1.0) {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    in_range(t, ray).then_some(TriangleHit { t, u, v })
}

/// `--precision double`: the watertight test with every step (shear, edge functions,
/// barycentrics, distance) in `f64`, rounded to `f32` once at the end; an edge function within
/// its `f64` error bound of 0 is decided exactly, as in the default test's refinement.
#[inline]
pub fn intersect_triangle_double(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<TriangleHit> {
    refined_hit(ray, shear_axes(ray.dir), [p0, p1, p2], [0.0; 3], [true; 3])
}

/// Unnormalised geometric normal `(p1 - p0) x (p2 - p0)`: counter-clockwise faces point at the viewer.
pub fn face_normal(p0: Vec3, p1: Vec3, p2: Vec3) -> Vec3 {
    (p1 - p0).cross(p2 - p0)
}

/// The unit geometric normal of a hit triangle, `+y` for one without area: one formula for the
/// surface, the hit record and the record taken from the packed leaves, so all give the same bits.
#[inline]
pub fn unit_face_normal([p0, p1, p2]: [Vec3; 3]) -> Vec3 {
    face_normal(p0, p1, p2).normalize_or(Vec3::Y)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(o: Vec3, d: Vec3, p: [Vec3; 3]) -> Option<TriangleHit> {
        let r = Ray::new(o, d);
        intersect_triangle(&r, &WatertightRay::new(d), p[0], p[1], p[2])
    }

    #[test]
    fn barycentrics_follow_embree_convention() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let h = hit(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z, tri).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.u - 0.25).abs() < 1e-6 && (h.v - 0.5).abs() < 1e-6);
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles of a quad split along the diagonal; rays aimed exactly at the diagonal
        // must hit at least one of them.
        let (a, b, c, d) = (
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        for i in 1..1000 {
            let s = i as f32 / 1000.0;
            let target = Vec3::new(s, s, 0.0);
            let o = Vec3::new(0.3, -0.2, 2.0);
            let dir = target - o;
            let h1 = hit(o, dir, [a, b, c]);
            let h2 = hit(o, dir, [a, c, d]);
            assert!(h1.is_some() || h2.is_some(), "leak at s={s}");
        }
    }

    #[test]
    fn edges_the_f64_shear_rounds_to_zero_are_decided_exactly() {
        // The ray crosses z = 0 at (1e-20, -1e-20): outside the edge y = 0 of a unit triangle
        // by 1e-20, where the f64 sheared coordinates (near 1) have no bits left. As "on the
        // edge" it was a hit that every box test (y >= 0) culled, so hierarchies disagreed
        // with brute force (found by the query fuzz target).
        let tri = [Vec3::X, Vec3::Y, -Vec3::X];
        for (o, d) in [
            (Vec3::new(0.0, 0.0, 1e-20), Vec3::new(1.0, -1.0, -1.0)),
            (Vec3::new(0.0, 0.0, 1e-30), Vec3::new(1.0, -1.0, -1.0)),
        ] {
            assert_eq!(hit(o, d, tri), None);
            assert_eq!(
                intersect_triangle_double(&Ray::new(o, d), tri[0], tri[1], tri[2]),
                None
            );
            // Just inside the edge instead: a hit.
            let inside = Vec3::new(0.0, 2e-20, o.z);
            assert!(hit(inside, d, tri).is_some());
        }
    }

    #[test]
    fn grazing_rays_get_the_plane_distance_to_f32_precision() {
        // Rays at 1e-6..1e-3 rad from a tilted triangle's plane, crossing it inside. The f64
        // plane distance is the reference; the sheared f32 formula alone was off by up to 1e-2.
        let tri = [
            Vec3::new(-1.0, 0.1, -1.0),
            Vec3::new(1.3, -0.2, -0.9),
            Vec3::new(0.1, 0.3, 1.2),
        ];
        let n = (tri[1] - tri[0])
            .cross(tri[2] - tri[0])
            .normalize()
            .as_dvec3();
        let tangent = n.cross(glam::DVec3::X).normalize();
        let mut worst = 0.0f64;
        for k in 0..200 {
            let angle = 10f64.powf(-6.0 + 3.0 * k as f64 / 200.0);
            let d = tangent * angle.cos() + n * angle.sin();
            let target = (tri[0].as_dvec3() + tri[1].as_dvec3() + tri[2].as_dvec3()) / 3.0;
            let o = (target - d * 3.0).as_vec3();
            let dir = d.as_vec3();
            let h = hit(o, dir, tri).expect("crosses the triangle's interior");
            let (od, dd) = (o.as_dvec3(), dir.as_dvec3());
            let p0 = tri[0].as_dvec3();
            let nn = (tri[1].as_dvec3() - p0).cross(tri[2].as_dvec3() - p0);
            let t_ref = nn.dot(p0 - od) / nn.dot(dd);
            worst = worst.max((h.t as f64 - t_ref).abs() / t_ref);
        }
        assert!(
            worst < 2.0 * f32::EPSILON as f64,
            "worst relative t error {worst:e}"
        );
    }
}

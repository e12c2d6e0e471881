//! Re-evaluation of the watertight triangle test's ill-conditioned quantities: an edge function
//! whose `f32` value lies within its rounding error of 0 (a ray through or near an edge, or a
//! ray grazing the plane, which makes every edge function tiny), and a plane distance whose
//! denominator cancels (a grazing ray).
//!
//! Watertightness is kept: whether an edge function is re-evaluated, and its new value, depend
//! only on the ray and the edge's two vertices, so both triangles sharing the edge make the same
//! choice and get the same value (negated), exactly as the `f32` values are shared.

use super::twofloat::{two_prod, two_sum};
use crate::math::{Ray, Vec3};
use glam::DVec3;

/// The ray's shear in `f64`, for re-evaluating edge functions.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shear64 {
    origin: DVec3,
    k: [usize; 3],
    s: [f64; 2],
}

impl Shear64 {
    /// The shear of `ray` for the axis permutation `k = [kx, ky, kz]` of its `f32` shear.
    pub(crate) fn new(ray: &Ray, k: [usize; 3]) -> Self {
        let d = ray.dir.as_dvec3();
        Self {
            origin: ray.origin.as_dvec3(),
            k,
            s: [d[k[0]] / d[k[2]], d[k[1]] / d[k[2]]],
        }
    }

    /// The sheared 2-D position of a vertex, and the magnitude `|x| + |y| + (|sx| + |sy|) |z|`
    /// of its unsheared offset that bounds the rounding of products of two such positions.
    fn project(&self, p: Vec3) -> (f64, f64, f64) {
        let v = p.as_dvec3() - self.origin;
        let [kx, ky, kz] = self.k;
        let m = v[kx].abs() + v[ky].abs() + (self.s[0].abs() + self.s[1].abs()) * v[kz].abs();
        (v[kx] - self.s[0] * v[kz], v[ky] - self.s[1] * v[kz], m)
    }

    /// The edge function of the directed edge `p -> q` (`qx * py - qy * px`), in `f64`, and a
    /// bound on its error: the difference `p - o` rounds once, the shear ratio, its product and
    /// the subtraction three more times, the products and their difference twice; 16 roundings
    /// of the magnitudes' product cover that with room, plus the smallest normal for products
    /// that fall below the normal range.
    pub(crate) fn edge(&self, p: Vec3, q: Vec3) -> (f64, f64) {
        let (px, py, mp) = self.project(p);
        let (qx, qy, mq) = self.project(q);
        let bound = 16.0 * f64::EPSILON * mp * mq + 4.0 * f64::MIN_POSITIVE;
        (qx * py - qy * px, bound)
    }
}

/// A compensated dot product (Ogita, Rump, Oishi 2005, Dot2): as accurate as if computed in
/// twice the precision, then rounded; `x` is given as an unevaluated sum `hi + lo` per component.
fn dot2(x_hi: DVec3, x_lo: DVec3, y: DVec3) -> f64 {
    let (mut s, mut c) = (0.0, 0.0);
    for i in 0..3 {
        let (p, e) = two_prod(x_hi[i], y[i]).parts();
        let (t, f) = two_sum(s, p).parts();
        s = t;
        c += f + e + x_lo[i] * y[i];
    }
    s + c
}

/// The triangle's normal `(p1 - p0) x (p2 - p0)` as an unevaluated sum `hi + lo`, accurate to
/// about `f64` precision squared of `|p1 - p0| |p2 - p0|`. The edges are taken exactly, as
/// two-sums: a difference of `f32` coordinates is exact in `f64` only when their exponents lie
/// within 29 of each other (1.4e14 - 1.8e-4 is not, and a needle 1e14 long and 1e-4 wide got a
/// normal tilted enough to put its plane units away near its short edge).
fn normal_dd(p0: DVec3, p1: DVec3, p2: DVec3) -> (DVec3, DVec3) {
    let edge =
        |q: DVec3| -> [(f64, f64); 3] { std::array::from_fn(|i| two_sum(q[i], -p0[i]).parts()) };
    let (a, b) = (edge(p1), edge(p2));
    let comp = |i: usize, j: usize| {
        let ((ai, ai_lo), (aj, aj_lo), (bi, bi_lo), (bj, bj_lo)) = (a[i], a[j], b[i], b[j]);
        let (x, ex) = two_prod(ai, bj).parts();
        let (y, ey) = two_prod(aj, bi).parts();
        // The low parts' products: each below eps |a| |b|, so their rounding is eps^2.
        let small =
            (ai * bj_lo + ai_lo * bj + ai_lo * bj_lo) - (aj * bi_lo + aj_lo * bi + aj_lo * bi_lo);
        let (s, es) = two_sum(x, -y).parts();
        two_sum(s, es + ex - ey + small).parts()
    };
    let (x, y, z) = (comp(1, 2), comp(2, 0), comp(0, 1));
    (DVec3::new(x.0, y.0, z.0), DVec3::new(x.1, y.1, z.1))
}

/// The ray parameter where `ray` meets the plane of `p0 p1 p2`, rounded once to `f32`; `None`
/// when the ray is parallel to the plane. Plain `f64` when the denominator is well conditioned;
/// compensated when it cancels (grazing rays: at 1e-12 rad plain `f64` keeps only 4 digits).
pub(crate) fn plane_distance(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<f32> {
    let (a, b, c) = (p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let (e1, e2) = (b - a, c - a);
    let n = e1.cross(e2);
    let den = n.dot(d);
    let num = n.dot(a - o);
    // The normal itself cancels on slivers: each component errs by up to 4 eps of
    // |e1| |e2| (max norms), so it is trusted to 2^-30 only above 2^-21 of that product.
    let normal_ok =
        n.abs().max_element() > e1.abs().max_element() * e2.abs().max_element() * 2f64.powi(-21);
    // The relative error of the f64 denominator is ~4 eps |n| |d| / |den|.
    let scale = n.abs().dot(d.abs());
    if normal_ok
        && den.abs() > scale * 2f64.powi(-26)
        && num.abs() > n.abs().dot((a - o).abs()) * 2f64.powi(-26)
    {
        return (den != 0.0).then(|| (num / den) as f32);
    }
    let (n_hi, n_lo) = normal_dd(a, b, c);
    let den = dot2(n_hi, n_lo, d);
    if den == 0.0 {
        return None;
    }
    // Any vertex lies on the exact plane, but the normal's residual error tilts the computed
    // one about the vertex chosen: take the one nearest the origin, so that a huge sliver seen
    // from beside its short edge is measured there (its far end may be 1e14 away). `p - o` is
    // exact in f64 for f32 inputs of similar magnitude; two_sum keeps it exact always.
    let near = [a, b, c]
        .into_iter()
        .min_by(|p, q| {
            (*p - o)
                .abs()
                .max_element()
                .total_cmp(&(*q - o).abs().max_element())
        })
        .unwrap_or(a);
    let mut dir_hi = DVec3::ZERO;
    let mut dir_lo = DVec3::ZERO;
    for i in 0..3 {
        let (h, l) = two_sum(near[i], -o[i]).parts();
        dir_hi[i] = h;
        dir_lo[i] = l;
    }
    let num = dot2(n_hi, n_lo, dir_hi) + dot2(n_hi, n_lo, dir_lo);
    Some((num / den) as f32)
}

//! Exact geometric predicates on floating-point inputs, by error-free transformations.
//!
//! A sum or product of two `f64`s is rounded, but its rounding error is itself an `f64`
//! (`two_sum`, `two_product`), so a polynomial in the inputs can be carried as an *expansion*: a
//! list of non-overlapping `f64`s whose exact sum is the exact value (Shewchuk, "Adaptive
//! Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997). The sign
//! of an expansion is the sign of its largest component, so orientation tests come out exact.
//!
//! Every `f32` converts to `f64` exactly, and the predicates here need inputs no larger than
//! 2^400 and, when nonzero, no smaller than 2^-400 in magnitude (every finite `f32` qualifies):
//! then no product of expansion components overflows or underflows, so nothing is lost.

use std::cmp::Ordering;

use crate::math::Vec3;

/// `a + b = s + e` exactly (see [`super::twofloat::two_sum`]).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    super::twofloat::two_sum(a, b).parts()
}

/// `a * b = p + e` exactly (see [`super::twofloat::two_prod`]).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    super::twofloat::two_prod(a, b).parts()
}

/// Adds `b` to the expansion `e` (non-overlapping, increasing magnitude) in place, dropping
/// zero components; the result is again non-overlapping and increasing (Shewchuk's
/// GROW-EXPANSION, his Theorem 10), and its exact sum is `sum(e) + b`.
pub(super) fn grow(e: &mut Vec<f64>, b: f64) {
    let mut q = b;
    let mut out = 0;
    for i in 0..e.len() {
        let (s, h) = two_sum(q, e[i]);
        q = s;
        if h != 0.0 {
            e[out] = h;
            out += 1;
        }
    }
    e.truncate(out);
    if q != 0.0 {
        e.push(q);
    }
}

/// The sign of an expansion: that of its largest (last) component, zeros having been dropped.
pub(super) fn sign(e: &[f64]) -> Ordering {
    e.last().map_or(Ordering::Equal, |x| x.total_cmp(&0.0))
}

/// Sign of `(b - a) x (c - a)`: `Greater` when `a, b, c` turn counter-clockwise, `Less` when
/// clockwise, `Equal` exactly when they are collinear (or coincide). Exact for inputs in the
/// range the module documents.
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Ordering {
    let left = (b[0] - a[0]) * (c[1] - a[1]);
    let right = (b[1] - a[1]) * (c[0] - a[0]);
    let det = left - right;
    // Filter: the rounded determinant is within 3 eps (|left| + |right|) of the exact one
    // (Shewchuk's bound, eps = 2^-53; 4 eps here). Below 2^-800 the bound's no-underflow
    // assumption fails, so tiny values take the exact path.
    let magnitude = left.abs() + right.abs();
    if det.abs() > 2.0 * f64::EPSILON * magnitude && magnitude > 1e-240 {
        return det.total_cmp(&0.0);
    }
    orient2d_exact(a, b, c)
}

/// [`orient2d`] without the filter: each difference is split into its rounded value and error,
/// so `(b - a) x (c - a)` is a sum of 8 exact products, each two `f64`s.
fn orient2d_exact(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Ordering {
    let diff = |x: f64, y: f64| {
        let (s, e) = two_sum(x, -y);
        [s, e]
    };
    let (bx, by, cx, cy) = (
        diff(b[0], a[0]),
        diff(b[1], a[1]),
        diff(c[0], a[0]),
        diff(c[1], a[1]),
    );
    let mut e = Vec::with_capacity(16);
    for (p, q, s) in [(bx, cy, 1.0), (by, cx, -1.0)] {
        for x in p {
            for y in q {
                let (hi, lo) = two_product(x, y);
                grow(&mut e, s * lo);
                grow(&mut e, s * hi);
            }
        }
    }
    sign(&e)
}

/// The `(i, j)` coordinates of `p` as exact `f64`s.
fn plane(p: Vec3, i: usize, j: usize) -> [f64; 2] {
    [p[i] as f64, p[j] as f64]
}

/// Sign of component `k` of `(p1 - p0) x (p2 - p0)`, in exact arithmetic on the `f32` inputs:
/// the orientation of the triangle projected along axis `k` (component `k` dropped, the other
/// two in cyclic order, so `k = 2` is the usual xy orientation).
pub fn cross_sign(p0: Vec3, p1: Vec3, p2: Vec3, k: usize) -> Ordering {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    orient2d(plane(p0, i, j), plane(p1, i, j), plane(p2, i, j))
}

/// Sign of the watertight test's edge function for the directed edge `p -> q` of a ray from
/// `o` along `d` (the sheared `qx py - qy px` with the shear axes `k = [kx, ky, kz]`), in exact
/// arithmetic on the `f32` inputs. The sheared cross product of `a = p - o` and `b = q - o`
/// is the triple product `(a x b) . d / d[kz]` in the permuted axes, so this is the sign of
/// `-(a x b) . d` times that of `d[kz]`: 6 monomials `a_i b_j d_k`, each difference split
/// into its rounded value and error, every product expanded exactly.
pub fn edge_sign(o: Vec3, d: Vec3, p: Vec3, q: Vec3, k: [usize; 3]) -> Ordering {
    let diff = |v: Vec3, i: usize| {
        let (s, e) = two_sum(v[i] as f64, -(o[i] as f64));
        [s, e]
    };
    let (a, b) = (k.map(|i| diff(p, i)), k.map(|i| diff(q, i)));
    let dk = k.map(|i| d[i] as f64);
    let mut e = Vec::with_capacity(96);
    // (a x b) . d = sum over the cyclic (i, j, l) of (a_i b_j - a_j b_i) d_l.
    for (i, j, l) in [(1, 2, 0), (2, 0, 1), (0, 1, 2)] {
        for (x, y, sign) in [(a[i], b[j], 1.0), (a[j], b[i], -1.0)] {
            for xv in x {
                for yv in y {
                    let (hi, lo) = two_product(xv, yv);
                    for part in [lo, hi] {
                        let (ph, pl) = two_product(part, dk[l]);
                        grow(&mut e, sign * pl);
                        grow(&mut e, sign * ph);
                    }
                }
            }
        }
    }
    let triple = sign(&e);
    if dk[2] < 0.0 {
        triple
    } else {
        triple.reverse()
    }
}

/// True exactly when the cross product `(p1 - p0) x (p2 - p0)` is the zero vector in exact
/// arithmetic on the `f32` inputs: the corners are collinear or coincide, so the triangle has
/// no area. Any triangle with the least real area gives `false`, whatever its size or distance
/// from the origin. A non-finite corner gives `true` (no triangle there to keep).
pub fn triangle_area_is_zero(p0: Vec3, p1: Vec3, p2: Vec3) -> bool {
    if !(p0.is_finite() && p1.is_finite() && p2.is_finite()) {
        return true;
    }
    (0..3).all(|k| cross_sign(p0, p1, p2, k) == Ordering::Equal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_free_transformations_are_exact() {
        let (s, e) = two_sum(1.0, 1e-30);
        assert_eq!((s, e), (1.0, 1e-30));
        let x = 1.0 + f64::EPSILON;
        let (p, e) = two_product(x, x);
        // (1 + u)^2 = 1 + 2u + u^2: the u^2 term is exactly the error.
        assert_eq!(
            (p, e),
            (1.0 + 2.0 * f64::EPSILON, f64::EPSILON * f64::EPSILON)
        );
        let mut acc = Vec::new();
        for b in [1e300, 1.0, -1e300, 1e-300, -1.0] {
            grow(&mut acc, b);
        }
        assert_eq!(acc, [1e-300]);
    }

    #[test]
    fn orientation_of_nearly_collinear_points_is_exact() {
        // Points on the line y = x, with c nudged by one ulp either way: the rounded
        // determinant is 0 or has the wrong sign; the exact one does not.
        let a = [0.5, 0.5];
        let b = [12.0, 12.0];
        for (cy, want) in [
            (24.0, Ordering::Equal),
            (24.0f64.next_up(), Ordering::Greater),
            (24.0f64.next_down(), Ordering::Less),
        ] {
            assert_eq!(orient2d(a, b, [24.0, cy]), want, "cy = {cy}");
            assert_eq!(orient2d(b, a, [24.0, cy]), want.reverse());
        }
        // Differences that are not exact in f64: 2^100 + 1 - 2^100 cancels in rounding.
        let big = 2f64.powi(100);
        assert_eq!(
            orient2d([big, 0.0], [big, 1.0], [1.0, 0.0]),
            Ordering::Greater
        );
        assert_eq!(
            orient2d([1e-30, 0.0], [big, 1e-30], [-big, -1e-30]),
            Ordering::Greater
        );
    }

    #[test]
    fn zero_area_only_for_exactly_collinear_or_coincident_corners() {
        let v = Vec3::new;
        // The external report's sliver: 1000 long, 0.001 high, area 0.5.
        assert!(!triangle_area_is_zero(
            v(0., 0., 0.),
            v(1000., 0., 0.),
            v(1000., 0.001, 0.)
        ));
        // Far from the origin, a few ulps apart.
        let o = v(148376.0, 1235.0, -223423.0);
        let ulp = |x: f32| x.next_up();
        let p1 = v(ulp(ulp(o.x)), o.y, o.z);
        let p2 = v(o.x, ulp(o.y), ulp(o.z));
        assert!(!triangle_area_is_zero(o, p1, p2));
        // Exactly collinear (midpoint) and coincident corners, far away too.
        let q = v(1e7, -3e6, 2.5e5);
        assert!(triangle_area_is_zero(o, q, (o + q) * 0.5));
        assert!(triangle_area_is_zero(o, o, q));
        assert!(triangle_area_is_zero(q, q, q));
        assert!(triangle_area_is_zero(o, q, v(f32::NAN, 0., 0.)));
        // Extreme magnitudes: subnormal offsets from huge coordinates.
        let tiny = f32::from_bits(1);
        assert!(!triangle_area_is_zero(
            v(0., 0., 0.),
            v(f32::MAX, 0., 0.),
            v(0., tiny, 0.)
        ));
        assert!(triangle_area_is_zero(
            v(-f32::MAX, 0., 0.),
            v(f32::MAX, 0., 0.),
            v(0., 0., 0.)
        ));
    }

    #[test]
    fn cross_sign_matches_the_f64_cross_product_where_it_is_exact() {
        // Small integers: the f64 cross product is exact, so its signs are the truth.
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 40) % 9) as f32 - 4.0
        };
        for _ in 0..2000 {
            let p = [0; 3].map(|_| Vec3::new(next(), next(), next()));
            let n = (p[1] - p[0]).as_dvec3().cross((p[2] - p[0]).as_dvec3());
            for k in 0..3 {
                assert_eq!(
                    cross_sign(p[0], p[1], p[2], k),
                    n[k].partial_cmp(&0.0).unwrap()
                );
            }
            assert_eq!(
                triangle_area_is_zero(p[0], p[1], p[2]),
                n == glam::DVec3::ZERO
            );
        }
    }
}

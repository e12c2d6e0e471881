//! Exact three-dimensional predicates on `f32` inputs, for point containment: which side of a
//! triangle's plane a point lies on, whether it lies on the closed triangle, and whether it
//! lies in a closed ball.
//!
//! Each is the sign of a polynomial in coordinate differences. A difference of two `f32`s is
//! an exact pair of `f64`s (two-sum), so the polynomial is a sum of products of such parts,
//! each expanded exactly (two-products) and summed as an expansion ([`super::exact`]). A filter
//! decides first from the rounded `f64` value where its error bound allows (Shewchuk's
//! `orient3d` bound), which it does for all but near-degenerate inputs. Every finite `f32`
//! input qualifies: no product of parts overflows or underflows `f64`.

use std::cmp::Ordering;

use super::exact::{cross_sign, grow, sign};
use super::twofloat::{two_prod, two_sum};
use crate::math::Vec3;

/// An exact value `hi + lo`: a difference of two `f32`s, or an `f32` (`lo = 0`).
type Part = [f64; 2];

/// `a - b` exactly.
fn diff(a: f32, b: f32) -> Part {
    let (hi, lo) = two_sum(a as f64, -(b as f64)).parts();
    [hi, lo]
}

/// `a - b` exactly, per coordinate.
fn diff3(a: Vec3, b: Vec3) -> [Part; 3] {
    [diff(a.x, b.x), diff(a.y, b.y), diff(a.z, b.z)]
}

/// Shewchuk's relative error bound of the rounded 3x3 determinant of rounded differences,
/// `(7 + 56 eps) eps` with `eps = 2^-53`, rounded up to `8 eps`.
const DET3_BOUND: f64 = 8.0 * f64::EPSILON / 2.0;

/// The sign of the determinant of the rows `u`, `v`, `w`, whose entries are exact parts.
fn det3_sign(u: [Part; 3], v: [Part; 3], w: [Part; 3]) -> Ordering {
    let hi = |r: [Part; 3]| r.map(|x| x[0]);
    let (a, b, c) = (hi(u), hi(v), hi(w));
    let (m0, m1, m2) = (
        [b[1] * c[2], b[2] * c[1]],
        [b[2] * c[0], b[0] * c[2]],
        [b[0] * c[1], b[1] * c[0]],
    );
    let det = a[0] * (m0[0] - m0[1]) + a[1] * (m1[0] - m1[1]) + a[2] * (m2[0] - m2[1]);
    let permanent = a[0].abs() * (m0[0].abs() + m0[1].abs())
        + a[1].abs() * (m1[0].abs() + m1[1].abs())
        + a[2].abs() * (m2[0].abs() + m2[1].abs());
    if det.abs() > DET3_BOUND * permanent {
        return det.total_cmp(&0.0);
    }
    if permanent == 0.0 && u.iter().chain(&v).chain(&w).all(|x| x[1] == 0.0) {
        return Ordering::Equal;
    }
    det3_exact(u, v, w)
}

/// [`det3_sign`] without the filter: the six signed monomials, each entry's two parts
/// multiplied out exactly.
fn det3_exact(u: [Part; 3], v: [Part; 3], w: [Part; 3]) -> Ordering {
    let mut e = Vec::with_capacity(64);
    for (i, j, k, s) in [
        (0, 1, 2, 1.0),
        (1, 2, 0, 1.0),
        (2, 0, 1, 1.0),
        (0, 2, 1, -1.0),
        (1, 0, 2, -1.0),
        (2, 1, 0, -1.0),
    ] {
        for x in u[i] {
            for y in v[j] {
                let (h, l) = two_prod(x, y).parts();
                for z in w[k] {
                    for part in [l, h] {
                        let (ph, pl) = two_prod(part, z).parts();
                        grow(&mut e, s * pl);
                        grow(&mut e, s * ph);
                    }
                }
            }
        }
    }
    sign(&e)
}

/// Which side of the plane of triangle `a b c` the point `p` lies on: the sign of
/// `n . (a - p)` with `n = (b - a) x (c - a)`, i.e. `Greater` when `p` lies behind the face
/// (opposite its normal), `Equal` on the plane or for a triangle without area. Exact.
pub fn orient3d(a: Vec3, b: Vec3, c: Vec3, p: Vec3) -> Ordering {
    det3_sign(diff3(a, p), diff3(b, p), diff3(c, p))
}

/// The sign of `((b - a) x (c - a)) . d`: how direction `d` meets the face's normal. Exact.
pub fn normal_dot_sign(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Ordering {
    let exact = |x: f32| [x as f64, 0.0];
    det3_sign(diff3(b, a), diff3(c, a), d.to_array().map(exact))
}

/// True when `p` lies on the closed triangle `a b c` (its interior, edges or corners), in exact
/// arithmetic. A triangle without area holds no point.
pub fn on_triangle(p: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
    let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
    if p.cmplt(lo).any() || p.cmpgt(hi).any() {
        return false;
    }
    if orient3d(a, b, c, p).is_ne() {
        return false;
    }
    // In the plane: project along an axis the plane is not parallel to (the triangle's
    // projection there has area), where inside means no edge sees `p` on the wrong side.
    let Some((k, turn)) = (0..3)
        .map(|k| (k, cross_sign(a, b, c, k)))
        .find(|(_, s)| s.is_ne())
    else {
        return false;
    };
    [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, w)| cross_sign(u, w, p, k) != turn.reverse())
}

/// True when `p` lies in the closed ball of centre `c` and radius `r`: the exact sign of
/// `|p - c|^2 - r^2` on the `f32` inputs.
pub fn ball_contains(c: Vec3, r: f32, p: Vec3) -> bool {
    let d = diff3(p, c);
    // Filter: the f64 value of |p - c|^2 - r^2 from the rounded differences errs by at most
    // a few eps of |p - c|^2 + r^2.
    let dh = d.map(|x| x[0]);
    let r2 = r as f64 * r as f64;
    let sum = dh[0] * dh[0] + dh[1] * dh[1] + dh[2] * dh[2];
    let value = sum - r2;
    if value.abs() > 8.0 * f64::EPSILON * (sum + r2) {
        return value < 0.0;
    }
    let mut e = Vec::with_capacity(32);
    for [h, l] in d {
        // (h + l)^2 = h^2 + 2 h l + l^2, each product exact as two f64s.
        for (x, y) in [(h, h), (2.0 * h, l), (l, l)] {
            let (ph, pl) = two_prod(x, y).parts();
            grow(&mut e, pl);
            grow(&mut e, ph);
        }
    }
    let (rh, rl) = two_prod(r as f64, r as f64).parts();
    grow(&mut e, -rl);
    grow(&mut e, -rh);
    sign(&e).is_le()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    /// Small integers: the f64 arithmetic is exact, so its signs are the truth.
    #[test]
    fn signs_match_exact_integer_arithmetic() {
        let mut seed = 11u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 40) % 7) as f32 - 3.0
        };
        for _ in 0..5000 {
            let mut point = || v(next(), next(), next());
            let (a, b, c, p) = (point(), point(), point(), point());
            let n = (b - a).as_dvec3().cross((c - a).as_dvec3());
            let want = n.dot((a - p).as_dvec3()).partial_cmp(&0.0).unwrap();
            assert_eq!(orient3d(a, b, c, p), want);
            assert_eq!(
                det3_exact(diff3(a, p), diff3(b, p), diff3(c, p)),
                want,
                "the exact path alone"
            );
            let want = n.dot(p.as_dvec3()).partial_cmp(&0.0).unwrap();
            assert_eq!(normal_dot_sign(a, b, c, p), want);
            let r = next().abs();
            let d2 = (p - a).as_dvec3().length_squared();
            assert_eq!(ball_contains(a, r, p), d2 <= (r * r) as f64);
        }
    }

    #[test]
    fn near_degenerate_inputs_are_decided_exactly() {
        // A plane through huge coordinates, and points one ulp off it either way.
        let (a, b, c) = (v(1e7, 0.0, 0.0), v(0.0, 1e7, 0.0), v(0.0, 0.0, 1e7));
        let on = v(5e6, 5e6, 0.0);
        assert_eq!(orient3d(a, b, c, on), Ordering::Equal);
        assert_eq!(orient3d(a, b, c, v(5e6, 5e6, 1e-30)), Ordering::Less);
        assert_eq!(orient3d(a, b, c, v(5e6, 5e6, -1e-30)), Ordering::Greater);
        assert!(on_triangle(on, [a, b, c]));
        assert!(!on_triangle(v(5e6, 5e6, 1e-30), [a, b, c]));
        // Corners, edge points, and a point just beyond an edge, in the plane.
        assert!(on_triangle(a, [a, b, c]));
        let (p, q) = (v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0));
        let r = v(0.0, 2.0, 0.0);
        assert!(on_triangle(v(1.0, 1.0, 0.0), [p, q, r]));
        assert!(!on_triangle(v(1.0, 1.0f32.next_up(), 0.0), [p, q, r]));
        assert!(on_triangle(v(1.0, 1.0f32.next_down(), 0.0), [p, q, r]));
        // Without area: nothing is on it.
        assert!(!on_triangle(p, [p, q, v(4.0, 0.0, 0.0)]));
        // Spheres: far centre, tiny radius; the boundary is inside.
        let c0 = v(1e6, -1e6, 3.0);
        assert!(ball_contains(c0, 0.5, c0 + v(0.5, 0.0, 0.0)));
        assert!(!ball_contains(
            c0,
            0.5,
            v(1e6 + 0.5, -1e6, 3.0f32.next_up())
        ));
        assert!(ball_contains(c0, 0.5, v(1e6, -1e6, 3.5)));
        assert!(ball_contains(v(0.0, 0.0, 0.0), 1e-30, v(0.0, 1e-30, 0.0)));
        assert!(!ball_contains(
            v(0.0, 0.0, 0.0),
            1e-30,
            v(1e-30, 1e-30, 0.0)
        ));
    }
}

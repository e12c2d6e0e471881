//! Which line hits of the group test certainly lie outside the ray's interval, decided in SSE
//! from the values the test already has, so that such a lane needs neither its corners nor the
//! `f64` plane distance (the nearest hit's one candidate in three on tumbledStones is in
//! range; a shadow ray's walls are all out of it).
//!
//! With the edge functions `e0, e1, e2` (each within its bound `b_i` of the exact one, all of
//! one certain sign on a line hit) and the vertices' offsets `dz_i = (p_i - o)[kz]` along the
//! shear's major axis (each rounded once), the exact distance is
//!
//! ```text
//! t = N / (D dir[kz]),   N = e0 dz0 + e1 dz1 + e2 dz2,   D = e0 + e1 + e2
//! ```
//!
//! (the barycentric mean of the sheared vertices' `z = dz / dir[kz]`). `N` as computed errs by
//! at most `(gamma(3) + u) S1 + (1 + u) S2` with `S1 = sum |e_i dz_i|`, `S2 = sum b_i |dz_i|`,
//! which [`ERR_S1`] and [`ERR_S2`] cover with room for their own roundings; `|D|` lies within
//! `sum |e_i| -+ sum b_i`, since the signs agree. A lane is outside when `t < 0` for certain
//! (and `t_min >= 0`), or when `t > t_max (1 + 2^-18)` for certain: the plane distance the
//! scalar test would compute is within a few `f64` ulps of `t`, so it rounds to an `f32` above
//! `t_max` (or to one at most `-0`) and that test rejects the lane as well. Nothing else
//! changes: lanes in range, and lanes whose range is uncertain, go on as before. Overflow and
//! NaN make every comparison false, which keeps the lane.

use crate::geometry::edge_bound::ABS_TINY;
use crate::math::Ray;

/// Unit roundoff of `f32`.
const U: f32 = f32::EPSILON * 0.5;
/// `8 u`: at least `gamma(3) + u` plus the roundings of `S1` and of the bound's sum.
const ERR_S1: f32 = 8.0 * U;
/// At least `1 + u` plus the roundings of `S2` and of the bound's sum.
const ERR_S2: f32 = 1.001;
/// The far limit's widening: covers the plane distance's own error, the roundings of the
/// limit's product and sums, and the step from `t_max` to the next `f32`.
const FAR_MARGIN: f32 = 1.0 + 1.0 / (1u32 << 18) as f32;

/// The ray's interval as the filter reads it.
#[derive(Clone, Copy)]
pub(in crate::accel::packed) struct Interval {
    /// Whether a distance below 0 lies outside (`t_min >= 0`).
    behind_outside: bool,
    /// `t_max` widened by [`FAR_MARGIN`].
    far: f32,
}

impl Interval {
    #[inline(always)]
    pub(in crate::accel::packed) fn of(ray: &Ray) -> Self {
        Self {
            behind_outside: ray.t_min >= 0.0,
            far: ray.t_max * FAR_MARGIN,
        }
    }
}

/// The lanes (bit `i` for lane `i`) whose line hit lies outside `interval` for certain, given
/// the edge functions `e`, their bounds `b`, the offsets `dz`, the determinant `det` and the
/// direction's major component `dir_kz`. Only meaningful for line-hit lanes.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) unsafe fn outside(
    interval: Interval,
    e: [std::arch::x86_64::__m128; 3],
    b: [std::arch::x86_64::__m128; 3],
    dz: [std::arch::x86_64::__m128; 3],
    det: std::arch::x86_64::__m128,
    dir_kz: f32,
) -> u32 {
    use std::arch::x86_64::*;
    // SAFETY (whole body): SSE is part of the x86-64 baseline; no memory is touched.
    unsafe {
        let sign = _mm_set1_ps(-0.0);
        let abs = |x: __m128| _mm_andnot_ps(sign, x);
        let (add, mul) = (|a, b| _mm_add_ps(a, b), |a, b| _mm_mul_ps(a, b));
        let p = [mul(e[0], dz[0]), mul(e[1], dz[1]), mul(e[2], dz[2])];
        let n = add(add(p[0], p[1]), p[2]);
        // N times the sign of D dir[kz]: the sign of the distance.
        let flip = _mm_and_ps(_mm_xor_ps(det, _mm_set1_ps(dir_kz)), sign);
        let n = _mm_xor_ps(n, flip);
        let s1 = add(add(abs(p[0]), abs(p[1])), abs(p[2]));
        let s2 = add(
            add(mul(b[0], abs(dz[0])), mul(b[1], abs(dz[1]))),
            mul(b[2], abs(dz[2])),
        );
        let err = add(
            add(mul(_mm_set1_ps(ERR_S1), s1), mul(_mm_set1_ps(ERR_S2), s2)),
            _mm_set1_ps(ABS_TINY),
        );
        let behind = if interval.behind_outside {
            _mm_cmplt_ps(n, _mm_xor_ps(err, sign))
        } else {
            _mm_setzero_ps()
        };
        let d_hi = add(
            add(add(abs(e[0]), abs(e[1])), abs(e[2])),
            add(add(b[0], b[1]), b[2]),
        );
        let low = _mm_sub_ps(n, err);
        let limit = add(
            mul(
                mul(_mm_set1_ps(interval.far), d_hi),
                _mm_set1_ps(dir_kz.abs()),
            ),
            _mm_set1_ps(ABS_TINY),
        );
        let beyond = _mm_and_ps(
            _mm_cmpgt_ps(low, _mm_setzero_ps()),
            _mm_cmpgt_ps(low, limit),
        );
        _mm_movemask_ps(_mm_or_ps(behind, beyond)) as u32
    }
}

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
//! (and `t_min >= 0`), or when `t > t_max (1 + 2^-18) + 2^-147` for certain: the plane
//! distance the scalar test would compute is within a few `f64` ulps of `t`, so it rounds to an
//! `f32` above `t_max` (or to one at most `-0`) and that test rejects the lane as well. Nothing
//! else changes: lanes in range, and lanes whose range is uncertain, go on as before. Below the
//! normal range a product errs absolutely, by up to 2^-150: the sums absorb that in `ABS_TINY`,
//! and the product the far limit is scaled by must stay normal (a tiny `t_max` times a huge
//! direction would multiply its rounding). Overflow and NaN make every comparison false, which
//! keeps the lane.

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
/// The far limit's absolute widening, for a subnormal `t_max`, where [`FAR_MARGIN`] rounds
/// away: four steps of the subnormal spacing 2^-149.
const FAR_SUBNORMAL: f32 = f32::from_bits(4);

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
            far: ray.t_max * FAR_MARGIN + FAR_SUBNORMAL,
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
        // `|D| |dir[kz]|` must not underflow: `t_max` (tiny for a ray with a huge direction)
        // would multiply its absolute rounding; a subnormal limit itself errs by 2^-150 at most.
        let scale = mul(d_hi, _mm_set1_ps(dir_kz.abs()));
        let limit = add(mul(_mm_set1_ps(interval.far), scale), _mm_set1_ps(ABS_TINY));
        let beyond = _mm_and_ps(
            _mm_and_ps(
                _mm_cmpge_ps(scale, _mm_set1_ps(f32::MIN_POSITIVE)),
                _mm_cmpgt_ps(low, _mm_setzero_ps()),
            ),
            _mm_cmpgt_ps(low, limit),
        );
        _mm_movemask_ps(_mm_or_ps(behind, beyond)) as u32
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::super::super::{Group, LANES};
    use super::super::GroupTest;
    use crate::accel::PADDING;
    use crate::geometry::triangle::{WatertightRay, intersect_triangle};
    use crate::math::{Ray, Vec3};
    use crate::rng::SampleRng;

    /// Uniform in [-1, 1).
    fn signed(rng: &mut SampleRng) -> f32 {
        2.0 * rng.next_f32() - 1.0
    }

    fn group(tris: &[[Vec3; 3]; LANES]) -> Group {
        let mut g = Group {
            v: [[f32::NAN; LANES]; 9],
            prim: [PADDING; LANES],
        };
        for (lane, tri) in tris.iter().enumerate() {
            g.prim[lane] = lane as u32;
            for (k, c) in tri.iter().enumerate() {
                for axis in 0..3 {
                    g.v[3 * k + axis][lane] = c[axis];
                }
            }
        }
        g
    }

    /// Whatever the filter rejects, the scalar watertight test rejects too: triangles at scales
    /// 1e-20 to 1e20, rays aimed through one of them with `t_max` within a few ulps either side
    /// of its hit, origins on its plane, behind it and far away. And the filter does reject
    /// (most lines meet the other three triangles' planes out of range).
    #[test]
    fn the_filter_rejects_only_what_the_exact_test_rejects() {
        let mut rng = SampleRng::new(40, 1, 2, 3);
        let (mut rejected, mut kept_at_the_end) = (0u32, 0u32);
        for _ in 0..40_000 {
            let scale = 10f32.powf(signed(&mut rng) * 20.0);
            let centre = Vec3::new(signed(&mut rng), signed(&mut rng), signed(&mut rng)) * scale;
            let corner = |rng: &mut SampleRng| {
                centre + Vec3::new(signed(rng), signed(rng), signed(rng)) * scale
            };
            let tris: [[Vec3; 3]; LANES] =
                std::array::from_fn(|_| [corner(&mut rng), corner(&mut rng), corner(&mut rng)]);
            let g = group(&tris);
            // Aimed at a point inside the first triangle, from near or far.
            let (b0, b1) = (rng.next_f32(), rng.next_f32());
            let (b0, b1) = if b0 + b1 > 1.0 {
                (1.0 - b0, 1.0 - b1)
            } else {
                (b0, b1)
            };
            let [p0, p1, p2] = tris[0];
            let target = p0 + (p1 - p0) * b0 + (p2 - p0) * b1;
            let away = Vec3::new(signed(&mut rng), signed(&mut rng), signed(&mut rng));
            let distance = scale * 10f32.powf(signed(&mut rng) * 3.0);
            let origin = target + away * distance;
            // Directions of any length: `t` from 1e-20 to 1e20 times the distance.
            let length = 10f32.powf(signed(&mut rng) * 20.0);
            let mut ray = Ray::new(origin, (target - origin) * length);
            if ray.dir.length_squared() == 0.0 || !ray.dir.is_finite() {
                continue;
            }
            let wr = WatertightRay::new(ray.dir);
            let hit_t = intersect_triangle(&ray, &wr, p0, p1, p2).map(|h| h.t);
            let ends = match hit_t {
                Some(t) => {
                    let k = (rng.next_f32() * 8.0) as i32 - 4;
                    let near = (0..k.abs())
                        .fold(t, |t, _| if k > 0 { t.next_up() } else { t.next_down() });
                    [near, t * (1.0 + 1e-6), t * (1.0 - 1e-6), f32::INFINITY]
                }
                None => [1.0, f32::INFINITY, scale, scale * 1e-3],
            };
            for (i, t_max) in ends.into_iter().enumerate() {
                // Some rays start on the first triangle's plane, hits at t ~ 0 either side.
                if i == 3 && rng.next_f32() < 0.3 {
                    ray.origin = target;
                }
                ray.t_max = t_max;
                let wr = WatertightRay::new(ray.dir);
                let test = GroupTest::new(&ray, &wr);
                let plain = test.decide(&g, (1 << LANES) - 1);
                let filtered = test.decide_in_range(&g, (1 << LANES) - 1, &ray);
                assert_eq!(
                    plain.scalar, filtered.scalar,
                    "the filter only drops line hits"
                );
                assert_eq!(filtered.line_hits & !plain.line_hits, 0);
                for (lane, [a, b, c]) in tris.iter().enumerate() {
                    let bit = 1 << lane;
                    if plain.line_hits & bit == 0 {
                        continue;
                    }
                    let exact = intersect_triangle(&ray, &wr, *a, *b, *c);
                    if filtered.line_hits & bit == 0 {
                        rejected += 1;
                        assert!(
                            exact.is_none(),
                            "lane {lane} of {tris:?} rejected, but {ray:?} hits it: {exact:?}"
                        );
                    } else if lane == 0 && exact.is_some() && t_max.is_finite() {
                        kept_at_the_end += 1;
                    }
                }
            }
        }
        assert!(rejected > 20_000, "only {rejected} lanes rejected");
        assert!(
            kept_at_the_end > 20_000,
            "only {kept_at_the_end} hits at t_max"
        );
    }
}

//! The watertight test's decisions for the four triangles of a packed group at once, in SSE.
//!
//! Every value is the one [`intersect_triangle`] computes for that lane: the same differences,
//! products and sums in the same order (no fused multiply-add), the edge bounds of
//! [`edge_bound`] operation for operation, the same comparisons. So each lane is either
//! decided here exactly as the scalar test would decide it (rejected by certain edge signs, or
//! a hit on the triangle's line with final `u`, `v`, only its distance left), or handed to the
//! scalar test whole (an edge within its rounding bound, a determinant out of range, or a lane
//! that holds no triangle).
//!
//! [`intersect_triangle`]: crate::geometry::triangle::intersect_triangle
//! [`edge_bound`]: crate::geometry::edge_bound::edge_bound

mod range;

use super::{Group, LANES};
use crate::geometry::edge_bound::{ABS_TINY, G, G2, GG, TINY};
use crate::geometry::triangle::WatertightRay;
use crate::math::Ray;

/// What the SIMD pass decided for the lanes of one group.
#[derive(Clone, Copy)]
pub(super) struct Decided {
    /// Lanes whose three edge functions lie outside their bounds, agree in sign and sum to a
    /// normal determinant: `u`, `v` are final; the distance remains to be computed.
    pub(super) line_hits: u32,
    /// Lanes the scalar test must decide itself.
    pub(super) scalar: u32,
    pub(super) u: [f32; LANES],
    pub(super) v: [f32; LANES],
}

impl Decided {
    /// Every lane to the scalar test (groups without triangles).
    const ALL_SCALAR: Self = Self {
        line_hits: 0,
        scalar: (1 << LANES) - 1,
        u: [0.0; LANES],
        v: [0.0; LANES],
    };
}

/// Per-ray constants of the pass, broadcast from the ray's shear.
#[derive(Clone, Copy)]
pub(super) struct GroupTest {
    /// The origin's coordinates along the shear's axes `k`.
    origin_k: [f32; 3],
    /// The widened shear ratios (`WatertightRay::w`).
    weight: [f32; 2],
    k: [usize; 3],
    sx: f32,
    sy: f32,
    /// The direction's component along the shear's major axis `k[2]`.
    dir_kz: f32,
}

impl GroupTest {
    #[inline(always)]
    pub(super) fn new(ray: &Ray, wr: &WatertightRay) -> Self {
        Self {
            origin_k: {
                let o = ray.origin.to_array();
                [o[wr.kx], o[wr.ky], o[wr.kz]]
            },
            weight: wr.w,
            k: [wr.kx, wr.ky, wr.kz],
            sx: wr.sx,
            sy: wr.sy,
            dir_kz: ray.dir.to_array()[wr.kz],
        }
    }

    /// The decisions for group `g`, lanes outside `valid` left undecided (neither set).
    #[inline(always)]
    pub(super) fn decide(&self, g: &Group, valid: u32) -> Decided {
        self.decide_within(g, valid, None)
    }

    /// [`Self::decide`], and a line hit whose distance certainly rounds outside `ray`'s
    /// interval is rejected here ([`range`]), without its corners and the `f64` plane distance.
    #[inline(always)]
    pub(super) fn decide_in_range(&self, g: &Group, valid: u32, ray: &Ray) -> Decided {
        self.decide_within(g, valid, Some(range::Interval::of(ray)))
    }

    #[inline(always)]
    fn decide_within(&self, g: &Group, valid: u32, interval: Option<range::Interval>) -> Decided {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: SSE is part of the x86-64 baseline.
            let mut d = unsafe { self.decide_sse(g, interval) };
            d.line_hits &= valid;
            d.scalar &= valid;
            d
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (g, interval);
            Decided {
                scalar: valid,
                ..Decided::ALL_SCALAR
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn decide_sse(&self, g: &Group, interval: Option<range::Interval>) -> Decided {
        use std::arch::x86_64::*;
        // SAFETY (whole body): each row is 4 contiguous f32; SSE is baseline on x86-64.
        unsafe {
            let row = |i: usize| _mm_loadu_ps(g.v[i].as_ptr());
            // A group without triangles (spheres, padding) goes to the scalar test whole.
            let first = row(0);
            if _mm_movemask_ps(_mm_cmpord_ps(first, first)) == 0 {
                return Decided::ALL_SCALAR;
            }
            let (sx, sy) = (_mm_set1_ps(self.sx), _mm_set1_ps(self.sy));
            // Written out: `[f32; N]::map` went through a call to `array::try_map` that was
            // not inlined (~60 instructions per group, callgrind).
            let [ox, oy, oz] = self.origin_k;
            let (ox, oy, oz) = (_mm_set1_ps(ox), _mm_set1_ps(oy), _mm_set1_ps(oz));
            let w = [_mm_set1_ps(self.weight[0]), _mm_set1_ps(self.weight[1])];
            let abs = |x: __m128| _mm_andnot_ps(_mm_set1_ps(-0.0), x);
            let (add, mul) = (|a, b| _mm_add_ps(a, b), |a, b| _mm_mul_ps(a, b));
            let tiny = _mm_set1_ps(TINY);
            let [kx, ky, kz] = self.k;
            // Vertex `k` relative to the origin, sheared, and its magnitudes (`magnitudes`).
            // The rows are read in shear order: indexing an array of the three offsets by the
            // axes kept them in memory (~40 instructions per group, callgrind).
            let vertex = |k: usize| {
                let dx = _mm_sub_ps(row(3 * k + kx), ox);
                let dy = _mm_sub_ps(row(3 * k + ky), oy);
                let dz = _mm_sub_ps(row(3 * k + kz), oz);
                let z = abs(dz);
                let mx = add(add(abs(dx), mul(w[0], z)), tiny);
                let my = add(add(abs(dy), mul(w[1], z)), tiny);
                let sheared_x = _mm_sub_ps(dx, mul(sx, dz));
                let sheared_y = _mm_sub_ps(dy, mul(sy, dz));
                (sheared_x, sheared_y, (mx, my), dz)
            };
            let (ax, ay, ma, dz_a) = vertex(0);
            let (bx, by, mb, dz_b) = vertex(1);
            let (cx, cy, mc, dz_c) = vertex(2);
            let (g2, g, gg, abs_tiny) = (
                _mm_set1_ps(G2),
                _mm_set1_ps(G),
                _mm_set1_ps(GG),
                _mm_set1_ps(ABS_TINY),
            );
            // `e = px qy - py qx`, and whether it lies outside `edge_bound` (false for NaN):
            // then its sign is certain.
            let edge =
                |(px, py, (mxp, myp)): (__m128, __m128, (__m128, __m128)),
                 (qx, qy, (mxq, myq)): (__m128, __m128, (__m128, __m128))| {
                    let (pq, qp) = (mul(px, qy), mul(py, qx));
                    let e = _mm_sub_ps(pq, qp);
                    let own = mul(g2, add(abs(pq), abs(qp)));
                    let inputs = mul(
                        g,
                        add(
                            add(mul(abs(px), myq), mul(abs(qy), mxp)),
                            add(mul(abs(py), mxq), mul(abs(qx), myp)),
                        ),
                    );
                    let cross = mul(gg, add(mul(mxp, myq), mul(mxq, myp)));
                    let bound = add(add(add(own, inputs), cross), abs_tiny);
                    (e, _mm_cmpgt_ps(abs(e), bound), bound)
                };
            let (e0, k0, b0) = edge((cx, cy, mc), (bx, by, mb));
            let (e1, k1, b1) = edge((ax, ay, ma), (cx, cy, mc));
            let (e2, k2, b2) = edge((bx, by, mb), (ax, ay, ma));
            let zero = _mm_setzero_ps();
            let neg = _mm_or_ps(
                _mm_or_ps(
                    _mm_and_ps(k0, _mm_cmplt_ps(e0, zero)),
                    _mm_and_ps(k1, _mm_cmplt_ps(e1, zero)),
                ),
                _mm_and_ps(k2, _mm_cmplt_ps(e2, zero)),
            );
            let pos = _mm_or_ps(
                _mm_or_ps(
                    _mm_and_ps(k0, _mm_cmpgt_ps(e0, zero)),
                    _mm_and_ps(k1, _mm_cmpgt_ps(e1, zero)),
                ),
                _mm_and_ps(k2, _mm_cmpgt_ps(e2, zero)),
            );
            // Two certain signs that disagree: the scalar test rejects the lane too, refined or
            // not (refinement keeps the certain edges' values).
            let rejected = _mm_movemask_ps(_mm_and_ps(neg, pos)) as u32;
            let all_known = _mm_movemask_ps(_mm_and_ps(_mm_and_ps(k0, k1), k2)) as u32;
            if all_known & !rejected == 0 {
                return Decided {
                    line_hits: 0,
                    scalar: !rejected & ((1 << LANES) - 1),
                    u: [0.0; LANES],
                    v: [0.0; LANES],
                };
            }
            let det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
            let det_abs = abs(det);
            let normal_det = _mm_and_ps(
                _mm_cmpge_ps(det_abs, _mm_set1_ps(f32::MIN_POSITIVE)),
                _mm_cmplt_ps(det_abs, _mm_set1_ps(f32::INFINITY)),
            );
            let inv_det = _mm_div_ps(_mm_set1_ps(1.0), det);
            let mut line_hits = all_known & !rejected & _mm_movemask_ps(normal_det) as u32;
            // Lines hit outside the interval are rejected: neither finished nor scalar.
            let mut outside = 0;
            if let Some(interval) = interval
                && line_hits != 0
            {
                // Only line hits: the other lanes' values (an uncertain edge, a determinant out
                // of range) prove nothing, and those lanes go to the scalar test.
                // SAFETY: SSE is part of the x86-64 baseline.
                outside = line_hits
                    & range::outside(
                        interval,
                        [e0, e1, e2],
                        [b0, b1, b2],
                        [dz_a, dz_b, dz_c],
                        det,
                        self.dir_kz,
                    );
                line_hits &= !outside;
            }
            let mut d = Decided {
                line_hits,
                scalar: !rejected & !line_hits & !outside & ((1 << LANES) - 1),
                u: [0.0; LANES],
                v: [0.0; LANES],
            };
            _mm_storeu_ps(d.u.as_mut_ptr(), _mm_mul_ps(e1, inv_det));
            _mm_storeu_ps(d.v.as_mut_ptr(), _mm_mul_ps(e2, inv_det));
            d
        }
    }
}

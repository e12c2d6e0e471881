//! Triangles copied into the wide hierarchy's leaf order, four to a group, one SSE register
//! per vertex coordinate, so a leaf's triangles are tested without chasing mesh indices.
//!
//! A group is first run through a SIMD filter that computes the watertight test's three edge
//! functions exactly as [`intersect_triangle`] does (the same differences and products in the
//! same order, no fused multiply-add), and rejects a lane only when two of them that lie
//! clearly outside their rounding bound have opposite signs. `intersect_triangle` rejects such
//! a lane too: it refines only edges within the bound, and keeps the others as computed. Every
//! lane the filter keeps goes through `intersect_triangle` itself, so the answers are exactly
//! those of the per-primitive path, bit for bit.

use super::leaves::{AnyLeaves, ClosestLeaves};
use super::{Closest, LEAF_ALIGN, PADDING, TraversalStats};
use crate::geometry::triangle::{PRODUCT_UNDERFLOW, UNDERFLOW, WatertightRay, intersect_triangle};
use crate::geometry::{Geometry, Primitive};
use crate::math::{Ray, Vec3};

/// Lanes per group: the wide hierarchy aligns its leaves to this.
const LANES: usize = LEAF_ALIGN;

/// The filter's margin on the edge functions' error bound: its own sums of the per-vertex
/// magnitudes round in another order than the scalar test's, by a few ulps at most.
const BOUND_MARGIN: f32 = 1.0 + 1.0 / 256.0;

/// Four triangles: `v[3 * k + axis][lane]` is coordinate `axis` of vertex `k`. Lanes that hold
/// no triangle (a sphere, or padding) are NaN, which the filter never rejects.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct Group {
    v: [[f32; LANES]; 9],
    /// The primitive of each lane, so a candidate needs no look-up in `prim_order`.
    prim: [u32; LANES],
}

/// A scene's triangles in the order of one hierarchy's `prim_order`.
#[derive(Clone, Debug)]
pub struct PackedLeaves {
    groups: Vec<Group>,
}

impl PackedLeaves {
    /// Packs the triangles of `geometry` in the order `prim_order` (whose leaves start at
    /// multiples of [`LEAF_ALIGN`] and whose length is one too).
    pub fn new(geometry: &Geometry, prim_order: &[u32]) -> Self {
        let groups = prim_order
            .chunks(LANES)
            .map(|chunk| {
                let mut g = Group {
                    v: [[f32::NAN; LANES]; 9],
                    prim: [PADDING; LANES],
                };
                for (lane, &p) in chunk.iter().enumerate() {
                    g.prim[lane] = p;
                    if p == PADDING {
                        continue;
                    }
                    if let Primitive::Triangle { mesh, tri } = geometry.prims()[p as usize] {
                        let corners = geometry.meshes()[mesh as usize].corners(tri);
                        for (k, c) in corners.iter().enumerate() {
                            for axis in 0..3 {
                                g.v[3 * k + axis][lane] = c[axis];
                            }
                        }
                    }
                }
                g
            })
            .collect();
        Self { groups }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.groups.as_slice())
    }
}

/// The watertight test over packed leaves, for one ray.
pub(crate) struct PackedWatertight<'a> {
    packed: &'a PackedLeaves,
    geometry: &'a Geometry,
    wr: WatertightRay,
    /// Rows of [`Group::v`] for `(a, b, c)` in shear order `(kx, ky, kz)`.
    rows: [usize; 9],
    origin: [f32; 3],
    weight: [f32; 3],
}

impl<'a> PackedWatertight<'a> {
    /// The test for `ray` over `packed`, built from `geometry` (which holds the spheres).
    #[inline(always)]
    pub(crate) fn new(packed: &'a PackedLeaves, geometry: &'a Geometry, ray: &Ray) -> Self {
        let wr = WatertightRay::new(ray.dir);
        let k = [wr.kx, wr.ky, wr.kz];
        Self {
            packed,
            geometry,
            rows: std::array::from_fn(|i| 3 * (i / 3) + k[i % 3]),
            origin: k.map(|a| ray.origin.to_array()[a]),
            weight: k.map(|a| wr.err_w.to_array()[a]),
            wr,
        }
    }

    /// Lanes of group `g` the exact test may accept.
    #[inline(always)]
    fn candidates(&self, g: usize) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: SSE is part of the x86-64 baseline.
            unsafe { self.candidates_sse(&self.packed.groups[g]) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = g;
            (1 << LANES) - 1
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn candidates_sse(&self, g: &Group) -> u32 {
        use std::arch::x86_64::*;
        // SAFETY (whole body): each row is 4 contiguous f32; SSE is baseline on x86-64.
        unsafe {
            let row = |i: usize| _mm_loadu_ps(g.v[self.rows[i]].as_ptr());
            // A group without triangles (spheres, padding) keeps every lane: skip the edges.
            let first = _mm_loadu_ps(g.v[0].as_ptr());
            if _mm_movemask_ps(_mm_cmpord_ps(first, first)) == 0 {
                return (1 << LANES) - 1;
            }
            let (sx, sy) = (_mm_set1_ps(self.wr.sx), _mm_set1_ps(self.wr.sy));
            let o = self.origin.map(|x| _mm_set1_ps(x));
            let w = self.weight.map(|x| _mm_set1_ps(x));
            let product_underflow = _mm_set1_ps(PRODUCT_UNDERFLOW);
            let abs = |x: __m128| _mm_andnot_ps(_mm_set1_ps(-0.0), x);
            // One vertex relative to the origin, sheared; and its error magnitude.
            let vertex = |k: usize| {
                let x = _mm_sub_ps(row(3 * k), o[0]);
                let y = _mm_sub_ps(row(3 * k + 1), o[1]);
                let z = _mm_sub_ps(row(3 * k + 2), o[2]);
                let m = _mm_add_ps(
                    _mm_add_ps(
                        _mm_add_ps(_mm_mul_ps(abs(x), w[0]), _mm_mul_ps(abs(y), w[1])),
                        _mm_mul_ps(abs(z), w[2]),
                    ),
                    product_underflow,
                );
                let sheared_x = _mm_sub_ps(x, _mm_mul_ps(sx, z));
                let sheared_y = _mm_sub_ps(y, _mm_mul_ps(sy, z));
                (sheared_x, sheared_y, m)
            };
            let (ax, ay, ma) = vertex(0);
            let (bx, by, mb) = vertex(1);
            let (cx, cy, mc) = vertex(2);
            let edge = |px: __m128, py: __m128, qx: __m128, qy: __m128| {
                _mm_sub_ps(_mm_mul_ps(px, qy), _mm_mul_ps(py, qx))
            };
            let e0 = edge(cx, cy, bx, by);
            let e1 = edge(ax, ay, cx, cy);
            let e2 = edge(bx, by, ax, ay);
            let margin = _mm_set1_ps(BOUND_MARGIN);
            let underflow = _mm_set1_ps(UNDERFLOW);
            let known = |e: __m128, m1: __m128, m2: __m128| {
                let bound = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(m1, m2), margin), underflow);
                _mm_cmpgt_ps(abs(e), bound)
            };
            let zero = _mm_setzero_ps();
            let (k0, k1, k2) = (known(e0, mb, mc), known(e1, mc, ma), known(e2, ma, mb));
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
            !(_mm_movemask_ps(_mm_and_ps(neg, pos)) as u32) & ((1 << LANES) - 1)
        }
    }

    /// The exact test of lane `lane` of group `g`, primitive `prim`.
    #[inline(always)]
    fn exact(
        &self,
        g: usize,
        lane: usize,
        prim: u32,
        ray: &Ray,
    ) -> Option<crate::geometry::PrimHit> {
        let v = &self.packed.groups[g].v;
        if v[0][lane].is_nan() {
            // Not a triangle: the geometry's own test (a sphere).
            return self.geometry.intersect(prim, ray, &self.wr);
        }
        let p = |k: usize| Vec3::new(v[3 * k][lane], v[3 * k + 1][lane], v[3 * k + 2][lane]);
        // A triangle that passes the exact test must pass its mesh's alpha test too, as in
        // `Geometry::intersect`.
        // Written out, not `Option::filter`: across the crate split rustc stopped inlining that
        // generic call here (+88 M instructions on tumbledStones, callgrind).
        let h = intersect_triangle(ray, &self.wr, p(0), p(1), p(2))?;
        if self.geometry.alpha_passes(prim, h.u, h.v) {
            Some(h.into())
        } else {
            None
        }
    }

    /// Calls `f(group, lane, prim)` for each lane of the leaf the filter keeps, until it says stop.
    #[inline(always)]
    fn each_candidate(
        &self,
        first: u32,
        prims: &[u32],
        mut f: impl FnMut(usize, usize, u32) -> bool,
    ) {
        let g0 = first as usize / LANES;
        let mut left = prims.len();
        let mut g = g0;
        while left > 0 {
            let lanes = left.min(LANES);
            let mut mask = self.candidates(g) & ((1 << lanes) - 1);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if f(g, lane, self.packed.groups[g].prim[lane]) {
                    return;
                }
            }
            left -= lanes;
            g += 1;
        }
    }
}

impl ClosestLeaves for PackedWatertight<'_> {
    #[inline(always)]
    fn closest(
        &mut self,
        first: u32,
        prims: &[u32],
        closest: &mut Closest,
        stats: &mut TraversalStats,
    ) {
        stats.prim_tests += prims.len() as u64;
        self.each_candidate(first, prims, |g, lane, prim| {
            if let Some(h) = self.exact(g, lane, prim, &closest.ray) {
                closest.offer(prim, h);
            }
            false
        });
    }
}

impl AnyLeaves for PackedWatertight<'_> {
    #[inline(always)]
    fn any(&mut self, first: u32, prims: &[u32], ray: &Ray, stats: &mut TraversalStats) -> bool {
        stats.prim_tests += prims.len() as u64;
        let mut blocked = false;
        self.each_candidate(first, prims, |g, lane, prim| {
            blocked = self.exact(g, lane, prim, ray).is_some();
            blocked
        });
        blocked
    }
}

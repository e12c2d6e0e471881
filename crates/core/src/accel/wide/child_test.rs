//! Testing all children of a wide node against one ray.
//!
//! The SIMD tests compute, lane by lane, exactly what [`crate::math::Aabb::hit_range_with`]
//! computes for a ray with finite, non-zero reciprocal components: `(plane - o) * inv` per
//! axis (a subtraction then a product, no fused multiply-add, so the same roundings), the
//! larger of the entries and `t_min`, the smaller of the exits widened by the same factor and
//! clamped to `t_max`. Choosing the near plane by the sign of the direction (the ray's octant)
//! gives the same value as taking the minimum of both planes, because rounding is monotone.
//! So a lane is culled exactly when the scalar test would cull its box, and the traversal's
//! answers stay those of brute force. Every other ray (a zero or extreme component) goes
//! through [`LaneByLane`], which applies the scalar slab test the ray needs to each lane.

use super::walk::{Entry, Stack, push_entered};
use super::{EMPTY_LANE, WideNode};
use crate::accel::bvh::CullBound;
use crate::math::slab::Slab;
use crate::math::{Aabb, ROBUST_BOX_SCALE, Ray};

/// Decides which children of a node a ray enters within `[t_min, t_max]`.
pub(crate) trait ChildTest<const W: usize>: Copy {
    /// A bit per entered lane, and each lane's conservative entry distance.
    fn test(&self, node: &WideNode<W>, t_min: f32, t_max: f32) -> (u32, [f32; W]);

    /// The culling bound for `ray` in a hierarchy bounded by `root`.
    #[inline(always)]
    fn cull_bound(&self, ray: &Ray, root: &Aabb) -> CullBound {
        CullBound::new(ray, root)
    }

    /// Pushes the entered lanes (`mask`) of `node` farthest first and returns the nearest, to
    /// visit next ([`push_entered`]; tests with faster instructions for it override this).
    #[inline(always)]
    fn push_entered<const N: usize>(
        &self,
        node: &WideNode<W>,
        mask: u32,
        near: &[f32; W],
        stack: &mut Stack<N>,
    ) -> Option<Entry> {
        push_entered(node, mask, near, stack)
    }
}

/// Any slab test, one lane at a time: the path for rays the SIMD tests do not cover, and for
/// CPUs without them.
#[derive(Clone, Copy)]
pub(crate) struct LaneByLane<S: Slab>(pub S);

impl<const W: usize, S: Slab> ChildTest<W> for LaneByLane<S> {
    #[inline(always)]
    fn test(&self, node: &WideNode<W>, t_min: f32, t_max: f32) -> (u32, [f32; W]) {
        let mut mask = 0;
        let mut near = [f32::INFINITY; W];
        for (lane, near) in near.iter_mut().enumerate() {
            if node.count[lane] == EMPTY_LANE {
                continue;
            }
            if let Some((n, _)) = self.0.range(&node.bounds(lane), t_min, t_max) {
                *near = n;
                mask |= 1 << lane;
            }
        }
        (mask, near)
    }
}

/// Per-ray constants of the SIMD tests: origin, reciprocal direction, and for each axis
/// the plane the ray enters by and the one it leaves by.
#[derive(Clone, Copy)]
pub(crate) struct Octant {
    pub(super) origin: [f32; 3],
    pub(super) inv: [f32; 3],
    /// Byte offsets into [`WideNode::planes`] of the entry and exit plane rows of x, y, z (an
    /// offset each, ready to add to the node's address: the batch walk reloads them at every
    /// node, where a plane index cost a bounds check or a shift and a flip per axis).
    /// Invariant: each is `32 * row` for a row below 6.
    pub(super) row_bytes: [u32; 6],
}

impl Octant {
    /// For a ray whose reciprocal direction `inv` is finite and non-zero in every component.
    #[inline(always)]
    pub(crate) fn new(ray: &Ray, inv: [f32; 3]) -> Self {
        let row_bytes = |k: usize| {
            let (axis, exit) = (k / 2, k % 2 == 1);
            let enters_by_max = inv[axis] < 0.0;
            let row = 2 * axis + (enters_by_max != exit) as usize;
            (row * size_of::<[f32; 8]>()) as u32
        };
        Self {
            origin: ray.origin.to_array(),
            inv,
            // Written out: `array::from_fn` was a call per element here (~17 instructions
            // each, callgrind).
            row_bytes: [
                row_bytes(0),
                row_bytes(1),
                row_bytes(2),
                row_bytes(3),
                row_bytes(4),
                row_bytes(5),
            ],
        }
    }
}

/// The 8-lane test in AVX2 registers. Only constructed once the CPU is known to have AVX2
/// ([`super::SimdPath::Avx2`] or wider).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub(crate) struct Avx2(pub Octant);

#[cfg(target_arch = "x86_64")]
impl ChildTest<8> for Avx2 {
    #[inline(always)]
    fn cull_bound(&self, ray: &Ray, root: &Aabb) -> CullBound {
        CullBound::with_inverse(ray, root, self.0.inv)
    }

    #[inline(always)]
    fn test(&self, node: &WideNode<8>, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
        // SAFETY: `Avx2` values exist only where AVX2 was detected at run time.
        unsafe { avx2_test(&self.0, node, t_min, t_max) }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn avx2_test(o: &Octant, node: &WideNode<8>, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
    use std::arch::x86_64::*;
    let p = node.planes.as_ptr().cast::<u8>();
    // SAFETY: every offset is that of a row of 8 f32 inside `planes` (the `Octant` invariant).
    let load = |k: usize| unsafe { _mm256_loadu_ps(p.add(o.row_bytes[k] as usize).cast()) };
    let axis = |a: usize| {
        let (org, inv) = (_mm256_set1_ps(o.origin[a]), _mm256_set1_ps(o.inv[a]));
        let near = _mm256_mul_ps(_mm256_sub_ps(load(2 * a), org), inv);
        let far = _mm256_mul_ps(_mm256_sub_ps(load(2 * a + 1), org), inv);
        (near, far)
    };
    entered([axis(0), axis(1), axis(2)], t_min, t_max)
}

/// The lanes entered, from each axis's entry and exit distances (`(near, far)` per axis): the
/// larger of the entries and `t_min` against the smaller of the exits, widened and clamped to
/// `t_max` as the scalar test does; with each lane's entry. Shared by the one-ray test and the
/// packet's (`super::packet`), whose distances bound its rays'.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
pub(super) fn entered(
    axes: [(std::arch::x86_64::__m256, std::arch::x86_64::__m256); 3],
    t_min: f32,
    t_max: f32,
) -> (u32, [f32; 8]) {
    use std::arch::x86_64::*;
    let [(nx, fx), (ny, fy), (nz, fz)] = axes;
    let near = _mm256_max_ps(
        _mm256_max_ps(nx, ny),
        _mm256_max_ps(nz, _mm256_set1_ps(t_min)),
    );
    let far = _mm256_min_ps(_mm256_min_ps(fx, fy), fz);
    let widened = _mm256_max_ps(far, _mm256_mul_ps(far, _mm256_set1_ps(ROBUST_BOX_SCALE)));
    let far = _mm256_min_ps(widened, _mm256_set1_ps(t_max));
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(near, far)) as u32;
    let mut out = [0.0f32; 8];
    // SAFETY: `out` holds 8 f32.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), near) };
    (mask, out)
}

//! Nearest hits of a packet of up to [`PACKET`] rays from one origin, walked together: the
//! samples of one pixel from a pinhole camera. One SIMD test per node decides for the whole
//! packet, on the bounds of its rays' reciprocal directions (an interval per axis); each ray
//! then tests the leaves the packet reaches with its own leaf tester.
//!
//! Why the answers stay exact: for one origin, a child box's entry distance on each axis,
//! `(plane - o) * inv` rounded as the single-ray test rounds it ([`super::child_test`]), is
//! monotone in `inv`, so its smallest value over the packet is the one at an end of the
//! interval; likewise the largest exit. The packet enters a box whenever any of its rays' own
//! tests would, so every ray reaches (at least) every leaf its single walk reaches, and extra
//! leaves only offer primitives that brute force tests too. Nearest hits do not depend on the
//! order primitives are offered in ([`crate::accel::Closest`]), so each ray's answer is bit for
//! bit its single walk's. Rays the interval cannot describe (another origin, a direction sign
//! differing within the packet, a zero or extreme component) are refused: the caller walks
//! them one at a time.

use super::walk::{Entry, STACK, Stack, prefetch_children, push_entered};
use super::{SimdPath, WideBvh};
use crate::accel::bvh::CullBound;
use crate::accel::leaves::ClosestLeaves;
use crate::accel::{Closest, Hit, TraversalStats};
use crate::math::slab::SlabKind;
use crate::math::{Ray, Vec3A, safe_inverse};

/// Rays per packet: one AVX2 register of lanes.
pub const PACKET: usize = 8;

/// What the packet's node test needs: the shared origin, per axis the interval of the rays'
/// reciprocal directions (one sign) and the plane the rays enter by, and the loosest of the
/// rays' culling bounds below.
#[derive(Clone, Copy)]
struct Frustum {
    origin: [f32; 3],
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
    near_plane: [usize; 3],
    t_min: f32,
}

impl Frustum {
    /// The packet's constants from its rays and their reciprocal directions `invs`, or `None`
    /// when the rays cannot share a walk (see the module), found before any other set-up;
    /// `t_min` is filled in by the caller from the rays' culling bounds.
    fn new(rays: &[Ray], invs: &[Vec3A]) -> Option<Self> {
        let first = rays.first()?;
        let origin = first.origin.to_array().map(f32::to_bits);
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for (ray, &inv) in rays.iter().zip(invs) {
            // Lens rays (depth of field) have an origin each.
            if ray.origin.to_array().map(f32::to_bits) != origin
                || SlabKind::with_inverse(ray, inv) != SlabKind::Finite
            {
                return None;
            }
            for a in 0..3 {
                lo[a] = lo[a].min(inv[a]);
                hi[a] = hi[a].max(inv[a]);
            }
        }
        // One sign per axis: the interval must not hold zero (and the near plane is shared).
        if (0..3).any(|a| (lo[a] < 0.0) != (hi[a] < 0.0)) {
            return None;
        }
        let plane = |a: usize| if lo[a] >= 0.0 { 0 } else { 1 };
        Some(Self {
            origin: first.origin.to_array(),
            inv_lo: lo,
            inv_hi: hi,
            near_plane: [plane(0), 2 + plane(1), 4 + plane(2)],
            t_min: f32::INFINITY,
        })
    }
}

impl WideBvh<8> {
    /// The nearest hit of each of `rays` (at most [`PACKET`]) into `out`, each ray's leaves
    /// tested by its own tester in `testers`; `false` (nothing written) when the packet cannot
    /// be walked together and the rays must go one at a time.
    pub(crate) fn intersect_packet<L: ClosestLeaves>(
        &self,
        rays: &[Ray],
        stats: &mut TraversalStats,
        testers: &mut [L],
        out: &mut [Option<Hit>],
    ) -> bool {
        debug_assert!(rays.len() <= PACKET && testers.len() >= rays.len());
        if self.nodes.is_empty() || rays.len() < 2 {
            return false;
        }
        match SimdPath::active() {
            // SAFETY: the CPU has what each path needs (`SimdPath::active`).
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => unsafe { self.packet_avx512(rays, stats, testers, out) },
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => unsafe { self.packet_avx2(rays, stats, testers, out) },
            _ => false,
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn packet_avx2<L: ClosestLeaves>(
        &self,
        rays: &[Ray],
        stats: &mut TraversalStats,
        testers: &mut [L],
        out: &mut [Option<Hit>],
    ) -> bool {
        // SAFETY: AVX2 and the bit instructions are present (this function's features).
        unsafe { self.packet_simd::<false, L>(rays, stats, testers, out) }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
    unsafe fn packet_avx512<L: ClosestLeaves>(
        &self,
        rays: &[Ray],
        stats: &mut TraversalStats,
        testers: &mut [L],
        out: &mut [Option<Hit>],
    ) -> bool {
        // SAFETY: AVX2, the bit instructions and AVX-512 F/VL are present (as above).
        unsafe { self.packet_simd::<true, L>(rays, stats, testers, out) }
    }

    /// The packet walk, with the AVX-512 node test and child ordering when `AVX512`.
    ///
    /// # Safety
    /// The CPU has AVX2 and the bit instructions, and AVX-512 F/VL when `AVX512`.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn packet_simd<const AVX512: bool, L: ClosestLeaves>(
        &self,
        rays: &[Ray],
        stats: &mut TraversalStats,
        testers: &mut [L],
        out: &mut [Option<Hit>],
    ) -> bool {
        let n = rays.len();
        let invs: [Vec3A; PACKET] = std::array::from_fn(|i| safe_inverse(rays[i.min(n - 1)].dir));
        let Some(mut frustum) = Frustum::new(rays, &invs[..n]) else {
            return false;
        };
        let culls: [CullBound; PACKET] = std::array::from_fn(|i| {
            CullBound::with_inverse(&rays[i.min(n - 1)], &self.bounds, invs[i].to_array())
        });
        for (ray, cull) in rays.iter().zip(&culls) {
            frustum.t_min = frustum.t_min.min(cull.lower(ray.t_min));
        }
        let mut closest: [Closest; PACKET] =
            std::array::from_fn(|i| Closest::new(&rays[i.min(n - 1)]));
        // The loosest of the rays' culling bounds: a box beyond it is beyond every ray's.
        let bound = |closest: &[Closest]| {
            closest[..n]
                .iter()
                .zip(&culls)
                .fold(f32::NEG_INFINITY, |m, (c, cull)| {
                    m.max(cull.widen(c.ray.t_max))
                })
        };
        let mut t_max = bound(&closest);
        let mut stack = Stack::<STACK>::new();
        let mut current = Entry {
            child: 0,
            count: 0,
            near: frustum.t_min,
        };
        loop {
            if current.count == 0 {
                let node = &self.nodes[current.child as usize];
                stats.nodes_visited += 1;
                // SAFETY: the CPU has what the path needs (the caller's promise).
                let next = unsafe {
                    if AVX512 {
                        let (mask, near) = frustum_test::<true>(&frustum, node, t_max);
                        prefetch_children(&self.nodes, node, mask, &testers[0]);
                        super::avx512::push_ranked(node, mask, &near, &mut stack)
                    } else {
                        let (mask, near) = frustum_test::<false>(&frustum, node, t_max);
                        prefetch_children(&self.nodes, node, mask, &testers[0]);
                        push_entered(node, mask, &near, &mut stack)
                    }
                };
                if let Some(next) = next {
                    current = next;
                    continue;
                }
            } else {
                let first = current.child as usize;
                if let Some(prims) = self.prim_order.get(first..first + current.count as usize) {
                    for i in 0..n {
                        // Only rays that may still hit something in the leaf test it.
                        if current.near <= culls[i].widen(closest[i].ray.t_max) {
                            testers[i].closest(current.child, prims, &mut closest[i], stats);
                        }
                    }
                    t_max = bound(&closest);
                }
            }
            loop {
                let Some(e) = stack.pop() else {
                    for (o, c) in out.iter_mut().zip(&closest[..n]) {
                        *o = c.best;
                    }
                    return true;
                };
                if e.near <= t_max {
                    current = e;
                    break;
                }
            }
        }
    }
}

/// The packet's test of all children of `node`: a lane is entered when the smallest entry of
/// any ray (per axis, at an end of the reciprocal interval) is below the largest exit, widened
/// and clamped as the single-ray test widens and clamps (to the loosest bound, `t_max`);
/// the lanes from an AVX-512 mask compare when `AVX512`.
///
/// # Safety
/// The CPU has AVX2 and the bit instructions, and AVX-512 F/VL when `AVX512`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn frustum_test<const AVX512: bool>(
    f: &Frustum,
    node: &super::WideNode<8>,
    t_max: f32,
) -> (u32, [f32; 8]) {
    // SAFETY: the caller's promise.
    unsafe {
        let axes = frustum_axes(f, node);
        if AVX512 {
            super::avx512::entered(axes, f.t_min, t_max)
        } else {
            super::child_test::entered(axes, f.t_min, t_max)
        }
    }
}

/// Per axis, the smallest entry and largest exit of the packet's rays into each lane's box.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn frustum_axes(
    f: &Frustum,
    node: &super::WideNode<8>,
) -> [(std::arch::x86_64::__m256, std::arch::x86_64::__m256); 3] {
    use std::arch::x86_64::*;
    let p = &node.planes;
    // SAFETY: each plane row is 8 contiguous f32 (unaligned loads).
    let load = |i: usize| unsafe { _mm256_loadu_ps(p[i].as_ptr()) };
    let axis = |a: usize| {
        let org = _mm256_set1_ps(f.origin[a]);
        let (lo, hi) = (_mm256_set1_ps(f.inv_lo[a]), _mm256_set1_ps(f.inv_hi[a]));
        // The same subtraction as every ray's test, then both ends of the interval.
        let d_near = _mm256_sub_ps(load(f.near_plane[a]), org);
        let d_far = _mm256_sub_ps(load(f.near_plane[a] ^ 1), org);
        let near = _mm256_min_ps(_mm256_mul_ps(d_near, lo), _mm256_mul_ps(d_near, hi));
        let far = _mm256_max_ps(_mm256_mul_ps(d_far, lo), _mm256_mul_ps(d_far, hi));
        (near, far)
    };
    [axis(0), axis(1), axis(2)]
}

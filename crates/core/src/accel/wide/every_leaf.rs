//! The walk of the all-hits query: every leaf whose box the ray's whole interval enters,
//! breadth first.
//!
//! Nothing a leaf answers changes which boxes are entered (the interval never shrinks), so the
//! order is free. Depth first, as the any-hit walk goes, the child just pushed is popped at
//! once and its node or leaf data, prefetched a moment before, is waited for; breadth first,
//! the rest of the level is walked meanwhile, so the prefetches land (the loads of nodes and
//! leaf groups were a third of the all-hits walk's time, perf, 69k bunny).

use super::child_test::{ChildTest, LaneByLane, Octant};
use super::walk::prefetch_children;
use super::{SimdPath, WideBvh};
use crate::accel::TraversalStats;
use crate::accel::leaves::AnyLeaves;
use crate::math::slab::{SlabF32, SlabF64, SlabKind};
use crate::math::{Ray, safe_inverse};

/// The queue of [`WideBvh::each_leaf`]: children still to visit, as `(child, count)` of
/// [`super::WideNode`]. Kept from ray to ray by the caller.
#[derive(Clone, Debug, Default)]
pub(crate) struct LevelQueue(Vec<(u32, u32)>);

impl WideBvh<8> {
    /// Calls `leaves.any` (whose answer is ignored) on every leaf whose box `ray`'s interval
    /// `(t_min, t_max]` enters, with the same conservative box tests as every other walk.
    #[inline(always)]
    pub(crate) fn each_leaf<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
        queue: &mut LevelQueue,
    ) {
        match SimdPath::active() {
            // SAFETY: the CPU has what each path needs (`SimdPath::active`).
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => return unsafe { self.each_leaf_avx512(ray, stats, leaves, queue) },
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => return unsafe { self.each_leaf_avx2(ray, stats, leaves, queue) },
            _ => {}
        }
        let inv = safe_inverse(ray.dir);
        match SlabKind::with_inverse(ray, inv) {
            SlabKind::Finite => {
                let test = LaneByLane(SlabF32::<false>::with_inverse(ray, inv));
                self.each_leaf_with(test, ray, stats, leaves, queue)
            }
            SlabKind::AxisParallel => {
                let test = LaneByLane(SlabF32::<true>::with_inverse(ray, inv));
                self.each_leaf_with(test, ray, stats, leaves, queue)
            }
            SlabKind::Wide => {
                self.each_leaf_with(LaneByLane(SlabF64::for_ray(ray)), ray, stats, leaves, queue)
            }
        }
    }

    /// The whole walk compiled for AVX2, so the node test and the leaf test inline into it.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn each_leaf_avx2<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
        queue: &mut LevelQueue,
    ) {
        self.each_leaf_simd(super::child_test::Avx2, ray, stats, leaves, queue)
    }

    /// The whole walk compiled for AVX-512.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
    unsafe fn each_leaf_avx512<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
        queue: &mut LevelQueue,
    ) {
        self.each_leaf_simd(super::avx512::Avx512, ray, stats, leaves, queue)
    }

    /// The walk with the SIMD child test `simd` makes for ordinary rays.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn each_leaf_simd<T: ChildTest<8>, L: AnyLeaves>(
        &self,
        simd: impl Fn(Octant) -> T,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
        queue: &mut LevelQueue,
    ) {
        let inv = safe_inverse(ray.dir);
        match SlabKind::with_inverse(ray, inv) {
            SlabKind::Finite => {
                let test = simd(Octant::new(ray, inv.to_array()));
                self.each_leaf_with(test, ray, stats, leaves, queue)
            }
            SlabKind::AxisParallel => {
                let test = LaneByLane(SlabF32::<true>::with_inverse(ray, inv));
                self.each_leaf_with(test, ray, stats, leaves, queue)
            }
            SlabKind::Wide => {
                self.each_leaf_with(LaneByLane(SlabF64::for_ray(ray)), ray, stats, leaves, queue)
            }
        }
    }
}

impl<const W: usize> WideBvh<W> {
    #[inline(always)]
    fn each_leaf_with<T: ChildTest<W>, L: AnyLeaves>(
        &self,
        child_test: T,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
        queue: &mut LevelQueue,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let cull = child_test.cull_bound(ray, &self.bounds);
        let (t_min, t_max) = (cull.lower(ray.t_min), cull.widen(ray.t_max));
        let queue = &mut queue.0;
        queue.clear();
        // The root: node 0.
        queue.push((0, 0));
        let mut next = 0;
        while let Some(&(child, count)) = queue.get(next) {
            next += 1;
            if count == 0 {
                let node = &self.nodes[child as usize];
                stats.nodes_visited += 1;
                let (mut mask, _) = child_test.test(node, t_min, t_max);
                prefetch_children(&self.nodes, node, mask, &*leaves);
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    queue.push((node.child[lane], node.count[lane]));
                }
            } else {
                // As in the other walks: never sliced with the sentinel.
                let first = child as usize;
                if let Some(prims) = self.prim_order.get(first..first + count as usize) {
                    leaves.any(child, prims, ray, stats);
                }
            }
        }
    }
}

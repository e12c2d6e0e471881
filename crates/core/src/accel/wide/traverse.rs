//! Walking the wide hierarchy one ray at a time: the child test each ray needs, chosen once
//! per ray, then the nearest hit front to back ([`super::nearest`]) or any hit.

use super::SimdPath;
use super::WideBvh;
use super::child_test::{ChildTest, LaneByLane, Octant};
use super::walk::{Entry, STACK, Stack, prefetch_children};
use crate::accel::leaves::{AnyLeaves, ClosestLeaves};
use crate::accel::{Hit, TraversalStats};
use crate::math::slab::{SlabF32, SlabF64, SlabKind};
use crate::math::{Ray, safe_inverse};

/// Runs `$body` with `$test` bound to the child test `$ray` needs: the SIMD one of the width
/// for ordinary rays, a lane-by-lane scalar slab test for zero or extreme direction components.
macro_rules! with_child_test {
    ($bvh:expr, $ray:expr, $simd:expr, |$test:ident| $body:expr) => {{
        let inv = safe_inverse($ray.dir);
        match SlabKind::with_inverse($ray, inv) {
            SlabKind::Finite => match $simd(Octant::new($ray, inv.to_array())) {
                Some($test) => $body,
                None => {
                    let $test = LaneByLane(SlabF32::<false>::with_inverse($ray, inv));
                    $body
                }
            },
            SlabKind::AxisParallel => {
                let $test = LaneByLane(SlabF32::<true>::with_inverse($ray, inv));
                $body
            }
            SlabKind::Wide => {
                let $test = LaneByLane(SlabF64::for_ray($ray));
                $body
            }
        }
    }};
}

impl WideBvh<8> {
    /// Nearest hit; the answer of [`crate::accel::Bvh::intersect`] and of brute force. The
    /// tester is borrowed (moving it into each call copied it per ray), so the caller can read
    /// what it kept (the packed leaves' slot of the hit).
    #[inline(always)]
    pub(crate) fn intersect<L: ClosestLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> Option<Hit> {
        match SimdPath::active() {
            // SAFETY: the CPU has what each path needs (`SimdPath::active`).
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => unsafe { self.intersect_avx512(ray, stats, test) },
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => unsafe { self.intersect_avx2(ray, stats, test) },
            _ => with_child_test!(self, ray, |_| None::<LaneByLane<SlabF32<false>>>, |t| self
                .intersect_with(t, ray, stats, test)),
        }
    }

    /// The whole walk compiled for AVX2, so the node test and the primitive test inline into it.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn intersect_avx2<L: ClosestLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> Option<Hit> {
        self.intersect_simd(super::child_test::Avx2, ray, stats, test)
    }

    /// The whole walk compiled for AVX-512 (32 vector registers, mask compares).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
    unsafe fn intersect_avx512<L: ClosestLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> Option<Hit> {
        self.intersect_simd(super::avx512::Avx512, ray, stats, test)
    }

    /// The nearest-hit walk with the SIMD child test `simd` makes for ordinary rays.
    #[inline(always)]
    fn intersect_simd<T: ChildTest<8>, L: ClosestLeaves>(
        &self,
        simd: impl Fn(Octant) -> T,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> Option<Hit> {
        with_child_test!(self, ray, |o| Some(simd(o)), |t| self
            .intersect_with(t, ray, stats, test))
    }

    /// True when anything blocks `ray`; stops at the first blocker.
    #[inline(always)]
    pub(crate) fn occluded<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        mut test: L,
    ) -> bool {
        match SimdPath::active() {
            // SAFETY: the CPU has what each path needs (`SimdPath::active`).
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => unsafe { self.occluded_avx512(ray, stats, &mut test) },
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => unsafe { self.occluded_avx2(ray, stats, &mut test) },
            _ => with_child_test!(self, ray, |_| None::<LaneByLane<SlabF32<false>>>, |t| self
                .occluded_with(t, ray, stats, &mut test)),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn occluded_avx2<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> bool {
        let simd = super::child_test::Avx2;
        with_child_test!(self, ray, |o| Some(simd(o)), |t| self
            .occluded_with(t, ray, stats, test))
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
    unsafe fn occluded_avx512<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> bool {
        let simd = super::avx512::Avx512;
        with_child_test!(self, ray, |o| Some(simd(o)), |t| self
            .occluded_with(t, ray, stats, test))
    }
}

impl<const W: usize> WideBvh<W> {
    #[inline(always)]
    fn occluded_with<T: ChildTest<W>, L: AnyLeaves>(
        &self,
        child_test: T,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let cull = child_test.cull_bound(ray, &self.bounds);
        let (t_min, t_max) = (cull.lower(ray.t_min), cull.widen(ray.t_max));
        let mut stack = Stack::<STACK>::new();
        let mut current = Entry {
            child: 0,
            count: 0,
            near: t_min,
        };
        loop {
            if current.count == 0 {
                let node = &self.nodes[current.child as usize];
                stats.nodes_visited += 1;
                let (mut mask, _) = child_test.test(node, t_min, t_max);
                prefetch_children(&self.nodes, node, mask, &*leaves);
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    stack.push(Entry {
                        child: node.child[lane],
                        count: node.count[lane],
                        near: 0.0,
                    });
                }
            } else {
                // As in `intersect_with`: never sliced with the sentinel.
                let first = current.child as usize;
                let prims = self.prim_order.get(first..first + current.count as usize);
                if prims.is_some_and(|prims| leaves.any(current.child, prims, ray, stats)) {
                    return true;
                }
            }
            match stack.pop() {
                Some(e) => current = e,
                None => return false,
            }
        }
    }
}

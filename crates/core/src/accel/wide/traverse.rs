//! Walking the wide hierarchy: nearest hit front to back, and any hit.
//!
//! The closest-hit walk tests all children of a node at once, continues with the nearest entered
//! child and pushes the others farthest first, each with its entry distance; a popped entry is
//! skipped when that distance lies beyond the (widened) best hit, which is exactly what testing
//! its box again would decide, since its entry does not depend on `t_max`.

use std::mem::MaybeUninit;

use super::child_test::{ChildTest, LaneByLane, Octant, has_avx2};
use super::{WideBvh, WideNode};
use crate::accel::bvh::MAX_DEPTH;
use crate::accel::leaves::{AnyLeaves, ClosestLeaves, Prefetch, prefetch_lines};
use crate::accel::{Closest, Hit, TraversalStats};
use crate::math::slab::{SlabF32, SlabF64, SlabKind};
use crate::math::{Ray, safe_inverse};

/// A child still to visit: what [`WideNode::child`] and [`WideNode::count`] hold for it, and
/// the ray's conservative entry distance into its box.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub(super) child: u32,
    pub(super) count: u32,
    pub(super) near: f32,
}

/// A fixed stack: each level of the tree pushes at most `W - 1` entries.
pub(super) struct Stack<const N: usize> {
    items: [MaybeUninit<Entry>; N],
    len: usize,
}

impl<const N: usize> Stack<N> {
    #[inline(always)]
    pub(super) fn new() -> Self {
        Self {
            // An array of `MaybeUninit` needs no initialisation: nothing is read before written.
            items: [const { MaybeUninit::uninit() }; N],
            len: 0,
        }
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: Entry) {
        self.items[self.len] = MaybeUninit::new(e);
        self.len += 1;
    }

    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: every slot below `len` was written by `push`.
        Some(unsafe { self.items[self.len].assume_init() })
    }
}

/// Stack capacity for widths up to 8: `W - 1` entries per level below the root, plus the
/// root's `W`.
pub(super) const STACK: usize = 7 * MAX_DEPTH + 8;

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
        #[cfg(target_arch = "x86_64")]
        if has_avx2() {
            // SAFETY: AVX2 and the bit instructions are present (`has_avx2`).
            return unsafe { self.intersect_avx2(ray, stats, test) };
        }
        with_child_test!(self, ray, |_| None::<LaneByLane<SlabF32<false>>>, |t| self
            .intersect_with(t, ray, stats, test))
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
        use super::child_test::Avx2;
        let inv = safe_inverse(ray.dir);
        match SlabKind::with_inverse(ray, inv) {
            SlabKind::Finite => {
                self.intersect_with(Avx2(Octant::new(ray, inv.to_array())), ray, stats, test)
            }
            SlabKind::AxisParallel => self.intersect_with(
                LaneByLane(SlabF32::<true>::with_inverse(ray, inv)),
                ray,
                stats,
                test,
            ),
            SlabKind::Wide => {
                self.intersect_with(LaneByLane(SlabF64::for_ray(ray)), ray, stats, test)
            }
        }
    }

    /// True when anything blocks `ray`; stops at the first blocker.
    #[inline(always)]
    pub(crate) fn occluded<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        mut test: L,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if has_avx2() {
            // SAFETY: AVX2 and the bit instructions are present (`has_avx2`).
            return unsafe { self.occluded_avx2(ray, stats, &mut test) };
        }
        with_child_test!(self, ray, |_| None::<LaneByLane<SlabF32<false>>>, |t| self
            .occluded_with(t, ray, stats, &mut test))
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn occluded_avx2<L: AnyLeaves>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: &mut L,
    ) -> bool {
        use super::child_test::Avx2;
        let inv = safe_inverse(ray.dir);
        match SlabKind::with_inverse(ray, inv) {
            SlabKind::Finite => {
                self.occluded_with(Avx2(Octant::new(ray, inv.to_array())), ray, stats, test)
            }
            SlabKind::AxisParallel => self.occluded_with(
                LaneByLane(SlabF32::<true>::with_inverse(ray, inv)),
                ray,
                stats,
                test,
            ),
            SlabKind::Wide => {
                self.occluded_with(LaneByLane(SlabF64::for_ray(ray)), ray, stats, test)
            }
        }
    }
}

impl<const W: usize> WideBvh<W> {
    #[inline(always)]
    fn intersect_with<T: ChildTest<W>, L: ClosestLeaves>(
        &self,
        child_test: T,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
    ) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let cull = child_test.cull_bound(ray, &self.bounds);
        let t_min = cull.lower(ray.t_min);
        let mut closest = Closest::new(ray);
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
                let (mask, near) = child_test.test(node, t_min, cull.widen(closest.ray.t_max));
                prefetch_children(&self.nodes, node, mask, &*leaves);
                if let Some(next) = push_entered(node, mask, &near, &mut stack) {
                    current = next;
                    continue;
                }
            } else {
                // `get`, not indexing: a lane is entered only by a ray with a finite origin
                // and direction (every query's frame sees to that), and an unused lane, whose
                // count is the `EMPTY_LANE` sentinel, is never entered by such a ray; should
                // one ever be, it is skipped rather than sliced with the sentinel.
                let first = current.child as usize;
                if let Some(prims) = self.prim_order.get(first..first + current.count as usize) {
                    leaves.closest(current.child, prims, &mut closest, stats);
                }
            }
            // Pop the next entry the ray may still reach before its best hit.
            loop {
                let Some(e) = stack.pop() else {
                    return closest.best;
                };
                if e.near <= cull.widen(closest.ray.t_max) {
                    current = e;
                    break;
                }
            }
        }
    }

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

/// Starts loading every entered child of `node`: each cache line of an interior child, and
/// the leaf data of a leaf (through its tester), so the ones pushed for later are in cache by
/// the time they are popped. Measured: -4% time per ray on the 69k bunny's incoherent rays,
/// -13% on the 1.1M one's (BENCHMARKS.md, Phase 14).
#[inline(always)]
pub(super) fn prefetch_children<const W: usize>(
    nodes: &[WideNode<W>],
    node: &WideNode<W>,
    mask: u32,
    leaves: &impl Prefetch,
) {
    let mut m = mask;
    while m != 0 {
        let lane = m.trailing_zeros() as usize;
        m &= m - 1;
        match node.count[lane] {
            0 => {
                if let Some(child) = nodes.get(node.child[lane] as usize) {
                    prefetch_lines(child);
                }
            }
            count => leaves.prefetch(node.child[lane], count),
        }
    }
}

/// Pushes the entered lanes of `node` farthest first and returns the nearest, to visit next.
#[inline(always)]
pub(super) fn push_entered<const W: usize, const N: usize>(
    node: &WideNode<W>,
    mask: u32,
    near: &[f32; W],
    stack: &mut Stack<N>,
) -> Option<Entry> {
    let entry = |lane: usize| Entry {
        child: node.child[lane],
        count: node.count[lane],
        near: near[lane],
    };
    match mask.count_ones() {
        0 => None,
        1 => Some(entry(mask.trailing_zeros() as usize)),
        2 => {
            // The most common split: one comparison, no sort.
            let a = entry(mask.trailing_zeros() as usize);
            let b = entry((31 - mask.leading_zeros()) as usize);
            let (near, far) = if b.near < a.near { (b, a) } else { (a, b) };
            stack.push(far);
            Some(near)
        }
        n => {
            // Insertion sort of the few entered lanes, nearest last.
            let mut sorted = [MaybeUninit::<Entry>::uninit(); W];
            let mut m = mask;
            for i in 0..n as usize {
                let lane = m.trailing_zeros() as usize;
                m &= m - 1;
                let e = entry(lane);
                let mut j = i;
                // SAFETY: slots below `i` were written in earlier iterations.
                while j > 0 && unsafe { sorted[j - 1].assume_init() }.near < e.near {
                    sorted[j] = sorted[j - 1];
                    j -= 1;
                }
                sorted[j] = MaybeUninit::new(e);
            }
            for s in &sorted[..n as usize - 1] {
                // SAFETY: the first `n` slots were written above.
                stack.push(unsafe { s.assume_init() });
            }
            // SAFETY: as above.
            Some(unsafe { sorted[n as usize - 1].assume_init() })
        }
    }
}

//! The closest-hit walk as a resumable state machine: [`NearestWalk::step`] does one node
//! visit or one leaf test and says whether the ray is done. The one-ray walk is a loop of
//! steps; the batch walk ([`super::in_flight`]) takes the steps of several rays in turn.
//! Both run the same steps in the same order for a ray, so its hit is the same bits.
//!
//! The walk tests all children of a node at once, continues with the nearest entered child
//! and pushes the others farthest first, each with its entry distance; a popped entry is
//! skipped when that distance lies beyond the (widened) best hit, which is exactly what
//! testing its box again would decide, since its entry does not depend on `t_max`.

use super::WideBvh;
use super::child_test::ChildTest;
use super::walk::{STACK, Stack, prefetch_children};
use crate::accel::bvh::CullBound;
use crate::accel::leaves::ClosestLeaves;
use crate::accel::{Closest, Hit, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::Ray;

/// The stack a closest-hit walk needs; kept apart from [`NearestWalk`] so the batch walk can
/// start a ray in a slot without moving the stack's 5 KB.
pub(crate) type NearestStack = Stack<STACK>;

/// One ray's closest-hit walk between two steps: everything but the stack.
pub(super) struct NearestWalk<T> {
    child_test: T,
    cull: CullBound,
    t_min: f32,
    /// `cull.widen(closest.ray.t_max)`, kept so the node tests and pops between two leaf
    /// tests (the only steps that shrink `t_max`) do not recompute it.
    t_far: f32,
    closest: Closest,
    /// The node or leaf the next step visits: its stack entry's `child` and `count`, held
    /// apart (copied as one 12-byte entry, the two were packed into one register and unpacked
    /// at every step: +0.8% instructions per ray, callgrind).
    child: u32,
    count: u32,
}

impl<T> NearestWalk<T> {
    /// Whether the next step visits a node (else it tests a leaf).
    #[inline(always)]
    pub(super) fn at_node(&self) -> bool {
        self.count == 0
    }

    /// The best hit so far (the answer once [`NearestWalk::step`] has said done).
    #[inline(always)]
    pub(super) fn best(&self) -> Option<Hit> {
        self.closest.best
    }

    /// The ray as the walk has shrunk it (`t_max` at the best hit so far).
    #[inline(always)]
    pub(super) fn ray(&self) -> &Ray {
        &self.closest.ray
    }

    /// Offers a hit found outside the leaf tests (inside an instance the walk entered); says
    /// whether it is the best so far.
    #[inline(always)]
    pub(super) fn offer(&mut self, prim: u32, hit: PrimHit) -> bool {
        let better = self.closest.offer(prim, hit);
        if better {
            self.t_far = self.cull.widen(self.closest.ray.t_max);
        }
        better
    }

    /// The walk of `ray` through `bvh` with `child_test` (the one the ray needs), starting at
    /// the root with `stack` emptied; `None` when the hierarchy is empty (nothing to hit).
    #[inline(always)]
    pub(super) fn start<const W: usize>(
        bvh: &WideBvh<W>,
        child_test: T,
        ray: &Ray,
        stack: &mut NearestStack,
    ) -> Option<Self>
    where
        T: ChildTest<W>,
    {
        if bvh.nodes.is_empty() {
            return None;
        }
        stack.clear();
        let cull = child_test.cull_bound(ray, &bvh.bounds);
        let t_min = cull.lower(ray.t_min);
        Some(Self {
            child_test,
            cull,
            t_min,
            t_far: cull.widen(ray.t_max),
            closest: Closest::new(ray),
            child: 0,
            count: 0,
        })
    }

    /// Visits the current node (testing its children, prefetching the entered ones, pushing
    /// all but the nearest) or tests the current leaf, then picks what to visit next. True
    /// while the ray has more to visit; false when it is done and [`Self::best`] is its answer.
    #[inline(always)]
    pub(super) fn step<const W: usize, L: ClosestLeaves>(
        &mut self,
        bvh: &WideBvh<W>,
        stack: &mut NearestStack,
        leaves: &mut L,
        stats: &mut TraversalStats,
    ) -> bool
    where
        T: ChildTest<W>,
    {
        let (child, count) = (self.child, self.count);
        if count == 0 {
            let node = &bvh.nodes[child as usize];
            stats.nodes_visited += 1;
            let (mask, near) = self.child_test.test(node, self.t_min, self.t_far);
            prefetch_children(&bvh.nodes, node, mask, &*leaves);
            if let Some(next) = self.child_test.push_entered(node, mask, &near, stack) {
                (self.child, self.count) = (next.child, next.count);
                return true;
            }
        } else {
            // `get`, not indexing: a lane is entered only by a ray with a finite origin
            // and direction (every query's frame sees to that), and an unused lane, whose
            // count is the `EMPTY_LANE` sentinel, is never entered by such a ray; should
            // one ever be, it is skipped rather than sliced with the sentinel.
            let first = child as usize;
            if let Some(prims) = bvh.prim_order.get(first..first + count as usize) {
                leaves.closest(child, prims, &mut self.closest, stats);
                self.t_far = self.cull.widen(self.closest.ray.t_max);
            }
        }
        // Pop the next entry the ray may still reach before its best hit.
        while let Some(e) = stack.pop() {
            if e.near <= self.t_far {
                (self.child, self.count) = (e.child, e.count);
                return true;
            }
        }
        false
    }
}

impl<const W: usize> WideBvh<W> {
    /// The one-ray closest-hit walk: steps until done.
    #[inline(always)]
    pub(super) fn intersect_with<T: ChildTest<W>, L: ClosestLeaves>(
        &self,
        child_test: T,
        ray: &Ray,
        stats: &mut TraversalStats,
        leaves: &mut L,
    ) -> Option<Hit> {
        let mut stack = NearestStack::new();
        let mut walk = NearestWalk::start(self, child_test, ray, &mut stack)?;
        while walk.step(self, &mut stack, leaves, stats) {}
        walk.best()
    }
}

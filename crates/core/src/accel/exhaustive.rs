//! The traversal of the paper's own code: every node whose box the ray crosses is visited,
//! both children always, with no front-to-back order and no culling by the best hit so far
//! (its `find_intersection` recursion). Kept as a reference point for Table I: the gains the
//! paper measured for scale lights are gains over this walk.

use super::bvh::{Bvh, CullBound, MAX_DEPTH};
use super::{Closest, Hit, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::Ray;
use crate::math::slab::{Slab, with_slab};

impl Bvh {
    /// Nearest hit, visiting every node the ray's line crosses within its original range.
    /// The same answer as [`Bvh::intersect`]; only the work differs.
    pub fn intersect_exhaustive<F>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        test: F,
    ) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        with_slab!(ray, |slab| self.exhaustive_with(slab, ray, stats, test))
    }

    fn exhaustive_with<S: Slab, F>(
        &self,
        slab: S,
        ray: &Ray,
        stats: &mut TraversalStats,
        mut test: F,
    ) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        let nodes = self.nodes();
        if nodes.is_empty() {
            return None;
        }
        let cull = CullBound::new(ray, &nodes[0].bounds);
        // The range never shrinks: that is the point of this traversal.
        let (t_min, t_max) = (cull.lower(ray.t_min), cull.widen(ray.t_max));
        let mut closest = Closest::new(ray);
        let mut stack = [0u32; MAX_DEPTH + 1];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = &nodes[stack[sp] as usize];
            stats.nodes_visited += 1;
            if slab.range(&node.bounds, t_min, t_max).is_none() {
                continue;
            }
            if node.is_leaf() {
                for &prim in self.leaf_prims(node) {
                    stats.prim_tests += 1;
                    // Each primitive is tested against the full ray, as the original does.
                    if let Some(h) = test(prim, ray) {
                        closest.offer(prim, h);
                    }
                }
            } else {
                stack[sp] = node.first + 1;
                stack[sp + 1] = node.first;
                sp += 2;
            }
        }
        closest.best
    }
}

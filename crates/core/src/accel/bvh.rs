//! A bounding-volume hierarchy stored as one flat node array, and its traversals.
//!
//! Node 0 is the root. An interior node's children sit next to each other at `first` and
//! `first + 1`; a leaf holds `count > 0` entries of `prim_order` starting at `first`.

use super::{Closest, Hit, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::slab::{Slab, with_slab};
use crate::math::{Aabb, Ray, gamma};

/// Traversal stack depth; builders stop splitting well before this (depth is checked in `validate`).
pub(crate) const MAX_DEPTH: usize = 64;

/// The largest coordinate magnitude of the ray's origin and the scene's bounds.
#[inline(always)]
fn coordinate_scale(ray: &Ray, root: &Aabb) -> f32 {
    ray.origin
        .abs()
        .max(root.min.abs())
        .max(root.max.abs())
        .max_element()
}

/// Relative margin of [`CullBound::with_inverse`] over [`CullBound::new`].
const INVERSE_MARGIN: f32 = 1.0 + 1.0 / 65536.0;

/// Relative widening of the `t_max` that boxes are culled against (see [`CullBound`]).
const CULL_SCALE: f32 = 1.0 + gamma(16);

/// The bound boxes are culled against. Culling must never drop a primitive whose hit brute
/// force would report, yet a primitive's computed `t` can round below its own box's computed
/// entry: a vertex or flat triangle on the box face by a few ulps of `t`, a sphere seen from
/// just outside it by ulps of the coordinates (`|f|^2 - r^2` cancels). So boxes are tested
/// against `t_max` widened relatively and by an absolute term scaled to the coordinates; leaves
/// still test primitives against the exact `t_max`, so answers stay bit-identical.
#[derive(Clone, Copy)]
pub(crate) struct CullBound {
    slack: f32,
}

impl CullBound {
    /// The absolute slack for `ray` in a scene bounded by `root`: gamma(16) of the largest
    /// coordinate magnitude, in units of `t` (divided by the direction's length).
    #[inline(always)]
    pub(crate) fn new(ray: &Ray, root: &Aabb) -> Self {
        let scale = coordinate_scale(ray, root);
        // The length in f64 only when squares of subnormal or huge components under/overflow
        // in f32 (the f32 length is then 0, subnormal or infinite).
        let len = ray.dir.length();
        let slack = if len.is_normal() && len < 1e18 {
            gamma(16) * scale / len * CULL_SCALE
        } else {
            (gamma(16) as f64 * scale as f64 / ray.dir.as_dvec3().length()) as f32
        };
        Self {
            slack: slack.next_up(),
        }
    }

    /// The same bound (or a larger one) without a square root or a division, for a ray whose
    /// reciprocal direction `inv` is finite and normal in every component: `1 / |d|` is at most
    /// `1 / max |d_i| = min |inv_i|`, and the relative margin covers the few ulps by which the
    /// two roundings of that can differ. A larger slack only culls less, so answers are the same.
    #[inline(always)]
    pub(crate) fn with_inverse(ray: &Ray, root: &Aabb, inv: [f32; 3]) -> Self {
        let scale = coordinate_scale(ray, root);
        let inv_len = inv[0].abs().min(inv[1].abs()).min(inv[2].abs());
        let slack = gamma(16) * scale * inv_len * (CULL_SCALE * INVERSE_MARGIN);
        Self {
            slack: slack.next_up(),
        }
    }

    /// `t_max` widened for the box test (towards +inf: a negative `t_max`, a ray queried
    /// behind its origin, is not scaled, which would move it the wrong way).
    #[inline(always)]
    pub(crate) fn widen(self, t_max: f32) -> f32 {
        (t_max * CULL_SCALE).max(t_max) + self.slack
    }

    /// `t_min` lowered for the box test: a hit just after the origin may round to a `t` past
    /// the exit of a box the origin lies just outside of (a ray leaving a surface).
    #[inline(always)]
    pub(crate) fn lower(self, t_min: f32) -> f32 {
        t_min - self.slack
    }
}

/// One node of the flat array.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Tight bounds of everything below.
    pub bounds: Aabb,
    /// Interior: index of the left child (right is `first + 1`). Leaf: start in `prim_order`.
    pub first: u32,
    /// Number of primitives in a leaf; 0 marks an interior node.
    pub count: u32,
}

impl Node {
    /// True for a leaf.
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A built hierarchy. Fields are private: builders establish the invariants `validate` checks.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    prim_order: Vec<u32>,
}

impl Bvh {
    /// Wraps a builder's output. An empty primitive list gives an empty hierarchy.
    pub(crate) fn from_parts(nodes: Vec<Node>, prim_order: Vec<u32>) -> Self {
        Self { nodes, prim_order }
    }

    /// The node array (root first).
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Primitive indices in leaf order.
    pub fn prim_order(&self) -> &[u32] {
        &self.prim_order
    }

    /// The primitives of leaf `node`.
    #[inline(always)]
    pub(crate) fn leaf_prims(&self, node: &Node) -> &[u32] {
        &self.prim_order[node.first as usize..(node.first + node.count) as usize]
    }

    /// Nearest hit, visiting children front to back and culling with the shrinking `t_max`.
    pub fn intersect<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        with_slab!(ray, |slab| self.intersect_with(slab, ray, stats, test))
    }

    fn intersect_with<S: Slab, F>(
        &self,
        slab: S,
        ray: &Ray,
        stats: &mut TraversalStats,
        mut test: F,
    ) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        if self.nodes.is_empty() {
            return None;
        }
        let mut node = &self.nodes[0];
        let cull = CullBound::new(ray, &node.bounds);
        // Fixed for the whole traversal: only `t_max` shrinks as hits are found.
        let t_min = cull.lower(ray.t_min);
        stats.nodes_visited += 1;
        slab.range(&node.bounds, t_min, cull.widen(ray.t_max))?;
        // Set up only once the root is hit: a ray that misses the scene pays for no stack.
        let mut closest = Closest::new(ray);
        let mut stack = [0u32; MAX_DEPTH + 1];
        let mut sp = 0;
        loop {
            if node.is_leaf() {
                for &prim in self.leaf_prims(node) {
                    stats.prim_tests += 1;
                    if let Some(h) = test(prim, &closest.ray) {
                        closest.offer(prim, h);
                    }
                }
            } else {
                let (l, r) = (
                    &self.nodes[node.first as usize],
                    &self.nodes[node.first as usize + 1],
                );
                stats.nodes_visited += 2;
                let t_max = cull.widen(closest.ray.t_max);
                let hl = slab.range(&l.bounds, t_min, t_max).map(|h| h.0);
                let hr = slab.range(&r.bounds, t_min, t_max).map(|h| h.0);
                match (hl, hr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b {
                            (node.first, node.first + 1)
                        } else {
                            (node.first + 1, node.first)
                        };
                        stack[sp] = far;
                        sp += 1;
                        node = &self.nodes[near as usize];
                        continue;
                    }
                    (Some(_), None) => {
                        node = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop, skipping subtrees that now lie beyond the best hit.
            loop {
                if sp == 0 {
                    return closest.best;
                }
                sp -= 1;
                let n = &self.nodes[stack[sp] as usize];
                if slab
                    .range(&n.bounds, t_min, cull.widen(closest.ray.t_max))
                    .is_some()
                {
                    node = n;
                    break;
                }
            }
        }
    }

    /// Any hit: returns at the first primitive that blocks the ray.
    pub fn occluded<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        with_slab!(ray, |slab| self.occluded_with(slab, ray, stats, test))
    }

    fn occluded_with<S: Slab, F>(
        &self,
        slab: S,
        ray: &Ray,
        stats: &mut TraversalStats,
        mut test: F,
    ) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        if self.nodes.is_empty() {
            return false;
        }
        let cull = CullBound::new(ray, &self.nodes[0].bounds);
        let (t_min, t_max) = (cull.lower(ray.t_min), cull.widen(ray.t_max));
        // A ray that misses the scene returns before the stack is set up (counted as the one
        // node visit the loop would make).
        if slab.range(&self.nodes[0].bounds, t_min, t_max).is_none() {
            stats.nodes_visited += 1;
            return false;
        }
        let mut stack = [0u32; MAX_DEPTH + 1];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp] as usize];
            stats.nodes_visited += 1;
            if slab.range(&node.bounds, t_min, t_max).is_none() {
                continue;
            }
            if node.is_leaf() {
                for &prim in self.leaf_prims(node) {
                    stats.prim_tests += 1;
                    if test(prim, ray) {
                        return true;
                    }
                }
            } else {
                stack[sp] = node.first + 1;
                stack[sp + 1] = node.first;
                sp += 2;
            }
        }
        false
    }

    /// Checks the invariants: every primitive referenced exactly once, children inside their
    /// parent, every node's box exactly the union of what it holds (tight), depth within the
    /// traversal stack. Returns a description of the first violation.
    pub fn validate(&self, prim_bounds: &[Aabb]) -> Result<(), String> {
        if prim_bounds.is_empty() {
            return if self.nodes.is_empty() {
                Ok(())
            } else {
                Err("nodes for no primitives".into())
            };
        }
        let mut seen = vec![0u32; prim_bounds.len()];
        self.validate_node(0, 1, prim_bounds, &mut seen)?;
        each_once(&seen)
    }

    fn validate_node(
        &self,
        index: u32,
        depth: usize,
        prim_bounds: &[Aabb],
        seen: &mut [u32],
    ) -> Result<Aabb, String> {
        if depth > MAX_DEPTH {
            return Err(format!(
                "node {index} at depth {depth} exceeds the traversal stack budget"
            ));
        }
        let node = self
            .nodes
            .get(index as usize)
            .ok_or(format!("node {index} out of range"))?;
        let actual = if node.is_leaf() {
            let end = (node.first + node.count) as usize;
            let prims = self
                .prim_order
                .get(node.first as usize..end)
                .ok_or(format!("leaf {index} out of range"))?;
            leaf_content(prims, prim_bounds, seen).map_err(|e| format!("leaf {index}: {e}"))?
        } else {
            if node.first <= index {
                return Err(format!(
                    "node {index}: child {} does not come after it",
                    node.first
                ));
            }
            let l = self.validate_node(node.first, depth + 1, prim_bounds, seen)?;
            let r = self.validate_node(node.first + 1, depth + 1, prim_bounds, seen)?;
            l.union(r)
        };
        if actual != node.bounds {
            return Err(format!(
                "node {index}: bounds {:?} are not tight (content {:?})",
                node.bounds, actual
            ));
        }
        Ok(actual)
    }
}

/// The union of a leaf's primitive boxes, counting each primitive in `seen` (for `validate`).
pub(crate) fn leaf_content(
    prims: &[u32],
    prim_bounds: &[Aabb],
    seen: &mut [u32],
) -> Result<Aabb, String> {
    let mut b = Aabb::EMPTY;
    for &p in prims {
        let pb = prim_bounds
            .get(p as usize)
            .ok_or(format!("bad primitive {p}"))?;
        seen[p as usize] += 1;
        b = b.union(*pb);
    }
    Ok(b)
}

/// Ok when every primitive was reached exactly once (for `validate`).
pub(crate) fn each_once(seen: &[u32]) -> Result<(), String> {
    match seen.iter().position(|&c| c != 1) {
        Some(p) => Err(format!("primitive {p} referenced {} times", seen[p])),
        None => Ok(()),
    }
}

//! The paper's partitions: `bsp` splits a node at the spatial centre of its bounds (the
//! baseline), `bsmp` at the median of its primitives' centroids (the paper's contribution).
//!
//! Both cycle the axis x → y → z with depth and partition objects (each primitive goes to one
//! side by its centroid), so children get tight bounds and a primitive is never duplicated.

use super::BuildOptions;
use super::bvh::{Bvh, MAX_DEPTH, Node};
use super::sah::partition;
use crate::math::{Aabb, Vec3};

/// Where a node is cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplitRule {
    /// At the centre of the node's bounds; when that separates nothing, the next axes are tried.
    SpatialCentre,
    /// At the median centroid, so both halves hold equal counts (`select_nth_unstable`, O(n)).
    MedianCentroid,
}

/// Builds a hierarchy with the given rule; leaves hold at most `opts.max_leaf_size` primitives
/// unless no split can separate them (or the depth limit is reached).
pub fn build(bounds: &[Aabb], opts: &BuildOptions, rule: SplitRule) -> Bvh {
    if bounds.is_empty() {
        return Bvh::from_parts(Vec::new(), Vec::new());
    }
    let centroids: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    let mut b = Builder {
        bounds,
        centroids: &centroids,
        nodes: Vec::new(),
        max_leaf: opts.max_leaf_size.max(1),
        rule,
    };
    b.nodes.push(Node {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    });
    b.split(0, &mut order, 0, 0);
    Bvh::from_parts(b.nodes, order)
}

struct Builder<'a> {
    bounds: &'a [Aabb],
    centroids: &'a [Vec3],
    nodes: Vec<Node>,
    max_leaf: usize,
    rule: SplitRule,
}

impl Builder<'_> {
    fn split(&mut self, index: usize, order: &mut [u32], offset: usize, depth: usize) {
        let node_bounds = order
            .iter()
            .fold(Aabb::EMPTY, |b, &p| b.union(self.bounds[p as usize]));
        let n = order.len();
        let leaf = Node {
            bounds: node_bounds,
            first: offset as u32,
            count: n as u32,
        };
        let mid = if n <= self.max_leaf || depth + 1 >= MAX_DEPTH {
            None
        } else {
            self.cut(order, &node_bounds, depth)
        };
        let Some(mid) = mid else {
            self.nodes[index] = leaf;
            return;
        };
        let first = self.nodes.len();
        self.nodes.push(leaf);
        self.nodes.push(leaf);
        self.nodes[index] = Node {
            bounds: node_bounds,
            first: first as u32,
            count: 0,
        };
        let (left, right) = order.split_at_mut(mid);
        self.split(first, left, offset, depth + 1);
        self.split(first + 1, right, offset + mid, depth + 1);
    }

    /// Partitions `order` and returns the size of the left part, or `None` when no cut separates.
    fn cut(&self, order: &mut [u32], node_bounds: &Aabb, depth: usize) -> Option<usize> {
        match self.rule {
            SplitRule::SpatialCentre => (0..3).map(|k| (depth + k) % 3).find_map(|axis| {
                let plane = node_bounds.center()[axis];
                let mid = partition(order, |p| self.centroids[p as usize][axis] < plane);
                (mid > 0 && mid < order.len()).then_some(mid)
            }),
            SplitRule::MedianCentroid => {
                let axis = depth % 3;
                let mid = order.len() / 2;
                // Ties broken by index keep the build deterministic whatever the input order.
                order.select_nth_unstable_by(mid, |&a, &b| {
                    self.centroids[a as usize][axis]
                        .total_cmp(&self.centroids[b as usize][axis])
                        .then(a.cmp(&b))
                });
                Some(mid)
            }
        }
    }
}

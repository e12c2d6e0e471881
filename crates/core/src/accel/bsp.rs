//! The paper's partitions: `bsp` splits a node at the spatial centre of its bounds (the
//! baseline), `bsmp` at the median of its primitives' centroids (the paper's contribution).
//!
//! Both cycle the axis x → y → z with depth and partition objects (each primitive goes to one
//! side by its centroid), so children get tight bounds and a primitive is never duplicated.

use super::BuildOptions;
use super::build::{build_hierarchy, partition};
use super::bvh::Bvh;
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
    let centroids: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
    let max_leaf = opts.max_leaf_size.max(1);
    build_hierarchy(bounds, &mut |order, node_bounds, depth| {
        if order.len() <= max_leaf {
            return None;
        }
        match rule {
            SplitRule::SpatialCentre => (0..3).map(|k| (depth + k) % 3).find_map(|axis| {
                let plane = node_bounds.center()[axis];
                let mid = partition(order, |p| centroids[p as usize][axis] < plane);
                (mid > 0 && mid < order.len()).then_some(mid)
            }),
            SplitRule::MedianCentroid => {
                let axis = depth % 3;
                let mid = order.len() / 2;
                // Ties broken by index keep the build deterministic whatever the input order.
                order.select_nth_unstable_by(mid, |&a, &b| {
                    centroids[a as usize][axis]
                        .total_cmp(&centroids[b as usize][axis])
                        .then(a.cmp(&b))
                });
                Some(mid)
            }
        }
    })
}

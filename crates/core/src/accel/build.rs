//! The recursion every hierarchy builder shares: a node gets the tight bounds of its
//! primitives, and a builder-specific `cut` decides whether and where to split it.

use super::bvh::{Bvh, MAX_DEPTH, Node};
use crate::math::Aabb;

/// Partitions the primitives `order` of a node (bounds given, `depth` 0 at the root) and
/// returns how many went left, or `None` to make the node a leaf.
pub(crate) type Cut<'a> = dyn FnMut(&mut [u32], &Aabb, usize) -> Option<usize> + 'a;

/// Builds the flat node array over primitives with the given bounds. Leaves are made where
/// `cut` says so, at one primitive, at the depth limit, and where a cut separates nothing.
pub(crate) fn build_hierarchy(bounds: &[Aabb], cut: &mut Cut<'_>) -> Bvh {
    if bounds.is_empty() {
        return Bvh::from_parts(Vec::new(), Vec::new());
    }
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    let mut nodes = vec![Node {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    }];
    split(bounds, cut, &mut nodes, 0, &mut order, 0, 0);
    Bvh::from_parts(nodes, order)
}

/// Fills node `index` with the primitives `order`, which start at `offset` in the final order.
fn split(
    bounds: &[Aabb],
    cut: &mut Cut<'_>,
    nodes: &mut Vec<Node>,
    index: usize,
    order: &mut [u32],
    offset: usize,
    depth: usize,
) {
    let node_bounds = order
        .iter()
        .fold(Aabb::EMPTY, |b, &p| b.union(bounds[p as usize]));
    let n = order.len();
    let leaf = Node {
        bounds: node_bounds,
        first: offset as u32,
        count: n as u32,
    };
    let mid = if n <= 1 || depth + 1 >= MAX_DEPTH {
        None
    } else {
        cut(order, &node_bounds, depth)
    };
    let Some(mid) = mid.filter(|&m| m > 0 && m < n) else {
        nodes[index] = leaf;
        return;
    };
    let first = nodes.len();
    nodes.extend([leaf, leaf]);
    nodes[index] = Node {
        bounds: node_bounds,
        first: first as u32,
        count: 0,
    };
    let (left, right) = order.split_at_mut(mid);
    split(bounds, cut, nodes, first, left, offset, depth + 1);
    split(
        bounds,
        cut,
        nodes,
        first + 1,
        right,
        offset + mid,
        depth + 1,
    );
}

/// Reorders `items` so those satisfying `left` come first; returns how many do.
pub(crate) fn partition(items: &mut [u32], mut left: impl FnMut(u32) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

//! Binned surface-area-heuristic builder (Wald 2007): 16 centroid bins per axis, all three axes.

use super::BuildOptions;
use super::bvh::{Bvh, MAX_DEPTH, Node};
use crate::math::{Aabb, Vec3};

const BINS: usize = 16;
/// Cost of one node visit relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// Builds a SAH hierarchy over primitives with the given bounds.
pub fn build(bounds: &[Aabb], opts: &BuildOptions) -> Bvh {
    if bounds.is_empty() {
        return Bvh::from_parts(Vec::new(), Vec::new());
    }
    let centroids: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    let mut nodes = Vec::with_capacity(2 * bounds.len() / opts.max_leaf_size.max(1) + 1);
    nodes.push(Node {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    });
    let mut b = Builder {
        bounds,
        centroids: &centroids,
        nodes,
        max_leaf: opts.max_leaf_size.max(1),
    };
    b.split(0, &mut order, 0, 1);
    Bvh::from_parts(b.nodes, order)
}

struct Builder<'a> {
    bounds: &'a [Aabb],
    centroids: &'a [Vec3],
    nodes: Vec<Node>,
    max_leaf: usize,
}

impl Builder<'_> {
    /// Fills node `index` with the primitives `order` (which start at `offset` in the final order).
    fn split(&mut self, index: usize, order: &mut [u32], offset: usize, depth: usize) {
        let node_bounds = order
            .iter()
            .fold(Aabb::EMPTY, |b, &p| b.union(self.bounds[p as usize]));
        let centroid_bounds = Aabb::from_points(order.iter().map(|&p| self.centroids[p as usize]));
        let n = order.len();
        let leaf = Node {
            bounds: node_bounds,
            first: offset as u32,
            count: n as u32,
        };
        if n <= 1 || depth >= MAX_DEPTH {
            self.nodes[index] = leaf;
            return;
        }
        let mid = match self.best_split(order, &centroid_bounds, &node_bounds) {
            Some((axis, bin, cost)) if cost < n as f32 || n > self.max_leaf => {
                let (lo, scale) = bin_mapping(&centroid_bounds, axis);
                partition(order, |p| {
                    bin_of(self.centroids[p as usize][axis], lo, scale) < bin
                })
            }
            Some(_) => {
                self.nodes[index] = leaf;
                return;
            }
            // All centroids coincide: no plane separates them, so halve by index to keep leaves small.
            None if n > self.max_leaf => n / 2,
            None => {
                self.nodes[index] = leaf;
                return;
            }
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

    /// Best `(axis, first bin of the right side, cost)`, cost in units of primitive tests.
    /// `None` when the centroids span no extent on any axis.
    fn best_split(&self, order: &[u32], cb: &Aabb, nb: &Aabb) -> Option<(usize, usize, f32)> {
        let mut best: Option<(usize, usize, f32)> = None;
        let parent_area = nb.surface_area().max(f32::MIN_POSITIVE);
        for axis in 0..3 {
            if cb.max[axis] <= cb.min[axis] {
                continue;
            }
            let (lo, scale) = bin_mapping(cb, axis);
            let mut bins = [(Aabb::EMPTY, 0u32); BINS];
            for &p in order {
                let b = bin_of(self.centroids[p as usize][axis], lo, scale);
                bins[b].0 = bins[b].0.union(self.bounds[p as usize]);
                bins[b].1 += 1;
            }
            // Sweep from the right to get the area and count right of each boundary.
            let mut right = [(0.0f32, 0u32); BINS];
            let (mut rb, mut rc) = (Aabb::EMPTY, 0);
            for i in (1..BINS).rev() {
                rb = rb.union(bins[i].0);
                rc += bins[i].1;
                right[i] = (rb.surface_area(), rc);
            }
            let (mut lb, mut lc) = (Aabb::EMPTY, 0);
            for i in 1..BINS {
                lb = lb.union(bins[i - 1].0);
                lc += bins[i - 1].1;
                let (ra, rc) = right[i];
                if lc == 0 || rc == 0 {
                    continue;
                }
                let cost =
                    TRAVERSAL_COST + (lb.surface_area() * lc as f32 + ra * rc as f32) / parent_area;
                if best.is_none_or(|b| cost < b.2) {
                    best = Some((axis, i, cost));
                }
            }
        }
        best
    }
}

/// Origin and bins-per-unit of the binning along `axis` of the centroid bounds.
fn bin_mapping(cb: &Aabb, axis: usize) -> (f32, f32) {
    (cb.min[axis], BINS as f32 / (cb.max[axis] - cb.min[axis]))
}

/// The bin of a centroid coordinate; the same formula for binning and partitioning, so the
/// partition matches the counts the cost was computed from.
#[inline(always)]
fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
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

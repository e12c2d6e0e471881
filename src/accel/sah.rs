//! Binned surface-area-heuristic builder (Wald 2007): 16 centroid bins per axis, all three axes.

use super::BuildOptions;
use super::build::{build_hierarchy, partition};
use super::bvh::Bvh;
use crate::math::{Aabb, Vec3};

const BINS: usize = 16;
/// Cost of one node visit relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// Builds a SAH hierarchy over primitives with the given bounds.
pub fn build(bounds: &[Aabb], opts: &BuildOptions) -> Bvh {
    let centroids: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
    let sah = Sah {
        bounds,
        centroids: &centroids,
    };
    let max_leaf = opts.max_leaf_size.max(1);
    build_hierarchy(bounds, &mut |order, node_bounds, _depth| {
        sah.cut(order, node_bounds, max_leaf)
    })
}

struct Sah<'a> {
    bounds: &'a [Aabb],
    centroids: &'a [Vec3],
}

impl Sah<'_> {
    /// Splits at the cheapest bin boundary when that beats a leaf (or the node is too big to
    /// be one); `None` makes a leaf.
    fn cut(&self, order: &mut [u32], node_bounds: &Aabb, max_leaf: usize) -> Option<usize> {
        let n = order.len();
        let centroid_bounds = Aabb::from_points(order.iter().map(|&p| self.centroids[p as usize]));
        match self.best_split(order, &centroid_bounds, node_bounds) {
            Some((axis, bin, cost)) if cost < n as f32 || n > max_leaf => {
                let (lo, scale) = bin_mapping(&centroid_bounds, axis);
                Some(partition(order, |p| {
                    bin_of(self.centroids[p as usize][axis], lo, scale) < bin
                }))
            }
            // All centroids coincide: no plane separates them, so halve by index to keep leaves small.
            None if n > max_leaf => Some(n / 2),
            _ => None,
        }
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

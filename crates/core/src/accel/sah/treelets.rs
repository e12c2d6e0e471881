//! The fast builder: primitives sorted in Morton order and cut into clusters of nearby ones
//! ([`morton`]), a surface-area-heuristic top over the clusters' boxes down to nodes of at most
//! [`GROUP`] primitives, and each of those built by the same binned/swept SAH builder as
//! [`super::build`] over all its primitives (after Pantaleoni and Luebke's HLBVH, with SAH
//! instead of Morton splits).
//!
//! Why it is faster: the full builder bins and partitions every primitive at every level, about
//! 18 levels on a million triangles; here the levels above the groups cost one radix sort and
//! sweeps over cluster boxes, and each group (about eight levels) is built from a copy of its
//! primitives small enough to stay in cache. What it gives up: above a group, a split cannot
//! cut through a cluster (an octree cell); below, the clusters no longer constrain anything,
//! which is why groups are several clusters large. BENCHMARKS.md ("Build") measures both the
//! speed and the SAH cost against the full builder.

use super::boxes::{Box3, Centroids, Ref};
use super::{Builder, Span, Subtree, graft, morton};
use crate::accel::BuildOptions;
use crate::accel::bvh::{Bvh, Node};
use crate::math::Aabb;
use rayon::prelude::*;

/// Largest cluster: small enough that the top's splits come close to the full builder's, large
/// enough that the top (a sweep over every split of the clusters) stays cheap.
const CLUSTER: usize = 64;

/// Top levels deeper than this split their clusters in half instead of by cost, so that
/// degenerate input (every box the same) cannot build a chain as deep as it has clusters.
const TOP_DEPTH: usize = 32;

/// Top nodes of at most this many primitives (groups) are built by the full builder over all
/// their primitives, across the cluster boundaries.
const GROUP: usize = 1024;

/// One cluster as the top sees it.
struct Cluster {
    bounds: Box3,
    centroids: Centroids,
    /// The centre of its box, per axis.
    centre: [f32; 3],
    /// The group lanes its primitives fill: the number of tests the cluster would cost as one leaf.
    slots: u32,
    /// Its primitives: `start..end` of the Morton order.
    prims: std::ops::Range<usize>,
}

/// A node of the top that the full builder builds, over all primitives of its clusters: its
/// place in the top, its depth, and its clusters (a range of the top's orders).
struct Group {
    node: usize,
    depth: usize,
    clusters: std::ops::Range<usize>,
}

/// Builds a hierarchy over primitives with the given `bounds`, `ref_of(p)` giving primitive
/// `p` as the builder reads it (see [`super::build`]).
pub(super) fn build(
    bounds: &[Aabb],
    ref_of: impl Fn(usize) -> Ref + Sync,
    opts: &BuildOptions,
    builder: &Builder,
) -> Bvh {
    let (ids, codes) = morton::sorted(bounds);
    let cluster_max = CLUSTER.max(opts.max_leaf_size);
    let group_max = GROUP.max(cluster_max);
    let ends = morton::clusters(&codes, cluster_max);
    drop(codes);

    // Each cluster's bounds, read through the Morton order.
    let mut clusters = Vec::with_capacity(ends.len());
    let mut start = 0;
    for &end in &ends {
        let refs = ids[start..end].iter().map(|&p| ref_of(p as usize));
        let (b, c, slots) = refs.fold((Box3::EMPTY, Centroids::EMPTY, 0), |(b, c, s), r| {
            (b.union(r.bounds()), c.grow(r.centroid2()), s + r.slots())
        });
        let a = b.aabb();
        let centre = (a.min + a.max) * 0.5;
        clusters.push(Cluster {
            bounds: b,
            centroids: c,
            centre: [centre.x, centre.y, centre.z],
            slots,
            prims: start..end,
        });
        start = end;
    }

    let mut nodes = Vec::with_capacity(start * 2 / 3 + 1);
    let mut top = Top::new(&clusters, group_max);
    top.build(&mut nodes);
    let (orders, groups) = (&top.orders[0], &top.groups);
    // Where each group's primitives start in the final order: groups in the top's order.
    let offsets: Vec<usize> = groups
        .iter()
        .scan(0, |at, g| {
            let here = *at;
            *at += g
                .clusters
                .clone()
                .map(|i| clusters[orders[i] as usize].prims.len())
                .sum::<usize>();
            Some(here)
        })
        .collect();

    // Each group's primitives gathered into scratch (its clusters in Morton order), built.
    let built: Vec<(Subtree, Vec<u32>)> = groups
        .par_iter()
        .zip(offsets.par_iter())
        .map_init(Vec::new, |refs: &mut Vec<Ref>, (g, &offset)| {
            let mut members: Vec<u32> = orders[g.clusters.clone()].to_vec();
            members.sort_unstable();
            refs.clear();
            let mut group_ids = Vec::new();
            let (mut group_bounds, mut centroids, mut slots) = (Box3::EMPTY, Centroids::EMPTY, 0);
            for &m in &members {
                let cluster = &clusters[m as usize];
                let prims = &ids[cluster.prims.clone()];
                group_ids.extend_from_slice(prims);
                refs.extend(prims.iter().map(|&p| ref_of(p as usize)));
                group_bounds = group_bounds.union(cluster.bounds);
                centroids = centroids.union(cluster.centroids);
                slots += cluster.slots;
            }
            let span = Span {
                refs,
                ids: &mut group_ids,
                bounds: group_bounds,
                centroids,
                slots,
            };
            (builder.subtree(span, offset, g.depth), group_ids)
        })
        .collect();
    let mut order = vec![0u32; start];
    for ((sub, group_ids), (g, &offset)) in built.into_iter().zip(groups.iter().zip(&offsets)) {
        order[offset..offset + group_ids.len()].copy_from_slice(&group_ids);
        graft(&mut nodes, g.node, sub);
    }
    Bvh::from_parts(nodes, order)
}

/// The top hierarchy over the clusters: every split of a node's clusters along each axis
/// priced by the surface area heuristic (their sorted orders kept per axis and partitioned
/// stably, so each level costs a pass over the clusters), down to one cluster per leaf.
struct Top<'a> {
    clusters: &'a [Cluster],
    /// See [`GROUP`].
    group_max: usize,
    /// The nodes left to the full builder, in the top's order.
    groups: Vec<Group>,
    /// Per axis, the cluster indices sorted by centre (ties by index).
    orders: [Vec<u32>; 3],
    /// Scratch: the half areas of the right sides of a sweep, and the side of each cluster.
    right_areas: Vec<f32>,
    left: Vec<bool>,
    moved: Vec<u32>,
}

impl<'a> Top<'a> {
    fn new(clusters: &'a [Cluster], group_max: usize) -> Self {
        let orders = std::array::from_fn(|axis| {
            let mut o: Vec<u32> = (0..clusters.len() as u32).collect();
            o.sort_by(|&a, &b| {
                let (ca, cb) = (clusters[a as usize].centre, clusters[b as usize].centre);
                ca[axis].total_cmp(&cb[axis]).then(a.cmp(&b))
            });
            o
        });
        Self {
            clusters,
            group_max,
            groups: Vec::new(),
            orders,
            right_areas: vec![0.0; clusters.len()],
            left: vec![false; clusters.len()],
            moved: Vec::with_capacity(clusters.len()),
        }
    }

    /// Fills `nodes` with the top, root at 0, and [`Top::groups`] with its nodes left to the
    /// full builder.
    fn build(&mut self, nodes: &mut Vec<Node>) {
        if self.clusters.is_empty() {
            return;
        }
        nodes.push(Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        self.fill(nodes, 0, 0..self.clusters.len(), 0);
    }

    fn fill(
        &mut self,
        nodes: &mut Vec<Node>,
        index: usize,
        range: std::ops::Range<usize>,
        depth: usize,
    ) {
        let prims: usize = self.orders[0][range.clone()]
            .iter()
            .map(|&c| self.clusters[c as usize].prims.len())
            .sum();
        if range.len() == 1 || prims <= self.group_max {
            self.groups.push(Group {
                node: index,
                depth,
                clusters: range,
            });
            return;
        }
        let (axis, mid) = self.best_split(range.clone(), depth);
        self.partition(range.clone(), axis, mid);
        let first = nodes.len();
        let half = Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        };
        nodes.extend([half, half]);
        nodes[index] = Node {
            bounds: self.bounds(range.clone()),
            first: first as u32,
            count: 0,
        };
        self.fill(nodes, first, range.start..mid, depth + 1);
        self.fill(nodes, first + 1, mid..range.end, depth + 1);
    }

    fn bounds(&self, range: std::ops::Range<usize>) -> Aabb {
        self.orders[0][range]
            .iter()
            .fold(Box3::EMPTY, |b, &c| {
                b.union(self.clusters[c as usize].bounds)
            })
            .aabb()
    }

    /// The cheapest split (axis, position in the range) by half area times slots on each side;
    /// of equal costs the most even. Below [`TOP_DEPTH`], the middle of axis 0.
    fn best_split(&mut self, range: std::ops::Range<usize>, depth: usize) -> (usize, usize) {
        let n = range.len();
        if depth >= TOP_DEPTH {
            return (0, range.start + n / 2);
        }
        let mut best = (f32::INFINITY, usize::MAX, 0, range.start + n / 2);
        for axis in 0..3 {
            let order = &self.orders[axis][range.clone()];
            let mut b = Box3::EMPTY;
            for i in (1..n).rev() {
                b = b.union(self.clusters[order[i] as usize].bounds);
                self.right_areas[i] = b.half_area();
            }
            let total: f32 = order
                .iter()
                .map(|&c| self.clusters[c as usize].slots as f32)
                .sum();
            let (mut b, mut slots) = (Box3::EMPTY, 0.0);
            for i in 1..n {
                let c = &self.clusters[order[i - 1] as usize];
                b = b.union(c.bounds);
                slots += c.slots as f32;
                let cost = b.half_area() * slots + self.right_areas[i] * (total - slots);
                let uneven = n.abs_diff(2 * i);
                if cost < best.0 || (cost == best.0 && uneven < best.1) {
                    best = (cost, uneven, axis, range.start + i);
                }
            }
        }
        (best.2, best.3)
    }

    /// Splits every axis's order of `range` at `mid` by the side `axis`'s order puts each
    /// cluster on, keeping each side sorted.
    fn partition(&mut self, range: std::ops::Range<usize>, axis: usize, mid: usize) {
        for (i, &c) in self.orders[axis][range.clone()].iter().enumerate() {
            self.left[c as usize] = range.start + i < mid;
        }
        for other in (0..3).filter(|&a| a != axis) {
            let order = &mut self.orders[other][range.clone()];
            self.moved.clear();
            let mut kept = 0;
            for i in 0..order.len() {
                let c = order[i];
                if self.left[c as usize] {
                    order[kept] = c;
                    kept += 1;
                } else {
                    self.moved.push(c);
                }
            }
            order[kept..].copy_from_slice(&self.moved);
        }
    }
}

//! The fast builder: primitives sorted in Morton order and cut into clusters of nearby ones
//! ([`morton`]), a surface-area-heuristic top over the clusters' boxes, and inside each cluster
//! the same binned/swept SAH builder as [`super::build`] (after Pantaleoni and Luebke's HLBVH,
//! with SAH instead of Morton splits below the clusters).
//!
//! Why it is faster: the full builder bins and partitions every primitive at every level, about
//! 18 levels on a million triangles; here the top levels cost one radix sort, and the clusters
//! (at most [`CLUSTER`] primitives, so about six levels each) are built where their primitives
//! already sit together in memory. What it gives up: a cluster is an octree cell, so no split
//! above a cluster can cut through one. BENCHMARKS.md ("Build") measures both the speed and the
//! SAH cost against the full builder.

use super::boxes::{Box3, Ref};
use super::{Builder, Span, graft, morton, scan};
use crate::accel::BuildOptions;
use crate::accel::bvh::{Bvh, Node};
use crate::math::Aabb;
use rayon::prelude::*;

/// Largest cluster: small enough that building clusters costs few levels, large enough that
/// the top (a sweep over every split of the clusters) stays cheap and cuts few good subtrees.
const CLUSTER: usize = 256;

/// Top levels deeper than this split their clusters in half instead of by cost, so that
/// degenerate input (every box the same) cannot build a chain as deep as it has clusters.
const TOP_DEPTH: usize = 32;

/// One cluster as the top sees it.
struct Cluster {
    bounds: Box3,
    /// The centre of its box, per axis.
    centre: [f32; 3],
    /// The group lanes its primitives fill: the number of tests the cluster would cost as one leaf.
    slots: f32,
}

/// Where a cluster's subtree goes: the top node it replaces and that node's depth.
#[derive(Clone, Copy, Default)]
struct Place {
    node: usize,
    depth: usize,
}

/// Builds a hierarchy over primitives with the given `bounds`, `ref_of(p)` giving primitive
/// `p` as the builder reads it (see [`super::build`]). The builder's copy of the boxes is made
/// once, already in Morton order (a copy in input order first would be 32 more bytes written
/// per primitive, most of it into freshly faulted pages).
pub(super) fn build(
    bounds: &[Aabb],
    ref_of: impl Fn(usize) -> Ref,
    opts: &BuildOptions,
    builder: &Builder,
) -> Bvh {
    let (mut ids, codes) = morton::sorted(bounds);
    let mut sorted: Vec<Ref> = ids.iter().map(|&p| ref_of(p as usize)).collect();
    let ends = morton::clusters(&codes, CLUSTER.max(opts.max_leaf_size));
    drop(codes);

    // Each cluster's span of the sorted primitives, with its bounds.
    let mut spans = Vec::with_capacity(ends.len());
    let (mut refs_left, mut ids_left) = (&mut sorted[..], &mut ids[..]);
    let mut start = 0;
    for &end in &ends {
        let (r, rest_r) = refs_left.split_at_mut(end - start);
        let (i, rest_i) = ids_left.split_at_mut(end - start);
        (refs_left, ids_left) = (rest_r, rest_i);
        let (bounds, centroids, slots) = scan(r);
        spans.push((
            Span {
                refs: r,
                ids: i,
                bounds,
                centroids,
                slots,
            },
            start,
        ));
        start = end;
    }
    let clusters: Vec<Cluster> = spans
        .iter()
        .map(|(s, _)| {
            let b = s.bounds.aabb();
            let c = (b.min + b.max) * 0.5;
            Cluster {
                bounds: s.bounds,
                centre: [c.x, c.y, c.z],
                slots: s.slots as f32,
            }
        })
        .collect();

    let mut nodes = Vec::with_capacity(start * 2 / 3 + 1);
    let mut places = vec![Place::default(); clusters.len()];
    Top::new(&clusters).build(&mut nodes, &mut places);

    let subtrees: Vec<_> = spans
        .into_par_iter()
        .zip(places.par_iter())
        .map(|((span, offset), place)| builder.subtree(span, offset, place.depth))
        .collect();
    for (sub, place) in subtrees.into_iter().zip(&places) {
        graft(&mut nodes, place.node, sub);
    }
    Bvh::from_parts(nodes, ids)
}

/// The top hierarchy over the clusters: every split of a node's clusters along each axis
/// priced by the surface area heuristic (their sorted orders kept per axis and partitioned
/// stably, so each level costs a pass over the clusters), down to one cluster per leaf.
struct Top<'a> {
    clusters: &'a [Cluster],
    /// Per axis, the cluster indices sorted by centre (ties by index).
    orders: [Vec<u32>; 3],
    /// Scratch: the half areas of the right sides of a sweep, and the side of each cluster.
    right_areas: Vec<f32>,
    left: Vec<bool>,
    moved: Vec<u32>,
}

impl<'a> Top<'a> {
    fn new(clusters: &'a [Cluster]) -> Self {
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
            orders,
            right_areas: vec![0.0; clusters.len()],
            left: vec![false; clusters.len()],
            moved: Vec::with_capacity(clusters.len()),
        }
    }

    /// Fills `nodes` with the top, root at 0; `places[c]` gets the node cluster `c` replaces.
    fn build(&mut self, nodes: &mut Vec<Node>, places: &mut [Place]) {
        if self.clusters.is_empty() {
            return;
        }
        nodes.push(Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        self.fill(nodes, places, 0, 0..self.clusters.len(), 0);
    }

    fn fill(
        &mut self,
        nodes: &mut Vec<Node>,
        places: &mut [Place],
        index: usize,
        range: std::ops::Range<usize>,
        depth: usize,
    ) {
        if range.len() == 1 {
            let c = self.orders[0][range.start] as usize;
            places[c] = Place { node: index, depth };
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
        self.fill(nodes, places, first, range.start..mid, depth + 1);
        self.fill(nodes, places, first + 1, mid..range.end, depth + 1);
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
            let total: f32 = order.iter().map(|&c| self.clusters[c as usize].slots).sum();
            let (mut b, mut slots) = (Box3::EMPTY, 0.0);
            for i in 1..n {
                let c = &self.clusters[order[i - 1] as usize];
                b = b.union(c.bounds);
                slots += c.slots;
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

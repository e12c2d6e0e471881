//! Binned surface-area-heuristic builder (Wald 2007): 16 centroid bins on all three axes at
//! once, in one pass over a node's primitives; a second pass partitions them and gathers both
//! children's bounds and centroid bounds, so no node ever scans its primitives a third time.
//! The two halves of large nodes are built in parallel (rayon); the tree does not depend on
//! how many threads there are, and neither does its layout (see [`Subtree`]).

use super::bvh::{Bvh, MAX_DEPTH, Node};
use super::{BuildOptions, LEAF_ALIGN};
use crate::math::{Aabb, Vec3, Vec3A};

const BINS: usize = 16;
/// Cost of one node visit relative to testing one group of [`LEAF_ALIGN`] primitives: the wide
/// hierarchy tests a node's boxes and a leaf's group of triangles with one SIMD test each.
const TRAVERSAL_COST: f32 = 1.0;

/// The cost of testing primitives that fill `slots` group lanes: whole groups, so leaves fill
/// their groups.
#[inline(always)]
fn leaf_cost(slots: u32) -> f32 {
    slots.div_ceil(LEAF_ALIGN as u32) as f32
}

/// Group lanes a primitive is priced at: a triangle shares its SIMD test with three others,
/// anything else (a sphere) is tested on its own, so it costs a whole group. Priced as one
/// lane, four spheres would always share a leaf, and every ray would test all four.
pub const SHARED_SLOTS: u8 = 1;
/// See [`SHARED_SLOTS`].
pub const ALONE_SLOTS: u8 = LEAF_ALIGN as u8;
/// Nodes with more primitives than this build their two halves as parallel tasks.
const PARALLEL_MIN: usize = 32 * 1024;

/// A box in SIMD registers.
#[derive(Clone, Copy, Debug)]
struct Box3 {
    min: Vec3A,
    max: Vec3A,
}

impl Box3 {
    const EMPTY: Self = Self {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    #[inline(always)]
    fn union(self, o: Self) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    #[inline(always)]
    fn grow(self, p: Vec3A) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Half the surface area (the factor 2 cancels in the cost ratio); 0 when empty.
    #[inline(always)]
    fn half_area(self) -> f32 {
        let e = (self.max - self.min).max(Vec3A::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    fn aabb(self) -> Aabb {
        Aabb {
            min: Vec3::from(self.min),
            max: Vec3::from(self.max),
        }
    }
}

/// What the builder reads of each primitive.
struct Prims<'s> {
    bounds: Vec<Box3>,
    centroids: Vec<Vec3A>,
    /// Group lanes per primitive ([`SHARED_SLOTS`] or [`ALONE_SLOTS`]); empty: all shared.
    slots: &'s [u8],
    max_leaf: usize,
}

/// A node's primitives with the bounds of their boxes and of their centroids.
struct Span<'a> {
    order: &'a mut [u32],
    bounds: Box3,
    centroid_bounds: Box3,
}

/// A subtree built on its own: its root at 0, children pairs after; `first` of interior nodes
/// indexes this vector, `first` of leaves the final primitive order.
struct Subtree {
    nodes: Vec<Node>,
}

/// Builds a SAH hierarchy over primitives with the given bounds, priced by the group lanes
/// each one's test fills (`slots[p]`, see [`ALONE_SLOTS`]; an empty slice prices every
/// primitive as [`SHARED_SLOTS`]).
pub fn build(bounds: &[Aabb], slots: &[u8], opts: &BuildOptions) -> Bvh {
    assert!(slots.is_empty() || slots.len() == bounds.len());
    if bounds.is_empty() {
        return Bvh::from_parts(Vec::new(), Vec::new());
    }
    let prims = Prims {
        bounds: bounds
            .iter()
            .map(|b| Box3 {
                min: b.min.into(),
                max: b.max.into(),
            })
            .collect(),
        centroids: bounds.iter().map(|b| Vec3A::from(b.center())).collect(),
        slots,
        max_leaf: opts.max_leaf_size.max(1),
    };
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    let (mut all, mut centroid_bounds) = (Box3::EMPTY, Box3::EMPTY);
    for (b, c) in prims.bounds.iter().zip(&prims.centroids) {
        all = all.union(*b);
        centroid_bounds = centroid_bounds.grow(*c);
    }
    let span = Span {
        order: &mut order,
        bounds: all,
        centroid_bounds,
    };
    let tree = prims.subtree(span, 0, 0);
    Bvh::from_parts(tree.nodes, order)
}

impl Prims<'_> {
    /// Builds the subtree over `span`, whose primitives start at `offset` in the final order.
    fn subtree(&self, span: Span<'_>, offset: usize, depth: usize) -> Subtree {
        let mut nodes = vec![leaf(&span, offset)];
        self.fill(&mut nodes, 0, span, offset, depth);
        Subtree { nodes }
    }

    /// Makes `nodes[index]` the node over `span` (a leaf, or an interior node whose subtrees
    /// are appended).
    fn fill(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        span: Span<'_>,
        offset: usize,
        depth: usize,
    ) {
        nodes[index] = leaf(&span, offset);
        let n = span.order.len();
        if n <= 1 || depth + 1 >= MAX_DEPTH {
            return;
        }
        let Some((left, right)) = self.split(span) else {
            return;
        };
        let first = nodes.len();
        nodes[index].first = first as u32;
        nodes[index].count = 0;
        let left_n = left.order.len();
        nodes.extend([leaf(&left, offset), leaf(&right, offset + left_n)]);
        if n >= PARALLEL_MIN {
            let (l, r) = rayon::join(
                || self.subtree(left, offset, depth + 1),
                || self.subtree(right, offset + left_n, depth + 1),
            );
            graft(nodes, first, l);
            graft(nodes, first + 1, r);
        } else {
            self.fill(nodes, first, left, offset, depth + 1);
            self.fill(nodes, first + 1, right, offset + left_n, depth + 1);
        }
    }

    /// Splits at the cheapest bin boundary when that beats a leaf (or the node is too big to
    /// be one); `None` makes a leaf.
    fn split<'a>(&self, span: Span<'a>) -> Option<(Span<'a>, Span<'a>)> {
        let n = span.order.len();
        let cb = span.centroid_bounds;
        let extent = cb.max - cb.min;
        // Bins per unit along each axis; 0 for an axis the centroids do not span.
        // (An extent so small that BINS / extent overflows counts as none: the offsets below
        // must stay finite.)
        let per_unit = Vec3A::splat(BINS as f32) / extent;
        let scale = Vec3A::select(
            extent.cmpgt(Vec3A::ZERO) & per_unit.is_finite_mask(),
            per_unit,
            Vec3A::ZERO,
        );
        let mut bins = [[(Box3::EMPTY, 0u32); BINS]; 3];
        for &p in span.order.iter() {
            let c = self.centroids[p as usize];
            let b = self.bounds[p as usize];
            let lanes = self.slots.get(p as usize).map_or(1, |&s| s as u32);
            let bin = bin_indices((c - cb.min) * scale);
            for axis in 0..3 {
                let slot = &mut bins[axis][bin[axis] as usize];
                slot.0 = slot.0.union(b);
                slot.1 += lanes;
            }
        }
        let lanes: u32 = bins[0].iter().map(|b| b.1).sum();
        let parent_area = span.bounds.half_area().max(f32::MIN_POSITIVE);
        let mut best: Option<(usize, usize, f32)> = None;
        for axis in 0..3 {
            if scale[axis] == 0.0 {
                continue;
            }
            let bins = &bins[axis];
            // Sweep from the right to get the area and count right of each boundary.
            // A boundary right after an empty bin costs the same as the one before it, which
            // wins the strict comparison below, so only boundaries after a full bin are priced
            // (the same choice, fewer areas on the small nodes deep in the tree).
            let mut right = [(0.0f32, 0u32); BINS];
            let (mut rb, mut rc) = (Box3::EMPTY, 0);
            for i in (1..BINS).rev() {
                rb = rb.union(bins[i].0);
                rc += bins[i].1;
                if bins[i - 1].1 > 0 {
                    right[i] = (rb.half_area(), rc);
                }
            }
            let (mut lb, mut lc) = (Box3::EMPTY, 0);
            for i in 1..BINS {
                if bins[i - 1].1 == 0 {
                    continue;
                }
                lb = lb.union(bins[i - 1].0);
                lc += bins[i - 1].1;
                let (ra, rc) = right[i];
                if rc == 0 {
                    continue;
                }
                let cost = TRAVERSAL_COST
                    + (lb.half_area() * leaf_cost(lc) + ra * leaf_cost(rc)) / parent_area;
                if best.is_none_or(|b| cost < b.2) {
                    best = Some((axis, i, cost));
                }
            }
        }
        match best {
            Some((axis, bin, cost)) if cost < leaf_cost(lanes) || n > self.max_leaf => {
                let (lo, s) = (cb.min[axis], scale[axis]);
                Some(self.partition(span, |c| bin_index((c[axis] - lo) * s) < bin))
            }
            // All centroids coincide: no plane separates them, so halve by index to keep leaves small.
            None if n > self.max_leaf => {
                let mid = n / 2;
                Some(self.partition_at(span, mid))
            }
            _ => None,
        }
    }

    /// Moves the primitives whose centroid satisfies `left` to the front, gathering both sides'
    /// bounds and centroid bounds on the way.
    fn partition<'a>(&self, span: Span<'a>, left: impl Fn(Vec3A) -> bool) -> (Span<'a>, Span<'a>) {
        let order = span.order;
        let (mut lb, mut lc, mut rb, mut rc) = (Box3::EMPTY, Box3::EMPTY, Box3::EMPTY, Box3::EMPTY);
        let mut mid = 0;
        for i in 0..order.len() {
            let p = order[i] as usize;
            let c = self.centroids[p];
            if left(c) {
                lb = lb.union(self.bounds[p]);
                lc = lc.grow(c);
                order.swap(i, mid);
                mid += 1;
            } else {
                rb = rb.union(self.bounds[p]);
                rc = rc.grow(c);
            }
        }
        let (l, r) = order.split_at_mut(mid);
        (
            Span {
                order: l,
                bounds: lb,
                centroid_bounds: lc,
            },
            Span {
                order: r,
                bounds: rb,
                centroid_bounds: rc,
            },
        )
    }

    /// Splits at position `mid` of the current order.
    fn partition_at<'a>(&self, span: Span<'a>, mid: usize) -> (Span<'a>, Span<'a>) {
        let (l, r) = span.order.split_at_mut(mid);
        let side = |order: &'a mut [u32]| {
            let (mut b, mut c) = (Box3::EMPTY, Box3::EMPTY);
            for &p in order.iter() {
                b = b.union(self.bounds[p as usize]);
                c = c.grow(self.centroids[p as usize]);
            }
            Span {
                order,
                bounds: b,
                centroid_bounds: c,
            }
        };
        (side(l), side(r))
    }
}

/// The bin of a centroid's scaled offset (finite, >= 0); the same result for binning and
/// partitioning, so the partition matches the counts the cost was computed from.
#[inline(always)]
fn bin_index(at: f32) -> usize {
    (at as usize).min(BINS - 1)
}

/// [`bin_index`] of three offsets at once: truncating `min(at, BINS - 1)` is the same as
/// truncating and then clamping, for finite non-negative offsets.
#[inline(always)]
fn bin_indices(at: Vec3A) -> [u32; 4] {
    let clamped = at.min(Vec3A::splat((BINS - 1) as f32));
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let mut out = [0u32; 4];
        // SAFETY: SSE2 is part of the x86-64 baseline; `out` holds four u32.
        unsafe {
            let v = _mm_cvttps_epi32(clamped.into());
            _mm_storeu_si128(out.as_mut_ptr().cast(), v);
        }
        out
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let c = clamped.to_array();
        [c[0] as u32, c[1] as u32, c[2] as u32, 0]
    }
}

/// A leaf over `span`, whose primitives start at `offset`.
fn leaf(span: &Span<'_>, offset: usize) -> Node {
    Node {
        bounds: span.bounds.aabb(),
        first: offset as u32,
        count: span.order.len() as u32,
    }
}

/// Puts a separately built subtree's root at `nodes[at]` and appends the rest, renumbering.
fn graft(nodes: &mut Vec<Node>, at: usize, sub: Subtree) {
    // The subtree's node i > 0 lands at base + i - 1.
    let base = nodes.len();
    let place = |i: u32| (base + i as usize - 1) as u32;
    let fix = |mut n: Node| {
        if !n.is_leaf() {
            n.first = place(n.first);
        }
        n
    };
    nodes[at] = fix(sub.nodes[0]);
    nodes.extend(sub.nodes[1..].iter().map(|&n| fix(n)));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four unit boxes in a row, two units apart.
    fn row_of_four() -> Vec<Aabb> {
        (0..4)
            .map(|i| {
                let x = 3.0 * i as f32;
                Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0))
            })
            .collect()
    }

    #[test]
    fn primitives_tested_alone_are_not_priced_as_sharing_a_group() {
        let bounds = row_of_four();
        let opts = BuildOptions { max_leaf_size: 4 };
        // Four triangles cost one group test together: one leaf.
        let shared = build(&bounds, &[SHARED_SLOTS; 4], &opts);
        assert_eq!(shared.nodes().len(), 1);
        assert_eq!(build(&bounds, &[], &opts).nodes(), shared.nodes());
        // Four spheres cost four tests together: split until each stands alone.
        let alone = build(&bounds, &[ALONE_SLOTS; 4], &opts);
        let leaves: Vec<u32> = alone
            .nodes()
            .iter()
            .filter(|n| n.is_leaf())
            .map(|n| n.count)
            .collect();
        assert_eq!(leaves, [1, 1, 1, 1]);
    }
}

//! Surface-area-heuristic builder. Large nodes are split at the best of 16 centroid bins on
//! all three axes (Wald 2007), found in one pass over their primitives ([`binned`]); small
//! nodes try every split of their primitives sorted along each axis ([`sweep`]), which finds
//! a split at least as cheap and, at that size, costs less than clearing and sweeping 48 bins.
//!
//! The builder works on a copy of the primitive boxes laid out for SIMD ([`Ref`]), reordered
//! in place as nodes are split, with the primitive indices alongside: every pass over a node
//! reads its primitives sequentially. The two halves of large nodes are built in parallel
//! (rayon); the tree does not depend on how many threads there are, and neither does its
//! layout (see [`Subtree`]).

mod binned;
mod boxes;
mod morton;
mod sweep;
mod treelets;

use super::bvh::{Bvh, MAX_DEPTH, Node};
use super::{BuildOptions, BuildQuality, LEAF_ALIGN};
use crate::math::Aabb;
use boxes::{Box3, Centroids, Ref};

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

/// A node's primitives (boxes and indices, reordered together) with the bounds of their
/// boxes and of their doubled centroids, and the group lanes they fill.
struct Span<'a> {
    refs: &'a mut [Ref],
    ids: &'a mut [u32],
    bounds: Box3,
    centroids: Centroids,
    slots: u32,
}

/// What a split knows of one side before it is cut: bounds, centroid bounds, slots.
type Side = (Box3, Centroids, u32);

impl<'a> Span<'a> {
    fn len(&self) -> usize {
        self.refs.len()
    }

    /// Cuts after the first `mid` primitives into sides with the given bounds.
    fn cut(self, mid: usize, left: Side, right: Side) -> (Span<'a>, Span<'a>) {
        let (lr, rr) = self.refs.split_at_mut(mid);
        let (li, ri) = self.ids.split_at_mut(mid);
        let span = |refs, ids, (bounds, centroids, slots): Side| Span {
            refs,
            ids,
            bounds,
            centroids,
            slots,
        };
        (span(lr, li, left), span(rr, ri, right))
    }

    /// Cuts at `mid`, scanning both halves for their bounds (when no plane separates them).
    fn cut_scanning(self, mid: usize) -> (Span<'a>, Span<'a>) {
        let (l, r) = (scan(&self.refs[..mid]), scan(&self.refs[mid..]));
        self.cut(mid, l, r)
    }
}

/// The bounds, centroid bounds and slots of `refs`.
fn scan(refs: &[Ref]) -> Side {
    refs.iter()
        .fold((Box3::EMPTY, Centroids::EMPTY, 0), |(b, c, s), r| {
            (b.union(r.bounds()), c.grow(r.centroid2()), s + r.slots())
        })
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
    let ref_of = |p: usize| Ref::new(&bounds[p], slots.get(p).copied().unwrap_or(SHARED_SLOTS));
    let builder = Builder {
        max_leaf: opts.max_leaf_size.max(1),
        #[cfg(target_arch = "x86_64")]
        avx2: std::arch::is_x86_feature_detected!("avx2"),
    };
    if opts.quality == BuildQuality::Fast {
        return treelets::build(bounds, ref_of, opts, &builder);
    }
    let mut refs: Vec<Ref> = (0..bounds.len()).map(ref_of).collect();
    let mut ids: Vec<u32> = (0..bounds.len() as u32).collect();
    let (all, centroids, slots) = scan(&refs);
    let span = Span {
        refs: &mut refs,
        ids: &mut ids,
        bounds: all,
        centroids,
        slots,
    };
    let tree = builder.subtree(span, 0, 0);
    Bvh::from_parts(tree.nodes, ids)
}

struct Builder {
    max_leaf: usize,
    /// The CPU has AVX2: splits are compiled for it (see [`Builder::split`]).
    #[cfg(target_arch = "x86_64")]
    avx2: bool,
}

impl Builder {
    /// Splits `span`, or keeps it a leaf (`None`): swept when small, binned otherwise. The
    /// splitting code is compiled twice, for the x86-64 baseline and for AVX2 (whose
    /// three-operand instructions and 8-lane boxes take a quarter fewer instructions), and the
    /// CPU picks.
    fn split<'a>(&self, span: Span<'a>) -> Option<(Span<'a>, Span<'a>)> {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: the CPU has AVX2.
            return unsafe { split_avx2(span, self.max_leaf) };
        }
        split_any(span, self.max_leaf)
    }

    /// Builds the subtree over `span`, whose primitives start at `offset` in the final order.
    fn subtree(&self, span: Span<'_>, offset: usize, depth: usize) -> Subtree {
        // About two nodes per leaf of three or four primitives.
        let mut nodes = Vec::with_capacity(span.len() * 2 / 3 + 1);
        nodes.push(leaf(&span, offset));
        self.fill(&mut nodes, 0, span, offset, depth);
        Subtree { nodes }
    }

    /// Makes `nodes[index]` (already the leaf over `span`) an interior node over `span` with
    /// its subtrees appended, unless `span` stays a leaf.
    fn fill(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        span: Span<'_>,
        offset: usize,
        depth: usize,
    ) {
        let n = span.len();
        // A split costs at least a node visit: no less than testing one group.
        let one_group = span.slots <= LEAF_ALIGN as u32 && n <= self.max_leaf;
        if one_group || n <= 1 || depth + 1 >= MAX_DEPTH {
            return;
        }
        let Some((left, right)) = self.split(span) else {
            return;
        };
        let first = nodes.len();
        nodes[index].first = first as u32;
        nodes[index].count = 0;
        let left_n = left.len();
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
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn split_avx2<'a>(span: Span<'a>, max_leaf: usize) -> Option<(Span<'a>, Span<'a>)> {
    split_any(span, max_leaf)
}

#[inline(always)]
fn split_any<'a>(span: Span<'a>, max_leaf: usize) -> Option<(Span<'a>, Span<'a>)> {
    if span.len() <= sweep::MAX_PRIMS {
        sweep::split(span, max_leaf)
    } else {
        binned::split(span, max_leaf)
    }
}

/// A leaf over `span`, whose primitives start at `offset`.
fn leaf(span: &Span<'_>, offset: usize) -> Node {
    Node {
        bounds: span.bounds.aabb(),
        first: offset as u32,
        count: span.len() as u32,
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
mod tests;

//! The split of a small node, the one binning would choose, found without bins: the
//! primitives sorted by bin along each axis, and each boundary between two bins priced. The
//! sides of a boundary hold the primitives of the bins either side of it, so their boxes,
//! slots and cost are those the bins give, and so is the choice (the lowest axis, then the
//! lowest boundary, of the cheapest); but a handful of primitives cost less to sort than 48
//! bins cost to clear and sweep. The three axes are swept together, one SIMD lane each.

mod rank;

use super::boxes::{Box3, Centroids, Ref, half_areas4};
use super::{LEAF_ALIGN, Side, Span, TRAVERSAL_COST, binned, leaf_cost};
use crate::math::Vec4;
use glam::BVec4A;

/// Nodes of up to this many primitives are swept.
pub(super) const MAX_PRIMS: usize = 16;

/// `leaf_cost(k)` for the slots of up to [`MAX_PRIMS`] triangles.
const GROUPS: [f32; MAX_PRIMS + 1] = {
    let mut t = [0.0; MAX_PRIMS + 1];
    let mut k = 0;
    while k <= MAX_PRIMS {
        t[k] = k.div_ceil(LEAF_ALIGN) as f32;
        k += 1;
    }
    t
};

/// Splits at the cheapest boundary when that beats a leaf (or the node is too big to be one);
/// `None` keeps the node a leaf.
#[inline(always)]
pub(super) fn split<'a>(span: Span<'a>, max_leaf: usize) -> Option<(Span<'a>, Span<'a>)> {
    let n = span.len();
    debug_assert!((2..=MAX_PRIMS).contains(&n));
    // A local copy: fixed size, so indexing it by a masked place needs no bounds check.
    let mut refs = [Ref::EMPTY; MAX_PRIMS];
    for (to, from) in refs.iter_mut().zip(span.refs.iter()) {
        *to = *from;
    }
    let bounds = |k: u8| refs[k as usize & (MAX_PRIMS - 1)].bounds();
    let (offset, scale) = (span.centroids.min, binned::scale_of(&span.centroids));
    let mut bins = [[0i32; 4]; MAX_PRIMS];
    for (b, r) in bins.iter_mut().zip(&refs[..n]) {
        *b = binned::bin_of(r.centroid2(), offset, scale);
    }
    // order[axis][k]: the primitive k-th by bin along axis.
    let order = rank::sorted(&bins[..n]);
    let bin = |a: usize, k: usize| bins[order[a][k] as usize & (MAX_PRIMS - 1)][a];
    let s = scale.to_array();
    let spans = [s[0] > 0.0, s[1] > 0.0, s[2] > 0.0, false];
    // Per boundary k, the axes on which it lies between two bins (inside one, binning sees
    // no boundary).
    let mut between = [[false; 4]; MAX_PRIMS];
    for (k, between) in (1..n).zip(&mut between[1..]) {
        *between = std::array::from_fn(|a| a < 3 && spans[a] && bin(a, k - 1) != bin(a, k));
    }
    // Per boundary k (the first k primitives go left), one lane per axis: the areas of both
    // sides.
    let mut left_area = [Vec4::ZERO; MAX_PRIMS];
    let mut right_area = [Vec4::ZERO; MAX_PRIMS];
    let mut side = [Box3::EMPTY; 4];
    for k in 1..n {
        for a in 0..3 {
            side[a] = side[a].union(bounds(order[a][k - 1]));
        }
        left_area[k] = Vec4::from_array(half_areas4(&side));
    }
    side = [Box3::EMPTY; 4];
    for k in (1..n).rev() {
        for a in 0..3 {
            side[a] = side[a].union(bounds(order[a][k]));
        }
        right_area[k] = Vec4::from_array(half_areas4(&side));
    }
    // The best boundary per axis (0: none yet) and its cost: areas weighted by leaf costs,
    // before the parent's area and the traversal are accounted for (the same for all).
    let (mut best, mut best_at) = (Vec4::INFINITY, Vec4::ZERO);
    let mut price = |k: usize, groups_left: Vec4, groups_right: Vec4| {
        let cost = left_area[k] * groups_left + right_area[k] * groups_right;
        let better = cost.cmplt(best) & BVec4A::from_array(between[k]);
        best = Vec4::select(better, cost, best);
        best_at = Vec4::select(better, Vec4::splat(k as f32), best_at);
    };
    if span.slots == n as u32 {
        // Triangles only: k slots on the left.
        for k in 1..n {
            price(k, Vec4::splat(GROUPS[k]), Vec4::splat(GROUPS[n - k]));
        }
    } else {
        let mut slots = [0u32; 3];
        for k in 1..n {
            let mut groups = [[0.0; 4]; 2];
            for a in 0..3 {
                slots[a] += refs[order[a][k - 1] as usize].slots();
                groups[0][a] = leaf_cost(slots[a]);
                groups[1][a] = leaf_cost(span.slots - slots[a]);
            }
            price(k, Vec4::from_array(groups[0]), Vec4::from_array(groups[1]));
        }
    }
    let (best, best_at) = (best.to_array(), best_at.to_array());
    // Ties to the lower axis.
    let axis = (0..3).fold(0, |b, a| if best[a] < best[b] { a } else { b });
    let at = best_at[axis] as usize;
    if at == 0 {
        // No boundary with a finite cost: halve by index, as binning does.
        return (n > max_leaf).then(|| span.cut_scanning(n / 2));
    }
    let parent_area = span.bounds.half_area().max(f32::MIN_POSITIVE);
    let cost = TRAVERSAL_COST + best[axis] / parent_area;
    if !(cost < leaf_cost(span.slots) || n > max_leaf) {
        return None;
    }
    Some(apply(span, &refs, &order[axis], at))
}

/// Reorders the span's primitives (a copy of whose boxes is `refs`) to `order` and cuts it
/// after the first `at`.
#[inline(always)]
fn apply<'a>(
    span: Span<'a>,
    refs: &[Ref; MAX_PRIMS],
    order: &[u8; MAX_PRIMS],
    at: usize,
) -> (Span<'a>, Span<'a>) {
    let n = span.len();
    let mut ids = [0u32; MAX_PRIMS];
    for (to, from) in ids.iter_mut().zip(span.ids.iter()) {
        *to = *from;
    }
    let mut side = |range: std::ops::Range<usize>| {
        let mut s: Side = (Box3::EMPTY, Centroids::EMPTY, 0);
        for k in range {
            let o = order[k] as usize & (MAX_PRIMS - 1);
            let r = refs[o];
            span.refs[k] = r;
            span.ids[k] = ids[o];
            s = (
                s.0.union(r.bounds()),
                s.1.grow(r.centroid2()),
                s.2 + r.slots(),
            );
        }
        s
    };
    let (left, right) = (side(0..at), side(at..n));
    span.cut(at, left, right)
}

// Places and indices are masked with `MAX_PRIMS - 1` to skip bounds checks.
const _: () =
    assert!(MAX_PRIMS.is_power_of_two() && MAX_PRIMS <= u8::MAX as usize && MAX_PRIMS > LEAF_ALIGN);

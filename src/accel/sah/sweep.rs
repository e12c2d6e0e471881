//! The split of a small node: its primitives sorted by centroid along each axis, and every
//! boundary between them priced. Each split a binned pass could choose is one of these, so
//! the node gets a split at least as cheap; and a handful of primitives cost less to sort
//! than 48 bins cost to clear and sweep.

use super::boxes::{Box3, Centroids, Ref};
use super::{LEAF_ALIGN, Side, Span, TRAVERSAL_COST, leaf_cost};

/// Nodes of up to this many primitives are swept.
pub(super) const MAX_PRIMS: usize = 16;

/// Splits at the cheapest boundary when that beats a leaf (or the node is too big to be one);
/// `None` keeps the node a leaf.
pub(super) fn split<'a>(span: Span<'a>, max_leaf: usize) -> Option<(Span<'a>, Span<'a>)> {
    let n = span.len();
    debug_assert!((2..=MAX_PRIMS).contains(&n));
    let refs = &*span.refs;
    let parent_area = span.bounds.half_area().max(f32::MIN_POSITIVE);
    // The first boundary priced is taken even at an infinite or NaN cost (boxes too large for
    // their areas to be finite): a node that must split still gets two non-empty sides.
    let (mut best_cost, mut best_at) = (f32::NAN, 0);
    let mut best_order = [0u8; MAX_PRIMS];
    let mut order = [0u8; MAX_PRIMS];
    // Per boundary k (the first k primitives go left): the right side's area and slots.
    let mut right = [(0.0f32, 0u32); MAX_PRIMS];
    for axis in 0..3 {
        sort_along(refs, axis, &mut order[..n]);
        let (mut rb, mut rs) = (Box3::EMPTY, 0);
        for k in (1..n).rev() {
            let r = &refs[order[k] as usize];
            rb = rb.union(r.bounds());
            rs += r.slots();
            right[k] = (rb.half_area(), rs);
        }
        let (mut lb, mut ls) = (Box3::EMPTY, 0);
        let mut improved = false;
        for k in 1..n {
            let r = &refs[order[k - 1] as usize];
            lb = lb.union(r.bounds());
            ls += r.slots();
            let (ra, rs) = right[k];
            let cost = TRAVERSAL_COST
                + (lb.half_area() * leaf_cost(ls) + ra * leaf_cost(rs)) / parent_area;
            if cost < best_cost || best_at == 0 {
                (best_cost, best_at, improved) = (cost, k, true);
            }
        }
        if improved {
            best_order = order;
        }
    }
    if !(best_cost < leaf_cost(span.slots) || n > max_leaf) {
        return None;
    }
    Some(apply(span, &best_order[..n], best_at))
}

/// Reorders the span's primitives to `order` and cuts it after the first `at`.
fn apply<'a>(span: Span<'a>, order: &[u8], at: usize) -> (Span<'a>, Span<'a>) {
    let n = order.len();
    let mut refs = [span.refs[0]; MAX_PRIMS];
    let mut ids = [0u32; MAX_PRIMS];
    refs[..n].copy_from_slice(span.refs);
    ids[..n].copy_from_slice(span.ids);
    let mut sides: [Side; 2] = [(Box3::EMPTY, Centroids::EMPTY, 0); 2];
    for (k, &o) in order.iter().enumerate() {
        let r = refs[o as usize];
        span.refs[k] = r;
        span.ids[k] = ids[o as usize];
        let (b, c, s) = &mut sides[(k >= at) as usize];
        (*b, *c, *s) = (b.union(r.bounds()), c.grow(r.centroid2()), *s + r.slots());
    }
    span.cut(at, sides[0], sides[1])
}

/// Fills `order` with the indices of `refs` sorted by centroid along `axis` (ties in index
/// order, so the result depends only on the primitives' order).
fn sort_along(refs: &[Ref], axis: usize, order: &mut [u8]) {
    let mut keys = [0u64; MAX_PRIMS];
    for (k, r) in refs.iter().enumerate() {
        keys[k] = (ordered(r.centroid2_on(axis)) as u64) << 32 | k as u64;
    }
    let keys = &mut keys[..refs.len()];
    // Insertion sort: a few comparisons for the handful of keys here.
    for i in 1..keys.len() {
        let key = keys[i];
        let mut j = i;
        while j > 0 && keys[j - 1] > key {
            keys[j] = keys[j - 1];
            j -= 1;
        }
        keys[j] = key;
    }
    for (o, k) in order.iter_mut().zip(keys.iter()) {
        *o = *k as u8;
    }
}

/// The bits of `x` as an unsigned integer in the order of the floats (negatives reversed).
#[inline(always)]
fn ordered(x: f32) -> u32 {
    let b = x.to_bits();
    if b >> 31 == 1 { !b } else { b | 1 << 31 }
}

const _: () = assert!(MAX_PRIMS <= u8::MAX as usize && MAX_PRIMS > LEAF_ALIGN);

//! The split of a large node: its primitives' centroids binned on all three axes in one pass,
//! the cheapest bin boundary chosen on all three at once, and the primitives partitioned in
//! place around it.

mod gather;

use super::boxes::{Box3, Centroids, Ref, half_areas4};
use super::{LEAF_ALIGN, Side, Span, TRAVERSAL_COST, leaf_cost};
use crate::math::{Vec3A, Vec4};
use glam::BVec4A;

/// Bins per axis.
const BINS: usize = 16;

/// The bins of all three axes, bin-major (`[bin][axis]`, axis 3 unused), so one bin's three
/// axes are priced together. Each count takes 8 bytes, a quarter of a box, so the binning loop
/// addresses a bin's box and count with one index (see [`gather`]).
#[repr(C, align(32))]
struct Bins {
    boxes: [[Box3; 4]; BINS],
    slots: [[[u32; 2]; 4]; BINS],
}

/// Slot counts of one boundary side, one lane per axis.
struct Counts {
    /// Each lane's [`leaf_cost`].
    groups: Vec4,
    /// Lanes with any primitive.
    any: BVec4A,
}

impl Counts {
    #[inline(always)]
    fn of(slots: [u32; 4]) -> Self {
        let f = |f: fn(u32) -> u32| Vec4::from_array(slots.map(|s| f(s) as i32 as f32));
        Self {
            groups: f(|s| s.div_ceil(LEAF_ALIGN as u32)),
            any: f(|s| s).cmpgt(Vec4::ZERO),
        }
    }
}

/// The chosen boundary: the primitives of bins `< bin` on `axis` go left.
struct Choice {
    axis: usize,
    bin: usize,
    /// Areas weighted by leaf costs, before the parent's area and the traversal.
    cost: f32,
}

/// Splits at the cheapest bin boundary when that beats a leaf (or the node is too big to be
/// one); `None` keeps the node a leaf.
#[inline(always)]
pub(super) fn split<'a>(span: Span<'a>, max_leaf: usize) -> Option<(Span<'a>, Span<'a>)> {
    let n = span.len();
    let cb = span.centroids;
    let scale = scale_of(&cb);
    let mut bins = Bins {
        boxes: [[Box3::EMPTY; 4]; BINS],
        slots: [[[0; 2]; 4]; BINS],
    };
    gather::gather(&mut bins, span.refs, span.slots == n as u32, cb.min, scale);
    let Some(c) = bins.choose(scale) else {
        // No plane separates the centroids (or no boundary has a finite cost): halve by index
        // to keep leaves small.
        return (n > max_leaf).then(|| span.cut_scanning(n / 2));
    };
    let parent_area = span.bounds.half_area().max(f32::MIN_POSITIVE);
    if !(TRAVERSAL_COST + c.cost / parent_area < leaf_cost(span.slots) || n > max_leaf) {
        return None;
    }
    let (left, right) = bins.sides(&c);
    let (lo, s) = (cb.min.to_array()[c.axis], scale.to_array()[c.axis]);
    // `bin_index(x) < bin` is `x < bin` for the offsets `x >= 0` (or NaN) binned here.
    let threshold = c.bin as f32;
    // One loop per axis, so the coordinate read is fixed at compile time.
    Some(match c.axis {
        0 => partition(span, left, right, |r| {
            (r.centroid2_on(0) - lo) * s < threshold
        }),
        1 => partition(span, left, right, |r| {
            (r.centroid2_on(1) - lo) * s < threshold
        }),
        _ => partition(span, left, right, |r| {
            (r.centroid2_on(2) - lo) * s < threshold
        }),
    })
}

/// Bins per unit along each axis; 0 for an axis the centroids do not span. (An extent so
/// small that `BINS / extent` overflows counts as none: the offsets binned must stay finite.)
#[inline(always)]
pub(super) fn scale_of(cb: &Centroids) -> Vec3A {
    let extent = cb.max - cb.min;
    let per_unit = Vec3A::splat(BINS as f32) / extent;
    Vec3A::select(
        extent.cmpgt(Vec3A::ZERO) & per_unit.is_finite_mask(),
        per_unit,
        Vec3A::ZERO,
    )
}

/// The bin of each axis of a centroid (lane 3: 0), for the node's centroid bounds starting at
/// `offset` and `scale` ([`scale_of`]): the bins [`gather`] counts it in.
#[inline(always)]
pub(super) fn bin_of(centroid: Vec3A, offset: Vec3A, scale: Vec3A) -> [i32; 4] {
    let at = (centroid - offset) * scale;
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let clamped = at.min(Vec3A::splat((BINS - 1) as f32));
        // SAFETY: SSE2 is part of the x86-64 baseline; truncating the clamped offsets (in
        // 0..16) gives the bins `gather::bin_indices` gives.
        unsafe {
            let bins = _mm_and_si128(_mm_cvttps_epi32(clamped.into()), _mm_set1_epi32(15));
            std::mem::transmute::<__m128i, [i32; 4]>(_mm_and_si128(
                bins,
                _mm_setr_epi32(-1, -1, -1, 0),
            ))
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let [x, y, z] = gather::bin_indices(at);
        [x as i32, y as i32, z as i32, 0]
    }
}

impl Bins {
    /// The cheapest boundary with primitives on both sides, over the axes the centroids span
    /// (ties to the lower axis, then the lower boundary); `None` if no boundary has a finite
    /// cost.
    #[inline(always)]
    fn choose(&self, scale: Vec3A) -> Option<Choice> {
        // Per boundary i (bins < i go left), one lane per axis: the area and slots right of it.
        let mut right_area = [Vec4::ZERO; BINS];
        let mut right_slots = [[0u32; 4]; BINS];
        let (mut r, mut rs) = ([Box3::EMPTY; 4], [0u32; 4]);
        for i in (1..BINS).rev() {
            for a in 0..3 {
                r[a] = r[a].union(self.boxes[i][a]);
                rs[a] += self.slots(i, a);
            }
            right_area[i] = Vec4::from_array(half_areas4(&r));
            right_slots[i] = rs;
        }
        let s = scale.to_array();
        let spans = Vec4::new(s[0], s[1], s[2], 0.0).cmpgt(Vec4::ZERO);
        let (mut best, mut best_bin) = (Vec4::INFINITY, Vec4::ZERO);
        let (mut l, mut ls) = ([Box3::EMPTY; 4], [0u32; 4]);
        for i in 1..BINS {
            for a in 0..3 {
                l[a] = l[a].union(self.boxes[i - 1][a]);
                ls[a] += self.slots(i - 1, a);
            }
            let (left, right) = (Counts::of(ls), Counts::of(right_slots[i]));
            let cost =
                Vec4::from_array(half_areas4(&l)) * left.groups + right_area[i] * right.groups;
            // A boundary after an empty bin costs the same as the one before it, which the
            // strict comparison keeps.
            let better = cost.cmplt(best) & spans & left.any & right.any;
            best = Vec4::select(better, cost, best);
            best_bin = Vec4::select(better, Vec4::splat(i as f32), best_bin);
        }
        let (best, best_bin) = (best.to_array(), best_bin.to_array());
        let axis = (0..3).fold(0, |b, a| if best[a] < best[b] { a } else { b });
        (best[axis] < f32::INFINITY).then_some(Choice {
            axis,
            bin: best_bin[axis] as usize,
            cost: best[axis],
        })
    }

    /// The slots counted in bin `bin` of `axis`.
    #[inline(always)]
    fn slots(&self, bin: usize, axis: usize) -> u32 {
        self.slots[bin][axis][0]
    }

    /// The bounds and slots of the two sides of `c`: the unions of their bins.
    #[inline(always)]
    fn sides(&self, c: &Choice) -> ((Box3, u32), (Box3, u32)) {
        let side = |bins: std::ops::Range<usize>| {
            bins.fold((Box3::EMPTY, 0), |(b, s), i| {
                (b.union(self.boxes[i][c.axis]), s + self.slots(i, c.axis))
            })
        };
        (side(0..c.bin), side(c.bin..BINS))
    }
}

/// Moves the primitives satisfying `is_left` to the front (Hoare: each primitive is classified
/// once, and only misplaced pairs move), gathering both sides' centroid bounds on the way.
#[inline(always)]
fn partition<'a>(
    span: Span<'a>,
    (left_bounds, left_slots): (Box3, u32),
    (right_bounds, right_slots): (Box3, u32),
    is_left: impl Fn(&Ref) -> bool,
) -> (Span<'a>, Span<'a>) {
    let (refs, ids) = (&mut *span.refs, &mut *span.ids);
    let (mut lc, mut rc) = (Centroids::EMPTY, Centroids::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    loop {
        while i < j && is_left(&refs[i]) {
            lc = lc.grow(refs[i].centroid2());
            i += 1;
        }
        while i < j && !is_left(&refs[j - 1]) {
            rc = rc.grow(refs[j - 1].centroid2());
            j -= 1;
        }
        if i >= j {
            break;
        }
        // refs[i] belongs right and refs[j - 1] left.
        j -= 1;
        let (right, left) = (refs[i], refs[j]);
        (refs[i], refs[j]) = (left, right);
        ids.swap(i, j);
        lc = lc.grow(left.centroid2());
        rc = rc.grow(right.centroid2());
        i += 1;
    }
    let left: Side = (left_bounds, lc, left_slots);
    span.cut(i, left, (right_bounds, rc, right_slots))
}

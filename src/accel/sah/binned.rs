//! The split of a large node: its primitives' centroids binned on all three axes in one pass,
//! the cheapest bin boundary chosen, and the primitives partitioned in place around it.

use super::boxes::{Box3, Centroids, Ref};
use super::{Side, Span, TRAVERSAL_COST, leaf_cost};
use crate::math::Vec3A;

/// Bins per axis.
const BINS: usize = 16;

/// The boxes and slot counts of each axis's bins.
struct Bins {
    boxes: [[Box3; BINS]; 3],
    slots: [[u32; BINS]; 3],
}

/// The chosen boundary: the primitives of bins `< bin` on `axis` go left.
struct Choice {
    axis: usize,
    bin: usize,
    cost: f32,
}

/// Splits at the cheapest bin boundary when that beats a leaf (or the node is too big to be
/// one); `None` keeps the node a leaf.
pub(super) fn split<'a>(span: Span<'a>, max_leaf: usize) -> Option<(Span<'a>, Span<'a>)> {
    let n = span.len();
    let cb = span.centroids;
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
    let mut bins = Bins {
        boxes: [[Box3::EMPTY; BINS]; 3],
        slots: [[0; BINS]; 3],
    };
    // Spans of triangles only (one slot each) count primitives without reading their slots.
    if span.slots == n as u32 {
        bins.gather::<false>(span.refs, cb.min, scale);
    } else {
        bins.gather::<true>(span.refs, cb.min, scale);
    }
    let parent_area = span.bounds.half_area().max(f32::MIN_POSITIVE);
    match bins.choose(scale, parent_area) {
        Some(c) if c.cost < leaf_cost(span.slots) || n > max_leaf => {
            let (left, right) = bins.sides(&c);
            let (lo, s) = (cb.min.to_array()[c.axis], scale.to_array()[c.axis]);
            // `bin_index(x) < bin` is `x < bin` for the offsets `x >= 0` (or NaN) binned here.
            let threshold = c.bin as f32;
            let is_left = |r: &Ref| (r.centroid2_on(c.axis) - lo) * s < threshold;
            Some(partition(span, left, right, is_left))
        }
        // All centroids coincide: no plane separates them, so halve by index to keep leaves small.
        None if n > max_leaf => Some(span.cut_scanning(n / 2)),
        _ => None,
    }
}

impl Bins {
    /// Counts the slots of each primitive in, and grows the box of, its centroid's bin on
    /// every axis. `MIXED`: the primitives' slots are read (else each counts one).
    #[inline(always)]
    fn gather<const MIXED: bool>(&mut self, refs: &[Ref], offset: Vec3A, scale: Vec3A) {
        for r in refs {
            let at = bin_indices((r.centroid2() - offset) * scale);
            let slots = if MIXED { r.slots() } else { 1 };
            for (axis, &bin) in at.iter().take(3).enumerate() {
                let bin = bin as usize & (BINS - 1);
                let b = &mut self.boxes[axis][bin];
                *b = b.union(r.bounds());
                self.slots[axis][bin] += slots;
            }
        }
    }

    /// The cheapest boundary over the axes the centroids span, if any.
    fn choose(&self, scale: Vec3A, parent_area: f32) -> Option<Choice> {
        let mut best: Option<Choice> = None;
        for axis in 0..3 {
            if scale[axis] == 0.0 {
                continue;
            }
            let (boxes, counts) = (&self.boxes[axis], &self.slots[axis]);
            // Sweep from the right to get the area and count right of each boundary.
            // A boundary right after an empty bin costs the same as the one before it, which
            // wins the strict comparison below, so only boundaries after a full bin are priced.
            let mut right = [(0.0f32, 0u32); BINS];
            let (mut rb, mut rc) = (Box3::EMPTY, 0);
            for i in (1..BINS).rev() {
                rb = rb.union(boxes[i]);
                rc += counts[i];
                if counts[i - 1] > 0 {
                    right[i] = (rb.half_area(), rc);
                }
            }
            let (mut lb, mut lc) = (Box3::EMPTY, 0);
            for i in 1..BINS {
                if counts[i - 1] == 0 {
                    continue;
                }
                lb = lb.union(boxes[i - 1]);
                lc += counts[i - 1];
                let (ra, rc) = right[i];
                if rc == 0 {
                    continue;
                }
                let cost = TRAVERSAL_COST
                    + (lb.half_area() * leaf_cost(lc) + ra * leaf_cost(rc)) / parent_area;
                if best.as_ref().is_none_or(|b| cost < b.cost) {
                    best = Some(Choice { axis, bin: i, cost });
                }
            }
        }
        best
    }

    /// The bounds and slots of the two sides of `c`: the unions of their bins.
    fn sides(&self, c: &Choice) -> ((Box3, u32), (Box3, u32)) {
        let (boxes, slots) = (&self.boxes[c.axis], &self.slots[c.axis]);
        let union = |bins: &[Box3]| bins.iter().fold(Box3::EMPTY, |a, &b| a.union(b));
        (
            (union(&boxes[..c.bin]), slots[..c.bin].iter().sum()),
            (union(&boxes[c.bin..]), slots[c.bin..].iter().sum()),
        )
    }
}

/// Moves the primitives satisfying `is_left` to the front (Hoare: each primitive is classified
/// once, and only misplaced pairs move), gathering both sides' centroid bounds on the way.
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
        refs.swap(i, j - 1);
        ids.swap(i, j - 1);
        lc = lc.grow(refs[i].centroid2());
        rc = rc.grow(refs[j - 1].centroid2());
        i += 1;
        j -= 1;
    }
    let left: Side = (left_bounds, lc, left_slots);
    span.cut(i, left, (right_bounds, rc, right_slots))
}

/// The bins of three scaled offsets (finite and >= 0, or NaN): truncated after clamping to the
/// last bin (NaN clamps to it too), the same as truncating and then clamping.
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

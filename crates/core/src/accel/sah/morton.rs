//! Morton order for the fast builder ([`super::treelets`]): primitives sorted along a Z-order
//! curve through their centroids, and that order cut into clusters of nearby primitives at the
//! curve's own octree boundaries.

use super::boxes::Centroids;
use crate::math::{Aabb, Vec3A};

/// Bits per axis of a code: 1,024 cells along each, 30 bits in all.
const BITS: u32 = 10;
/// Bits sorted per radix pass: three passes over 30 bits, 1,024 counters (4 KiB, in L1).
const RADIX: u32 = 10;

/// The primitives with boxes `bounds` in Morton order of their centroids (quantised over the
/// centroids' bounds into cubic cells), with their codes in that order. Equal codes keep their
/// input order, so the order depends on nothing but the input.
pub(super) fn sorted(bounds: &[Aabb]) -> (Vec<u32>, Vec<u32>) {
    // Doubled centroids, as the builder's (`Ref::centroid2`): the factor cancels in the scale.
    let centroid2 = |b: &Aabb| Vec3A::from(b.min) + Vec3A::from(b.max);
    let cb = bounds
        .iter()
        .fold(Centroids::EMPTY, |c, b| c.grow(centroid2(b)));
    // One scale for all axes, so that the octree's cells are cubes: scaled per axis, a flat
    // model's cells would be slabs across its thin axis, and clusters slices of its surface.
    let cells = (1u32 << BITS) as f32;
    let per_unit = cells / (cb.max - cb.min).max_element();
    // An infinite or zero extent (every centroid the same) puts all of them in cell 0.
    let scale = if per_unit.is_finite() { per_unit } else { 0.0 };
    let codes: Vec<u32> = bounds
        .iter()
        .map(|b| {
            let at = ((centroid2(b) - cb.min) * scale).min(Vec3A::splat(cells - 1.0));
            // `as` saturates: a NaN or negative offset (from rounding) lands in cell 0.
            interleave(at.x as u32) | interleave(at.y as u32) << 1 | interleave(at.z as u32) << 2
        })
        .collect();
    radix_sort(codes)
}

/// Spreads the low [`BITS`] bits of `v` to every third bit.
fn interleave(v: u32) -> u32 {
    let mut x = v & 0x3ff;
    x = (x | x << 16) & 0x0300_00ff;
    x = (x | x << 8) & 0x0300_f00f;
    x = (x | x << 4) & 0x030c_30c3;
    (x | x << 2) & 0x0924_9249
}

/// Stable least-significant-digit radix sort of `codes`: the permutation (input index per
/// output position) and the sorted codes.
fn radix_sort(codes: Vec<u32>) -> (Vec<u32>, Vec<u32>) {
    let n = codes.len();
    let mut keys = codes;
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut keys_out = vec![0u32; n];
    let mut order_out = vec![0u32; n];
    let mask = (1u32 << RADIX) - 1;
    for pass in 0..(3 * BITS).div_ceil(RADIX) {
        let shift = pass * RADIX;
        let mut starts = vec![0usize; 1 << RADIX];
        for &k in &keys {
            starts[((k >> shift) & mask) as usize] += 1;
        }
        let mut sum = 0;
        for s in &mut starts {
            (*s, sum) = (sum, sum + *s);
        }
        for (&k, &o) in keys.iter().zip(&order) {
            let digit = ((k >> shift) & mask) as usize;
            keys_out[starts[digit]] = k;
            order_out[starts[digit]] = o;
            starts[digit] += 1;
        }
        std::mem::swap(&mut keys, &mut keys_out);
        std::mem::swap(&mut order, &mut order_out);
    }
    (order, keys)
}

/// Cuts sorted `codes` into consecutive clusters of at most `max` primitives, each a cell of the
/// octree the codes describe (split at the highest bit in which a range's codes differ), or half
/// of a run of equal codes; returns the end of each cluster, in order.
pub(super) fn clusters(codes: &[u32], max: usize) -> Vec<usize> {
    let mut ends = Vec::with_capacity(codes.len() / max.max(1) * 2 + 1);
    // An explicit stack of ranges, right half pushed first, so clusters come out in order.
    let mut todo = vec![(0, codes.len())];
    while let Some((lo, hi)) = todo.pop() {
        if hi - lo <= max {
            if hi > lo {
                ends.push(hi);
            }
            continue;
        }
        let differ = codes[lo] ^ codes[hi - 1];
        let mid = if differ == 0 {
            lo + (hi - lo) / 2
        } else {
            let bit = 1u32 << (31 - differ.leading_zeros());
            lo + codes[lo..hi].partition_point(|&c| c & bit == 0)
        };
        todo.push((mid, hi));
        todo.push((lo, mid));
    }
    ends
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interleave_spreads_each_bit_to_every_third_position() {
        for b in 0..BITS {
            assert_eq!(interleave(1 << b), 1 << (3 * b));
        }
        assert_eq!(interleave(0x3ff), 0x0924_9249);
    }

    #[test]
    fn radix_sort_is_a_stable_sort() {
        let mut state = 12345u64;
        let codes: Vec<u32> = (0..5000)
            .map(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                // Few distinct values, so stability is exercised.
                ((state >> 33) as u32 % 97) << 20 | ((state >> 40) as u32 & 7)
            })
            .collect();
        let (order, sorted) = radix_sort(codes.clone());
        let mut expect: Vec<u32> = (0..codes.len() as u32).collect();
        expect.sort_by_key(|&i| codes[i as usize]);
        assert_eq!(order, expect);
        assert!(
            sorted
                .iter()
                .zip(&order)
                .all(|(&c, &i)| c == codes[i as usize])
        );
    }

    #[test]
    fn clusters_cover_the_codes_in_cells_of_bounded_size() {
        let codes: Vec<u32> = (0..1000u32).map(|i| i / 3 * 5).collect();
        for max in [1, 4, 64, 2000] {
            let ends = clusters(&codes, max);
            let mut start = 0;
            for &end in &ends {
                assert!(end > start && end - start <= max);
                start = end;
            }
            assert_eq!(start, codes.len());
        }
        // Equal codes are halved until they fit.
        let same = vec![7u32; 100];
        let ends = clusters(&same, 10);
        assert_eq!(ends.len(), 16);
        assert!(clusters(&[], 4).is_empty());
    }
}

//! Sorting a small node's primitives by centroid along all three axes at once: each one's
//! place is the number of centroids before it, counted with one SIMD comparison per pair of
//! primitives for all three axes (n^2 / 2 comparisons, no branches; n is at most 16).

use super::MAX_PRIMS;
use crate::accel::sah::boxes::Ref;

/// `order[axis][k]`: the index of the primitive k-th by centroid along `axis`, ties in index
/// order (so the result depends only on the primitives' order).
#[inline(always)]
pub(super) fn sorted(refs: &[Ref]) -> [[u8; MAX_PRIMS]; 3] {
    debug_assert!(refs.len() <= MAX_PRIMS);
    let places = places(refs);
    let mut order = [[0u8; MAX_PRIMS]; 3];
    for (i, place) in places.iter().enumerate().take(refs.len()) {
        for a in 0..3 {
            order[a][place[a] as usize & (MAX_PRIMS - 1)] = i as u8;
        }
    }
    order
}

/// Each primitive's place along each axis.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn places(refs: &[Ref]) -> [[u32; 4]; MAX_PRIMS] {
    use std::arch::x86_64::*;
    let n = refs.len();
    // SAFETY (whole body): SSE2 is part of the x86-64 baseline.
    unsafe {
        // Centroid bits as integers in the order of the floats, signed: negative floats have
        // their magnitude bits flipped.
        let mut keys = [_mm_setzero_si128(); MAX_PRIMS];
        for (key, r) in keys.iter_mut().zip(refs) {
            let bits = _mm_castps_si128(r.centroid2().into());
            let flip = _mm_and_si128(_mm_srai_epi32::<31>(bits), _mm_set1_epi32(i32::MAX));
            *key = _mm_xor_si128(bits, flip);
        }
        // Place of i: the keys below it, and the equal keys of lower index. Each pair j < i
        // is compared once: `j > i` (all ones) moves j up one place, else i.
        let mut place: [__m128i; MAX_PRIMS] = std::array::from_fn(|i| _mm_set1_epi32(i as i32));
        for i in 1..n {
            for j in 0..i {
                let above = _mm_cmpgt_epi32(keys[j], keys[i]);
                place[i] = _mm_add_epi32(place[i], above);
                place[j] = _mm_sub_epi32(place[j], above);
            }
        }
        place.map(|p| std::mem::transmute::<__m128i, [u32; 4]>(p))
    }
}

/// Each primitive's place along each axis (without SIMD: sorted one axis at a time).
#[cfg(not(target_arch = "x86_64"))]
fn places(refs: &[Ref]) -> [[u32; 4]; MAX_PRIMS] {
    let mut places = [[0u32; 4]; MAX_PRIMS];
    for a in 0..3 {
        let mut idx: Vec<usize> = (0..refs.len()).collect();
        idx.sort_by(|&i, &j| {
            let (ci, cj) = (refs[i].centroid2_on(a), refs[j].centroid2_on(a));
            ci.total_cmp(&cj).then(i.cmp(&j))
        });
        for (p, &i) in idx.iter().enumerate() {
            places[i][a] = p as u32;
        }
    }
    places
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Aabb, Vec3};

    /// The places are those of a plain sort by centroid, ties (here: many) in index order.
    #[test]
    fn places_are_those_of_a_sort() {
        let coords = [
            3.0, -1.0, 3.0, 0.0, -0.0, 7.5, -1.0, 3.0, 2.0, 2.0, -9.0, 3.0, 0.5, 1.0,
        ];
        for n in [2, 5, 9, MAX_PRIMS] {
            let refs: Vec<Ref> = (0..n)
                .map(|i| {
                    let c = |k: usize| coords[(i * 5 + k * 3) % coords.len()];
                    let p = Vec3::new(c(0), c(1), c(2));
                    Ref::new(&Aabb::new(p, p), 1)
                })
                .collect();
            let order = sorted(&refs);
            for (a, order) in order.iter().enumerate() {
                let mut expected: Vec<usize> = (0..n).collect();
                expected.sort_by(|&i, &j| {
                    let (ci, cj) = (refs[i].centroid2_on(a), refs[j].centroid2_on(a));
                    ci.total_cmp(&cj).then(i.cmp(&j))
                });
                let got: Vec<usize> = order[..n].iter().map(|&i| i as usize).collect();
                assert_eq!(got, expected, "axis {a}, {n} primitives");
            }
        }
    }
}

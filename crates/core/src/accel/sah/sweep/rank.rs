//! Sorting a small node's primitives by a key on each axis, all three axes at once: each
//! one's place is the number of keys before it, counted with one SIMD comparison per pair of
//! primitives for all three axes (n^2 / 2 comparisons, no branches; n is at most 16).

use super::MAX_PRIMS;

/// `order[axis][k]`: the index of the primitive k-th by `keys[..][axis]`, ties in index order
/// (so the result depends only on the primitives' order).
#[inline(always)]
pub(super) fn sorted(keys: &[[i32; 4]]) -> [[u8; MAX_PRIMS]; 3] {
    debug_assert!(keys.len() <= MAX_PRIMS);
    let places = places(keys);
    let mut order = [[0u8; MAX_PRIMS]; 3];
    for (i, place) in places.iter().enumerate().take(keys.len()) {
        for a in 0..3 {
            order[a][place[a] as usize & (MAX_PRIMS - 1)] = i as u8;
        }
    }
    order
}

/// Each primitive's place along each axis.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn places(keys: &[[i32; 4]]) -> [[u32; 4]; MAX_PRIMS] {
    use std::arch::x86_64::*;
    let n = keys.len();
    // SAFETY (whole body): SSE2 is part of the x86-64 baseline; a key is four i32.
    unsafe {
        let keys: [__m128i; MAX_PRIMS] = std::array::from_fn(|i| {
            keys.get(i)
                .map_or(_mm_setzero_si128(), |k| _mm_loadu_si128(k.as_ptr().cast()))
        });
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
fn places(keys: &[[i32; 4]]) -> [[u32; 4]; MAX_PRIMS] {
    let mut places = [[0u32; 4]; MAX_PRIMS];
    for a in 0..3 {
        let mut idx: Vec<usize> = (0..keys.len()).collect();
        idx.sort_by_key(|&i| (keys[i][a], i));
        for (p, &i) in idx.iter().enumerate() {
            places[i][a] = p as u32;
        }
    }
    places
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The places are those of a plain sort by key, ties (here: many) in index order.
    #[test]
    fn places_are_those_of_a_sort() {
        let coords = [
            3,
            -1,
            3,
            0,
            0,
            7,
            -1,
            3,
            2,
            2,
            -9,
            3,
            5,
            1,
            i32::MAX,
            i32::MIN,
        ];
        for n in [2, 5, 9, MAX_PRIMS] {
            let keys: Vec<[i32; 4]> = (0..n)
                .map(|i| std::array::from_fn(|k| coords[(i * 5 + k * 3) % coords.len()]))
                .collect();
            let order = sorted(&keys);
            for (a, order) in order.iter().enumerate() {
                let mut expected: Vec<usize> = (0..n).collect();
                expected.sort_by_key(|&i| (keys[i][a], i));
                let got: Vec<usize> = order[..n].iter().map(|&i| i as usize).collect();
                assert_eq!(got, expected, "axis {a}, {n} primitives");
            }
        }
    }
}

//! The binning pass: every primitive's box grows, and its slots count in, its centroid's bin
//! on each axis. The hottest loop of the build, so it has an AVX2 version: one 32-byte load
//! per primitive, and one 8-lane minimum and store per axis (the boxes are `(min, -max)`).

use super::{BINS, Bins};
use crate::accel::sah::boxes::Ref;
use crate::math::Vec3A;

/// Bins `refs` at `(centroid - offset) * scale` (bins per unit, 0 on an axis not binned).
/// `uniform`: every primitive has one slot.
pub(super) fn gather(bins: &mut Bins, refs: &[Ref], uniform: bool, offset: Vec3A, scale: Vec3A) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2.
        unsafe {
            if uniform {
                avx2::<false>(bins, refs, offset, scale);
            } else {
                avx2::<true>(bins, refs, offset, scale);
            }
        }
        return;
    }
    if uniform {
        portable::<false>(bins, refs, offset, scale);
    } else {
        portable::<true>(bins, refs, offset, scale);
    }
}

/// The bin of each axis: the scaled offset (finite and >= 0, or NaN) clamped to the last bin
/// (NaN clamps to it too), then truncated.
#[inline(always)]
pub(super) fn bin_indices(at: Vec3A) -> [usize; 3] {
    at.min(Vec3A::splat((BINS - 1) as f32))
        .to_array()
        .map(|x| x as usize & (BINS - 1))
}

/// `MIXED`: the primitives' slots are read (else each counts one).
fn portable<const MIXED: bool>(bins: &mut Bins, refs: &[Ref], offset: Vec3A, scale: Vec3A) {
    for r in refs {
        let at = bin_indices((r.centroid2() - offset) * scale);
        let slots = if MIXED { r.slots() } else { 1 };
        for (axis, &bin) in at.iter().enumerate() {
            let b = &mut bins.boxes[bin][axis];
            *b = b.union(r.bounds());
            bins.slots[bin][axis][0] += slots;
        }
    }
}

/// [`portable`] with AVX2: the same bins (the same operations on each lane, in registers).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn avx2<const MIXED: bool>(bins: &mut Bins, refs: &[Ref], offset: Vec3A, scale: Vec3A) {
    use std::arch::x86_64::*;
    let (offset, scale): (__m128, __m128) = (offset.into(), scale.into());
    let last = _mm_set1_ps((BINS - 1) as f32);
    let mask = _mm_set1_epi32((BINS - 1) as i32);
    // Bin b of axis a is entry 4 b + a of both arrays; its box starts 32 bytes times the entry
    // in, its count 8 bytes times the entry.
    let lanes = _mm_setr_epi32(0, 8, 16, 24);
    let boxes = bins.boxes.as_mut_ptr().cast::<u8>();
    let slots = bins.slots.as_mut_ptr().cast::<u8>();
    for r in refs {
        // SAFETY: `Ref` and `Box3` are 32 bytes aligned to 32 and laid out alike (min, then
        // -max); the entries `4 * bin + axis` are below 64 (`bin` is masked to 0..16), inside
        // the 16 x 4 arrays of boxes and of 8-byte counts.
        unsafe {
            let v = _mm256_load_ps((r as *const Ref).cast());
            let min = _mm256_castps256_ps128(v);
            let centroid = _mm_sub_ps(min, _mm256_extractf128_ps::<1>(v));
            let x = _mm_min_ps(_mm_mul_ps(_mm_sub_ps(centroid, offset), scale), last);
            let bin = _mm_and_si128(_mm_cvttps_epi32(x), mask);
            // Eight times the entry.
            let at = _mm_add_epi32(_mm_slli_epi32::<5>(bin), lanes);
            let n = if MIXED {
                // The slots ride in the spare lane of the minimum.
                _mm_cvttss_si32(_mm_shuffle_ps::<0xFF>(min, min)) as u32
            } else {
                1
            };
            for e in [
                _mm_cvtsi128_si32(at),
                _mm_extract_epi32::<1>(at),
                _mm_extract_epi32::<2>(at),
            ] {
                let e = e as usize;
                let b = boxes.add(4 * e).cast::<f32>();
                // The primitive first: the bin's box is then the operand read from memory.
                _mm256_store_ps(b, _mm256_min_ps(v, _mm256_load_ps(b)));
                *slots.add(e).cast::<u32>() += n;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Aabb, Vec3};

    /// The AVX2 loop fills the bins exactly as the portable one does, slots included.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn avx2_bins_are_the_portable_bins() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let mut s = 7u32;
        let mut next = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1 << 24) as f32
        };
        let refs: Vec<Ref> = (0..500)
            .map(|i| {
                let c = Vec3::new(next(), next(), next()) * 10.0;
                let b = Aabb::new(c, c + Vec3::new(next(), next(), next()));
                Ref::new(&b, if i % 3 == 0 { 4 } else { 1 })
            })
            .collect();
        let (offset, scale) = (Vec3A::ZERO, Vec3A::new(1.4, 1.5, 0.0));
        let empty = || Bins {
            boxes: [[crate::accel::sah::boxes::Box3::EMPTY; 4]; BINS],
            slots: [[[0; 2]; 4]; BINS],
        };
        for mixed in [false, true] {
            let (mut a, mut b) = (empty(), empty());
            if mixed {
                portable::<true>(&mut a, &refs, offset, scale);
                // SAFETY: checked above.
                unsafe { avx2::<true>(&mut b, &refs, offset, scale) };
            } else {
                portable::<false>(&mut a, &refs, offset, scale);
                // SAFETY: checked above.
                unsafe { avx2::<false>(&mut b, &refs, offset, scale) };
            }
            assert_eq!(a.slots, b.slots);
            for (x, y) in a.boxes.iter().flatten().zip(b.boxes.iter().flatten()) {
                assert_eq!(x.min.to_array(), y.min.to_array());
                assert_eq!(x.neg_max.to_array(), y.neg_max.to_array());
            }
        }
    }
}

//! [`super::noise`] at eight points at once with AVX2, bit for bit.
//!
//! Shading the paper's textured scenes is dominated by noise: every turbulence sums nine
//! harmonics and every normal map reads three rotated lookups, each a separate scalar
//! evaluation with fourteen dependent table loads. Here each lane runs the scalar formula
//! unchanged (the same IEEE multiplies, adds and subtractions in the same order, no fused
//! multiply-add), so the lanes are exactly what the scalar code returns; only the table loads
//! become gathers and the floors one rounding instruction.
//!
//! The kernel covers coordinates below 2^23 in magnitude, where the hardware floor and
//! [`floor_fast`](crate::math::floor_fast) agree and the cell index fits an `i32` exactly;
//! anything else (huge, infinite or NaN inputs) is left to the scalar code by returning `None`.

use std::arch::x86_64::*;

use super::{GRADIENTS, PERM};
use crate::math::Vec3;

/// The permutation widened to `i32` for the 32-bit gathers.
static PERM32: [i32; 512] = {
    let mut out = [0i32; 512];
    let mut i = 0;
    while i < 512 {
        out[i] = PERM[i] as i32;
        i += 1;
    }
    out
};

/// One gradient component for all sixteen hashes, split in the two halves `permutevar`
/// indexes (low three bits), the high half chosen by the hash's bit 3.
const fn gradient_column(axis: usize) -> [[f32; 8]; 2] {
    let mut out = [[0.0; 8]; 2];
    let mut h = 0;
    while h < 16 {
        out[h / 8][h % 8] = GRADIENTS[h][axis];
        h += 1;
    }
    out
}
const GRAD_X: [[f32; 8]; 2] = gradient_column(0);
const GRAD_Y: [[f32; 8]; 2] = gradient_column(1);
const GRAD_Z: [[f32; 8]; 2] = gradient_column(2);

/// Above this magnitude floats are integers and `floor_fast` passes them through unchanged;
/// the kernel stays strictly below it.
const EXACT_LIMIT: f32 = 8_388_608.0;

/// True when the running CPU can take the AVX2 path. `is_x86_feature_detected!` caches its
/// answer, so this costs one load and a test per call.
#[inline]
pub fn available() -> bool {
    is_x86_feature_detected!("avx2")
}

#[inline]
#[target_feature(enable = "avx2")]
fn perm(index: __m256i) -> __m256i {
    // SAFETY: every index is at most 511: a permutation entry (<= 255) plus a masked
    // coordinate (<= 255) plus 1, which is what the doubled table is sized for.
    unsafe { _mm256_i32gather_epi32::<4>(PERM32.as_ptr(), index) }
}

#[inline]
#[target_feature(enable = "avx2")]
fn gradient(column: &[[f32; 8]; 2], h: __m256i) -> __m256 {
    // SAFETY: both halves are eight-float arrays.
    let (lo, hi) = unsafe {
        (
            _mm256_loadu_ps(column[0].as_ptr()),
            _mm256_loadu_ps(column[1].as_ptr()),
        )
    };
    let pick_hi = _mm256_castsi256_ps(_mm256_slli_epi32::<28>(h));
    _mm256_blendv_ps(
        _mm256_permutevar8x32_ps(lo, h),
        _mm256_permutevar8x32_ps(hi, h),
        pick_hi,
    )
}

#[inline]
#[target_feature(enable = "avx2")]
fn fade(t: __m256) -> __m256 {
    let cube = _mm256_mul_ps(_mm256_mul_ps(t, t), t);
    let inner = _mm256_sub_ps(_mm256_mul_ps(t, _mm256_set1_ps(6.0)), _mm256_set1_ps(15.0));
    let poly = _mm256_add_ps(_mm256_mul_ps(t, inner), _mm256_set1_ps(10.0));
    _mm256_mul_ps(cube, poly)
}

/// [`fade`] on four lanes.
#[inline]
#[target_feature(enable = "avx2")]
fn fade4(t: __m128) -> __m128 {
    let cube = _mm_mul_ps(_mm_mul_ps(t, t), t);
    let inner = _mm_sub_ps(_mm_mul_ps(t, _mm_set1_ps(6.0)), _mm_set1_ps(15.0));
    let poly = _mm_add_ps(_mm_mul_ps(t, inner), _mm_set1_ps(10.0));
    _mm_mul_ps(cube, poly)
}

#[inline]
#[target_feature(enable = "avx2")]
fn lerp(t: __m256, a: __m256, b: __m256) -> __m256 {
    _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)))
}

/// `g . d` for the gradient hashed as `h`, summed x + y first as the scalar `corner` does.
#[inline]
#[target_feature(enable = "avx2")]
fn corner(h: __m256i, dx: __m256, dy: __m256, dz: __m256) -> __m256 {
    let h = _mm256_and_si256(h, _mm256_set1_epi32(15));
    let xy = _mm256_add_ps(
        _mm256_mul_ps(gradient(&GRAD_X, h), dx),
        _mm256_mul_ps(gradient(&GRAD_Y, h), dy),
    );
    _mm256_add_ps(xy, _mm256_mul_ps(gradient(&GRAD_Z, h), dz))
}

/// Splits one coordinate into its lattice index (masked to the period) and the offsets from
/// the cell's low and high corners.
#[inline]
#[target_feature(enable = "avx2")]
fn axis(v: __m256) -> (__m256i, __m256, __m256) {
    let cell = _mm256_round_ps::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(v);
    let f = _mm256_sub_ps(v, cell);
    let i = _mm256_and_si256(_mm256_cvttps_epi32(cell), _mm256_set1_epi32(255));
    (i, f, _mm256_sub_ps(f, _mm256_set1_ps(1.0)))
}

/// All-ones in the lanes whose magnitude is below [`EXACT_LIMIT`]; the ordered compare is
/// false for NaN, so NaN lanes fail too.
#[inline]
#[target_feature(enable = "avx2")]
fn inside(v: __m256) -> __m256 {
    let magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0), v);
    _mm256_cmp_ps::<_CMP_LT_OQ>(magnitude, _mm256_set1_ps(EXACT_LIMIT))
}

/// Noise at the eight points `(x[i], y[i], z[i])`, or `None` when a coordinate is outside the
/// kernel's range (see the module docs).
#[target_feature(enable = "avx2")]
pub fn noise8(x: __m256, y: __m256, z: __m256) -> Option<__m256> {
    let ok = _mm256_and_ps(_mm256_and_ps(inside(x), inside(y)), inside(z));
    if _mm256_movemask_ps(ok) != 0xFF {
        return None;
    }
    let (xi, fx, gx) = axis(x);
    let (yi, fy, gy) = axis(y);
    let (zi, fz, gz) = axis(z);
    let (u, v, w) = (fade(fx), fade(fy), fade(fz));

    let one = _mm256_set1_epi32(1);
    let a = _mm256_add_epi32(perm(xi), yi);
    let b = _mm256_add_epi32(perm(_mm256_add_epi32(xi, one)), yi);
    let aa = _mm256_add_epi32(perm(a), zi);
    let ab = _mm256_add_epi32(perm(_mm256_add_epi32(a, one)), zi);
    let ba = _mm256_add_epi32(perm(b), zi);
    let bb = _mm256_add_epi32(perm(_mm256_add_epi32(b, one)), zi);

    // Offsets `f - 0` are `f` itself bit for bit (even for -0), so only `f - 1` is computed.
    let near = lerp(
        v,
        lerp(
            u,
            corner(perm(aa), fx, fy, fz),
            corner(perm(ba), gx, fy, fz),
        ),
        lerp(
            u,
            corner(perm(ab), fx, gy, fz),
            corner(perm(bb), gx, gy, fz),
        ),
    );
    let far = lerp(
        v,
        lerp(
            u,
            corner(perm(_mm256_add_epi32(aa, one)), fx, fy, gz),
            corner(perm(_mm256_add_epi32(ba, one)), gx, fy, gz),
        ),
        lerp(
            u,
            corner(perm(_mm256_add_epi32(ab, one)), fx, gy, gz),
            corner(perm(_mm256_add_epi32(bb, one)), gx, gy, gz),
        ),
    );
    Some(lerp(w, near, far))
}

/// Noise at one point, its eight lattice corners in the eight lanes (corner `i` offset by
/// `(i & 1, i >> 1 & 1, i >> 2)`), or `None` outside the kernel's range. The lerps pair the
/// lanes exactly as the scalar code pairs its corners.
#[target_feature(enable = "avx2")]
pub fn noise1(p: Vec3) -> Option<f32> {
    let v = _mm_setr_ps(p.x, p.y, p.z, 0.0);
    let magnitude = _mm_andnot_ps(_mm_set1_ps(-0.0), v);
    if _mm_movemask_ps(_mm_cmplt_ps(magnitude, _mm_set1_ps(EXACT_LIMIT))) != 0xF {
        return None;
    }
    let cell = _mm_floor_ps(v);
    let f = _mm_sub_ps(v, cell);
    let mut lattice = [0i32; 4];
    // SAFETY: `lattice` holds four i32.
    unsafe { _mm_storeu_si128(lattice.as_mut_ptr().cast(), _mm_cvttps_epi32(cell)) };
    let [x, y, z, _] = lattice.map(|i| (i & 255) as usize);
    // The first two hash levels, as scalar loads; `& 511` only spares the bounds checks, the
    // indices never exceed 511.
    let hash = |i: usize| PERM[i & 511] as usize;
    let (a, b) = (hash(x) + y, hash(x + 1) + y);
    let (aa, ab, ba, bb) = (hash(a) + z, hash(a + 1) + z, hash(b) + z, hash(b + 1) + z);
    let index = _mm256_setr_epi32(
        aa as i32,
        ba as i32,
        ab as i32,
        bb as i32,
        aa as i32 + 1,
        ba as i32 + 1,
        ab as i32 + 1,
        bb as i32 + 1,
    );
    let g = _mm_sub_ps(f, _mm_set1_ps(1.0));
    let (fx, gx) = (
        _mm256_set1_ps(p_lane::<0>(f)),
        _mm256_set1_ps(p_lane::<0>(g)),
    );
    let (fy, gy) = (
        _mm256_set1_ps(p_lane::<1>(f)),
        _mm256_set1_ps(p_lane::<1>(g)),
    );
    let (fz, gz) = (
        _mm256_set1_ps(p_lane::<2>(f)),
        _mm256_set1_ps(p_lane::<2>(g)),
    );
    let c = corner(
        perm(index),
        _mm256_blend_ps::<0b1010_1010>(fx, gx),
        _mm256_blend_ps::<0b1100_1100>(fy, gy),
        _mm256_blend_ps::<0b1111_0000>(fz, gz),
    );
    let t = fade4(f);
    let (u, v, w) = (
        _mm_shuffle_ps::<0x00>(t, t),
        _mm_shuffle_ps::<0x55>(t, t),
        p_lane::<2>(t),
    );
    // Even lanes (x offset 0) low, odd lanes high: lerp along x gives
    // [(y0, z0), (y1, z0), (y0, z1), (y1, z1)].
    let split = _mm256_permutevar8x32_ps(c, _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7));
    let (lo, hi) = (
        _mm256_castps256_ps128(split),
        _mm256_extractf128_ps::<1>(split),
    );
    let along_x = _mm_add_ps(lo, _mm_mul_ps(u, _mm_sub_ps(hi, lo)));
    // [(z0), (z1)] from the y0 and y1 lanes.
    let y0 = _mm_shuffle_ps::<0b00_00_10_00>(along_x, along_x);
    let y1 = _mm_shuffle_ps::<0b00_00_11_01>(along_x, along_x);
    let along_y = _mm_add_ps(y0, _mm_mul_ps(v, _mm_sub_ps(y1, y0)));
    let (near, far) = (p_lane::<0>(along_y), p_lane::<1>(along_y));
    Some(near + w * (far - near))
}

/// Lane `I` of a four-float vector.
#[inline]
#[target_feature(enable = "avx2")]
fn p_lane<const I: i32>(v: __m128) -> f32 {
    f32::from_bits(_mm_extract_ps::<I>(v) as u32)
}

/// The harmonic numbers 1..=8 of [`super::turbulence`]'s first eight terms, one per lane.
const HARMONICS: [f32; 8] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0];

/// The terms `|noise(k q)| / k` for k = 1..=8, or `None` outside the kernel's range.
#[target_feature(enable = "avx2")]
pub fn turbulence_terms8(q: Vec3) -> Option<[f32; 8]> {
    // SAFETY: HARMONICS holds eight floats.
    let k = unsafe { _mm256_loadu_ps(HARMONICS.as_ptr()) };
    let n = noise8(
        _mm256_mul_ps(_mm256_set1_ps(q.x), k),
        _mm256_mul_ps(_mm256_set1_ps(q.y), k),
        _mm256_mul_ps(_mm256_set1_ps(q.z), k),
    )?;
    let terms = _mm256_div_ps(_mm256_andnot_ps(_mm256_set1_ps(-0.0), n), k);
    let mut out = [0.0f32; 8];
    // SAFETY: `out` holds eight floats.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), terms) };
    Some(out)
}

/// `(noise(x, y, z), noise(y, z, x), noise(z, x, y))` at `q`, or `None` outside the range.
/// Three one-point calls: cheaper than an eight-lane call with five lanes idle (3 gathers
/// instead of 14, and fewer instructions).
#[target_feature(enable = "avx2")]
pub fn rotations(q: Vec3) -> Option<Vec3> {
    Some(Vec3::new(
        noise1(q)?,
        noise1(Vec3::new(q.y, q.z, q.x))?,
        noise1(Vec3::new(q.z, q.x, q.y))?,
    ))
}

#[cfg(test)]
mod tests {
    use super::super::{noise_rotations_scalar, noise_scalar, splitmix64, turbulence_scalar};
    use super::*;

    /// Points of every kind the kernel must reproduce: spread over many cells and both signs,
    /// on and next to lattice planes, signed zeros, and a few past its range.
    fn points() -> Vec<Vec3> {
        let mut state = 99u64;
        let mut next = move || (splitmix64(&mut state) >> 40) as f32 / (1u64 << 24) as f32;
        let mut out: Vec<Vec3> = (0..20_000)
            .map(|i| {
                let span = [2.0, 50.0, 600.0, 1e5][i % 4];
                (Vec3::new(next(), next(), next()) - 0.5) * span
            })
            .collect();
        let edges = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            255.5,
            -1e-7,
            1e-7,
            0.999_999_9,
            4e6,
            -4.2e6,
        ];
        for &a in &edges {
            for &b in &edges {
                out.push(Vec3::new(a, b, 0.25));
                out.push(Vec3::new(-0.0, a, b));
            }
        }
        out.extend([
            Vec3::new(8_388_607.0, 1.0, 2.0),
            Vec3::new(1e9, 1.0, 2.0),
            Vec3::new(f32::NAN, 0.5, 0.5),
            Vec3::new(0.5, f32::INFINITY, 0.5),
        ]);
        out
    }

    #[test]
    fn noise8_is_the_scalar_noise_bit_for_bit() {
        if !available() {
            return;
        }
        let pts = points();
        let mut fast = 0;
        for chunk in pts.chunks_exact(8) {
            let lane = |f: fn(&Vec3) -> f32| chunk.iter().map(f).collect::<Vec<_>>();
            let (x, y, z) = (lane(|p| p.x), lane(|p| p.y), lane(|p| p.z));
            // SAFETY: AVX2 is available (checked above); the vectors hold eight floats.
            let got = unsafe {
                noise8(
                    _mm256_loadu_ps(x.as_ptr()),
                    _mm256_loadu_ps(y.as_ptr()),
                    _mm256_loadu_ps(z.as_ptr()),
                )
            };
            let in_range = chunk
                .iter()
                .all(|p| p.abs().max_element() < EXACT_LIMIT && !p.is_nan());
            assert_eq!(got.is_some(), in_range, "{chunk:?}");
            if let Some(got) = got {
                let mut lanes = [0.0f32; 8];
                // SAFETY: as above.
                unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), got) };
                for (p, v) in chunk.iter().zip(lanes) {
                    assert_eq!(v.to_bits(), noise_scalar(*p).to_bits(), "at {p:?}");
                }
                fast += 1;
            }
        }
        assert!(fast > 2000);
    }

    #[test]
    fn noise1_and_the_dispatching_noise_are_the_scalar_noise_bit_for_bit() {
        for p in points() {
            let want = noise_scalar(p).to_bits();
            assert_eq!(super::super::noise(p).to_bits(), want, "at {p:?}");
            if available() {
                // SAFETY: AVX2 is available.
                let got = unsafe { noise1(p) };
                let in_range = p.abs().max_element() < EXACT_LIMIT && !p.is_nan();
                assert_eq!(got.is_some(), in_range, "{p:?}");
                if let Some(got) = got {
                    assert_eq!(got.to_bits(), want, "at {p:?}");
                }
            }
        }
    }

    #[test]
    fn turbulence_and_rotations_match_the_scalar_paths() {
        for p in points() {
            assert_eq!(
                super::super::turbulence(p).to_bits(),
                turbulence_scalar(p).to_bits(),
                "turbulence at {p:?}"
            );
            let (got, want) = (super::super::noise_rotations(p), noise_rotations_scalar(p));
            for i in 0..3 {
                assert_eq!(got[i].to_bits(), want[i].to_bits(), "rotation {i} at {p:?}");
            }
        }
    }
}

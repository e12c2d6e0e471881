//! 3-D gradient noise after Ken Perlin's "Improving Noise" (SIGGRAPH 2002): quintic fade,
//! twelve edge-midpoint gradients, a 256-entry permutation doubled to skip index wrapping.
//!
//! The permutation is lumis's own: a Fisher-Yates shuffle of 0..=255 driven by SplitMix64 from a
//! fixed seed, computed at compile time, so every build and every thread sees the same noise.

use crate::math::{Vec3, floor_fast};

#[cfg(target_arch = "x86_64")]
mod avx2;

/// Seed of the permutation shuffle; changing it changes every procedural texture in every image.
const PERM_SEED: u64 = 0x6C75_6D69_735F_6E7A;

/// The shuffled lattice hash, stored twice so `PERM[PERM[x] + y]` never needs a wrap.
static PERM: [u8; 512] = build_permutation(PERM_SEED);

/// Gradients at the lattice points: the twelve midpoints of a cube's edges, padded to sixteen
/// with four of them repeated (as in the 2002 paper) so a 4-bit hash picks one without bias
/// along any axis and without a division.
const GRADIENTS: [[f32; 3]; 16] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [0.0, -1.0, -1.0],
];

/// One SplitMix64 step: advances `state` and returns a well-mixed 64-bit value.
const fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A Fisher-Yates shuffle of 0..=255 from `seed`, written out twice.
const fn build_permutation(seed: u64) -> [u8; 512] {
    let mut p = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        p[i] = i as u8;
        i += 1;
    }
    let mut state = seed;
    let mut i = 255;
    while i > 0 {
        // Modulo bias of a 64-bit draw over at most 256 outcomes is below 2^-56: irrelevant here.
        let j = (splitmix64(&mut state) % (i as u64 + 1)) as usize;
        let t = p[i];
        p[i] = p[j];
        p[j] = t;
        i -= 1;
    }
    let mut out = [0u8; 512];
    let mut k = 0;
    while k < 512 {
        out[k] = p[k & 255];
        k += 1;
    }
    out
}

/// Perlin's quintic fade 6t^5 - 15t^4 + 10t^3: zero first and second derivatives at 0 and 1,
/// which keeps the noise C2 across cell faces (the 1985 cubic left visible creases).
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Dot product of the gradient hashed at lattice corner `(x, y, z)` (each in 0..=256) with the
/// offset `d` from that corner.
#[inline]
fn corner(x: usize, y: usize, z: usize, d: Vec3) -> f32 {
    let h = PERM[PERM[PERM[x] as usize + y] as usize + z] as usize & 15;
    let g = GRADIENTS[h];
    g[0] * d.x + g[1] * d.y + g[2] * d.z
}

#[inline]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// Gradient noise at point `p` (any space; the lattice has unit spacing and period 256).
///
/// Zero at every lattice point, continuous with continuous first and second derivatives,
/// roughly in [-1, 1] (the exact extremes are about ±1.04), mean zero. Never panics: points
/// beyond the `i32` range saturate onto one lattice cell, NaN in gives NaN out.
pub fn noise(p: Vec3) -> f32 {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        if let Some(n) = unsafe { avx2::noise1(p) } {
            return n;
        }
    }
    noise_scalar(p)
}

/// [`noise`] in plain scalar code: the definition the vector kernels reproduce bit for bit, and
/// the path for CPUs without AVX2 and for coordinates past 2^23.
fn noise_scalar(p: Vec3) -> f32 {
    let cell = Vec3::new(floor_fast(p.x), floor_fast(p.y), floor_fast(p.z));
    let f = p - cell;
    // `as i32` saturates and `& 255` wraps negatives correctly in two's complement.
    let x = (cell.x as i32 & 255) as usize;
    let y = (cell.y as i32 & 255) as usize;
    let z = (cell.z as i32 & 255) as usize;
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let c = |dx: usize, dy: usize, dz: usize| {
        let d = f - Vec3::new(dx as f32, dy as f32, dz as f32);
        corner(x + dx, y + dy, z + dz, d)
    };
    let near = lerp(
        v,
        lerp(u, c(0, 0, 0), c(1, 0, 0)),
        lerp(u, c(0, 1, 0), c(1, 1, 0)),
    );
    let far = lerp(
        v,
        lerp(u, c(0, 0, 1), c(1, 0, 1)),
        lerp(u, c(0, 1, 1), c(1, 1, 1)),
    );
    lerp(w, near, far)
}

/// How many harmonics [`turbulence`] sums; the paper's `.scn` textures use nine.
pub const TURBULENCE_LEVELS: u32 = 9;

/// Turbulence as the paper's ray tracer sums it: `sum over k = 1..=9 of |noise(k q)| / k`
/// at noise-space point `q`. Harmonics `k` rather than octaves `2^k` keep the finest detail
/// at 9x the base frequency, which is what its 1-sample-per-pixel images were made with.
/// Non-negative; about 0.6 on average and rarely above 1.3.
pub fn turbulence(q: Vec3) -> f32 {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        if let Some(terms) = unsafe { avx2::turbulence_terms8(q) } {
            // Summed in the scalar order, k = 1 first, so the rounding is the same.
            let last = TURBULENCE_LEVELS as f32;
            return terms.iter().sum::<f32>() + noise(q * last).abs() / last;
        }
    }
    turbulence_scalar(q)
}

/// [`turbulence`] one harmonic at a time: the definition, and the path for CPUs without AVX2
/// and for points the vector kernel does not cover.
fn turbulence_scalar(q: Vec3) -> f32 {
    (1..=TURBULENCE_LEVELS)
        .map(|k| {
            let k = k as f32;
            noise_scalar(q * k).abs() / k
        })
        .sum()
}

/// `(noise(x, y, z), noise(y, z, x), noise(z, x, y))` at `q = (x, y, z)`: the three rotated
/// lookups of a normal map, evaluated together where the CPU allows.
pub fn noise_rotations(q: Vec3) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        if let Some(n) = unsafe { avx2::rotations(q) } {
            return n;
        }
    }
    noise_rotations_scalar(q)
}

fn noise_rotations_scalar(q: Vec3) -> Vec3 {
    Vec3::new(
        noise_scalar(q),
        noise_scalar(Vec3::new(q.y, q.z, q.x)),
        noise_scalar(Vec3::new(q.z, q.x, q.y)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic points spread over many lattice cells, negative and positive.
    fn points(n: usize) -> impl Iterator<Item = Vec3> {
        let mut state = 12345u64;
        (0..n).map(move |_| {
            let mut next = || (splitmix64(&mut state) >> 40) as f32 / (1u64 << 24) as f32;
            Vec3::new(next(), next(), next()) * 200.0 - Vec3::splat(100.0)
        })
    }

    #[test]
    fn permutation_is_a_permutation_and_doubled() {
        let mut seen = [false; 256];
        for &v in &PERM[..256] {
            assert!(!seen[v as usize], "{v} twice");
            seen[v as usize] = true;
        }
        assert_eq!(PERM[..256], PERM[256..]);
        // A shuffle that left the identity would make the noise axis-aligned and obviously tiled.
        assert!(
            PERM.iter()
                .take(256)
                .enumerate()
                .filter(|&(i, &v)| i == v as usize)
                .count()
                < 8
        );
    }

    #[test]
    fn deterministic() {
        for p in points(1000) {
            assert_eq!(noise(p).to_bits(), noise(p).to_bits());
        }
        // A pinned value catches an accidental change of seed, table or formula; the corner
        // dot products and lerps are plain IEEE arithmetic, so it is exact on every platform.
        assert_eq!(noise(Vec3::new(1.3, -2.7, 0.45)).to_bits(), 3_185_998_692); // -0.11254004
    }

    #[test]
    fn zero_at_lattice_points() {
        for x in -5..5 {
            for y in -5..5 {
                for z in -5..5 {
                    let p = Vec3::new(x as f32, y as f32, z as f32);
                    assert_eq!(noise(p), 0.0, "{p}");
                }
            }
        }
        assert_eq!(noise(Vec3::new(300.0, -1000.0, 256.0)), 0.0);
    }

    #[test]
    fn bounded() {
        let mut max = 0.0f32;
        for p in points(200_000) {
            max = max.max(noise(p).abs());
        }
        assert!(max <= 1.05, "max |noise| = {max}");
        // Improved noise reaches well past 0.5; far smaller would mean a broken gradient set.
        assert!(max > 0.6, "max |noise| = {max}");
    }

    #[test]
    fn continuous() {
        // The gradient magnitude is bounded (about 2.5 per unit), so a 1e-3 step moves < 0.01.
        let h = 1e-3;
        for p in points(20_000) {
            for d in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE.normalize()] {
                let change = (noise(p + d * h) - noise(p)).abs();
                assert!(change < 0.01, "jump {change} at {p} along {d}");
            }
        }
        // Across a cell face in particular.
        let a = noise(Vec3::new(3.0 - 1e-4, 0.5, 0.25));
        let b = noise(Vec3::new(3.0 + 1e-4, 0.5, 0.25));
        assert!((a - b).abs() < 1e-3);
    }

    #[test]
    fn mean_near_zero() {
        let n = 200_000;
        let mean: f64 = points(n).map(|p| noise(p) as f64).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01, "mean {mean}");
    }

    #[test]
    fn periodic_with_period_256() {
        for p in points(100) {
            assert!((noise(p) - noise(p + Vec3::new(256.0, -256.0, 512.0))).abs() < 1e-3);
        }
    }

    #[test]
    fn turbulence_is_non_negative_and_sized() {
        let n = 20_000;
        let mut sum = 0.0;
        for p in points(n) {
            let t = turbulence(p * 0.1);
            assert!((0.0..3.0).contains(&t), "{t}");
            sum += t;
        }
        let mean = sum / n as f32;
        assert!((0.3..0.9).contains(&mean), "mean turbulence {mean}");
        assert_eq!(turbulence(Vec3::new(2.0, -7.0, 11.0)), 0.0);
    }
}

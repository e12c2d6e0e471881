//! Which samples the base pass takes, and when a pixel needs the rest.

use crate::math::Vec4;

/// Linear radiance below which two values count as alike whatever their ratio: keeps the
/// contrast of near-black pixels (and of exact zeros) from being noise over noise. About one
/// 8-bit sRGB step above black.
const DARK: f32 = 1e-3;

/// The strata the base pass takes of a pixel's `n x n` (sample indices `s = row * n + column`,
/// ascending, so that a pixel's samples can be summed in the full render's order):
/// `n = 1`: the one sample (nothing to adapt); `n = 2`: the diagonal pair 0 and 3;
/// `n >= 3`: four strata, rows and columns `floor(n / 4)` and `floor(3n / 4)`, one near the
/// middle of each quadrant of the pixel.
pub fn base_strata(n: u32) -> Vec<u32> {
    match n {
        0 | 1 => vec![0],
        2 => vec![0, 3],
        _ => {
            let (a, b) = (n / 4, 3 * n / 4);
            vec![a * n + a, a * n + b, b * n + a, b * n + b]
        }
    }
}

/// The relative contrast of two linear RGBA values: the largest over the channels of
/// `|a - b| / (|a| + |b| + DARK)`, in [0, 1) for finite values; NaN when either holds a NaN.
/// Scaling both colours by an exposure leaves it alone (above [`DARK`]).
pub fn contrast(a: Vec4, b: Vec4) -> f32 {
    let d = (a - b).abs() / (a.abs() + b.abs() + Vec4::splat(DARK));
    // A NaN channel must refine the pixel: max_element would skip it.
    if d.is_nan() {
        return f32::NAN;
    }
    d.max_element()
}

/// Whether a pixel keeps its base samples: every contrast among its base samples' values
/// (`own`, each the mean of one sample's lens rays) and between its base mean and each
/// neighbour's (`neighbours`) is below `threshold`. A threshold of 0 therefore refines every
/// pixel, and a NaN anywhere refines its pixel.
pub fn converged(threshold: f32, own: &[Vec4], mean: Vec4, neighbours: &[Vec4]) -> bool {
    let below = |c: f32| c < threshold;
    own.iter()
        .enumerate()
        .all(|(i, &a)| own[i + 1..].iter().all(|&b| below(contrast(a, b))))
        && neighbours.iter().all(|&b| below(contrast(mean, b)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base_strata_are_ascending_distinct_and_inside_the_pixel() {
        assert_eq!(base_strata(1), [0]);
        assert_eq!(base_strata(2), [0, 3]);
        // 3x3: the four corners; 4x4: (1,1), (3,1), (1,3), (3,3).
        assert_eq!(base_strata(3), [0, 2, 6, 8]);
        assert_eq!(base_strata(4), [5, 7, 13, 15]);
        for n in 3..=64 {
            let s = base_strata(n);
            assert!(s.windows(2).all(|w| w[0] < w[1]), "{n}: {s:?}");
            assert!(s.iter().all(|&s| s < n * n), "{n}: {s:?}");
            // One in each quadrant of the pixel.
            let quadrant = |s: u32| (2 * (s % n) >= n, 2 * (s / n) >= n);
            let mut q: Vec<_> = s.iter().map(|&s| quadrant(s)).collect();
            q.dedup();
            assert_eq!(q.len(), 4, "{n}: {s:?}");
        }
    }

    #[test]
    fn contrast_is_relative_symmetric_and_exposure_free() {
        let a = Vec4::new(0.2, 0.4, 0.1, 1.0);
        let b = Vec4::new(0.6, 0.4, 0.1, 1.0);
        // Red: 0.4 / (0.8 + 0.001).
        assert!((contrast(a, b) - 0.4 / 0.801).abs() < 1e-6);
        assert_eq!(contrast(a, b), contrast(b, a));
        assert_eq!(contrast(a, a), 0.0);
        // Alpha alone: a covered and an uncovered sample of black.
        let clear = Vec4::ZERO;
        let black = Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!(contrast(clear, black) > 0.99);
        // Four stops brighter (colour only) leaves the red contrast within the DARK term.
        let scale = |v: Vec4| (v.truncate() * 16.0).extend(v.w);
        assert!((contrast(scale(a), scale(b)) - 0.5).abs() < 1e-3);
        assert!(contrast(Vec4::splat(f32::NAN), a).is_nan());
    }

    #[test]
    fn threshold_zero_refines_everything_and_a_nan_refines_its_pixel() {
        let flat = [Vec4::ONE; 4];
        assert!(!converged(0.0, &flat, Vec4::ONE, &[Vec4::ONE; 8]));
        assert!(converged(1e-6, &flat, Vec4::ONE, &[Vec4::ONE; 8]));
        let edge = [Vec4::ONE, Vec4::ONE, Vec4::ZERO, Vec4::ONE];
        assert!(!converged(0.5, &edge, Vec4::ONE, &[]));
        // Flat itself, but next to an edge.
        let mut near = [Vec4::ONE; 8];
        near[5] = Vec4::splat(0.5);
        assert!(!converged(0.2, &flat, Vec4::ONE, &near));
        assert!(converged(0.4, &flat, Vec4::ONE, &near));
        near[5] = Vec4::splat(f32::NAN);
        assert!(!converged(1.0, &flat, Vec4::ONE, &near));
    }
}

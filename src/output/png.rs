//! PNG output: an 8-bit sRGB preview of the film composited over black.

use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::atomic::write_atomically;
use super::{OutputError, check_not_empty};
use crate::film::Film;

/// Writes `film` to `path` as 8-bit RGB PNG, atomically.
///
/// Linear RGB is scaled by `2^exposure_stops`, clamped to `[0, 1]`, encoded with the piecewise
/// sRGB transfer function and rounded to nearest. The film is premultiplied, so its RGB already
/// is the image composited over black; alpha is dropped. NaN pixels become black.
pub fn write_png(path: &Path, film: &Film, exposure_stops: f32) -> Result<(), OutputError> {
    check_not_empty(path, film)?;
    if !exposure_stops.is_finite() {
        return Err(OutputError::BadExposure {
            path: path.to_path_buf(),
            stops: exposure_stops,
        });
    }
    let scale = exposure_stops.exp2();
    let bytes: Vec<u8> = film
        .rgba()
        .iter()
        .flat_map(|p| (p.truncate() * scale).to_array())
        .map(linear_to_srgb8)
        .collect();

    write_atomically(path, |w| {
        PngEncoder::new(w)
            .write_image(
                &bytes,
                film.width(),
                film.height(),
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|source| OutputError::Png {
                path: path.to_path_buf(),
                source,
            })
    })
}

/// Linear value to an 8-bit sRGB code value (IEC 61966-2-1), clamped, rounded to nearest.
pub fn linear_to_srgb8(linear: f32) -> u8 {
    // NaN is tested explicitly because `clamp` would pass it through to the cast.
    let c = if linear.is_nan() || linear <= 0.0 {
        0.0
    } else {
        linear.min(1.0)
    };
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_known_values() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(0.5), 188);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(7.0), 255);
        assert_eq!(linear_to_srgb8(f32::INFINITY), 255);
        // Linear segment: 0.001 * 12.92 * 255 = 3.29.
        assert_eq!(linear_to_srgb8(0.001), 3);
    }
}

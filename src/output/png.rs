//! PNG output: an 8-bit preview of the film composited over black, through a
//! [`DisplayTransform`].

use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::atomic::write_atomically;
use super::{DisplayTransform, Tonemap};
use super::{OutputError, check_not_empty};
use crate::film::Film;

/// Writes `film` to `path` as 8-bit RGB PNG, atomically.
///
/// Linear RGB is scaled by `2^exposure_stops`, clamped to `[0, 1]`, encoded by `display` (the
/// piecewise sRGB transfer function, or none) and rounded to nearest. The film is
/// premultiplied, so its RGB already is the image composited over black; alpha is dropped.
/// NaN pixels become black.
pub fn write_png(
    path: &Path,
    film: &Film,
    exposure_stops: f32,
    display: DisplayTransform,
) -> Result<(), OutputError> {
    write_png_with(path, film, exposure_stops, display, Tonemap::None)
}

/// [`write_png`] with a tone curve between the exposure and the display transform
/// (`--tonemap`); only the PNG is tone mapped, the EXR stays linear.
pub fn write_png_with(
    path: &Path,
    film: &Film,
    exposure_stops: f32,
    display: DisplayTransform,
    tonemap: Tonemap,
) -> Result<(), OutputError> {
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
        .map(|v| display.encode8(tonemap.apply(v)))
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

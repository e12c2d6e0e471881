//! PNG output: an 8-bit preview of the film composited over black, through a
//! [`DisplayTransform`].

use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::staged::write_atomically;
use super::{OutputError, check_not_empty};
use lumis_core::film::Film;
use lumis_core::film::{DisplayTransform, Tonemap};

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
    let bytes = encode_png_with(path, film, exposure_stops, display, tonemap)?;
    write_atomically(path, |w| {
        use std::io::Write as _;
        w.write_all(&bytes).map_err(|source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        })
    })
}

/// The bytes [`write_png_with`] would write (`path` only names the file in errors), for
/// staging with the other outputs of a run.
pub fn encode_png_with(
    path: &Path,
    film: &Film,
    exposure_stops: f32,
    display: DisplayTransform,
    tonemap: Tonemap,
) -> Result<Vec<u8>, OutputError> {
    check_not_empty(path, film)?;
    if !exposure_stops.is_finite() {
        return Err(OutputError::BadExposure {
            path: path.to_path_buf(),
            stops: exposure_stops,
        });
    }
    let scale = exposure_stops.exp2();
    let pixels: Vec<u8> = film
        .rgba()
        .iter()
        .flat_map(|p| (p.truncate() * scale).to_array())
        .map(|v| display.encode8(tonemap.apply(v)))
        .collect();
    let mut encoded = Vec::new();
    PngEncoder::new(&mut encoded)
        .write_image(
            &pixels,
            film.width(),
            film.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|source| OutputError::Png {
            path: path.to_path_buf(),
            source,
        })?;
    Ok(encoded)
}

//! The develop step: a rendered [`Film`] becomes the images a render writes. One function for
//! every caller: `lumis render`, `lumis merge` (on the film it rebuilt from the tiles) and the
//! Python package, so the three cannot drift apart.
//!
//! ```text
//! film ─► exposure (fixed, or automatic over the film) ─► finite check
//!      ─► per output, by extension: EXR (linear, exposure recorded) | PNG (tonemap, display)
//! ```
//!
//! A farm tile ([`ExrMetadata::tile`]) is written before exposure: the merge computes an
//! automatic exposure over the whole image, so each tile's floats must stay as rendered.

use std::path::{Path, PathBuf};

use lumis_core::film::{DisplayTransform, Film, Tonemap, auto_exposure};

use super::{ExrCamera, ExrMetadata, OutputError, encode_exr, encode_png_with};

/// How a film is developed, besides what [`ExrMetadata`] records.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Develop {
    /// Exposure in stops, linear colour x `2^exposure`; `None`: automatic over the film
    /// ([`auto_exposure`]), or none at all for a farm tile (the merge decides).
    pub exposure: Option<f32>,
    /// The PNG's tone curve between the exposure and the display transform.
    pub tonemap: Tonemap,
    /// The PNG's display transform.
    pub display: DisplayTransform,
}

/// A developed film: the exposure it got and the encoded images, in the order asked.
#[derive(Debug)]
pub struct Developed {
    /// The exposure applied, in stops (for a farm tile: recorded only, 0 when automatic).
    pub exposure: f32,
    /// Whether the exposure was computed from the film.
    pub auto_exposure: bool,
    /// Each output's path and bytes, ready to be staged with the run's other outputs.
    pub images: Vec<(PathBuf, Vec<u8>)>,
}

/// Exposes `film` in place (unless `meta` says it is a farm tile), checks every sample is
/// finite, and encodes it as each of `paths` by extension (`.exr`, `.png`, compared
/// case-insensitively). `camera` is what the EXR header records of the camera
/// ([`ExrCamera::new`] for a render, read back from a tile for a merge). `meta.exposure` is
/// set to the exposure applied. Writes nothing: the caller stages the bytes
/// ([`super::StagedOutputs`]) so that a failure leaves no file changed.
pub fn develop(
    film: &mut Film,
    camera: &ExrCamera,
    paths: &[&Path],
    how: &Develop,
    meta: &mut ExrMetadata,
) -> Result<Developed, OutputError> {
    let (exposure, auto) = expose(film, how.exposure, meta.tile.is_some());
    meta.exposure = exposure;
    // The last line of defence of the NaN guarantee: nothing is encoded from a film with a
    // non-finite sample (the loaders' limits should make this unreachable).
    if let Some(path) = paths.first() {
        lumis_core::film::check_finite(film).map_err(|source| OutputError::NonFinite {
            path: path.to_path_buf(),
            source,
        })?;
    }
    let images = paths
        .iter()
        .map(|&path| Ok((path.to_path_buf(), encode(path, film, camera, how, meta)?)))
        .collect::<Result<_, OutputError>>()?;
    Ok(Developed {
        exposure,
        auto_exposure: auto,
        images,
    })
}

/// Applies the exposure `fixed` (or the automatic one) to `film`. A tile keeps its floats:
/// a fixed exposure is only recorded (the merge applies it), an automatic one is the merge's
/// to compute over the whole image (0 here). Returns the stops and whether they were computed.
pub fn expose(film: &mut Film, fixed: Option<f32>, tile: bool) -> (f32, bool) {
    match (fixed, tile) {
        (Some(ev), true) => (ev, false),
        (None, true) => (0.0, false),
        (Some(ev), false) => {
            film.expose(ev);
            (ev, false)
        }
        (None, false) => {
            let ev = auto_exposure(film);
            film.expose(ev);
            (ev, true)
        }
    }
}

/// The bytes of the already exposed `film` as the image `path` names by extension.
fn encode(
    path: &Path,
    film: &Film,
    camera: &ExrCamera,
    how: &Develop,
    meta: &ExrMetadata,
) -> Result<Vec<u8>, OutputError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        // The film is already exposed: the PNG adds no exposure of its own.
        Some("png") => encode_png_with(path, film, 0.0, how.display, how.tonemap),
        Some("exr") => encode_exr(path, film, camera, meta),
        _ => Err(OutputError::UnsupportedExtension {
            path: path.to_path_buf(),
        }),
    }
}

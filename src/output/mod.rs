//! Writing a finished [`Film`] to disk: HDR OpenEXR with AOV layers, or a display-referred PNG.
//!
//! This is the only module that touches image files. Every writer encodes into a temporary file
//! in the target's directory and renames it over the target only once encoding has succeeded
//! (see `atomic.rs`), so a failed or interrupted write never leaves a truncated image behind and
//! never destroys an existing one.
//!
//! ```toml
//! [output]
//! path = "render.exr"   # .exr or .png, chosen by extension (case-insensitive)
//! float_rgba = false    # EXR only: f32 instead of half for R, G, B, A
//! exposure = 0.0        # stops: linear colour x 2^exposure, in the EXR and the PNG
//! display = "srgb"      # PNG only: "srgb" transfer curve or "clamp" (value x 255)
//! ```

mod aov_layers;
mod atomic;
mod cryptomatte;
mod display;
mod exposure;
mod finite;
mod tonemap;

// Public for the binary's other result files (`lumis hits` writes .npy arrays through it).
pub use self::atomic::write_atomically;
mod exr;
mod header_order;
mod layout;
mod png;

use std::path::{Path, PathBuf};

use crate::camera::Camera;
use crate::film::Film;

pub use self::aov_layers::AovLayers;
pub use self::display::{DisplayTransform, linear_to_srgb8};
pub use self::exposure::{AUTO_EXPOSURE_PERCENTILE, AUTO_EXPOSURE_TARGET, auto_exposure};
pub use self::exr::{
    ATTR_EXPOSURE, ATTR_LENS_RADIUS, ATTR_LENS_SAMPLES, ATTR_LENS_SQUARE, ATTR_PARTIAL,
    ATTR_RENDER_SECONDS, ATTR_RENDERER, ATTR_SPP, ATTR_SPP_PER_AXIS, ExrMetadata, SOFTWARE,
    imath_m44f, write_exr,
};
pub use self::finite::{NonFinite, check_finite};
pub use self::layout::ChannelLayout;
pub use self::png::{write_png, write_png_with};
pub use self::tonemap::Tonemap;

/// Writes `text` to `path` atomically (a report beside the images, e.g. `--stats-json`).
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    use std::io::Write as _;
    write_atomically(path, |w| {
        w.write_all(text.as_bytes())
            .map_err(|source| OutputError::Write {
                path: path.to_path_buf(),
                source,
            })
    })
}

/// Why an image could not be written. Every variant names the target path.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The film has no pixels; neither format can hold a 0-pixel image.
    #[error("cannot write {}: the film is empty ({width}x{height} pixels)", path.display())]
    EmptyFilm {
        /// Target path.
        path: PathBuf,
        /// Film width in pixels.
        width: u32,
        /// Film height in pixels.
        height: u32,
    },
    /// The extension is neither `.exr` nor `.png`.
    #[error("cannot write {}: unknown image extension (expected .exr or .png)", path.display())]
    UnsupportedExtension {
        /// Target path.
        path: PathBuf,
    },
    /// The PNG exposure is NaN or infinite.
    #[error("cannot write {}: exposure {stops} stops is not a finite number", path.display())]
    BadExposure {
        /// Target path.
        path: PathBuf,
        /// The rejected exposure in stops.
        stops: f32,
    },
    /// The temporary file next to the target could not be created (missing directory,
    /// no permission, read-only file system).
    #[error("cannot create a temporary file next to {}", path.display())]
    CreateTemp {
        /// Target path.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The OpenEXR encoder failed.
    #[error("failed to encode OpenEXR image {}", path.display())]
    Exr {
        /// Target path.
        path: PathBuf,
        /// The encoder's error.
        #[source]
        source: ::exr::error::Error,
    },
    /// The PNG encoder failed.
    #[error("failed to encode PNG image {}", path.display())]
    Png {
        /// Target path.
        path: PathBuf,
        /// The encoder's error.
        #[source]
        source: image::ImageError,
    },
    /// Flushing or syncing the finished temporary file failed.
    #[error("failed to write image data for {}", path.display())]
    Write {
        /// Target path.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The film holds a NaN or infinite sample; nothing was written.
    #[error("cannot write {}", path.display())]
    NonFinite {
        /// Target path.
        path: PathBuf,
        /// How many samples, and the first.
        #[source]
        source: NonFinite,
    },
    /// The finished temporary file could not be renamed onto the target (for example, the
    /// target is a directory). The temporary file has been removed.
    #[error("cannot move the finished image into place at {}", path.display())]
    Persist {
        /// Target path.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// Writes `film` as OpenEXR (`.exr`) or PNG (`.png`) depending on the extension of `path`,
/// compared case-insensitively. `meta` and `camera` are used only for EXR, `exposure_stops`
/// and `display` only for PNG (the EXR stays linear).
pub fn write_by_extension(
    path: &Path,
    film: &Film,
    camera: &Camera,
    meta: &ExrMetadata,
    exposure_stops: f32,
    display: DisplayTransform,
) -> Result<(), OutputError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("exr") => write_exr(path, film, camera, meta),
        Some("png") => write_png(path, film, exposure_stops, display),
        _ => Err(OutputError::UnsupportedExtension {
            path: path.to_path_buf(),
        }),
    }
}

/// Rejects films with no pixels before any file is created, so nothing on disk changes.
fn check_not_empty(path: &Path, film: &Film) -> Result<(), OutputError> {
    if film.width() == 0 || film.height() == 0 {
        return Err(OutputError::EmptyFilm {
            path: path.to_path_buf(),
            width: film.width(),
            height: film.height(),
        });
    }
    Ok(())
}

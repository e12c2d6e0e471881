//! Writing a finished [`Film`] to disk: HDR OpenEXR with AOV layers, or a display-referred PNG,
//! and reading lumis's own EXR files back.
//!
//! [`develop`] is the one way from a rendered film to encoded images (exposure, finite check,
//! encoding by extension), for `lumis render`, `lumis merge` and the Python package alike.
//! [`exr`] owns lumis's EXR files both ways: header schema, attribute order, writing, and
//! reading a file back into a film and the metadata that writes it again ([`ExrFile`]).
//!
//! This is the only module that touches image files. Every writer encodes into a temporary file
//! in the target's directory and renames it over the target only once encoding has succeeded
//! (see `staged.rs`), so a failed or interrupted write never leaves a truncated image behind and
//! never destroys an existing one. A run with several outputs stages them all in one
//! [`StagedOutputs`] and renames them only when every one was written, after checking them
//! up front with [`prepare_outputs`] (directories exist and are writable, no output is an input
//! of the run or another output, none is a FIFO, device or directory). A symlink to a regular
//! file is written through (`target.rs`).
//!
//! ```toml
//! [output]
//! path = "render.exr"   # .exr or .png, chosen by extension (case-insensitive)
//! float_rgba = false    # EXR only: f32 instead of half for R, G, B, A
//! exposure = 0.0        # stops: linear colour x 2^exposure, in the EXR and the PNG
//! display = "srgb"      # PNG only: "srgb" transfer curve or "clamp" (value x 255)
//! ```

mod develop;
mod error;
pub mod exr;
mod frame;
mod png;
mod preflight;
mod staged;
mod target;
mod temps;

pub use self::develop::{Develop, Developed, develop, expose};
pub use self::error::OutputError;
pub use self::preflight::{PlannedOutput, prepare_outputs};
// Public for the binary's other result files (`lumis hits` writes .npy arrays through them).
pub use self::staged::{StagedOutputs, TempWriter, write_atomically};
pub use self::temps::{STALE_AFTER, remove_staged_temps, remove_stale_temps};

use std::path::Path;

use lumis_core::film::Film;

pub use self::exr::{
    ATTR_EXPOSURE, ATTR_FRAME, ATTR_LENS_RADIUS, ATTR_LENS_SAMPLES, ATTR_LENS_SQUARE, ATTR_PARTIAL,
    ATTR_RENDER_SECONDS, ATTR_RENDERER, ATTR_REPLAY, ATTR_SCENE_HASH, ATTR_SEED, ATTR_SETTINGS,
    ATTR_SPP, ATTR_SPP_PER_AXIS, ATTR_TILE, ATTR_TILE_BEAUTY, ATTR_TILE_DISPLAY,
    ATTR_TILE_EXPOSURE, ATTR_TILE_RGBA, AovLayers, ChannelLayout, CryptoHeader, ExrCamera, ExrFile,
    ExrHeader, ExrImage, ExrMetadata, HeaderValue, ReadError, RenderIdentity, SOFTWARE,
    TILE_ATTR_PREFIX, TILE_EXPOSURE_AUTO, TileHeader, encode_exr, exr_channels, imath_m44f,
    read_exr, write_exr,
};
pub use self::frame::numbered_path;
pub use self::png::{encode_png_with, write_png, write_png_with};
/// The samples of one EXR channel ([`exr_channels`]): half or float.
pub use ::exr::prelude::FlatSamples as ExrSamples;

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

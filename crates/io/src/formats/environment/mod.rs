//! Latitude-longitude HDR environment images (`--env`, `[environment]`): Radiance RGBE
//! (`.hdr`, `.pic`) and OpenEXR (`.exr`), chosen by extension, decoded to linear RGB texels.
//!
//! **Orientation.** Row 0 is the top of the image, the +Y pole; column 0 is the left edge.
//! How a texel maps to a direction is Mitsuba 3's `envmap` convention, which
//! `lumis_core::environment::latlong` implements: column `u` looks along -Z at the left edge,
//! +X a quarter of the way across. A latitude-longitude map should be twice as wide as it is
//! high; other aspect ratios are read all the same (as Mitsuba 3 does), their texels simply
//! cover unequal angles across and down. At least [`MIN_WIDTH`]x[`MIN_HEIGHT`] texels.
//!
//! **Limits.** The header's size is read and checked before any pixel is decoded or any
//! buffer sized from it: at most [`MAX_WIDTH`] texels across, [`MAX_HEIGHT`] down and
//! [`MAX_TEXELS`] in all (a 16384x8192 map, 1.5 GiB of texels). Compressed data can
//! legitimately expand by more than any fixed ratio (a uniform RGBE scanline of 32768 texels
//! takes 12 bytes), so, unlike [`super::images`], there is no budget relative to the file's
//! size: these absolute limits are the bound, and a header that lies about its data is found
//! out row by row as the pixels run out (see `radiance.rs` and `openexr.rs`).
//!
//! **Clamps.** The renderer wants finite, non-negative radiance within
//! [`MAX_RADIANCE`] (`lumis_core::scene::limits`), so every texel component is
//! clamped on reading: NaN and negative values (−∞ included) become 0; +∞ and values above
//! `MAX_RADIANCE` become `MAX_RADIANCE`. [`EnvironmentImage::clamped`] counts the texels with
//! any component changed, for the caller to warn about.
//!
//! Every error is a [`SceneError`] naming the file; decoders run under the
//! [panic guard](crate::files::guard), so a damaged file is an error, never a crash or a
//! printed panic.

mod openexr;
mod radiance;

#[cfg(test)]
mod tests;

use std::path::Path;

use lumis_core::scene::limits::MAX_RADIANCE;

use super::{SceneError, read_file};
use crate::files::guard::guarded;

/// Most texels across a map: with [`MAX_TEXELS`], a 2:1 map is at most 16384x8192, a wider
/// panorama at most 32768x4096.
pub const MAX_WIDTH: u32 = 32_768;
/// Most texels down a map.
pub const MAX_HEIGHT: u32 = 16_384;
/// Most texels in all: 2^27, a 16384x8192 map (1.5 GiB as `[f32; 3]`).
pub const MAX_TEXELS: u64 = 1 << 27;
/// Fewest texels across: one column would not change with the azimuth, no map at all.
pub const MIN_WIDTH: u32 = 2;
/// Fewest texels down.
pub const MIN_HEIGHT: u32 = 1;

/// A decoded latitude-longitude environment image: linear RGB, row-major, row 0 = the top of
/// the image (the +Y "up" pole), column 0 = the left edge. Texels are finite, in
/// `0..=MAX_RADIANCE`, and `texels.len() == width * height`.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentImage {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// The texels, row-major from the top-left.
    pub texels: Vec<[f32; 3]>,
    /// Texels that were not finite or were negative or above `MAX_RADIANCE` and were clamped.
    pub clamped: u64,
}

/// Reads `path` (Radiance `.hdr`/`.pic` RGBE, or OpenEXR `.exr`), chosen by extension
/// (case-insensitive); other extensions are an error naming the supported ones.
pub fn read_environment_image(path: &Path) -> Result<EnvironmentImage, SceneError> {
    // The extension first: an unsupported file is refused without being read.
    format_of(path)?;
    decode_environment_image(&read_file(path)?, path)
}

/// Same, from bytes already read (`path` only names the file in errors and picks the format).
pub fn decode_environment_image(bytes: &[u8], path: &Path) -> Result<EnvironmentImage, SceneError> {
    let invalid = |message: String| SceneError::invalid(path, "environment image", message);
    let decode = match format_of(path)? {
        Format::Radiance => radiance::decode,
        Format::OpenExr => openexr::decode,
    };
    let Decoded {
        width,
        height,
        mut texels,
    } = guarded(|| decode(bytes))
        .map_err(invalid)?
        .map_err(invalid)?;
    debug_assert_eq!(texels.len(), width as usize * height as usize);
    let clamped = texels.iter_mut().map(clamp_texel).filter(|&c| c).count() as u64;
    Ok(EnvironmentImage {
        width,
        height,
        texels,
        clamped,
    })
}

/// The file formats read here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Radiance,
    OpenExr,
}

/// The format of `path`, by its extension.
fn format_of(path: &Path) -> Result<Format, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("hdr" | "pic") => Ok(Format::Radiance),
        Some("exr") => Ok(Format::OpenExr),
        other => Err(SceneError::invalid(
            path,
            "environment image",
            format!(
                "{}: environment images are Radiance RGBE (.hdr, .pic) or OpenEXR (.exr)",
                other.map_or("no extension".into(), |e| format!("unknown extension .{e}"))
            ),
        )),
    }
}

/// What a format's decoder hands back, before the clamps.
struct Decoded {
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
}

/// `Ok` when a `width x height` image is within the limits above; the error gives the size
/// and the limit. Called with the header's size before anything is sized from it.
fn check_size(width: u64, height: u64) -> Result<(), String> {
    if width < u64::from(MIN_WIDTH) || height < u64::from(MIN_HEIGHT) {
        return Err(format!(
            "a {width}x{height} image; an environment map has at least {MIN_WIDTH}x{MIN_HEIGHT} \
             texels"
        ));
    }
    if width > u64::from(MAX_WIDTH)
        || height > u64::from(MAX_HEIGHT)
        || width.saturating_mul(height) > MAX_TEXELS
    {
        return Err(format!(
            "a {width}x{height} image is larger than lumis reads: at most {MAX_WIDTH} texels \
             across, {MAX_HEIGHT} down and {MAX_TEXELS} in all (16384x8192)"
        ));
    }
    Ok(())
}

/// Clamps the components of `texel` to `0..=MAX_RADIANCE` (NaN to 0, +∞ to `MAX_RADIANCE`);
/// `true` when any changed.
fn clamp_texel(texel: &mut [f32; 3]) -> bool {
    let mut changed = false;
    for c in texel {
        let clamped = if c.is_nan() || *c < 0.0 {
            0.0
        } else if *c > MAX_RADIANCE {
            MAX_RADIANCE
        } else {
            continue;
        };
        *c = clamped;
        changed = true;
    }
    changed
}

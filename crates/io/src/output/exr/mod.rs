//! lumis's OpenEXR files: one single-part scanline image, ZIP16 (lossless), holding the beauty
//! pass and the AOV layers a compositor needs; written here and read back here.
//!
//! | channel                 | type          | content                                            |
//! |-------------------------|---------------|----------------------------------------------------|
//! | `R`, `G`, `B`, `A`      | HALF or FLOAT | linear, premultiplied RGBA exactly as in the film (exposure already applied) |
//! | `Z`                     | FLOAT         | camera-space depth along the view axis; `+inf` where the centre ray missed |
//! | `N.X`, `N.Y`, `N.Z`     | FLOAT         | world-space unit shading normal; 0 where missed    |
//! | `id.prim`, `id.object`  | FLOAT         | primitive / object index as a float; -1 where missed |
//!
//! Optional layers: `albedo`, `P`, `uv` (`aov_layers.rs`, `--aov`), the light-path, per-light
//! and shadow passes (`pass_layers.rs`, `--aov lightpaths,lights`), the Cryptomatte layers
//! and their metadata (`cryptomatte.rs`, `--cryptomatte`); `--layout blender` renames every
//! channel to Blender's convention ([`ChannelLayout`]).
//!
//! The header carries the camera as the standard `worldToCamera` and `worldToNDC` M44f
//! attributes, so a compositor can project world positions into the image; `chromaticities`
//! (Rec.709/sRGB primaries, D65 white: the colours are linear sRGB); with depth of field the
//! standard `focus` (distance to the plane in focus, scene units) and `lumis/lensRadius` (or
//! `lumis/lensSquareSize`) and `lumis/lensSamples`; and
//! the sample counts (`lumis/spp` pixel samples in total, `lumis/sppPerAxis`).
//!
//! A render of part of the image (`--crop`, `--pixel-bounds`) is stored as that data window
//! inside the full display window, as OpenEXR intends; the camera matrices are the full
//! image's. A render stopped early (Ctrl-C) says so in `lumis/partial` = 1; its unfinished
//! pixels are 0 with alpha 0.
//!
//! This folder is the one owner of lumis's EXR files, both ways: each schema module
//! (`layout.rs`, `aov_layers.rs`, `cryptomatte.rs`, `provenance.rs`, `frame.rs`, `camera.rs`)
//! writes its channels or attributes and reads them back; `write.rs` encodes a [`Film`] with an
//! [`ExrMetadata`] and an [`ExrCamera`], `header_order.rs` fixes the attribute order, and
//! `read.rs` (with `header.rs` and `pixels.rs`) reads a file lumis wrote back into the same
//! three, so that writing them again gives the same bytes. `lumis merge` reads its tiles so.
//!
//! [`Film`]: lumis_core::film::Film

mod aov_layers;
mod camera;
mod cryptomatte;
mod frame;
mod header;
mod header_order;
mod layout;
mod pass_layers;
mod pixels;
mod provenance;
mod read;
mod write;

pub use self::aov_layers::AovLayers;
pub use self::camera::{ExrCamera, imath_m44f};
pub use self::cryptomatte::CryptoHeader;
pub use self::frame::ATTR_FRAME;
pub use self::header::{ExrHeader, HeaderValue, StandardAttributes};
pub use self::layout::ChannelLayout;
pub use self::provenance::{
    ATTR_REPLAY, ATTR_SCENE_HASH, ATTR_SEED, ATTR_SETTINGS, ATTR_TILE, ATTR_TILE_BEAUTY,
    ATTR_TILE_DISPLAY, ATTR_TILE_EXPOSURE, ATTR_TILE_RGBA, RenderIdentity, TILE_ATTR_PREFIX,
    TILE_EXPOSURE_AUTO, TileHeader,
};
pub use self::read::{ExrFile, ExrImage, MAX_CHANNELS, MAX_SAMPLES, ReadError, read_exr};
pub use self::write::{encode_exr, exr_channels, write_exr};

/// Value of the standard `software` attribute and of [`ATTR_RENDERER`]: `"lumis <version>"`.
pub const SOFTWARE: &str = concat!("lumis ", env!("CARGO_PKG_VERSION"));
/// Custom string attribute naming the renderer and its version ([`SOFTWARE`]).
pub const ATTR_RENDERER: &str = "lumis/renderer";
/// Custom int attribute: pixel samples per pixel in total (`sppPerAxis^2`).
pub const ATTR_SPP: &str = "lumis/spp";
/// Custom int attribute: the stratified pixel samples per axis (`--spp`).
pub const ATTR_SPP_PER_AXIS: &str = "lumis/sppPerAxis";
/// Custom int attribute: lens rays per pixel sample (only with depth of field).
pub const ATTR_LENS_SAMPLES: &str = "lumis/lensSamples";
/// Custom float attribute: the thin lens radius in scene units (only with depth of field).
pub const ATTR_LENS_RADIUS: &str = "lumis/lensRadius";
/// Custom float attribute: the side of the `.scn` square lens ("dispersion"), scene units.
pub const ATTR_LENS_SQUARE: &str = "lumis/lensSquareSize";
/// Custom int attribute, present (= 1) only when the render was stopped before every tile.
pub const ATTR_PARTIAL: &str = "lumis/partial";
/// Custom float attribute: wall-clock render time in seconds.
pub const ATTR_RENDER_SECONDS: &str = "lumis/renderSeconds";
/// Custom float attribute: the exposure in stops (EV) the colour was scaled by, `2^EV`.
pub const ATTR_EXPOSURE: &str = "lumis/exposure";

/// The FLOAT channels every file has besides RGBA (lumis names): depth, normal, ids.
const BASE_FLOAT_CHANNELS: [&str; 6] = ["Z", "N.X", "N.Y", "N.Z", "id.prim", "id.object"];

/// The largest finite half float; RGBA stored as half is clamped to it.
pub const HALF_MAX: f32 = 65504.0;

/// Render facts written into the EXR header alongside the pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrMetadata {
    /// Store `R,G,B,A` as 32-bit float instead of half. Half covers up to 65504 with ~3
    /// significant digits, enough for display; float keeps the film's values bit-exact.
    pub float_rgba: bool,
    /// Stratified pixel samples per axis (the pixel gets its square); the attributes saturate
    /// at `i32::MAX` because EXR has no unsigned int attribute.
    pub spp_per_axis: u32,
    /// Lens rays per pixel sample (written only when the camera has depth of field).
    pub lens_samples: u32,
    /// The `Z` value of pixels whose centre ray escaped: `+inf` by default, or a large
    /// finite value for compositors whose depth merges break on infinities (`--z-miss`).
    /// Read back from the pixels that missed (`+inf` when none did).
    pub z_miss: f32,
    /// The render was stopped early; recorded as `lumis/partial`.
    pub partial: bool,
    /// Wall-clock render time in seconds, written only when given (`--timing-metadata`): it
    /// differs between runs, and the same input must give the same bytes by default.
    pub render_seconds: Option<f32>,
    /// The exposure in stops already applied to the film's colour ([`lumis_core::film::Film::expose`]);
    /// recorded, not applied, here.
    pub exposure: f32,
    /// The optional AOV layers to write (albedo, position, uv).
    pub aov_layers: AovLayers,
    /// The channel naming convention.
    pub layout: ChannelLayout,
    /// What the render was made from (scene hash, seed, settings); not written when `None`.
    pub identity: Option<RenderIdentity>,
    /// Set for a farm tile (`--tile`): RGBA is then stored as float before exposure, for
    /// `lumis merge` to finish (see `provenance.rs`).
    pub tile: Option<TileHeader>,
    /// The frame of an animation the image is: `lumis/frame`, `framesPerSecond`, `timeCode`
    /// (`frame.rs`); `None` for a still.
    pub frame: Option<lumis_core::scene::Frame>,
}

impl Default for ExrMetadata {
    fn default() -> Self {
        Self {
            float_rgba: false,
            spp_per_axis: 1,
            lens_samples: 1,
            render_seconds: None,
            exposure: 0.0,
            z_miss: f32::INFINITY,
            partial: false,
            aov_layers: AovLayers::default(),
            layout: ChannelLayout::Lumis,
            identity: None,
            tile: None,
            frame: None,
        }
    }
}

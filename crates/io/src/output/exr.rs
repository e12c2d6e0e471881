//! OpenEXR output: one single-part scanline image, ZIP16 (lossless), holding the beauty pass
//! and the AOV layers a compositor needs.
//!
//! | channel                 | type          | content                                            |
//! |-------------------------|---------------|----------------------------------------------------|
//! | `R`, `G`, `B`, `A`      | HALF or FLOAT | linear, premultiplied RGBA exactly as in the film (exposure already applied) |
//! | `Z`                     | FLOAT         | camera-space depth along the view axis; `+inf` where the centre ray missed |
//! | `N.X`, `N.Y`, `N.Z`     | FLOAT         | world-space unit shading normal; 0 where missed    |
//! | `id.prim`, `id.object`  | FLOAT         | primitive / object index as a float; -1 where missed |
//!
//! Optional layers: `albedo`, `P`, `uv` ([`super::aov_layers`], `--aov`), the Cryptomatte
//! layers and their metadata ([`super::cryptomatte`], `--cryptomatte`); `--layout blender`
//! renames every channel to Blender's convention ([`super::layout`]).
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

use std::io::Write;
use std::path::Path;

use ::exr::meta::attribute::Chromaticities;
use ::exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Blocks, Compression, Encoding, FlatSamples, Image,
    ImageAttributes, IntegerBounds, Layer, LayerAttributes, LineOrder, SmallVec, Text, Vec2,
    WritableImage, f16,
};

use super::aov_layers::{self, AovLayers};
use super::cryptomatte;
use super::header_order::sorted_header;
use super::layout::ChannelLayout;
use super::provenance::{self, RenderIdentity, TileHeader};
use super::staged::write_atomically;
use super::{OutputError, check_not_empty};
use lumis_core::camera::{Camera, Lens};
use lumis_core::film::Film;
use lumis_core::math::{Mat4, Vec4};

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
    /// `lumis merge` to finish (see [`super::provenance`]).
    pub tile: Option<TileHeader>,
    /// The frame of an animation the image is: `lumis/frame`, `framesPerSecond`, `timeCode`
    /// ([`super::frame`]); `None` for a still.
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

/// Writes `film` to `path` as OpenEXR (channels and attributes in the module docs), atomically:
/// the target is replaced only after the whole file has been encoded. `camera` must be the
/// camera that rendered the film; its matrices are computed for the film's size.
pub fn write_exr(
    path: &Path,
    film: &Film,
    camera: &Camera,
    meta: &ExrMetadata,
) -> Result<(), OutputError> {
    let bytes = encode_exr(path, film, camera, meta)?;
    write_atomically(path, |w| {
        w.write_all(&bytes).map_err(|source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        })
    })
}

/// The bytes [`write_exr`] would write (`path` only names the file in errors), for staging
/// with the other outputs of a run.
pub fn encode_exr(
    path: &Path,
    film: &Film,
    camera: &Camera,
    meta: &ExrMetadata,
) -> Result<Vec<u8>, OutputError> {
    check_not_empty(path, film)?;
    lumis_core::film::check_finite(film).map_err(|source| OutputError::NonFinite {
        path: path.to_path_buf(),
        source,
    })?;
    let (full_width, full_height) = film.full_size();
    let mut attributes = ImageAttributes::new(IntegerBounds::from_dimensions(Vec2(
        full_width as usize,
        full_height as usize,
    )));
    attributes.chromaticities = Some(REC709_D65);
    let mut image = Image::new(attributes, build_layer(film, camera, meta));
    super::frame::stamp(&mut image, meta.frame);
    let mut encoded = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut encoded)
        .map_err(|source| OutputError::Exr {
            path: path.to_path_buf(),
            source,
        })?;
    let encoded = encoded.into_inner();
    // Same input, same bytes: the crate's attribute order varies from run to run.
    Ok(sorted_header(&encoded).unwrap_or(encoded))
}

/// The OpenEXR/Imath M44f memory layout of a glam column-vector matrix.
///
/// Imath multiplies row vectors (`p' = p * M`) and stores `M` row-major, so the EXR matrix is
/// the transpose of glam's `M`; row-major storage of the transpose is exactly glam's
/// column-major array. The exr crate writes the 16 floats in array order, unchanged.
pub fn imath_m44f(m: Mat4) -> [f32; 16] {
    m.to_cols_array()
}

/// The Rec.709 / sRGB primaries and the D65 white point (CIE 1931 xy), as ITU-R BT.709 gives
/// them: the colour space of lumis's linear RGB.
const REC709_D65: Chromaticities = Chromaticities {
    red: Vec2(0.64, 0.33),
    green: Vec2(0.30, 0.60),
    blue: Vec2(0.15, 0.06),
    white: Vec2(0.3127, 0.3290),
};

/// An RGBA value as half. Half tops out at 65504: a brighter (finite) value would round to
/// infinity, so it is clamped there; `--float` keeps the film's values.
pub(crate) fn half_rgba(v: f32) -> f16 {
    f16::from_f32(v.clamp(-HALF_MAX, HALF_MAX))
}

/// The channels of the EXR [`encode_exr`] writes for `film`, by name, in the file's order
/// (sorted by name, as EXR requires), each `width x height` samples in row order: exactly the
/// values stored (RGBA as half unless `meta.float_rgba`, the rest float). The Python package
/// returns these as its render's arrays.
pub fn exr_channels(film: &Film, meta: &ExrMetadata) -> Vec<(String, FlatSamples)> {
    channel_list(film, meta)
        .into_iter()
        .map(|c| (c.name.to_string(), c.sample_data))
        .collect()
}

/// The channels of the layer, named by `meta.layout` and sorted by name.
fn channel_list(film: &Film, meta: &ExrMetadata) -> SmallVec<[AnyChannel<FlatSamples>; 4]> {
    let rgba = film.rgba();
    let aov = film.aov();
    let beauty = |component: fn(Vec4) -> f32| {
        let values = rgba.iter().map(|&p| component(p));
        // A tile keeps the film's floats: the merge converts them, as here, after exposure.
        if meta.float_rgba || meta.tile.is_some() {
            FlatSamples::F32(values.collect())
        } else {
            FlatSamples::F16(values.map(half_rgba).collect())
        }
    };
    let float = |values: Vec<f32>| FlatSamples::F32(values);
    // Ids are floats because compositors handle FLOAT everywhere and -1 must survive; f32 is
    // exact for indices up to 2^24.
    let mut channels = vec![
        channel("R", beauty(|p| p.x)),
        channel("G", beauty(|p| p.y)),
        channel("B", beauty(|p| p.z)),
        channel("A", beauty(|p| p.w)),
        channel(
            "Z",
            float(
                aov.iter()
                    .map(|a| {
                        if a.depth.is_finite() {
                            a.depth
                        } else {
                            meta.z_miss
                        }
                    })
                    .collect(),
            ),
        ),
        channel("N.X", float(aov.iter().map(|a| a.normal.x).collect())),
        channel("N.Y", float(aov.iter().map(|a| a.normal.y).collect())),
        channel("N.Z", float(aov.iter().map(|a| a.normal.z).collect())),
        channel(
            "id.prim",
            float(aov.iter().map(|a| a.prim_id as f32).collect()),
        ),
        channel(
            "id.object",
            float(aov.iter().map(|a| a.object_id as f32).collect()),
        ),
    ];
    for (name, values) in aov_layers::channels(film, meta.aov_layers, meta.layout) {
        channels.push(channel(name, float(values)));
    }
    for layer in film.crypto() {
        for (name, values) in cryptomatte::channels(layer) {
            channels.push(channel(&name, float(values)));
        }
    }
    for c in &mut channels {
        c.name = Text::from(meta.layout.channel(&c.name.to_string()).as_str());
    }
    // EXR requires channels sorted by name.
    AnyChannels::sort(SmallVec::from_vec(channels)).list
}

/// Builds the single layer: channels from the film, attributes from the camera and `meta`.
fn build_layer(
    film: &Film,
    camera: &Camera,
    meta: &ExrMetadata,
) -> Layer<AnyChannels<FlatSamples>> {
    let (width, height) = (film.width(), film.height());
    let (full_width, full_height) = film.full_size();
    let (ox, oy) = film.origin();
    let dof = camera.has_depth_of_field();
    let mut attributes = LayerAttributes {
        layer_position: Vec2(ox as i32, oy as i32),
        world_to_camera: Some(imath_m44f(camera.world_to_camera())),
        world_to_normalized_device: Some(imath_m44f(camera.world_to_ndc(full_width, full_height))),
        software_name: Some(Text::from(SOFTWARE)),
        focus: dof.then(|| camera.focus_distance()),
        ..LayerAttributes::default()
    };
    let int = |n: u64| AttributeValue::I32(i32::try_from(n).unwrap_or(i32::MAX));
    let per_axis = u64::from(meta.spp_per_axis);
    let mut extra = Vec::new();
    if dof {
        extra.push((ATTR_LENS_SAMPLES, int(u64::from(meta.lens_samples))));
        match camera.lens() {
            Lens::Disk(r) => extra.push((ATTR_LENS_RADIUS, AttributeValue::F32(r))),
            Lens::Square(s) => extra.push((ATTR_LENS_SQUARE, AttributeValue::F32(s))),
            Lens::Pinhole => {}
        }
    }
    if let Some(seconds) = meta.render_seconds {
        extra.push((ATTR_RENDER_SECONDS, AttributeValue::F32(seconds)));
    }
    if meta.partial {
        extra.push((ATTR_PARTIAL, AttributeValue::I32(1)));
    }
    // A tile's colour is not exposed yet: the merge records the exposure it applies.
    if meta.tile.is_none() {
        extra.push((ATTR_EXPOSURE, AttributeValue::F32(meta.exposure)));
    }
    for (name, value) in [
        (ATTR_RENDERER, AttributeValue::Text(Text::from(SOFTWARE))),
        (ATTR_SPP, int(per_axis * per_axis)),
        (ATTR_SPP_PER_AXIS, int(per_axis)),
    ]
    .into_iter()
    .chain(extra)
    {
        attributes.other.insert(Text::from(name), value);
    }
    attributes.other.extend(provenance::attributes(
        meta.identity.as_ref(),
        meta.tile.as_ref(),
        meta.float_rgba,
        meta.layout,
    ));
    for layer in film.crypto() {
        attributes
            .other
            .extend(cryptomatte::attributes(layer, meta.layout));
    }

    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    Layer::new(
        Vec2(width as usize, height as usize),
        attributes,
        encoding,
        AnyChannels {
            list: channel_list(film, meta),
        },
    )
}

/// A full-resolution channel. `quantize_linearly` (pLinear) only steers lossy B44/DWA
/// compression; it is off, as in OpenEXR's own default, since we write lossless ZIP.
fn channel(name: &str, samples: FlatSamples) -> AnyChannel<FlatSamples> {
    AnyChannel {
        name: Text::from(name),
        sample_data: samples,
        quantize_linearly: false,
        sampling: Vec2(1, 1),
    }
}

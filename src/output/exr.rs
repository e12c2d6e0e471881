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
//! attributes, so a compositor can project world positions into the image.

use std::path::Path;

use ::exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Blocks, Compression, Encoding, FlatSamples, Image,
    Layer, LayerAttributes, LineOrder, SmallVec, Text, Vec2, WritableImage, f16,
};

use super::aov_layers::{self, AovLayers};
use super::atomic::write_atomically;
use super::cryptomatte;
use super::layout::ChannelLayout;
use super::{OutputError, check_not_empty};
use crate::camera::Camera;
use crate::film::Film;
use crate::math::{Mat4, Vec4};

/// Value of the standard `software` attribute and of [`ATTR_RENDERER`]: `"lumis <version>"`.
pub const SOFTWARE: &str = concat!("lumis ", env!("CARGO_PKG_VERSION"));
/// Custom string attribute naming the renderer and its version ([`SOFTWARE`]).
pub const ATTR_RENDERER: &str = "lumis/renderer";
/// Custom int attribute: samples per pixel.
pub const ATTR_SPP: &str = "lumis/spp";
/// Custom float attribute: wall-clock render time in seconds.
pub const ATTR_RENDER_SECONDS: &str = "lumis/renderSeconds";
/// Custom float attribute: the exposure in stops (EV) the colour was scaled by, `2^EV`.
pub const ATTR_EXPOSURE: &str = "lumis/exposure";

/// Render facts written into the EXR header alongside the pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExrMetadata {
    /// Store `R,G,B,A` as 32-bit float instead of half. Half covers up to 65504 with ~3
    /// significant digits, enough for display; float keeps the film's values bit-exact.
    pub float_rgba: bool,
    /// Samples per pixel; saturates at `i32::MAX` because EXR has no unsigned int attribute.
    pub spp: u32,
    /// Wall-clock render time in seconds.
    pub render_seconds: f32,
    /// The exposure in stops already applied to the film's colour ([`crate::film::Film::expose`]);
    /// recorded, not applied, here.
    pub exposure: f32,
    /// The optional AOV layers to write (albedo, position, uv).
    pub aov_layers: AovLayers,
    /// The channel naming convention.
    pub layout: ChannelLayout,
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
    check_not_empty(path, film)?;
    let image = Image::from_layer(build_layer(film, camera, meta));
    write_atomically(path, |w| {
        image
            .write()
            .to_buffered(w)
            .map_err(|source| OutputError::Exr {
                path: path.to_path_buf(),
                source,
            })
    })
}

/// The OpenEXR/Imath M44f memory layout of a glam column-vector matrix.
///
/// Imath multiplies row vectors (`p' = p * M`) and stores `M` row-major, so the EXR matrix is
/// the transpose of glam's `M`; row-major storage of the transpose is exactly glam's
/// column-major array. The exr crate writes the 16 floats in array order, unchanged.
pub fn imath_m44f(m: Mat4) -> [f32; 16] {
    m.to_cols_array()
}

/// Builds the single layer: channels from the film, attributes from the camera and `meta`.
fn build_layer(
    film: &Film,
    camera: &Camera,
    meta: &ExrMetadata,
) -> Layer<AnyChannels<FlatSamples>> {
    let (width, height) = (film.width(), film.height());
    let rgba = film.rgba();
    let aov = film.aov();

    let beauty = |component: fn(Vec4) -> f32| {
        let values = rgba.iter().map(|&p| component(p));
        if meta.float_rgba {
            FlatSamples::F32(values.collect())
        } else {
            FlatSamples::F16(values.map(f16::from_f32).collect())
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
        channel("Z", float(aov.iter().map(|a| a.depth).collect())),
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
    for (name, values) in aov_layers::channels(film, meta.aov_layers) {
        channels.push(channel(name, float(values)));
    }
    for layer in film.crypto() {
        for (name, values) in cryptomatte::channels(layer, meta.layout) {
            channels.push(channel(&name, float(values)));
        }
    }
    for c in &mut channels {
        c.name = Text::from(meta.layout.channel(&c.name.to_string()).as_str());
    }

    let mut attributes = LayerAttributes {
        world_to_camera: Some(imath_m44f(camera.world_to_camera())),
        world_to_normalized_device: Some(imath_m44f(camera.world_to_ndc(width, height))),
        software_name: Some(Text::from(SOFTWARE)),
        ..LayerAttributes::default()
    };
    let spp = i32::try_from(meta.spp).unwrap_or(i32::MAX);
    for (name, value) in [
        (ATTR_RENDERER, AttributeValue::Text(Text::from(SOFTWARE))),
        (ATTR_SPP, AttributeValue::I32(spp)),
        (
            ATTR_RENDER_SECONDS,
            AttributeValue::F32(meta.render_seconds),
        ),
        (ATTR_EXPOSURE, AttributeValue::F32(meta.exposure)),
    ] {
        attributes.other.insert(Text::from(name), value);
    }
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
        // EXR requires channels sorted by name; `sort` does that for us.
        AnyChannels::sort(SmallVec::from_vec(channels)),
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

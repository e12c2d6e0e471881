//! Encoding a [`Film`] as lumis's OpenEXR file (the channels and attributes in the module
//! docs of `output::exr`), deterministically: the same film, metadata and camera give the same
//! bytes, which is what lets `lumis merge` rewrite a single render's file.

use std::io::Write;
use std::path::Path;

use ::exr::meta::attribute::Chromaticities;
use ::exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Blocks, Compression, Encoding, FlatSamples, Image,
    ImageAttributes, IntegerBounds, Layer, LayerAttributes, LineOrder, SmallVec, Text, Vec2,
    WritableImage, f16,
};

use super::camera::imath_m44f;
use super::header_order::sorted_header;
use super::{
    ATTR_EXPOSURE, ATTR_LENS_RADIUS, ATTR_LENS_SAMPLES, ATTR_LENS_SQUARE, ATTR_PARTIAL,
    ATTR_RENDER_SECONDS, ATTR_RENDERER, ATTR_SPP, ATTR_SPP_PER_AXIS, ExrCamera, ExrMetadata,
    HALF_MAX, SOFTWARE, aov_layers, cryptomatte, frame, pass_layers, provenance,
};
use crate::output::staged::write_atomically;
use crate::output::{OutputError, check_not_empty};
use lumis_core::camera::Lens;
use lumis_core::film::Film;
use lumis_core::math::Vec4;

/// Writes `film` to `path` as OpenEXR (channels and attributes in the module docs), atomically:
/// the target is replaced only after the whole file has been encoded. `camera` is what the
/// header records of the camera that rendered the film ([`ExrCamera::new`] for the film's
/// full size).
pub fn write_exr(
    path: &Path,
    film: &Film,
    camera: &ExrCamera,
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
    camera: &ExrCamera,
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
    frame::stamp(&mut image, meta.frame);
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
fn half_rgba(v: f32) -> f16 {
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
    for (name, values) in pass_layers::channels(film) {
        channels.push(channel(&name, float(values)));
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
    camera: &ExrCamera,
    meta: &ExrMetadata,
) -> Layer<AnyChannels<FlatSamples>> {
    let (width, height) = (film.width(), film.height());
    let (ox, oy) = film.origin();
    let dof = camera.focus.is_some();
    let mut attributes = LayerAttributes {
        layer_position: Vec2(ox as i32, oy as i32),
        world_to_camera: Some(imath_m44f(camera.world_to_camera)),
        world_to_normalized_device: Some(imath_m44f(camera.world_to_ndc)),
        software_name: Some(Text::from(SOFTWARE)),
        focus: camera.focus,
        ..LayerAttributes::default()
    };
    let int = |n: u64| AttributeValue::I32(i32::try_from(n).unwrap_or(i32::MAX));
    let per_axis = u64::from(meta.spp_per_axis);
    let mut extra = Vec::new();
    if dof {
        extra.push((ATTR_LENS_SAMPLES, int(u64::from(meta.lens_samples))));
        match camera.lens {
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

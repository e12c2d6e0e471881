//! A header lumis wrote, read back into the values that wrote it: the [`ExrMetadata`], the
//! [`ExrCamera`], the window of the full image, the Cryptomatte layers, and the channels the
//! pixels must then have. Each schema module reads its own part (`provenance.rs`,
//! `frame.rs`, `camera.rs`, `cryptomatte.rs`, `aov_layers.rs`, `layout.rs`); this one puts
//! them together and keeps, for a caller comparing headers (`lumis merge`), every custom
//! attribute by name and a fingerprint of the standard ones.

use std::collections::{BTreeMap, BTreeSet};

use ::exr::meta::header::Header;
use ::exr::prelude::{
    AttributeValue, Compression, ImageAttributes, IntegerBounds, LayerAttributes, LineOrder,
    SampleType, Text, Vec2,
};

use super::cryptomatte::{self, CryptoHeader};
use super::{
    ATTR_EXPOSURE, ATTR_LENS_SAMPLES, ATTR_PARTIAL, ATTR_RENDER_SECONDS, ATTR_SPP_PER_AXIS,
    AovLayers, ChannelLayout, ExrCamera, ExrMetadata, aov_layers, frame, pass_layers, provenance,
};
use lumis_core::film::PixelWindow;

/// What a header lumis wrote says, in lumis's terms.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrHeader {
    /// The full image (the display window), in pixels.
    pub full_size: (u32, u32),
    /// The pixels the file holds (the data window) in the full image.
    pub window: PixelWindow,
    /// The metadata that writes this header again, but for `z_miss`, which only the pixels
    /// tell ([`super::ExrImage::meta`] has it).
    pub meta: ExrMetadata,
    /// The camera the header records.
    pub camera: ExrCamera,
    /// The Cryptomatte layers, in the order of their metadata keys.
    pub crypto: Vec<CryptoHeader>,
    /// The RGB pass layers (lumis names: `diffuse`, `light.key`, `shadow`), in channel order.
    pub passes: Vec<String>,
    /// Every custom attribute (`lumis/...`, `cryptomatte/...`), by name.
    pub attributes: BTreeMap<String, HeaderValue>,
    /// The channels as `name (type)`, in the file's (alphabetical) order.
    pub channels: Vec<String>,
    /// The standard attributes, for comparing two headers.
    pub standard: StandardAttributes,
}

/// A custom attribute's value.
#[derive(Clone, Debug, PartialEq)]
pub enum HeaderValue {
    /// A string attribute (its bytes read as UTF-8, invalid sequences replaced).
    Text(String),
    /// Any other type, as its debug text.
    Other(String),
}

impl std::fmt::Display for HeaderValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Text(s) | Self::Other(s) => f.write_str(s),
        }
    }
}

/// The standard attributes of a header (compression, chromaticities, camera matrices, time
/// code, ...) but the windows, opaque: two are equal when the headers agree in all of them.
#[derive(Clone, Debug, PartialEq)]
pub struct StandardAttributes {
    compression: Compression,
    line_order: LineOrder,
    image: ImageAttributes,
    layer: LayerAttributes,
}

/// The string attribute `name` of `header`, if it is one.
pub(super) fn text(header: &Header, name: &str) -> Option<String> {
    match header.own_attributes.other.get(&Text::from(name)) {
        Some(AttributeValue::Text(t)) => Some(String::from_utf8_lossy(t.bytes()).into_owned()),
        _ => None,
    }
}

/// The int attribute `name` of `header` as a count of at least 1.
fn count(header: &Header, name: &str) -> Result<u32, String> {
    match header.own_attributes.other.get(&Text::from(name)) {
        Some(AttributeValue::I32(n)) if *n >= 1 => Ok(*n as u32),
        Some(other) => Err(format!(
            "{name} = {other:?}: expected a count of at least 1"
        )),
        None => Err(format!("no {name} attribute: not an EXR lumis wrote")),
    }
}

impl ExrHeader {
    /// Reads `header` (one scanline part whose sizes were checked), or says what in it lumis
    /// would not have written.
    pub(super) fn read(header: &Header) -> Result<Self, String> {
        let display = header.shared_attributes.display_window;
        if display.position != Vec2(0, 0) {
            return Err(format!(
                "the display window starts at {:?}; lumis's start at (0, 0)",
                display.position
            ));
        }
        let full_size = (display.size.0 as u32, display.size.1 as u32);
        let window = data_window(header)?;
        // The tile's attributes first: they say how to read the rest.
        let tile = provenance::read_tile(header)?;
        let names: BTreeSet<String> = header
            .channels
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        let has = |name: &str| names.contains(name);
        let layout = match &tile {
            Some(t) => ChannelLayout::ALL
                .into_iter()
                .find(|l| l.beauty().as_slice() == t.beauty.as_slice() && has(&t.beauty[0])),
            None => ChannelLayout::ALL.into_iter().find(|l| has(&l.beauty()[0])),
        };
        let Some(layout) = layout else {
            return Err(match &tile {
                Some(t) => format!(
                    "{} = {:?}: expected the names of its four R, G, B, A channels",
                    super::ATTR_TILE_BEAUTY,
                    t.beauty.join(",")
                ),
                None => "no R or ViewLayer.Combined.R channel: not an EXR lumis wrote".into(),
            });
        };
        let aov_layers = aov_layers::present(layout, has);
        let crypto = cryptomatte::read_headers(header, layout, has)?;
        let passes = pass_layers::present(layout, &names);
        let float_rgba =
            check_channels(header, layout, aov_layers, &passes, &crypto, tile.is_some())?;
        let camera = ExrCamera::read(header)?;
        let other = &header.own_attributes.other;
        let float = |name: &str| match other.get(&Text::from(name)) {
            Some(AttributeValue::F32(v)) => Some(*v),
            _ => None,
        };
        let exposure = match &tile {
            // A tile's colour is not exposed; what develop records for one.
            Some(t) => t.tile.exposure.unwrap_or(0.0),
            None => {
                float(ATTR_EXPOSURE).ok_or_else(|| format!("no float {ATTR_EXPOSURE} attribute"))?
            }
        };
        let meta = ExrMetadata {
            float_rgba: tile.as_ref().map_or(float_rgba, |t| t.float_rgba),
            spp_per_axis: count(header, ATTR_SPP_PER_AXIS)?,
            lens_samples: match camera.focus {
                Some(_) => count(header, ATTR_LENS_SAMPLES)?,
                None => 1,
            },
            z_miss: f32::INFINITY,
            partial: other.contains_key(&Text::from(ATTR_PARTIAL)),
            render_seconds: float(ATTR_RENDER_SECONDS),
            exposure,
            aov_layers,
            layout,
            identity: provenance::read_identity(header)?,
            tile: tile.map(|t| t.tile),
            frame: frame::read(header)?,
        };
        Ok(Self {
            full_size,
            window,
            meta,
            camera,
            crypto,
            passes,
            attributes: other
                .iter()
                .map(|(k, v)| {
                    let value = match v {
                        AttributeValue::Text(t) => {
                            HeaderValue::Text(String::from_utf8_lossy(t.bytes()).into_owned())
                        }
                        other => HeaderValue::Other(format!("{other:?}")),
                    };
                    (k.to_string(), value)
                })
                .collect(),
            channels: header
                .channels
                .list
                .iter()
                .map(|c| format!("{} ({:?})", c.name, c.sample_type))
                .collect(),
            standard: StandardAttributes {
                compression: header.compression,
                line_order: header.line_order,
                image: ImageAttributes {
                    display_window: IntegerBounds::zero(),
                    ..header.shared_attributes.clone()
                },
                layer: LayerAttributes {
                    layer_position: Vec2(0, 0),
                    other: Default::default(),
                    ..header.own_attributes.clone()
                },
            },
        })
    }
}

/// The data window in the full image; it must lie inside the display window (at (0, 0)).
fn data_window(header: &Header) -> Result<PixelWindow, String> {
    let display = header.shared_attributes.display_window.size;
    let at = header.own_attributes.layer_position;
    let size = header.layer_size;
    let (x0, y0) = (i64::from(at.0), i64::from(at.1));
    let (x1, y1) = (x0 + size.0 as i64, y0 + size.1 as i64);
    if x0 < 0 || y0 < 0 || x1 > display.0 as i64 || y1 > display.1 as i64 {
        return Err(format!(
            "a data window x {x0}..{x1}, y {y0}..{y1} outside the {}x{} display window; \
             lumis stores a part of its image",
            display.0, display.1
        ));
    }
    // Inside a display window of at most MAX_SIDE pixels a side: every bound fits a u32.
    Ok(PixelWindow {
        x0: x0 as u32,
        x1: x1 as u32,
        y0: y0 as u32,
        y1: y1 as u32,
    })
}

/// Checks the channel list is what lumis writes for these layers: the beauty pass (HALF or
/// FLOAT, FLOAT in a tile), depth, normal and ids, the optional AOV and Cryptomatte layers
/// (FLOAT), and nothing else. Returns whether RGBA is FLOAT.
fn check_channels(
    header: &Header,
    layout: ChannelLayout,
    aov: AovLayers,
    passes: &[String],
    crypto: &[CryptoHeader],
    tile: bool,
) -> Result<bool, String> {
    let types: BTreeMap<String, SampleType> = header
        .channels
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_type))
        .collect();
    let beauty = layout.beauty();
    let rgba_type = types[&beauty[0]];
    let mut expected: BTreeMap<String, SampleType> =
        beauty.into_iter().map(|n| (n, rgba_type)).collect();
    let aov_names = aov_layers::names(aov, layout);
    let pass_names = pass_layers::names(passes);
    let float_names = super::BASE_FLOAT_CHANNELS
        .iter()
        .chain(&aov_names)
        .map(|n| layout.channel(n))
        .chain(pass_names.iter().map(|n| layout.channel(n)))
        .chain(crypto.iter().flat_map(|c| c.channels(layout)));
    expected.extend(float_names.map(|n| (n, SampleType::F32)));
    for c in &header.channels.list {
        if (c.sampling.0, c.sampling.1) != (1, 1) {
            return Err(format!(
                "channel {} is subsampled; lumis writes none",
                c.name
            ));
        }
    }
    for (name, want) in &expected {
        match types.get(name) {
            None => return Err(format!("no channel {name}: not an EXR lumis wrote")),
            Some(got) if got != want => {
                return Err(format!("channel {name} is {got:?}, expected {want:?}"));
            }
            Some(_) => {}
        }
    }
    if let Some(extra) = types.keys().find(|n| !expected.contains_key(*n)) {
        return Err(format!("channel {extra} is not one lumis writes"));
    }
    match rgba_type {
        SampleType::F32 => Ok(true),
        SampleType::F16 if !tile => Ok(false),
        SampleType::F16 => Err(format!(
            "channel {} is not FLOAT; a tile keeps RGBA as float",
            layout.beauty()[0]
        )),
        other => Err(format!("channel {} is {other:?}", layout.beauty()[0])),
    }
}

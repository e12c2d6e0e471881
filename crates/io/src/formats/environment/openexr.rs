//! OpenEXR (`.exr`) environment maps through the `exr` crate: the header read and checked
//! first, then only the colour channels decoded, as `f32` whatever they are stored as.
//!
//! The colour is taken from the first part (the first "layer" in the `exr` crate's words),
//! from the first of these its channels offer:
//!
//! 1. `R`, `G`, `B`;
//! 2. `<layer>.R`, `<layer>.G`, `<layer>.B` of a single layer (a Blender multilayer file's
//!    `ViewLayer.Combined.R`, ...); of several such layers, Blender's `Combined` pass if there
//!    is exactly one, else an error listing them;
//! 3. a luminance-only `Y`, read as grey (not with `RY`/`BY` chroma, which is refused).
//!
//! Other channels (alpha, depth, ...) are not decoded. Channels are half or float; integer
//! (`u32`) colour and subsampled channels are refused.
//! Tiled and mip-mapped files are read at their full resolution. The data window is the
//! image (an environment map has no use for a display window around it); `y` grows down, so
//! its first row is the top of the map.

use std::collections::HashMap;
use std::io::{self, Cursor, Read, Seek, SeekFrom};

use ::exr::error::Error as ExrError;
use ::exr::meta::MetaData;
use ::exr::meta::attribute::{ChannelDescription, SampleType, Text};
use ::exr::meta::header::Header;
use ::exr::prelude::{ReadChannels, ReadLayers, ReadSpecificChannel, Vec2, read};

use super::{Decoded, check_size};

/// The texels of the OpenEXR file `bytes`, or what is wrong with it.
pub(super) fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let mut file = Watched::new(bytes);
    let meta = MetaData::read_from_buffered(&mut file, false).map_err(|e| {
        if file.past_end {
            format!("truncated: the file ends inside the OpenEXR header ({e})")
        } else {
            format!("not an OpenEXR file lumis can read: {e}")
        }
    })?;
    let header = first_part(&meta)?;
    let list = &header.channels.list;
    let name = |i: usize| list[i].name.clone();
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    let mut file = Watched::new(bytes);
    let texels = match colour_channels(list)? {
        Colour::Rgb([r, g, b]) => read_rgb(&mut file, [name(r), name(g), name(b)]),
        Colour::Grey(y) => read_grey(&mut file, name(y)),
    }
    .map_err(|e| {
        if file.past_end {
            format!(
                "truncated: the header declares {width}x{height} texels but the file ends \
                 inside the pixel data ({e})"
            )
        } else {
            format!("cannot decode the pixels: {e}")
        }
    })?;
    if texels.written < texels.texels.len() {
        return Err(format!(
            "incomplete: the header declares {width}x{height} texels but the file holds {} of \
             them",
            texels.written
        ));
    }
    Ok(Decoded {
        // check_size bounded both.
        width: width as u32,
        height: height as u32,
        texels: texels.texels,
    })
}

/// The header of the part to read, once every part's size is within the limits, none is
/// deep, and the first has no subsampled channel (the crate would misread its lines).
fn first_part(meta: &MetaData) -> Result<&Header, String> {
    // Every part is checked, not only the one read: the crate walks all parts' chunk tables.
    let parts = meta.headers.len();
    for (i, header) in meta.headers.iter().enumerate() {
        let part = if parts > 1 {
            format!("part {i}: ")
        } else {
            String::new()
        };
        if header.deep {
            return Err(format!("{part}deep data; lumis reads flat images"));
        }
        let size = header.layer_size;
        check_size(size.width() as u64, size.height() as u64).map_err(|e| format!("{part}{e}"))?;
    }
    let header = meta.headers.first().ok_or("a file without parts")?;
    let subsampled: Vec<String> = (header.channels.list.iter())
        .filter(|c| c.sampling != Vec2(1, 1))
        .map(|c| c.name.to_string())
        .collect();
    if !subsampled.is_empty() {
        return Err(format!(
            "subsampled channels ({}); lumis reads channels stored at every pixel",
            subsampled.join(", ")
        ));
    }
    Ok(header)
}

/// [`choose_channels`], refusing integer colour.
fn colour_channels(list: &[ChannelDescription]) -> Result<Colour, String> {
    let colour = choose_channels(list)?;
    let used: &[usize] = match &colour {
        Colour::Rgb(rgb) => rgb,
        Colour::Grey(y) => std::slice::from_ref(y),
    };
    match used
        .iter()
        .map(|&i| &list[i])
        .find(|c| c.sample_type == SampleType::U32)
    {
        Some(c) => Err(format!(
            "channel {} holds integers (u32); lumis reads half or float colour",
            c.name
        )),
        None => Ok(colour),
    }
}

/// Where the colour is, as indices into the part's channel list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Colour {
    /// Red, green and blue channels.
    Rgb([usize; 3]),
    /// A luminance channel, read as grey.
    Grey(usize),
}

/// The colour channels among `list` (see the module docs for the order of preference); the
/// error lists the channels there are.
fn choose_channels(list: &[ChannelDescription]) -> Result<Colour, String> {
    let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
    let index: HashMap<&str, usize> = names.iter().enumerate().map(|(i, n)| (&**n, i)).collect();
    let rgb_of = |prefix: &str| -> Option<[usize; 3]> {
        let at = |c: &str| index.get(format!("{prefix}{c}").as_str()).copied();
        Some([at("R")?, at("G")?, at("B")?])
    };
    if let Some(rgb) = rgb_of("") {
        return Ok(Colour::Rgb(rgb));
    }
    let layers: Vec<(&str, [usize; 3])> = names
        .iter()
        .filter_map(|n| {
            let layer = n.strip_suffix(".R")?;
            Some((layer, rgb_of(&format!("{layer}."))?))
        })
        .collect();
    let combined = |layer: &str| layer == "Combined" || layer.ends_with(".Combined");
    match layers.as_slice() {
        [] => {}
        [(_, rgb)] => return Ok(Colour::Rgb(*rgb)),
        several => {
            let mut beauty = several.iter().filter(|(layer, _)| combined(layer));
            if let (Some((_, rgb)), None) = (beauty.next(), beauty.next()) {
                return Ok(Colour::Rgb(*rgb));
            }
            let layers: Vec<&str> = several.iter().map(|(layer, _)| *layer).collect();
            return Err(format!(
                "several RGB layers ({}); lumis reads a file's only one, or Blender's \
                 `Combined` pass: save the environment as an RGB image",
                layers.join(", ")
            ));
        }
    }
    if let Some(&y) = index.get("Y") {
        if index.contains_key("RY") || index.contains_key("BY") {
            return Err("a luminance-chroma file (Y, RY, BY); lumis reads RGB or \
                        luminance-only (Y) files"
                .into());
        }
        return Ok(Colour::Grey(y));
    }
    Err(format!(
        "no colour channels: lumis reads R, G, B (or one layer's <layer>.R, .G, .B, or a \
         luminance Y), and the first part has {}",
        channel_list(&names)
    ))
}

/// `names` for a message, the first few of a long list.
fn channel_list(names: &[String]) -> String {
    const SHOWN: usize = 16;
    match names.len() {
        0 => "no channels".into(),
        n if n <= SHOWN => format!("channels {}", names.join(", ")),
        n => format!(
            "channels {} and {} more",
            names[..SHOWN].join(", "),
            n - SHOWN
        ),
    }
}

/// The decoded texels of one layer, and how many of them the file wrote.
struct Texels {
    width: usize,
    texels: Vec<[f32; 3]>,
    written: usize,
}

impl Texels {
    /// Room for a layer of `size` texels, all 0. Only called for the part whose size
    /// `check_size` accepted; zeroed pages are committed as they are written.
    fn new<T>(size: Vec2<usize>, _channels: &T) -> Self {
        Self {
            width: size.width(),
            texels: vec![[0.0; 3]; size.area()],
            written: 0,
        }
    }

    /// Stores the texel at `position` of the layer.
    fn set(&mut self, position: Vec2<usize>, texel: [f32; 3]) {
        let i = position.y() * self.width + position.x();
        if position.x() < self.width
            && let Some(t) = self.texels.get_mut(i)
        {
            *t = texel;
            self.written += 1;
        }
    }
}

/// The file's bytes as the decoder reads them, noting whether it asked for bytes past the
/// end: the crate reports a truncated file as an invalid reference, not as its end.
struct Watched<'a> {
    bytes: Cursor<&'a [u8]>,
    past_end: bool,
}

impl<'a> Watched<'a> {
    /// `bytes` from their start.
    fn new(bytes: &'a [u8]) -> Self {
        Self {
            bytes: Cursor::new(bytes),
            past_end: false,
        }
    }
}

impl Read for Watched<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.bytes.read(buf)?;
        self.past_end |= n < buf.len();
        Ok(n)
    }
}

impl Seek for Watched<'_> {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        self.bytes.seek(to)
    }
}

/// Decodes the red, green and blue channels named `rgb` of the first part.
fn read_rgb(file: &mut Watched<'_>, [r, g, b]: [Text; 3]) -> Result<Texels, ExrError> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required(r)
        .required(g)
        .required(b)
        .collect_pixels(
            Texels::new,
            |t: &mut Texels, at, (r, g, b): (f32, f32, f32)| t.set(at, [r, g, b]),
        )
        .first_valid_layer()
        .all_attributes()
        // On this thread, so that the panic guard covers the decoding.
        .non_parallel()
        .from_buffered(file)?;
    Ok(image.layer_data.channel_data.pixels)
}

/// Decodes the luminance channel named `y` of the first part, as grey.
fn read_grey(file: &mut Watched<'_>, y: Text) -> Result<Texels, ExrError> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required(y)
        .collect_pixels(Texels::new, |t: &mut Texels, at, (y,): (f32,)| {
            t.set(at, [y; 3])
        })
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(file)?;
    Ok(image.layer_data.channel_data.pixels)
}

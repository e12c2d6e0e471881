//! `lumis merge`: the tiles of one render assembled into the file a single render writes.
//!
//! 1. every tile's header is read and checked ([`read`]), then the set is checked to be one
//!    render's whole split ([`check`]);
//! 2. each tile's channels are copied into full-image channels (strips are whole rows, so each
//!    is one contiguous block);
//! 3. the colour is finished as a single render finishes it ([`finish`]);
//! 4. the header is the first tile's without the tile's own attributes, with the exposure and
//!    the union of the Cryptomatte manifests, and the file is encoded with the tiles'
//!    compression and the single render's attribute order.

mod check;
mod finish;
pub mod read;

use std::path::{Path, PathBuf};

use ::exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Blocks, Encoding, FlatSamples, Image, Layer, SmallVec,
    Text, Vec2, WritableImage,
};

use self::check::{check_tiles, left_out_of_merge};
use self::read::TileFile;
use super::FarmError;
use lumis_core::film::DisplayTransform;
use lumis_core::math::Vec4;

/// A merged image.
#[derive(Debug)]
pub struct Merged {
    /// The EXR file's bytes.
    pub bytes: Vec<u8>,
    /// The exposure applied, in stops.
    pub exposure: f32,
    /// Whether it was computed over the whole image (automatic exposure).
    pub auto_exposure: bool,
    /// The exposed linear premultiplied RGBA in float, row-major (for a PNG preview).
    pub rgba: Vec<Vec4>,
    /// The render's PNG display transform.
    pub display: DisplayTransform,
    /// The image size.
    pub size: (u32, u32),
    /// How many tiles went in.
    pub tiles: u32,
}

/// Merges the tile files `paths` (in any order) into one EXR.
pub fn merge_tiles(paths: &[PathBuf]) -> Result<Merged, FarmError> {
    if paths.is_empty() {
        return Err(FarmError::NoTiles);
    }
    let tiles = paths
        .iter()
        .map(|p| TileFile::open(p))
        .collect::<Result<Vec<_>, _>>()?;
    check_tiles(&tiles)?;
    let first = &tiles[0];
    let (width, height) = first.full_size();
    let pixels = width as usize * height as usize;

    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for tile in &tiles {
        let layer = tile.pixels()?;
        let window = tile.window();
        let offset = window.y0 as usize * width as usize;
        if channels.is_empty() {
            channels = layer
                .channel_data
                .list
                .iter()
                .map(|c| full_channel(c, pixels, &tile.path))
                .collect::<Result<_, _>>()?;
        }
        for (full, part) in channels.iter_mut().zip(&layer.channel_data.list) {
            finish::reject_nan(&part.sample_data, &part.name, &tile.path)?;
            copy_into(&mut full.sample_data, &part.sample_data, offset);
        }
    }
    let finished = finish::finish_rgba(first, &mut channels)?;

    let mut layer_attributes = first.header.own_attributes.clone();
    layer_attributes.layer_position = first.header.shared_attributes.display_window.position;
    let other = &mut layer_attributes.other;
    other.retain(|name, _| !left_out_of_merge(&name.to_string()));
    other.insert(
        Text::from(crate::output::ATTR_EXPOSURE),
        AttributeValue::F32(finished.stops),
    );
    if let Some(seconds) = total_seconds(&tiles) {
        other.insert(
            Text::from(crate::output::ATTR_RENDER_SECONDS),
            AttributeValue::F32(seconds),
        );
    }
    for (name, value) in finish::merged_manifests(&tiles)? {
        other.insert(name, value);
    }
    let encoding = Encoding {
        compression: first.header.compression,
        blocks: Blocks::ScanLines,
        line_order: first.header.line_order,
    };
    let layer = Layer::new(
        Vec2(width as usize, height as usize),
        layer_attributes,
        encoding,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let image = Image::new(first.header.shared_attributes.clone(), layer);
    let mut encoded = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut encoded)
        .map_err(FarmError::Encode)?;
    let encoded = encoded.into_inner();
    // The same attribute order as a single render's file (see `output::header_order`).
    let bytes = crate::output::sorted_header(&encoded).unwrap_or(encoded);
    Ok(Merged {
        bytes,
        exposure: finished.stops,
        auto_exposure: finished.automatic,
        rgba: finished.rgba,
        display: finished.display,
        size: (width, height),
        tiles: first.spec.count,
    })
}

/// An empty full-image channel like `part`, its memory reserved fallibly.
fn full_channel(
    part: &AnyChannel<FlatSamples>,
    pixels: usize,
    path: &Path,
) -> Result<AnyChannel<FlatSamples>, FarmError> {
    let too_large = || FarmError::Format {
        path: path.to_path_buf(),
        message: format!(
            "not enough memory for {pixels} pixels of channel {}",
            part.name
        ),
    };
    fn zeros<T: Clone + Default>(n: usize) -> Option<Vec<T>> {
        let mut v = Vec::new();
        v.try_reserve_exact(n).ok()?;
        v.resize(n, T::default());
        Some(v)
    }
    let sample_data = match &part.sample_data {
        FlatSamples::F16(_) => FlatSamples::F16(zeros(pixels).ok_or_else(too_large)?),
        FlatSamples::F32(_) => FlatSamples::F32(zeros(pixels).ok_or_else(too_large)?),
        FlatSamples::U32(_) => FlatSamples::U32(zeros(pixels).ok_or_else(too_large)?),
    };
    Ok(AnyChannel {
        name: part.name.clone(),
        sample_data,
        quantize_linearly: part.quantize_linearly,
        sampling: part.sampling,
    })
}

/// Copies `part` into `full` from sample `offset` on (same sample type, checked by the
/// header comparison).
fn copy_into(full: &mut FlatSamples, part: &FlatSamples, offset: usize) {
    match (full, part) {
        (FlatSamples::F16(f), FlatSamples::F16(p)) => {
            f[offset..offset + p.len()].copy_from_slice(p)
        }
        (FlatSamples::F32(f), FlatSamples::F32(p)) => {
            f[offset..offset + p.len()].copy_from_slice(p)
        }
        (FlatSamples::U32(f), FlatSamples::U32(p)) => {
            f[offset..offset + p.len()].copy_from_slice(p)
        }
        _ => unreachable!("the tiles' channel types were checked to be equal"),
    }
}

/// The sum of the tiles' render times, when every tile recorded one (`--timing-metadata`).
fn total_seconds(tiles: &[TileFile]) -> Option<f32> {
    let name = Text::from(crate::output::ATTR_RENDER_SECONDS);
    tiles
        .iter()
        .map(|t| match t.header.own_attributes.other.get(&name) {
            Some(AttributeValue::F32(s)) => Some(*s),
            _ => None,
        })
        .sum()
}

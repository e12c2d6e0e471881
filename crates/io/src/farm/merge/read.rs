//! Opening one tile: its header first, checked against lumis's own limits before any pixel is
//! decoded, so that a hostile or foreign file is refused without a large allocation.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use ::exr::meta::header::Header;
use ::exr::meta::{BlockDescription, MetaData};
use ::exr::prelude::{
    AnyChannels, AttributeValue, FlatSamples, Layer, ReadChannels, ReadLayers, Text,
};

use crate::farm::FarmError;
use crate::files::{guard::guarded, read_regular};
use crate::output::ATTR_TILE;
use lumis_core::film::PixelWindow;
use lumis_core::film::TileSpec;
use lumis_core::scene::{MAX_PIXELS, MAX_SIDE};

/// Most channels a tile may have: 128 Cryptomatte levels of two types are 512, the other
/// layers under 30.
pub const MAX_CHANNELS: usize = 2048;
/// Most samples (pixels x channels) a merged image may have: 8 GiB as floats.
pub const MAX_SAMPLES: u64 = 1 << 31;

/// A tile file whose header has been read and checked.
pub struct TileFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// Which tile it says it is.
    pub spec: TileSpec,
    /// Its only header.
    pub header: Header,
    bytes: Vec<u8>,
}

impl TileFile {
    /// Reads `path` and checks its header: one scanline part, a `lumis/tile` attribute, and
    /// sizes within lumis's limits.
    pub fn open(path: &Path) -> Result<TileFile, FarmError> {
        let format = |message: String| FarmError::Format {
            path: path.to_path_buf(),
            message,
        };
        let bytes = read_regular(path).map_err(|source| FarmError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let meta = guarded(|| MetaData::read_from_buffered(Cursor::new(&bytes[..]), false))
            .map_err(format)?
            .map_err(|e| format(format!("not an OpenEXR file lumis can read: {e}")))?;
        if meta.headers.len() != 1 {
            return Err(format(format!(
                "a {}-part OpenEXR file; lumis tiles have one part",
                meta.headers.len()
            )));
        }
        let header = meta.headers.into_iter().next().expect("one header");
        if header.deep || !matches!(header.blocks, BlockDescription::ScanLines) {
            return Err(format(
                "a deep or tiled OpenEXR file; lumis tiles are flat scanline images".into(),
            ));
        }
        let spec = match text(&header, ATTR_TILE) {
            Some(s) => s
                .parse::<TileSpec>()
                .map_err(|e| format(format!("{ATTR_TILE} = {s:?}: {e}")))?,
            None => {
                return Err(format(format!(
                    "no {ATTR_TILE} attribute: not a tile written by `lumis render --tile I/N`"
                )));
            }
        };
        let size = header.shared_attributes.display_window.size;
        let (w, h) = (size.0 as u64, size.1 as u64);
        let channels = header.channels.list.len();
        if w == 0
            || h == 0
            || w > u64::from(MAX_SIDE)
            || h > u64::from(MAX_SIDE)
            || w * h > MAX_PIXELS
        {
            return Err(format(format!(
                "a {w}x{h} display window; lumis renders at most {MAX_SIDE} pixels a side and \
                 {MAX_PIXELS} in all"
            )));
        }
        // The data window is what gets decoded: no larger than the image it is a part of.
        let layer = header.layer_size;
        if layer.0 as u64 > w || layer.1 as u64 > h {
            return Err(format(format!(
                "a {}x{} data window in a {w}x{h} display window; a tile is a part of its image",
                layer.0, layer.1
            )));
        }
        if channels > MAX_CHANNELS || w * h * channels as u64 > MAX_SAMPLES {
            return Err(format(format!(
                "{channels} channels of {w}x{h} pixels: more than a merge holds \
                 ({MAX_CHANNELS} channels, {MAX_SAMPLES} samples)"
            )));
        }
        Ok(TileFile {
            path: path.to_path_buf(),
            spec,
            header,
            bytes,
        })
    }

    /// The pixels this tile holds, in the full image's coordinates.
    pub fn window(&self) -> PixelWindow {
        let origin = self.header.shared_attributes.display_window.position;
        let at = self.header.own_attributes.layer_position;
        let size = self.header.layer_size;
        // Relative to the display window's origin, which lumis puts at (0, 0); a negative
        // offset becomes a huge column, which the split check then refuses.
        let x0 = (i64::from(at.0) - i64::from(origin.0)) as u32;
        let y0 = (i64::from(at.1) - i64::from(origin.1)) as u32;
        PixelWindow {
            x0,
            x1: x0.saturating_add(size.0 as u32),
            y0,
            y1: y0.saturating_add(size.1 as u32),
        }
    }

    /// The full image's size (the display window).
    pub fn full_size(&self) -> (u32, u32) {
        let size = self.header.shared_attributes.display_window.size;
        (size.0 as u32, size.1 as u32)
    }

    /// Decodes the pixels (every channel, as stored).
    pub fn pixels(&self) -> Result<Layer<AnyChannels<FlatSamples>>, FarmError> {
        let format = |message: String| FarmError::Format {
            path: self.path.clone(),
            message,
        };
        let image = guarded(|| {
            ::exr::prelude::read()
                .no_deep_data()
                .largest_resolution_level()
                .all_channels()
                .first_valid_layer()
                .all_attributes()
                // On this thread, so that the panic guard covers the decoding.
                .non_parallel()
                .from_buffered(Cursor::new(&self.bytes[..]))
        })
        .map_err(format)?
        .map_err(|e| format(format!("cannot decode the pixels: {e}")))?;
        Ok(image.layer_data)
    }
}

/// The string attribute `name` of `header`, if it is one.
pub fn text(header: &Header, name: &str) -> Option<String> {
    match header.own_attributes.other.get(&Text::from(name)) {
        Some(AttributeValue::Text(t)) => Some(String::from_utf8_lossy(t.bytes()).into_owned()),
        _ => None,
    }
}

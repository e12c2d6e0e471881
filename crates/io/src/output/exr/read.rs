//! Reading an EXR file lumis wrote back into the film, metadata and camera that write it
//! again, byte for byte: `encode_exr(film, camera, meta)` of what [`read_exr`] returns is the
//! file it read (tested for every layer kind and both layouts).
//!
//! The header is read and checked first ([`ExrFile::open`]), against lumis's own limits
//! before any pixel is decoded, so that a hostile or foreign file is refused without a large
//! allocation; a caller that compares headers (`lumis merge`) decodes the pixels
//! ([`ExrFile::read`]) only once they agree. Every error names the file; decoding runs under
//! a panic guard, so a damaged file is an error, never a crash.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use ::exr::meta::{BlockDescription, MetaData};
use ::exr::prelude::{ReadChannels, ReadLayers};

use super::{ExrCamera, ExrHeader, ExrMetadata, pixels};
use crate::files::{guard::guarded, read_regular};
use lumis_core::film::Film;
use lumis_core::scene::{MAX_PIXELS, MAX_SIDE};

/// Most channels a file may have: 128 Cryptomatte levels of two types are 512, the other
/// layers under 30.
pub const MAX_CHANNELS: usize = 2048;
/// Most samples (pixels of the full image x channels) a file may describe: 8 GiB as floats.
pub const MAX_SAMPLES: u64 = 1 << 31;

/// Why an EXR file could not be read back.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be read from disk.
    // The cause is printed by the error chain, so not repeated here.
    #[error("{}: cannot read the file", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is no OpenEXR file lumis can read, or not one lumis writes.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What was found and what was expected.
        message: String,
    },
}

/// An EXR file lumis wrote: its header read and checked, its pixels not decoded yet.
pub struct ExrFile {
    path: PathBuf,
    header: ExrHeader,
    bytes: Vec<u8>,
}

/// A file read back: what [`super::encode_exr`] writes it from.
#[derive(Clone, Debug)]
pub struct ExrImage {
    /// The pixels, as a window of the full image (colour as stored: exposed, unless a tile).
    pub film: Film,
    /// The metadata, `z_miss` included.
    pub meta: ExrMetadata,
    /// The camera the header records.
    pub camera: ExrCamera,
}

/// Reads the file lumis wrote at `path` (header and pixels).
pub fn read_exr(path: &Path) -> Result<ExrImage, ReadError> {
    ExrFile::open(path)?.read()
}

impl ExrFile {
    /// Reads `path` and its header: one flat scanline part, sizes within lumis's limits, and
    /// the channels and attributes lumis writes.
    pub fn open(path: &Path) -> Result<ExrFile, ReadError> {
        let format = |message: String| ReadError::Format {
            path: path.to_path_buf(),
            message,
        };
        let bytes = read_regular(path).map_err(|source| ReadError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let meta = guarded(|| MetaData::read_from_buffered(Cursor::new(&bytes[..]), false))
            .map_err(format)?
            .map_err(|e| format(format!("not an OpenEXR file lumis can read: {e}")))?;
        if meta.headers.len() != 1 {
            return Err(format(format!(
                "a {}-part OpenEXR file; lumis writes one part",
                meta.headers.len()
            )));
        }
        let header = meta.headers.into_iter().next().expect("one header");
        if header.deep || !matches!(header.blocks, BlockDescription::ScanLines) {
            return Err(format(
                "a deep or tiled OpenEXR file; lumis writes flat scanline images".into(),
            ));
        }
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
                "a {}x{} data window in a {w}x{h} display window; a file holds a part of its \
                 image",
                layer.0, layer.1
            )));
        }
        if channels > MAX_CHANNELS || w * h * channels as u64 > MAX_SAMPLES {
            return Err(format(format!(
                "{channels} channels of {w}x{h} pixels: more than lumis reads \
                 ({MAX_CHANNELS} channels, {MAX_SAMPLES} samples)"
            )));
        }
        let header = ExrHeader::read(&header).map_err(format)?;
        Ok(ExrFile {
            path: path.to_path_buf(),
            header,
            bytes,
        })
    }

    /// Where the file was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What its header says.
    pub fn header(&self) -> &ExrHeader {
        &self.header
    }

    /// Decodes the pixels into the film they were written from.
    pub fn read(&self) -> Result<ExrImage, ReadError> {
        let format = |message: String| ReadError::Format {
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
        let (film, z_miss) = pixels::film(&self.header, &image.layer_data).map_err(format)?;
        Ok(ExrImage {
            film,
            meta: ExrMetadata {
                z_miss,
                ..self.header.meta.clone()
            },
            camera: self.header.camera,
        })
    }
}

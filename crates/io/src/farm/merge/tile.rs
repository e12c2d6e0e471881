//! Opening one tile: a lumis EXR read back through `output::exr` (header first, checked
//! against lumis's limits before any pixel is decoded), which must be a farm tile.

use std::path::Path;

use crate::farm::FarmError;
use crate::output::{ATTR_TILE, ExrFile, ExrImage, ReadError, TileHeader};
use lumis_core::film::{PixelWindow, TileSpec};

/// A tile file whose header has been read and checked.
pub struct TileFile {
    /// The file, its header read.
    pub file: ExrFile,
    /// What makes it a tile: which one, and how the merge finishes the image.
    pub tile: TileHeader,
}

impl From<ReadError> for FarmError {
    fn from(e: ReadError) -> Self {
        match e {
            ReadError::Read { path, source } => FarmError::Read { path, source },
            ReadError::Format { path, message } => FarmError::Format { path, message },
        }
    }
}

impl TileFile {
    /// Reads `path`'s header: a lumis EXR with a `lumis/tile` attribute.
    pub fn open(path: &Path) -> Result<TileFile, FarmError> {
        let file = ExrFile::open(path)?;
        let Some(tile) = file.header().meta.tile else {
            return Err(FarmError::Format {
                path: path.to_path_buf(),
                message: format!(
                    "no {ATTR_TILE} attribute: not a tile written by `lumis render --tile I/N`"
                ),
            });
        };
        Ok(TileFile { file, tile })
    }

    /// Where it was read from.
    pub fn path(&self) -> &Path {
        self.file.path()
    }

    /// Which tile it says it is.
    pub fn spec(&self) -> TileSpec {
        self.tile.spec
    }

    /// The pixels this tile holds, in the full image's coordinates.
    pub fn window(&self) -> PixelWindow {
        self.file.header().window
    }

    /// The full image's size (the display window).
    pub fn full_size(&self) -> (u32, u32) {
        self.file.header().full_size
    }

    /// Decodes the pixels.
    pub fn read(&self) -> Result<ExrImage, FarmError> {
        Ok(self.file.read()?)
    }
}

//! `lumis merge`: the tiles of one render assembled into the film a single render makes, then
//! developed by the same step (`output::develop`), so the outputs are the single render's.
//!
//! 1. every tile's header is read back through `output::exr` ([`tile`]) and the set is
//!    checked to be one render's whole split (`check.rs`), before any pixel is decoded;
//! 2. each tile's pixels are read back into a film of its strip and pasted into the film of
//!    the whole image ([`lumis_core::film::Film::paste`]); the Cryptomatte manifests are
//!    merged (`manifests.rs`);
//! 3. the metadata is the first tile's without the tile's own part, with the tiles' total
//!    render time, and the camera the tiles' headers record;
//! 4. [`Merged::develop`] exposes the film as the tiles say (a fixed exposure, or automatic
//!    over the whole image) and encodes the EXR and the PNG preview exactly as `lumis render`
//!    does. The merge has no EXR code of its own.

mod check;
mod manifests;
pub mod tile;

use std::path::{Path, PathBuf};

use self::check::check_tiles;
use self::tile::TileFile;
use super::FarmError;
use crate::output::{Develop, Developed, ExrCamera, ExrMetadata, OutputError, develop};
use lumis_core::film::{DisplayTransform, Film, PixelWindow, Tonemap};

/// The assembled image of a farm render, not developed yet.
#[derive(Debug)]
pub struct Merged {
    /// The whole image's film, colour as rendered (before exposure).
    pub film: Film,
    /// What the merged EXR records (no tile attributes; the exposure is set by the develop).
    pub meta: ExrMetadata,
    /// The camera the tiles record.
    pub camera: ExrCamera,
    /// The exposure the render asked for, in stops; `None`: automatic over the whole image.
    pub exposure: Option<f32>,
    /// The render's PNG display transform.
    pub display: DisplayTransform,
    /// How many tiles went in.
    pub tiles: u32,
}

impl Merged {
    /// Develops the film as `lumis render` would have: exposure, then each of `paths` encoded
    /// by extension; the PNG with `tonemap` and `display` (default: the render's).
    pub fn develop(
        &mut self,
        paths: &[&Path],
        tonemap: Tonemap,
        display: Option<DisplayTransform>,
    ) -> Result<Developed, OutputError> {
        let how = Develop {
            exposure: self.exposure,
            tonemap,
            display: display.unwrap_or(self.display),
        };
        develop(&mut self.film, &self.camera, paths, &how, &mut self.meta)
    }
}

/// Reads, checks and assembles the tile files `paths` (in any order).
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

    let mut film = Film::window(width, height, PixelWindow::full(width, height));
    for layer in manifests::merged_layers(&tiles, pixels)? {
        film.add_crypto(layer);
    }
    let mut z_miss = None;
    // One tile decoded at a time: the merge holds the whole film and one strip.
    for tile in &tiles {
        let image = tile.read()?;
        if image.film.aov().iter().any(|a| a.prim_id < 0) {
            z_miss.get_or_insert(image.meta.z_miss);
        }
        film.paste(&image.film)
            .map_err(|message| FarmError::Format {
                path: tile.path().to_path_buf(),
                message,
            })?;
    }
    let header = first.file.header();
    let meta = ExrMetadata {
        // The miss value is in the pixels of the tiles that have a miss (the settings, which
        // record it, were compared).
        z_miss: z_miss.unwrap_or(f32::INFINITY),
        partial: false,
        render_seconds: total_seconds(&tiles),
        tile: None,
        ..header.meta.clone()
    };
    Ok(Merged {
        film,
        meta,
        camera: header.camera,
        exposure: first.tile.exposure,
        display: first.tile.display,
        tiles: first.spec().count,
    })
}

/// The sum of the tiles' render times, when every tile recorded one (`--timing-metadata`).
fn total_seconds(tiles: &[TileFile]) -> Option<f32> {
    tiles
        .iter()
        .map(|t| t.file.header().meta.render_seconds)
        .sum()
}

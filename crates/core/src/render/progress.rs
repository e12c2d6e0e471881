//! What a render tells the outside while it runs, and how the outside stops it.

use crate::math::Vec4;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A flag another thread raises to stop a render between tiles.
#[derive(Clone, Debug, Default)]
pub struct CancelFlag(Arc<AtomicBool>);

impl CancelFlag {
    /// Asks the render to stop (safe from a signal handler's thread).
    pub fn raise(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// True once [`Self::raise`] was called.
    pub fn is_raised(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Two flags are equal when they are the same flag.
impl PartialEq for CancelFlag {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Eq for CancelFlag {}

/// Listens to a render's progress, from every worker thread.
pub trait TileProgress: Send + Sync {
    /// The render has `tiles` tiles to do.
    fn start(&self, tiles: u64);
    /// One more tile is done.
    fn tile_done(&self);
    /// The pixels of a tile just done, before [`TileProgress::tile_done`] is told of it (a live
    /// view shows them; the default ignores them).
    fn tile_pixels(&self, _tile: &TilePixels<'_>) {}
    /// The render is over (finished or stopped).
    fn finish(&self);
}

/// The linear RGBA of one finished tile, as the film will hold it: `width x height` pixels in
/// rows, the top-left one at `(x0, y0)` of the full image.
#[derive(Clone, Copy, Debug)]
pub struct TilePixels<'a> {
    /// Column of the tile's first pixel in the full image.
    pub x0: u32,
    /// Row of the tile's first pixel in the full image.
    pub y0: u32,
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    pixels: &'a [(Vec4, crate::film::PixelAov)],
}

impl TilePixels<'_> {
    /// Each pixel's RGBA, row by row.
    pub fn rgba(&self) -> impl Iterator<Item = Vec4> + '_ {
        self.pixels.iter().map(|(rgba, _)| *rgba)
    }
}

impl<'a> TilePixels<'a> {
    pub(super) fn new(
        (x0, y0): (u32, u32),
        width: u32,
        pixels: &'a [(Vec4, crate::film::PixelAov)],
    ) -> Self {
        Self {
            x0,
            y0,
            width,
            height: (pixels.len() as u32).checked_div(width).unwrap_or(0),
            pixels,
        }
    }
}

/// Where a render reports its progress: nowhere (the default), or to each of its
/// [`TileProgress`] listeners in turn (a progress bar, a live view).
#[derive(Clone, Default)]
pub struct ProgressSink(Vec<Arc<dyn TileProgress>>);

impl ProgressSink {
    /// Reports to `listener`.
    pub fn to(listener: Arc<dyn TileProgress>) -> Self {
        Self(vec![listener])
    }

    /// Reports to `listener` too, after the listeners already there.
    pub fn and(mut self, listener: Arc<dyn TileProgress>) -> Self {
        self.0.push(listener);
        self
    }

    pub(super) fn start(&self, tiles: u64) {
        self.0.iter().for_each(|p| p.start(tiles));
    }

    pub(super) fn tile_done(&self, tile: &TilePixels<'_>) {
        for p in &self.0 {
            p.tile_pixels(tile);
            p.tile_done();
        }
    }

    pub(super) fn finish(&self) {
        self.0.iter().for_each(|p| p.finish());
    }
}

impl std::fmt::Debug for ProgressSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ProgressSink({} listeners)", self.0.len())
    }
}

/// Two sinks are equal when they report to the same listeners (or both to none).
impl PartialEq for ProgressSink {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len() && self.0.iter().zip(&other.0).all(|(a, b)| Arc::ptr_eq(a, b))
    }
}

impl Eq for ProgressSink {}

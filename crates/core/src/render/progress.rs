//! What a render tells the outside while it runs, and how the outside stops it.

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
    /// The render is over (finished or stopped).
    fn finish(&self);
}

/// Where a render reports its progress: nowhere (the default) or a [`TileProgress`].
#[derive(Clone, Default)]
pub struct ProgressSink(Option<Arc<dyn TileProgress>>);

impl ProgressSink {
    /// Reports to `listener`.
    pub fn to(listener: Arc<dyn TileProgress>) -> Self {
        Self(Some(listener))
    }

    pub(super) fn start(&self, tiles: u64) {
        if let Some(p) = &self.0 {
            p.start(tiles);
        }
    }

    pub(super) fn tile_done(&self) {
        if let Some(p) = &self.0 {
            p.tile_done();
        }
    }

    pub(super) fn finish(&self) {
        if let Some(p) = &self.0 {
            p.finish();
        }
    }
}

impl std::fmt::Debug for ProgressSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() {
            "ProgressSink(listening)"
        } else {
            "ProgressSink(none)"
        })
    }
}

/// Two sinks are equal when they report to the same listener (or both to none).
impl PartialEq for ProgressSink {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        }
    }
}

impl Eq for ProgressSink {}

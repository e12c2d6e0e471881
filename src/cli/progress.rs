//! The render's progress bar on stderr (indicatif), listening to the core's tile reports.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use lumis_core::render::{ProgressSink, TileProgress};
use std::sync::Arc;

/// A bar on stderr when `enabled` (the caller checks that stderr is a terminal), else nothing.
pub fn bar(enabled: bool) -> ProgressSink {
    if !enabled {
        return ProgressSink::default();
    }
    ProgressSink::to(Arc::new(TileBar(ProgressBar::with_draw_target(
        None,
        ProgressDrawTarget::stderr(),
    ))))
}

struct TileBar(ProgressBar);

impl TileProgress for TileBar {
    fn start(&self, tiles: u64) {
        self.0.set_length(tiles);
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}% tiles {pos}/{len} ETA {eta}",
        ) {
            self.0.set_style(style.progress_chars("=> "));
        }
    }

    fn tile_done(&self) {
        self.0.inc(1);
    }

    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

//! The live view's handle: what the render and its caller hold. It starts the sender thread
//! (`sender.rs`), hands it each finished tile and, at the end, the finished image.

use super::DisplayServer;
use super::sender::{FINISH_WAIT, Rect, Shared, State};
use crate::output::{ExrMetadata, ExrSamples, exr_channels};
use lumis_core::film::Film;
use lumis_core::render::{TilePixels, TileProgress};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::sync::{Arc, Condvar, Mutex};

/// Where the live view's warnings go (the command line prints them).
pub type Warn = Arc<dyn Fn(String) + Send + Sync>;

/// A render's live view in a viewer: a [`TileProgress`] listener that streams each finished
/// tile (see the module). Make it with [`LiveView::open`], give it to the render's progress
/// sink, and call [`LiveView::finish`] with the image as written when the render is over.
pub struct LiveView {
    shared: Arc<Shared>,
    done: Mutex<Option<Receiver<()>>>,
}

impl LiveView {
    /// Starts streaming image `name` (`full` pixels wide and high, of which the render makes
    /// `window`: `(x0, y0, width, height)`) to `server` on a thread of its own; `warn` is told
    /// when the viewer cannot be reached or is lost. Never fails: without a viewer the render
    /// goes on with a warning.
    pub fn open(
        server: &DisplayServer,
        name: &str,
        full: (u32, u32),
        window: (u32, u32, u32, u32),
        warn: Warn,
    ) -> Arc<Self> {
        let (x, y, w, h) = window;
        let shared = Arc::new(Shared {
            server: server.clone(),
            name: name.to_string(),
            full,
            window: Rect { x, y, w, h },
            state: Mutex::new(State {
                rgba: vec![0.0; w as usize * h as usize * 4],
                dirty: Vec::new(),
                finished: None,
                closed: false,
            }),
            wake: Condvar::new(),
            gone: AtomicBool::new(false),
            warn,
        });
        let (tx, rx) = channel::<()>();
        let theirs = Arc::clone(&shared);
        let spawned = std::thread::Builder::new()
            .name("lumis-display".into())
            .spawn(move || {
                theirs.serve();
                theirs.gone.store(true, Ordering::Relaxed);
                drop(tx);
            });
        if let Err(e) = spawned {
            shared.gone.store(true, Ordering::Relaxed);
            (shared.warn)(format!("could not start the live view's thread: {e}"));
        }
        Arc::new(Self {
            shared,
            done: Mutex::new(Some(rx)),
        })
    }

    /// [`LiveView::finish`] with the channels of the EXR that `film` (developed: exposed) and
    /// `meta` make, as stored (half values as the file rounds them).
    pub fn finish_with_exr(&self, film: &Film, meta: &ExrMetadata) {
        let channels = exr_channels(film, meta)
            .into_iter()
            .map(|(name, samples)| {
                let values = match samples {
                    ExrSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
                    ExrSamples::F32(v) => v,
                    ExrSamples::U32(v) => v.iter().map(|&u| u as f32).collect(),
                };
                (name, values)
            })
            .collect();
        self.finish(channels);
    }

    /// Sends the finished image, `channels` each over the window as the EXR holds them (names
    /// as in the file), after the tiles still waiting; waits at most about a second for the
    /// viewer to take it.
    pub fn finish(&self, channels: Vec<(String, Vec<f32>)>) {
        {
            let mut st = self.shared.lock();
            st.finished = Some(channels);
            st.closed = true;
        }
        self.shared.wake.notify_all();
        let Some(done) = self.done.lock().ok().and_then(|mut d| d.take()) else {
            return;
        };
        if let Err(RecvTimeoutError::Timeout) = done.recv_timeout(FINISH_WAIT) {
            (self.shared.warn)(format!(
                "the display server at {} did not take the finished image within a second; \
                 it may show an unfinished one",
                self.shared.server
            ));
        }
    }
}

impl Drop for LiveView {
    fn drop(&mut self) {
        self.shared.lock().closed = true;
        self.shared.wake.notify_all();
    }
}

impl TileProgress for LiveView {
    fn start(&self, _tiles: u64) {}
    fn tile_done(&self) {}
    fn finish(&self) {}

    fn tile_pixels(&self, tile: &TilePixels<'_>) {
        if self.shared.gone.load(Ordering::Relaxed) {
            return;
        }
        let win = self.shared.window;
        let inside = tile.x0 >= win.x
            && tile.y0 >= win.y
            && tile.x0 + tile.width <= win.x + win.w
            && tile.y0 + tile.height <= win.y + win.h;
        if !inside || tile.width == 0 {
            return;
        }
        {
            let mut st = self.shared.lock();
            let (dx, dy) = ((tile.x0 - win.x) as usize, (tile.y0 - win.y) as usize);
            let stride = win.w as usize;
            for (i, p) in tile.rgba().enumerate() {
                let (c, r) = (i % tile.width as usize, i / tile.width as usize);
                let at = ((dy + r) * stride + dx + c) * 4;
                st.rgba[at..at + 4].copy_from_slice(&p.to_array());
            }
            st.dirty.push(Rect {
                x: tile.x0,
                y: tile.y0,
                w: tile.width,
                h: tile.height,
            });
        }
    }
}

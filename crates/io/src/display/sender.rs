//! The live view's sender: one thread that owns the connection, fed through an image the
//! render's workers copy their tiles into.

use super::DisplayServer;
use super::packets::{Region, create_image, update_image};
use crate::output::{ExrMetadata, ExrSamples, exr_channels};
use lumis_core::film::Film;
use lumis_core::render::{TilePixels, TileProgress};
use std::io::{ErrorKind, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// How long one connection attempt may take.
const CONNECT_TIMEOUT: Duration = Duration::from_millis(500);
/// A write that cannot go on for this long means the viewer stopped reading.
const WRITE_TIMEOUT: Duration = Duration::from_secs(1);
/// Connections tried in one render (the first and the reconnects after drops together).
const ATTEMPTS: u32 = 3;
/// The pause between two attempts.
const RETRY_PAUSE: Duration = Duration::from_millis(200);
/// The longest [`LiveView::finish`] waits for the viewer to take the finished image.
const FINISH_WAIT: Duration = Duration::from_secs(1);
/// Floats per update packet at most (16 MiB): large images go out in bands of rows.
const PACKET_FLOATS: usize = 1 << 22;
/// How often the sender wakes to send the tiles finished since: workers never wake it, so a
/// render pays one copy per tile and no thread switch, and the viewer gets at most this many
/// updates per second's fraction.
const SEND_EVERY: Duration = Duration::from_millis(40);
/// The channels streamed while the render runs.
const RGBA: [&str; 4] = ["R", "G", "B", "A"];

/// Where the live view's warnings go (the command line prints them).
pub type Warn = Arc<dyn Fn(String) + Send + Sync>;

/// A render's live view in a viewer: a [`TileProgress`] listener that streams each finished
/// tile (see the module). Make it with [`LiveView::open`], give it to the render's progress
/// sink, and call [`LiveView::finish`] with the image as written when the render is over.
pub struct LiveView {
    shared: Arc<Shared>,
    done: Mutex<Option<Receiver<()>>>,
}

/// A rectangle of pixels in the full image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Rect {
    x: u32,
    y: u32,
    w: u32,
    h: u32,
}

/// The tiles `rects` as one update per row of tiles: the span from the row's leftmost to its
/// rightmost waiting tile (tiles finish in rows, so little is sent twice).
fn by_rows(mut rects: Vec<Rect>) -> Vec<Rect> {
    rects.sort_unstable_by_key(|r| (r.y, r.h, r.x));
    let mut rows: Vec<Rect> = Vec::new();
    for r in rects {
        match rows.last_mut() {
            Some(row) if row.y == r.y && row.h == r.h => {
                let end = (row.x + row.w).max(r.x + r.w);
                row.x = row.x.min(r.x);
                row.w = end - row.x;
            }
            _ => rows.push(r),
        }
    }
    rows
}

struct Shared {
    server: DisplayServer,
    name: String,
    full: (u32, u32),
    /// The pixels this render makes (a crop or a farm tile: part of the full image).
    window: Rect,
    state: Mutex<State>,
    wake: Condvar,
    /// The sender gave up: tiles are no longer copied.
    gone: AtomicBool,
    warn: Warn,
}

/// What the workers hand the sender.
struct State {
    /// The window's RGBA so far, interleaved.
    rgba: Vec<f32>,
    /// Tiles finished and not yet sent.
    dirty: Vec<Rect>,
    /// The finished image, each channel over the window, to send once the tiles are out.
    finished: Option<Vec<(String, Vec<f32>)>>,
    /// Nothing more will come.
    closed: bool,
}

/// Why a connection ended early.
enum Lost {
    /// Closed or reset by the viewer: worth another connection.
    Dropped(std::io::Error),
    /// The viewer stopped reading: another connection would stall too.
    Stalled,
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

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic elsewhere while holding the lock leaves plain pixel data: still usable.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The sender thread: connect, stream, reconnect after a drop, give up after
    /// [`ATTEMPTS`] connections or a viewer that stopped reading.
    fn serve(&self) {
        let mut attempts = 0;
        while attempts < ATTEMPTS {
            let Some(mut stream) = self.connect(&mut attempts) else {
                return;
            };
            match self.session(&mut stream, attempts > 1) {
                Ok(()) => return,
                Err(Lost::Stalled) => {
                    (self.warn)(format!(
                        "the display server at {} stopped reading; the live view ends here \
                         (the render goes on)",
                        self.server
                    ));
                    return;
                }
                Err(Lost::Dropped(e)) if attempts < ATTEMPTS => (self.warn)(format!(
                    "lost the display server at {} ({e}); reconnecting",
                    self.server
                )),
                Err(Lost::Dropped(e)) => (self.warn)(format!(
                    "lost the display server at {} ({e}); the live view ends here (the render \
                     goes on)",
                    self.server
                )),
            }
        }
    }

    /// A connection, trying until `attempts` reaches [`ATTEMPTS`]; `None` (with a warning)
    /// when none could be made.
    fn connect(&self, attempts: &mut u32) -> Option<TcpStream> {
        let mut last = String::new();
        while *attempts < ATTEMPTS {
            if *attempts > 0 {
                std::thread::sleep(RETRY_PAUSE);
            }
            *attempts += 1;
            match self.try_connect() {
                Ok(s) => return Some(s),
                Err(e) => last = e.to_string(),
            }
        }
        (self.warn)(format!(
            "could not connect to the display server at {} ({last}); rendering without a live \
             view",
            self.server
        ));
        None
    }

    fn try_connect(&self) -> std::io::Result<TcpStream> {
        let mut last = std::io::Error::new(ErrorKind::NotFound, "the host has no address");
        for addr in (self.server.host(), self.server.port()).to_socket_addrs()? {
            match TcpStream::connect_timeout(&addr, CONNECT_TIMEOUT) {
                Ok(s) => {
                    s.set_write_timeout(Some(WRITE_TIMEOUT))?;
                    s.set_nodelay(true)?;
                    return Ok(s);
                }
                Err(e) => last = e,
            }
        }
        Err(last)
    }

    /// One connection: create the image, send every tile made so far when `resume`, then the
    /// tiles as they come and the finished image.
    fn session(&self, stream: &mut TcpStream, resume: bool) -> Result<(), Lost> {
        let (w, h) = self.full;
        send(stream, &create_image(&self.name, w, h, &RGBA))?;
        if resume {
            self.lock().dirty.push(self.window);
        }
        loop {
            let mut st = self.lock();
            while st.dirty.is_empty() && st.finished.is_none() && !st.closed {
                st = self
                    .wake
                    .wait_timeout(st, SEND_EVERY)
                    .unwrap_or_else(|e| e.into_inner())
                    .0;
            }
            if !st.dirty.is_empty() {
                let rects = std::mem::take(&mut st.dirty);
                drop(st);
                for r in by_rows(rects) {
                    self.send_rgba(stream, r)?;
                }
                continue;
            }
            let Some(channels) = st.finished.take() else {
                return Ok(());
            };
            drop(st);
            let sent = self.send_finished(stream, &channels);
            if sent.is_err() {
                // Another connection sends it again.
                self.lock().finished = Some(channels);
            }
            return sent;
        }
    }

    /// The RGBA of rectangle `r` of the window, in bands that fit a packet.
    fn send_rgba(&self, stream: &mut TcpStream, r: Rect) -> Result<(), Lost> {
        let win = self.window;
        for (y, rows) in bands(r, 4) {
            let values: Vec<f32> = {
                let st = self.lock();
                (y..y + rows)
                    .flat_map(|row| {
                        let at =
                            ((row - win.y) as usize * win.w as usize + (r.x - win.x) as usize) * 4;
                        st.rgba[at..at + r.w as usize * 4].to_vec()
                    })
                    .collect()
            };
            let region = Region {
                x: r.x,
                y,
                width: r.w,
                height: rows,
                values: &values,
            };
            send(stream, &update_image(&self.name, &RGBA, &region))?;
        }
        Ok(())
    }

    /// The finished image, every channel as the file holds it: the image is made again with
    /// the file's channels when they are not the streamed RGBA.
    fn send_finished(
        &self,
        stream: &mut TcpStream,
        channels: &[(String, Vec<f32>)],
    ) -> Result<(), Lost> {
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        if sorted != ["A", "B", "G", "R"] {
            let (w, h) = self.full;
            send(stream, &create_image(&self.name, w, h, &names))?;
        }
        let win = self.window;
        let n = names.len();
        for (y, rows) in bands(win, n) {
            let first = (y - win.y) as usize * win.w as usize;
            let count = rows as usize * win.w as usize;
            let mut values = Vec::with_capacity(count * n);
            for p in first..first + count {
                values.extend(
                    channels
                        .iter()
                        .map(|(_, v)| v.get(p).copied().unwrap_or(0.0)),
                );
            }
            let region = Region {
                x: win.x,
                y,
                width: win.w,
                height: rows,
                values: &values,
            };
            send(stream, &update_image(&self.name, &names, &region))?;
        }
        Ok(())
    }
}

/// The rows of `r` in bands of at most [`PACKET_FLOATS`] values of `channels` channels:
/// `(first row, rows)`.
fn bands(r: Rect, channels: usize) -> impl Iterator<Item = (u32, u32)> {
    let per_row = (r.w as usize * channels.max(1)).max(1);
    let step = (PACKET_FLOATS / per_row).clamp(1, u32::MAX as usize) as u32;
    (r.y..r.y + r.h)
        .step_by(step as usize)
        .map(move |y| (y, step.min(r.y + r.h - y)))
}

fn send(stream: &mut TcpStream, packet: &[u8]) -> Result<(), Lost> {
    stream.write_all(packet).map_err(|e| match e.kind() {
        ErrorKind::WouldBlock | ErrorKind::TimedOut => Lost::Stalled,
        _ => Lost::Dropped(e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waiting_tiles_go_out_a_row_at_a_time() {
        let t = |x, y| Rect { x, y, w: 16, h: 16 };
        let rows = by_rows(vec![t(32, 16), t(0, 0), t(48, 16), t(16, 0), t(0, 32)]);
        let want = [
            Rect {
                x: 0,
                y: 0,
                w: 32,
                h: 16,
            },
            Rect {
                x: 32,
                y: 16,
                w: 32,
                h: 16,
            },
            Rect {
                x: 0,
                y: 32,
                w: 16,
                h: 16,
            },
        ];
        assert_eq!(rows, want);
        // A clipped last column keeps its own width.
        let rows = by_rows(vec![
            Rect {
                x: 64,
                y: 0,
                w: 8,
                h: 16,
            },
            t(48, 0),
        ]);
        assert_eq!(
            rows,
            [Rect {
                x: 48,
                y: 0,
                w: 24,
                h: 16
            }]
        );
    }

    #[test]
    fn bands_cover_the_rows_once() {
        let r = Rect {
            x: 0,
            y: 3,
            w: 4096,
            h: 2000,
        };
        let b: Vec<(u32, u32)> = bands(r, 16).collect();
        assert_eq!(b.first().unwrap().0, 3);
        assert_eq!(b.iter().map(|x| x.1).sum::<u32>(), 2000);
        assert!(
            b.iter()
                .all(|&(_, rows)| rows as usize * 4096 * 16 <= PACKET_FLOATS)
        );
        assert!(b.windows(2).all(|w| w[0].0 + w[0].1 == w[1].0));
    }
}

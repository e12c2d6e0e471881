//! The live view's sender: one thread that owns the connection, fed through an image the
//! render's workers copy their tiles into.

use super::DisplayServer;
use super::packets::{Region, create_image, update_image};
use super::view::Warn;
use std::io::{ErrorKind, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::atomic::AtomicBool;
use std::sync::{Condvar, Mutex, MutexGuard};
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
pub(super) const FINISH_WAIT: Duration = Duration::from_secs(1);
/// Floats per update packet at most (16 MiB): large images go out in bands of rows.
const PACKET_FLOATS: usize = 1 << 22;
/// How often the sender wakes to send the tiles finished since: workers never wake it, so a
/// render pays one copy per tile and no thread switch, and the viewer gets at most this many
/// updates per second's fraction.
const SEND_EVERY: Duration = Duration::from_millis(40);
/// The channels streamed while the render runs.
const RGBA: [&str; 4] = ["R", "G", "B", "A"];
/// A rectangle of pixels in the full image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Rect {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) w: u32,
    pub(super) h: u32,
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

pub(super) struct Shared {
    pub(super) server: DisplayServer,
    pub(super) name: String,
    pub(super) full: (u32, u32),
    /// The pixels this render makes (a crop or a farm tile: part of the full image).
    pub(super) window: Rect,
    pub(super) state: Mutex<State>,
    pub(super) wake: Condvar,
    /// The sender gave up: tiles are no longer copied.
    pub(super) gone: AtomicBool,
    pub(super) warn: Warn,
}

/// What the workers hand the sender.
pub(super) struct State {
    /// The window's RGBA so far, interleaved.
    pub(super) rgba: Vec<f32>,
    /// Tiles finished and not yet sent.
    pub(super) dirty: Vec<Rect>,
    /// The finished image, each channel over the window, to send once the tiles are out.
    pub(super) finished: Option<Vec<(String, Vec<f32>)>>,
    /// Nothing more will come.
    pub(super) closed: bool,
}

/// Why a connection ended early.
enum Lost {
    /// Closed or reset by the viewer: worth another connection.
    Dropped(std::io::Error),
    /// The viewer stopped reading: another connection would stall too.
    Stalled,
}

impl Shared {
    pub(super) fn lock(&self) -> MutexGuard<'_, State> {
        // A panic elsewhere while holding the lock leaves plain pixel data: still usable.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The sender thread: connect, stream, reconnect after a drop, give up after
    /// [`ATTEMPTS`] connections or a viewer that stopped reading.
    pub(super) fn serve(&self) {
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
            self.send_rows(stream, &RGBA, r, (y, rows), &values)?;
        }
        Ok(())
    }

    /// Rows `y..y + rows` of the columns of `r`, `values` interleaved over `names`.
    fn send_rows(
        &self,
        stream: &mut TcpStream,
        names: &[&str],
        r: Rect,
        (y, rows): (u32, u32),
        values: &[f32],
    ) -> Result<(), Lost> {
        let region = Region {
            x: r.x,
            y,
            width: r.w,
            height: rows,
            values,
        };
        send(stream, &update_image(&self.name, names, &region))
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
            self.send_rows(stream, &names, win, (y, rows), &values)?;
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

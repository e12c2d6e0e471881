//! A viewer for the tests: a TCP server that decodes tev's packets (`CreateImage`,
//! `UpdateImageV3`; the layout of tev's `Ipc.cpp`, written here from that source, not from
//! lumis's sender) and rebuilds the images, as tev would show them.

use std::collections::BTreeMap;
use std::io::Read;
use std::net::{TcpListener, TcpStream};
use std::thread::JoinHandle;

/// One image as the viewer holds it.
#[derive(Debug, Default)]
pub struct Shown {
    pub width: usize,
    pub height: usize,
    /// Each channel's values, row-major over the whole image (0 where nothing was sent).
    pub channels: BTreeMap<String, Vec<f32>>,
    /// Update packets received.
    pub updates: usize,
    /// Of those, the ones of just R, G, B and A (the tiles streamed while rendering).
    pub rgba_updates: usize,
    /// Create packets received.
    pub creates: usize,
}

/// What a viewer received over its connections.
#[derive(Debug, Default)]
pub struct Received {
    pub images: BTreeMap<String, Shown>,
    pub connections: usize,
}

/// A receiver on a free port of 127.0.0.1, accepting connections until one has ended and
/// `connections` were accepted; its [`Received`] when joined.
pub fn start(connections: usize) -> (u16, JoinHandle<Received>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let handle = std::thread::spawn(move || {
        let mut received = Received::default();
        for stream in listener.incoming().take(connections) {
            received.connections += 1;
            read_all(stream.unwrap(), &mut received);
        }
        received
    });
    (port, handle)
}

/// Decodes every packet of `stream` until it closes.
fn read_all(mut stream: TcpStream, into: &mut Received) {
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).unwrap();
    let mut at = 0;
    while at < bytes.len() {
        let len = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert!(
            len >= 5 && at + len <= bytes.len(),
            "packet of {len} bytes at {at}"
        );
        decode(&bytes[at + 4..at + len], into);
        at += len;
    }
}

struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn u8(&mut self) -> u8 {
        let v = self.0[0];
        self.0 = &self.0[1..];
        v
    }
    fn i32(&mut self) -> i32 {
        let v = i32::from_le_bytes(self.0[..4].try_into().unwrap());
        self.0 = &self.0[4..];
        v
    }
    fn i64(&mut self) -> i64 {
        let v = i64::from_le_bytes(self.0[..8].try_into().unwrap());
        self.0 = &self.0[8..];
        v
    }
    fn string(&mut self) -> String {
        let end = self
            .0
            .iter()
            .position(|&b| b == 0)
            .expect("a string ends in 0");
        let s = String::from_utf8(self.0[..end].to_vec()).unwrap();
        self.0 = &self.0[end + 1..];
        s
    }
}

fn decode(packet: &[u8], into: &mut Received) {
    let mut f = Fields(packet);
    let kind = f.u8();
    let _grab_focus = f.u8();
    let name = f.string();
    match kind {
        4 => {
            let (width, height) = (f.i32() as usize, f.i32() as usize);
            let n = f.i32() as usize;
            let shown = into.images.entry(name).or_default();
            // tev replaces an image of the same name with a blank one.
            shown.width = width;
            shown.height = height;
            shown.creates += 1;
            shown.channels = (0..n)
                .map(|_| (f.string(), vec![0.0; width * height]))
                .collect();
            assert!(f.0.is_empty(), "trailing bytes in CreateImage");
        }
        6 => {
            let n = f.i32() as usize;
            let names: Vec<String> = (0..n).map(|_| f.string()).collect();
            let (x, y, w, h) = (f.i32(), f.i32(), f.i32(), f.i32());
            let offsets: Vec<i64> = (0..n).map(|_| f.i64()).collect();
            let strides: Vec<i64> = (0..n).map(|_| f.i64()).collect();
            let floats: Vec<f32> =
                f.0.chunks_exact(4)
                    .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                    .collect();
            let shown = into
                .images
                .get_mut(&name)
                .unwrap_or_else(|| panic!("update of {name}, never created"));
            shown.updates += 1;
            shown.rgba_updates += usize::from(names == ["R", "G", "B", "A"]);
            let pixels = (w * h) as usize;
            for (c, channel) in names.iter().enumerate() {
                let plane = shown
                    .channels
                    .get_mut(channel)
                    .unwrap_or_else(|| panic!("update of channel {channel} not created"));
                for p in 0..pixels {
                    let (px, py) = (x as usize + p % w as usize, y as usize + p / w as usize);
                    assert!(
                        px < shown.width && py < shown.height,
                        "update outside the image"
                    );
                    let v = floats[(offsets[c] + p as i64 * strides[c]) as usize];
                    plane[py * shown.width + px] = v;
                }
            }
        }
        other => panic!("unexpected packet type {other}"),
    }
}

//! The packets of tev's network protocol that a renderer sends: each is its length (a `u32`
//! counting itself), a type byte, then the fields in order, integers little-endian, strings
//! UTF-8 ending in a zero byte. The layout follows tev's `Ipc.cpp` (`setCreateImage`,
//! `setUpdateImage` of type `UpdateImageV3`) and the `tevclient` package.

/// tev's `IpcPacket::CreateImage`: a blank image with named channels (replacing one of the
/// same name).
pub(crate) const CREATE_IMAGE: u8 = 4;
/// tev's `IpcPacket::UpdateImageV3`: a rectangle of some channels, each read at its own offset
/// and stride in one block of floats.
pub(crate) const UPDATE_IMAGE_V3: u8 = 6;

/// A packet being written: the length is filled in by [`Packet::finish`].
struct Packet(Vec<u8>);

impl Packet {
    fn new(kind: u8, grab_focus: bool, image: &str, capacity: usize) -> Self {
        let mut p = Packet(Vec::with_capacity(capacity + 64 + image.len()));
        p.0.extend_from_slice(&0u32.to_le_bytes());
        p.0.push(kind);
        p.0.push(u8::from(grab_focus));
        p.string(image);
        p
    }

    /// A string field. A zero byte would end it early in the reader, so none is sent.
    fn string(&mut self, s: &str) {
        self.0.extend(s.bytes().filter(|&b| b != 0));
        self.0.push(0);
    }

    fn i32(&mut self, v: u32) {
        // Sizes and positions are bounded by the renderer's image limits (far below 2^31).
        self.0
            .extend_from_slice(&(v.min(i32::MAX as u32) as i32).to_le_bytes());
    }

    fn finish(mut self) -> Vec<u8> {
        let len = u32::try_from(self.0.len()).unwrap_or(u32::MAX);
        self.0[..4].copy_from_slice(&len.to_le_bytes());
        self.0
    }
}

/// `CreateImage`: an image `name` of `width x height` pixels with `channels`, shown at once.
pub(crate) fn create_image(name: &str, width: u32, height: u32, channels: &[&str]) -> Vec<u8> {
    let mut p = Packet::new(CREATE_IMAGE, true, name, 16 * channels.len());
    p.i32(width);
    p.i32(height);
    p.i32(channels.len() as u32);
    for c in channels {
        p.string(c);
    }
    p.finish()
}

/// A rectangle of an image: its place and size in the image, and its pixels with their
/// channels interleaved (`values[(row * width + column) * channels + channel]`).
pub(crate) struct Region<'a> {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
    pub values: &'a [f32],
}

/// `UpdateImageV3`: `region`'s values of `channels` into image `name` (not brought to the
/// front). The caller keeps packets far below 4 GiB (the length is a `u32`).
pub(crate) fn update_image(name: &str, channels: &[&str], region: &Region<'_>) -> Vec<u8> {
    let n = channels.len();
    debug_assert_eq!(
        region.values.len(),
        region.width as usize * region.height as usize * n
    );
    let mut p = Packet::new(
        UPDATE_IMAGE_V3,
        false,
        name,
        4 * region.values.len() + 32 * n,
    );
    p.i32(n as u32);
    for c in channels {
        p.string(c);
    }
    p.i32(region.x);
    p.i32(region.y);
    p.i32(region.width);
    p.i32(region.height);
    // Interleaved: channel c starts at float c and steps over all n.
    for c in 0..n {
        p.0.extend_from_slice(&(c as i64).to_le_bytes());
    }
    for _ in 0..n {
        p.0.extend_from_slice(&(n as i64).to_le_bytes());
    }
    for v in region.values {
        p.0.extend_from_slice(&v.to_le_bytes());
    }
    p.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn create_image_layout() {
        let p = create_image("a.exr", 3, 2, &["R", "G"]);
        let mut want = vec![];
        want.extend_from_slice(&0u32.to_le_bytes());
        want.extend_from_slice(&[CREATE_IMAGE, 1]);
        want.extend_from_slice(b"a.exr\0");
        for v in [3i32, 2, 2] {
            want.extend_from_slice(&v.to_le_bytes());
        }
        want.extend_from_slice(b"R\0G\0");
        let len = want.len() as u32;
        want[..4].copy_from_slice(&len.to_le_bytes());
        assert_eq!(p, want);
    }

    #[test]
    fn update_image_layout() {
        let values = [1.0f32, 2.0, 3.0, 4.0];
        let region = Region {
            x: 5,
            y: 6,
            width: 2,
            height: 1,
            values: &values,
        };
        let p = update_image("n", &["R", "A"], &region);
        assert_eq!(
            u32::from_le_bytes(p[..4].try_into().unwrap()) as usize,
            p.len()
        );
        assert_eq!(&p[4..8], &[UPDATE_IMAGE_V3, 0, b'n', 0]);
        let ints: Vec<i32> = p[8..36]
            .chunks(4)
            .map(|b| i32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(ints[0], 2);
        assert_eq!(&p[12..16], b"R\0A\0");
        let after_names = 16;
        let xywh: Vec<i32> = p[after_names..after_names + 16]
            .chunks(4)
            .map(|b| i32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(xywh, [5, 6, 2, 1]);
        let longs: Vec<i64> = p[after_names + 16..after_names + 48]
            .chunks(8)
            .map(|b| i64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(longs, [0, 1, 2, 2]);
        let floats: Vec<f32> = p[after_names + 48..]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(floats, values);
    }
}

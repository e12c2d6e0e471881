//! Image decoding with bounded memory, shared by OBJ/MTL textures and glTF images. An image
//! header declares its size, and the `image` crate allocates the whole pixel buffer from it
//! before reading a single pixel; a few hundred bytes could otherwise ask for gigabytes.
//!
//! Limits (documented in docs/robustness.md): at most [`MAX_SIDE`] texels on a side, and a
//! decoded size of at most [`MAX_RATIO`] times the file's size plus [`SLACK`] bytes. The ratio
//! is above what PNG's deflate can reach (about 1032:1) and what a flat JPEG reaches, so real
//! images pass and only headers that lie about their data are refused.

use std::io::Cursor;

use ::image::{DynamicImage, ImageReader, Limits};

/// Largest image side accepted.
pub const MAX_SIDE: u32 = 16_384;
/// Most decoded bytes per byte of file.
pub const MAX_RATIO: u64 = 1100;
/// Decoded bytes always allowed, whatever the file size (a 512x512 RGBA image).
pub const SLACK: u64 = 1 << 20;
/// Bytes a texel may take in the decoder's buffer (RGBA, 16 bits per channel).
const TEXEL_BYTES: u64 = 8;

/// Decodes PNG or JPEG `bytes` (format sniffed from the content) within the limits above; the
/// error says which limit or what the decoder reported.
pub(crate) fn decode_bounded(bytes: &[u8]) -> Result<DynamicImage, String> {
    let budget = (bytes.len() as u64)
        .saturating_mul(MAX_RATIO)
        .saturating_add(SLACK);
    let reader = || {
        ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    let (w, h) = reader()?.into_dimensions().map_err(|e| e.to_string())?;
    if w > MAX_SIDE || h > MAX_SIDE {
        return Err(format!(
            "{w}x{h} is larger than {MAX_SIDE} texels on a side"
        ));
    }
    let declared = u64::from(w) * u64::from(h) * TEXEL_BYTES;
    if declared > budget {
        return Err(format!(
            "the header declares {w}x{h} texels, far more than the file's {} bytes can hold",
            bytes.len()
        ));
    }
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    // The pixel buffer plus the conversions the callers make afterwards are within this.
    limits.max_alloc = Some(budget.saturating_mul(2));
    let mut reader = reader()?;
    reader.limits(limits);
    reader.decode().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PNG signature, a header declaring `w x h` RGBA texels and an empty image data chunk:
    /// enough for a decoder to learn the size, with no pixels behind it.
    fn png_header(w: u32, h: u32) -> Vec<u8> {
        let mut ihdr = w.to_be_bytes().to_vec();
        ihdr.extend(h.to_be_bytes());
        ihdr.extend([8, 6, 0, 0, 0]);
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        for (kind, data) in [(b"IHDR", ihdr), (b"IDAT", Vec::new())] {
            let body = [&kind[..], &data].concat();
            let crc = body.iter().fold(!0u32, |mut c, &b| {
                c ^= u32::from(b);
                for _ in 0..8 {
                    c = if c & 1 == 1 {
                        (c >> 1) ^ 0xEDB8_8320
                    } else {
                        c >> 1
                    };
                }
                c
            });
            png.extend((data.len() as u32).to_be_bytes());
            png.extend(&body);
            png.extend((!crc).to_be_bytes());
        }
        png
    }

    #[test]
    fn headers_that_outgrow_their_file_are_refused_before_decoding() {
        let e = decode_bounded(&png_header(16_000, 16_000)).unwrap_err();
        assert!(e.contains("far more than the file"), "{e}");
        let e = decode_bounded(&png_header(20_000, 1)).unwrap_err();
        assert!(e.contains("larger than 16384"), "{e}");
        // Within the budget, the decoder itself reports the missing data.
        assert!(decode_bounded(&png_header(4, 4)).is_err());
    }
}

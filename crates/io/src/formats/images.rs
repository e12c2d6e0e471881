//! Image decoding with bounded memory, shared by OBJ/MTL textures and glTF images. An image
//! header declares its size, and the `image` crate allocates the whole pixel buffer from it
//! before reading a single pixel; a few hundred bytes could otherwise ask for gigabytes.
//!
//! Limits (documented in docs/robustness.md): at most [`MAX_SIDE`] texels on a side, and a
//! decoded size of at most [`MAX_RATIO`] times the file's size plus [`SLACK`] bytes. The ratio
//! is above what PNG's deflate can reach (about 1032:1) and what a flat JPEG reaches, so real
//! images pass and only headers that lie about their data are refused.

use std::io::Cursor;
use std::path::Path;

use ::image::{DynamicImage, ImageReader, Limits};
use lumis_core::math::Vec3;
use lumis_core::texture::{ImageTexture, Texels, srgb_to_linear};

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
fn decode_bounded(bytes: &[u8]) -> Result<DynamicImage, String> {
    let budget = (bytes.len() as u64)
        .saturating_mul(MAX_RATIO)
        .saturating_add(SLACK);
    let reader = || {
        let r = ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        // The image crate reads more (Radiance HDR, for environments), but textures are PNG
        // or JPEG only: the budgets below are sized for 8-bit and 16-bit texels.
        match r.format() {
            Some(image::ImageFormat::Png | image::ImageFormat::Jpeg) => Ok(r),
            Some(other) => Err(format!("a {other:?} image; textures are PNG or JPEG")),
            None => Err("not a PNG or JPEG image".to_string()),
        }
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

/// Decodes PNG or JPEG `bytes` (format sniffed from the content) into a linear RGB texture,
/// treating the 8-bit channels as sRGB; alpha is dropped. `path` names the file in errors.
pub fn image_texture(bytes: &[u8], path: &Path) -> Result<ImageTexture, String> {
    let decode_err =
        |message: String| format!("cannot decode texture {}: {message}", path.display());
    let img = decode_bounded(bytes).map_err(decode_err)?;
    let rgb = img.to_rgb8();
    let lut: [f32; 256] = std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0));
    let texels = rgb
        .pixels()
        .map(|p| Vec3::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]))
        .collect();
    ImageTexture::new(rgb.width(), rgb.height(), texels)
        .ok_or_else(|| decode_err("the image is empty".into()))
}

/// Decodes PNG or JPEG `bytes` (sniffed from the content) to RGBA8 texels: 16-bit channels are
/// rounded to 8 bits, grey and grey-alpha images are expanded, missing alpha is 255.
pub fn texels(bytes: &[u8], path: &Path) -> Result<Texels, String> {
    let img = decode_bounded(bytes)
        .map_err(|e| format!("cannot decode {}: {e}", path.display()))?
        .to_rgba8();
    let (w, h) = img.dimensions();
    let rgba = img.pixels().map(|p| p.0).collect();
    Texels::new(w, h, rgba).ok_or_else(|| format!("{}: the image is empty", path.display()))
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

    #[test]
    fn undecodable_bytes_name_the_file() {
        let err = image_texture(b"not an image", Path::new("t.png")).unwrap_err();
        assert!(err.contains("t.png"), "{err}");
    }
}

//! Radiance RGBE (`.hdr`, `.pic`) through the `image` crate's decoder, one scanline at a time.
//!
//! The header is parsed first, on its own, and its size checked before anything is sized
//! from it. The scanlines are then decoded one by one, each by a decoder given a one-row
//! header followed by the file's remaining bytes: the decoder reads exactly the bytes of a
//! scanline (flat, or either run-length encoding) and no more, so the next row starts where
//! it stopped. Decoding by rows rather than in one call keeps the decoder from allocating the
//! whole image twice (its own buffer and the output) before reading a byte of it, lets the
//! texels fill a buffer whose pages are only committed as rows arrive, and tells which row a
//! truncated file ends in.
//!
//! Only the standard orientation (`-Y <height> +X <width>`: rows top to bottom, texels left
//! to right) is read, as the decoder reads no other. `EXPOSURE` and `COLORCORR` header lines
//! are ignored: the stored values are taken as the radiance, as renderers commonly take them.

use std::io::{Cursor, ErrorKind, Read};

use ::image::codecs::hdr::HdrDecoder;
use ::image::{ImageDecoder, ImageError};

use super::{Decoded, check_size};

/// Bytes a decoded texel takes: three `f32`, native-endian.
const TEXEL_BYTES: usize = 12;

/// The texels of the Radiance file `bytes`, or what is wrong with it.
pub(super) fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    // Old writers sign `#?RGBE` or another program name; the decoder's strict mode accepts
    // only `#?RADIANCE`, its lenient mode any header (it skips lines starting with `#`).
    let strict = bytes.starts_with(b"#?RADIANCE");
    if !strict && !bytes.starts_with(b"#?") {
        return Err(
            "not a Radiance RGBE file: it does not start with the `#?RADIANCE` signature".into(),
        );
    }
    let mut file = Cursor::new(bytes);
    let (width, height) = HdrDecoder::with_strictness(&mut file, strict)
        .map_err(|e| format!("cannot read the Radiance header: {e}"))?
        .dimensions();
    check_size(width.into(), height.into())?;
    let mut texels = reserve_texels(width, height)?;
    let row_header = format!("#?RADIANCE\n\n-Y 1 +X {width}\n").into_bytes();
    let mut row = vec![0u8; width as usize * TEXEL_BYTES];
    for y in 0..height {
        let at_row = |e: ImageError| match e {
            ImageError::IoError(io) if io.kind() == ErrorKind::UnexpectedEof => format!(
                "truncated: the header declares {width}x{height} texels but the pixel data \
                 ends after {y} of the {height} rows"
            ),
            e => format!("row {y} of {height}: {e}"),
        };
        HdrDecoder::new(Cursor::new(&row_header[..]).chain(&mut file))
            .map_err(at_row)?
            .read_image(&mut row)
            .map_err(at_row)?;
        texels.extend(row.chunks_exact(TEXEL_BYTES).map(|t| {
            let c = |i: usize| f32::from_ne_bytes([t[i], t[i + 1], t[i + 2], t[i + 3]]);
            [c(0), c(4), c(8)]
        }));
    }
    Ok(Decoded {
        width,
        height,
        texels,
    })
}

/// An empty buffer for the `width x height` texels of an image whose size [`check_size`]
/// accepted, reserved without being touched (a failed reservation is an error, not an
/// abort): its pages are committed only as rows are decoded into it, so a header that lies
/// about its data costs address space, not memory.
fn reserve_texels(width: u32, height: u32) -> Result<Vec<[f32; 3]>, String> {
    let count = width as usize * height as usize;
    let mut texels = Vec::new();
    texels.try_reserve_exact(count).map_err(|_| {
        format!("cannot allocate memory for {width}x{height} texels ({count} x 12 bytes)")
    })?;
    Ok(texels)
}

//! Issue 27 end to end through the binary: the environment seen by escaping rays in every
//! scene format and lighting surfaces as ambient light; the light-path and per-light passes
//! adding up to the beauty; the shadow catcher composited onto a plate; bad environment files.

mod bad_files;
mod catcher;
mod escape;
mod passes;
mod sun;

use std::path::Path;

/// Writes a `w x h` latitude-longitude Radiance `.hdr` whose texel at the centre of column
/// `i`, row `j` (row 0 at the top) is `f(u, v)`, as flat RGBE (lossy: ~1% per texel).
pub fn write_hdr(path: &Path, w: usize, h: usize, f: impl Fn(f32, f32) -> [f32; 3]) {
    let mut bytes = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    for j in 0..h {
        for i in 0..w {
            let c = f((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
            bytes.extend(rgbe(c));
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// One RGBE texel: a shared exponent with 8-bit mantissas.
fn rgbe(c: [f32; 3]) -> [u8; 4] {
    let m = c[0].max(c[1]).max(c[2]);
    if m < 1e-32 {
        return [0; 4];
    }
    let e = m.log2().floor() as i32 + 1;
    let scale = 256.0 / 2f32.powi(e);
    let q = |v: f32| (v * scale).clamp(0.0, 255.0) as u8;
    [q(c[0]), q(c[1]), q(c[2]), (e + 128) as u8]
}

/// The value an RGBE texel written from `c` decodes to (what lumis reads back).
pub fn rgbe_round(c: [f32; 3]) -> [f32; 3] {
    let [r, g, b, e] = rgbe(c);
    if e == 0 {
        return [0.0; 3];
    }
    let f = 2f32.powi(i32::from(e) - 136);
    [r, g, b].map(|v| f32::from(v) * f)
}

/// Four colours by quarter of u: [0, .25) red, [.25, .5) green, [.5, .75) blue, [.75, 1)
/// white (u = atan2(x, -z) / 2pi: -Z, +X, +Z, -X at the quarters' starts).
pub fn quarters(u: f32, _v: f32) -> [f32; 3] {
    match (u * 4.0) as u32 {
        0 => [1.0, 0.0, 0.0],
        1 => [0.0, 1.0, 0.0],
        2 => [0.0, 0.0, 1.0],
        _ => [1.0, 1.0, 1.0],
    }
}

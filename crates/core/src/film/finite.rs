//! The NaN guarantee's last check: a film holding a non-finite sample is never written.
//!
//! Colour (RGBA), normals, albedo, position and uv must be finite everywhere; depth may be
//! `+inf` only where the centre ray missed (the documented miss value, replaced by `--z-miss`
//! on write). The loaders' value limits (`scene::limits`) make this unreachable for accepted
//! input; if it ever fires, the render fails loudly instead of shipping a poisoned image.

use crate::film::{Film, PixelAov};

/// Non-finite samples of a film: how many, and the first (full-image pixel and channel).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the render produced {count} non-finite sample(s) (first: {channel} at pixel ({x}, {y})); \
     no image was written"
)]
pub struct NonFinite {
    /// Number of non-finite channel values.
    pub count: usize,
    /// Column of the first, in the full image.
    pub x: u32,
    /// Row of the first, in the full image.
    pub y: u32,
    /// Its channel (`R`, `Z`, `N.X`, ...).
    pub channel: &'static str,
}

/// The channels of one pixel that must be finite, by name.
fn samples(rgba: [f32; 4], a: &PixelAov) -> [(&'static str, f32); 16] {
    // A miss's depth is +inf by design; any other non-finite depth is a bug.
    let depth = if a.depth == f32::INFINITY && a.prim_id < 0 {
        0.0
    } else {
        a.depth
    };
    [
        ("R", rgba[0]),
        ("G", rgba[1]),
        ("B", rgba[2]),
        ("A", rgba[3]),
        ("Z", depth),
        ("N.X", a.normal.x),
        ("N.Y", a.normal.y),
        ("N.Z", a.normal.z),
        ("albedo.R", a.albedo.x),
        ("albedo.G", a.albedo.y),
        ("albedo.B", a.albedo.z),
        ("P.X", a.position.x),
        ("P.Y", a.position.y),
        ("P.Z", a.position.z),
        ("uv.U", a.uv.x),
        ("uv.V", a.uv.y),
    ]
}

/// `Ok` when every sample of `film` is finite (depth: or `+inf` on a miss).
pub fn check_finite(film: &Film) -> Result<(), NonFinite> {
    let mut first = None;
    let mut count = 0;
    let (ox, oy) = film.origin();
    let w = film.width() as usize;
    for (i, (p, a)) in film.rgba().iter().zip(film.aov()).enumerate() {
        for (channel, v) in samples(p.to_array(), a) {
            if !v.is_finite() {
                count += 1;
                first.get_or_insert((i, channel));
            }
        }
    }
    for pass in film.passes() {
        for (i, v) in pass.values().iter().enumerate() {
            if !v.is_finite() {
                count += 1;
                first.get_or_insert((i, "pass"));
            }
        }
    }
    match first {
        None => Ok(()),
        Some((i, channel)) => Err(NonFinite {
            count,
            x: ox + (i % w) as u32,
            y: oy + (i / w) as u32,
            channel,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Vec3, Vec4};

    #[test]
    fn misses_pass_and_every_non_finite_sample_is_counted() {
        let mut film = Film::new(3, 2);
        assert_eq!(check_finite(&film), Ok(()));
        let hit = PixelAov {
            depth: 2.0,
            prim_id: 0,
            object_id: 0,
            ..PixelAov::MISS
        };
        film.set(1, 0, Vec4::new(f32::NAN, 0.0, f32::INFINITY, 1.0), hit);
        film.set(
            2,
            1,
            Vec4::ONE,
            PixelAov {
                depth: f32::INFINITY,
                normal: Vec3::new(0.0, f32::NAN, 0.0),
                ..hit
            },
        );
        let e = check_finite(&film).unwrap_err();
        assert_eq!((e.count, e.x, e.y, e.channel), (4, 1, 0, "R"));
        assert!(e.to_string().contains("4 non-finite"), "{e}");
    }
}

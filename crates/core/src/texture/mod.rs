//! Surface colours: procedural patterns and normal perturbation for the paper's `.scn`
//! materials, image textures (see [`ImageTexture`]) for OBJ/MTL `map_Kd`, and glTF's sampled
//! textures ([`TextureRef`]).
//!
//! Every procedural pattern is a function of the world-space hit point `p` (solid texturing, like
//! the original ray tracer), so spheres and triangles need no texture coordinates; only
//! [`Texture::Image`] reads the surface's `uv`. `scale` is
//! always a length in world units: the pattern at `p` with scale `s` equals the pattern at
//! `p / s` with scale 1. The `.scn` files give some kinds a frequency instead;
//! [`Texture::from_scn_scale`] converts.
//!
//! ```text
//! sphere 315 -150 0  150  Marble 0.4 0.3 0.2  0.6 0.7 0.8  0.5  50 0.15  NormalMap 0.5 0.25
//! ```
//! becomes `Texture::Marble { a: (0.4, 0.3, 0.2), b: (0.6, 0.7, 0.8), scale: 0.5 }
//! .from_scn_scale()` and `NormalMap { scale: 0.5, amount: 0.25 }`.

mod image;
mod normal_map;
pub mod perlin;
mod sampled;

pub use image::{ImageTexture, srgb_to_linear};
pub use normal_map::NormalMap;
pub use sampled::{Encoding, Sampler, Texels, TextureRef, UvTransform, Wrap};

use std::sync::Arc;

use crate::math::{Vec2, Vec3};
use perlin::{noise, turbulence};

/// A surface colour (linear RGB) that may vary with the world-space hit point or the texture
/// coordinates.
///
/// For every kind but `Solid`, `scale` must be finite and positive (see [`Texture::validate`]);
/// `a` is the colour where the pattern value is 1 and `b` where it is 0, matching the `.scn`
/// files' first and second colours.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// One colour everywhere.
    Solid(Vec3),
    /// 3-D checker of cubes with edge `scale` and a corner at `origin`: with
    /// `c = floor((p - origin) / s)`, `a` where `c.x + c.y + c.z` is even, `b` where it is odd.
    Checkerboard {
        /// Colour of the even cells, including the cell `origin + [0, scale)^3`.
        a: Vec3,
        /// Colour of the odd cells.
        b: Vec3,
        /// Cube edge length (world units).
        scale: f32,
        /// A corner of the grid (world units); `.scn` checkers have theirs at
        /// [`SCN_CHECKER_ORIGIN`].
        origin: Vec3,
    },
    /// Blotchy clouds: `t = turbulence(p / scale)`, colour `b + t (a - b)`. As in the original,
    /// `t` is not clamped: where the turbulence exceeds 1 (rarely above 1.3) the colour goes
    /// past `a`, away from `b` (components clamped at 0).
    Turbulence {
        /// Colour where the turbulence is strong.
        a: Vec3,
        /// Colour where it is weak.
        b: Vec3,
        /// Size of the largest blotches (world units per noise cell).
        scale: f32,
    },
    /// Veins: a sine band across x + y, warped by turbulence stretched along y;
    /// with `q = p / scale`, `t = 0.5 + 0.5 sin(q.x + q.y + turbulence(q.x, 3 q.y, q.z))`.
    Marble {
        /// Colour at the sine's crests.
        a: Vec3,
        /// Colour at its troughs.
        b: Vec3,
        /// Noise cell size (world units); the vein bands repeat every `2 pi scale` along x + y.
        scale: f32,
    },
    /// Growth rings: `g = 5 noise(p / scale)`, `t = g - trunc(g)`, colour `b + t (a - b)`, so
    /// rings follow the noise's level sets. The original's fractional part truncates towards
    /// zero: where the noise is negative `t` lies in (-1, 0] and the colour goes past `b`, away
    /// from `a` (components clamped at 0); those rings are the broad bright bands of its wood.
    Wood {
        /// Colour at the outer edge of each ring.
        a: Vec3,
        /// Colour at its inner edge.
        b: Vec3,
        /// Noise cell size (world units).
        scale: f32,
    },
    /// Three marble patterns, each stretched along a different axis: pattern one blends
    /// `a`/`b`, two blends `b`/`c`, three blends `c`/`a`, and the colour is a quarter of each
    /// (the original's weights, which sum to 3/4: not an average).
    CrissCross {
        /// First colour.
        a: Vec3,
        /// Second colour.
        b: Vec3,
        /// Third colour.
        c: Vec3,
        /// Noise cell size along each pattern's long-frequency axis (world units).
        scale: f32,
    },
    /// An image looked up at the surface's texture coordinates (bilinear, repeating), times
    /// `tint`. Shared, since many materials may use one image.
    Image {
        /// The texels.
        image: Arc<ImageTexture>,
        /// Multiplies every texel (MTL's `Kd` with `map_Kd`).
        tint: Vec3,
    },
}

/// `b + t (a - b)`: `a` at `t = 1`, as the original ray tracer weights its first colour.
#[inline]
fn mix(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    b + (a - b) * t
}

/// [`mix`] for weights outside [0, 1] (the original extrapolates there), with negative
/// components cut to 0: a negative albedo would subtract light.
#[inline]
fn mix_past(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    mix(a, b, t).max(Vec3::ZERO)
}

/// Where the original's checker grid has a corner: it counts cells from
/// `p + 3,893,343` so that its truncating `(int)` never meets a negative value (and the seam
/// that truncation leaves at 0 lies far away). The offset is not a multiple of the usual cell
/// sizes, so the grid is shifted against the origin (by 7 units for a 50-unit cell).
pub const SCN_CHECKER_ORIGIN: Vec3 = Vec3::splat(-3_893_343.0);

/// Weight of each CrissCross pattern in the sum (the original's; three of them make 3/4).
const CRISS_WEIGHT: f32 = 0.25;

/// One marble pattern in noise space: a sine band along `dir` warped by turbulence of `q`
/// stretched by `stretch`; in [0, 1].
#[inline]
fn veins(q: Vec3, dir: Vec3, stretch: Vec3) -> f32 {
    0.5 + 0.5 * (q.dot(dir) + turbulence(q * stretch)).sin()
}

/// Per-axis frequency factors of the original CrissCross's three patterns: each is smooth
/// along one axis, slowly varying along the next and fine along the third.
const CRISS_STRETCH: [Vec3; 3] = [
    Vec3::new(0.35, 0.05, 1.0),
    Vec3::new(1.0, 0.35, 0.05),
    Vec3::new(0.05, 1.0, 0.35),
];
/// The directions (and the original's 0.05 frequency) of the CrissCross patterns' sine bands.
const CRISS_BANDS: [Vec3; 3] = [
    Vec3::new(0.05, 0.0, 0.05),
    Vec3::new(0.05, 0.05, 0.0),
    Vec3::new(0.0, 0.05, 0.05),
];

impl Texture {
    /// True when [`Texture::eval`] reads its `uv` argument.
    pub fn reads_uv(&self) -> bool {
        matches!(self, Texture::Image { .. })
    }

    /// Colour (linear RGB) at world point `p` and texture coordinates `uv`; only `Image` reads
    /// `uv`. Checkerboard and Marble results lie in the convex hull of the kind's colours,
    /// CrissCross's in 3/4 of it; Turbulence and Wood extrapolate a little past their colours
    /// (see the variants), never below 0.
    pub fn eval(&self, p: Vec3, uv: Vec2) -> Vec3 {
        match *self {
            Texture::Solid(c) => c,
            Texture::Image { ref image, tint } => tint * image.sample(uv),
            Texture::Checkerboard {
                a,
                b,
                scale,
                origin,
            } => {
                // f64: an origin millions of units away would round `p - origin` in f32.
                let cell = ((p.as_dvec3() - origin.as_dvec3()) / scale as f64).floor();
                // Parity per axis by bit tests: summing saturated integers could overflow.
                let odd = (cell.x as i64 ^ cell.y as i64 ^ cell.z as i64) & 1;
                if odd == 0 { a } else { b }
            }
            Texture::Turbulence { a, b, scale } => mix_past(a, b, turbulence(p / scale)),
            Texture::Marble { a, b, scale } => mix(
                a,
                b,
                veins(
                    p / scale,
                    Vec3::new(1.0, 1.0, 0.0),
                    Vec3::new(1.0, 3.0, 1.0),
                ),
            ),
            Texture::Wood { a, b, scale } => {
                let rings = 5.0 * noise(p / scale);
                mix_past(a, b, rings - rings.trunc())
            }
            Texture::CrissCross { a, b, c, scale } => {
                let q = p / scale;
                let t = [0, 1, 2].map(|i| veins(q, CRISS_BANDS[i], CRISS_STRETCH[i]));
                (mix(a, b, t[0]) + mix(b, c, t[1]) + mix(c, a, t[2])) * CRISS_WEIGHT
            }
        }
    }

    /// True when the texture is black everywhere (all of its colours are zero; for an image,
    /// when its tint is).
    pub fn is_black(&self) -> bool {
        self.colours().iter().all(|c| *c == Vec3::ZERO)
    }

    /// The colours the texture blends, the last repeated to fill three slots (so the set, its
    /// convex hull and "all black" are unchanged, and shading allocates nothing).
    fn colours(&self) -> [Vec3; 3] {
        match *self {
            Texture::Solid(c) | Texture::Image { tint: c, .. } => [c; 3],
            Texture::Checkerboard { a, b, .. }
            | Texture::Turbulence { a, b, .. }
            | Texture::Marble { a, b, .. }
            | Texture::Wood { a, b, .. } => [a, b, b],
            Texture::CrissCross { a, b, c, .. } => [a, b, c],
        }
    }

    /// The pattern's world-space scale, `None` for `Solid` and `Image`.
    pub fn scale(&self) -> Option<f32> {
        match *self {
            Texture::Solid(_) | Texture::Image { .. } => None,
            Texture::Checkerboard { scale, .. }
            | Texture::Turbulence { scale, .. }
            | Texture::Marble { scale, .. }
            | Texture::Wood { scale, .. }
            | Texture::CrissCross { scale, .. } => Some(scale),
        }
    }

    /// Checks the invariants `eval` relies on: finite, positive scale; finite colours.
    pub fn validate(&self) -> Result<(), &'static str> {
        if self.colours().iter().any(|c| !c.is_finite()) {
            return Err("texture colour is not finite");
        }
        match self.scale() {
            Some(s) if !(s.is_finite() && s > 0.0) => {
                Err("texture scale must be finite and positive")
            }
            _ => Ok(()),
        }
    }

    /// Reads `scale` as the `.scn` file's `scale` parameter for this kind and returns the texture
    /// with the world-space scale that draws the pattern the paper's ray tracer drew.
    ///
    /// The original multiplies the point by its scale (a frequency) for the noise kinds, with
    /// extra constant factors; Checkerboard's is already a cell size, and its grid gets the
    /// original's corner [`SCN_CHECKER_ORIGIN`]. Non-positive values give an infinite or
    /// negative scale, which [`Texture::validate`] rejects.
    pub fn from_scn_scale(self) -> Texture {
        match self {
            Texture::Solid(_) | Texture::Image { .. } => self,
            Texture::Checkerboard { a, b, scale, .. } => Texture::Checkerboard {
                a,
                b,
                scale,
                origin: SCN_CHECKER_ORIGIN,
            },
            // Noise at 0.05 * s * p.
            Texture::Turbulence { a, b, scale } => Texture::Turbulence {
                a,
                b,
                scale: 20.0 / scale,
            },
            // Noise at 0.05 * s * p (times 3 along y), sine of 0.05 * s * (x + y).
            Texture::Marble { a, b, scale } => Texture::Marble {
                a,
                b,
                scale: 20.0 / scale,
            },
            // Noise at s * p.
            Texture::Wood { a, b, scale } => Texture::Wood {
                a,
                b,
                scale: 1.0 / scale,
            },
            // Noise at 0.5 * s * p times the per-axis factors.
            Texture::CrissCross { a, b, c, scale } => Texture::CrissCross {
                a,
                b,
                c,
                scale: 2.0 / scale,
            },
        }
    }
}

#[cfg(test)]
mod tests;

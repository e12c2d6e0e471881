//! Image textures: a grid of linear RGB texels looked up by texture coordinates.
//!
//! Convention (glTF's): `uv = (0, 0)` is the image's top-left corner, `u` grows to the right and
//! `v` downwards; texel `(x, y)` covers `[x, x+1] / width x [y, y+1] / height`, so its centre is
//! at `((x + 0.5) / width, (y + 0.5) / height)`. Loaders whose format puts `v = 0` at the bottom
//! (OBJ) flip `v` when they read the coordinates.
//!
//! ```text
//! newmtl checker
//! Kd 1 1 1
//! map_Kd checker.png     # -> Texture::Image { image: checker.png, tint: Kd }
//! ```

use crate::math::{Vec2, Vec3};

/// A decoded image: `width x height` linear RGB texels, row 0 at the top. Fields are private:
/// the constructors guarantee `texels.len() == width * height > 0` and finite texels.
#[derive(Clone, PartialEq)]
pub struct ImageTexture {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl std::fmt::Debug for ImageTexture {
    // The texels would drown any message that prints a material.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ImageTexture({}x{})", self.width, self.height)
    }
}

impl ImageTexture {
    /// An image from linear RGB texels in rows from the top; `None` unless
    /// `texels.len() == width * height`, the image is non-empty and every texel is finite.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Option<Self> {
        let ok = width > 0
            && height > 0
            && texels.len() as u64 == u64::from(width) * u64::from(height)
            && texels.iter().all(|t| t.is_finite());
        ok.then_some(Self {
            width,
            height,
            texels,
        })
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Texel `(x, y)` (row `y` from the top), coordinates wrapped into the image (REPEAT).
    pub fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.rem_euclid(i64::from(self.width)) as usize;
        let y = y.rem_euclid(i64::from(self.height)) as usize;
        self.texels[y * self.width as usize + x]
    }

    /// Bilinearly filtered colour (linear RGB) at `uv`, wrapping outside `[0, 1)` (REPEAT).
    /// At a texel centre it is exactly that texel. Non-finite `uv` reads as `(0, 0)`.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        // Texel centres sit at half-integers; shift so they land on integers.
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // Saturating float-to-int casts keep absurd coordinates in range for rem_euclid.
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self
            .texel(x0, y0)
            .lerp(self.texel(x0.wrapping_add(1), y0), fx);
        let bottom = self
            .texel(x0, y0.wrapping_add(1))
            .lerp(self.texel(x0.wrapping_add(1), y0.wrapping_add(1)), fx);
        top.lerp(bottom, fy)
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1), `c` in [0, 1].
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_two() -> ImageTexture {
        let t = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE];
        ImageTexture::new(2, 2, t.to_vec()).unwrap()
    }

    #[test]
    fn texel_centres_are_exact_and_top_left_is_uv_zero() {
        let img = two_by_two();
        assert_eq!(img.sample(Vec2::new(0.25, 0.25)), Vec3::X);
        assert_eq!(img.sample(Vec2::new(0.75, 0.25)), Vec3::Y);
        assert_eq!(img.sample(Vec2::new(0.25, 0.75)), Vec3::Z);
        assert_eq!(img.sample(Vec2::new(0.75, 0.75)), Vec3::ONE);
    }

    #[test]
    fn bilinear_between_centres_and_repeat_wrap() {
        let img = two_by_two();
        let mid = img.sample(Vec2::new(0.5, 0.25));
        assert!((mid - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
        // uv = (0, 0.25) is halfway between texel (1, 0) wrapped from the left and texel (0, 0).
        assert!((img.sample(Vec2::new(0.0, 0.25)) - mid).length() < 1e-6);
        assert_eq!(img.sample(Vec2::new(1.25, -0.75)), Vec3::X);
        assert!(img.sample(Vec2::new(f32::NAN, 1e30)).is_finite());
    }

    #[test]
    fn new_rejects_bad_sizes_and_srgb_decodes_to_linear() {
        assert!(ImageTexture::new(2, 2, vec![Vec3::ONE; 3]).is_none());
        assert!(ImageTexture::new(0, 0, Vec::new()).is_none());
        assert!(ImageTexture::new(1, 1, vec![Vec3::NAN]).is_none());
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.21404).abs() < 1e-4);
    }
}

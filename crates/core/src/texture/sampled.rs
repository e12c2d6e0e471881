//! Images as glTF uses them: 8-bit RGBA texels read through a sampler (wrap mode per axis,
//! nearest or bilinear filter) after an optional `KHR_texture_transform`, from one of a mesh's
//! texture coordinate sets.
//!
//! Texels stay 8-bit (4 bytes each, a quarter of linear floats: a 2048x2048 map is 16 MiB) and
//! are decoded per lookup, because one image may be read as sRGB colour (base colour,
//! emission) by one material and as linear data (normals, metal/roughness, occlusion) by another.
//!
//! Filtering: Whitted rays carry no footprint, so there is no minification level to choose;
//! every lookup uses the magnification filter (`NEAREST` or, by default, `LINEAR`), and a
//! mipmapped `minFilter` is read as its linear base level.

use std::sync::Arc;

use super::image::srgb_to_linear;
use crate::math::{Vec2, Vec3, Vec4};

/// A decoded image: `width x height` RGBA8 texels, row 0 at the top (glTF's `uv = (0, 0)`).
/// Fields are private: [`Texels::new`] guarantees `rgba.len() == width * height > 0`.
#[derive(Clone, PartialEq)]
pub struct Texels {
    width: u32,
    height: u32,
    rgba: Vec<[u8; 4]>,
}

impl std::fmt::Debug for Texels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Texels({}x{})", self.width, self.height)
    }
}

impl Texels {
    /// An image from RGBA8 texels in rows from the top; `None` unless the sizes agree and the
    /// image is non-empty.
    pub fn new(width: u32, height: u32, rgba: Vec<[u8; 4]>) -> Option<Self> {
        let ok =
            width > 0 && height > 0 && rgba.len() as u64 == u64::from(width) * u64::from(height);
        ok.then_some(Self {
            width,
            height,
            rgba,
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

    /// Texel `(x, y)`, already wrapped into the image, as 0..=1 floats.
    fn texel(&self, x: usize, y: usize) -> Vec4 {
        let [r, g, b, a] = self.rgba[y * self.width as usize + x];
        Vec4::new(r as f32, g as f32, b as f32, a as f32) / 255.0
    }
}

/// What a texture coordinate outside `[0, 1]` reads (glTF's `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles (glTF's default).
    #[default]
    Repeat,
    /// The edge texel continues.
    Clamp,
    /// The image tiles, every other copy mirrored.
    Mirror,
}

impl Wrap {
    /// Texel index `i` of a row or column of `n` texels, wrapped into `0..n`.
    fn index(self, i: i64, n: u32) -> usize {
        let n = i64::from(n);
        (match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let k = i.rem_euclid(2 * n);
                if k < n { k } else { 2 * n - 1 - k }
            }
        }) as usize
    }
}

/// A sampler: wrap mode per axis and the filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sampler {
    /// Along `u`.
    pub wrap_u: Wrap,
    /// Along `v`.
    pub wrap_v: Wrap,
    /// `NEAREST` magnification: the texel under `uv`, no blending.
    pub nearest: bool,
}

/// `KHR_texture_transform`: `uv' = T(offset) R(rotation) S(scale) uv`, the extension's order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Added last.
    pub offset: Vec2,
    /// Radians, counter-clockwise in the image as the extension draws it.
    pub rotation: f32,
    /// Multiplies first.
    pub scale: Vec2,
}

impl UvTransform {
    /// `uv` transformed; the extension's matrix, which with `v` downwards turns the image
    /// counter-clockwise.
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let s = uv * self.scale;
        let (sin, cos) = self.rotation.sin_cos();
        Vec2::new(cos * s.x + sin * s.y, -sin * s.x + cos * s.y) + self.offset
    }
}

/// How a texture's texels are to be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Colour: RGB through the sRGB transfer function, alpha linear.
    Srgb,
    /// Data (normals, metal/roughness, occlusion): every channel as stored.
    Linear,
}

/// One texture reference of a material: image, sampler, transform, coordinate set, encoding.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRef {
    /// The texels, shared by every reference to the image.
    pub image: Arc<Texels>,
    /// Wrap and filter.
    pub sampler: Sampler,
    /// `KHR_texture_transform`, if given.
    pub transform: Option<UvTransform>,
    /// Which `TEXCOORD_n` (0 or 1) it reads.
    pub tex_coord: u32,
    /// Colour or data.
    pub encoding: Encoding,
}

impl TextureRef {
    /// The filtered texel (RGBA, each in 0..=1, RGB linear light for sRGB textures) at the
    /// surface whose texture coordinate sets are `uvs`. Non-finite coordinates read `(0, 0)`.
    pub fn sample(&self, uvs: &[Vec2; 2]) -> Vec4 {
        let uv = uvs[(self.tex_coord as usize).min(1)];
        let uv = self.transform.map_or(uv, |t| t.apply(uv));
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        let raw = self.filtered(uv);
        match self.encoding {
            Encoding::Linear => raw,
            Encoding::Srgb => {
                let rgb = Vec3::new(
                    srgb_to_linear(raw.x),
                    srgb_to_linear(raw.y),
                    srgb_to_linear(raw.z),
                );
                rgb.extend(raw.w)
            }
        }
    }

    /// The stored values at `uv`, nearest or bilinear (blending the stored values, then
    /// decoding: what GPUs do for linear images and close to their sRGB filtering).
    fn filtered(&self, uv: Vec2) -> Vec4 {
        let img = &*self.image;
        let s = self.sampler;
        // Texel centres sit at half-integers; shift so they land on integers.
        let x = uv.x * img.width as f32 - 0.5;
        let y = uv.y * img.height as f32 - 0.5;
        if s.nearest {
            // Saturating float-to-int casts keep absurd coordinates in range.
            let (xi, yi) = ((x + 0.5).floor() as i64, (y + 0.5).floor() as i64);
            return img.texel(
                s.wrap_u.index(xi, img.width),
                s.wrap_v.index(yi, img.height),
            );
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let xs = [x0, x0.saturating_add(1)].map(|i| s.wrap_u.index(i, img.width));
        let ys = [y0, y0.saturating_add(1)].map(|i| s.wrap_v.index(i, img.height));
        let top = img.texel(xs[0], ys[0]).lerp(img.texel(xs[1], ys[0]), fx);
        let bottom = img.texel(xs[0], ys[1]).lerp(img.texel(xs[1], ys[1]), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(sampler: Sampler, transform: Option<UvTransform>) -> TextureRef {
        // 2x1: black, white.
        let image = Arc::new(Texels::new(2, 1, vec![[0, 0, 0, 255], [255, 255, 255, 0]]).unwrap());
        TextureRef {
            image,
            sampler,
            transform,
            tex_coord: 0,
            encoding: Encoding::Linear,
        }
    }

    fn at(t: &TextureRef, u: f32) -> f32 {
        t.sample(&[Vec2::new(u, 0.5), Vec2::ZERO]).x
    }

    #[test]
    fn wrap_modes_outside_the_unit_square() {
        let nearest = |wrap| {
            reference(
                Sampler {
                    wrap_u: wrap,
                    wrap_v: wrap,
                    nearest: true,
                },
                None,
            )
        };
        // u = 1.25 lies in texel 2: REPEAT reads texel 0, CLAMP texel 1, MIRROR texel 1.
        assert_eq!(at(&nearest(Wrap::Repeat), 1.25), 0.0);
        assert_eq!(at(&nearest(Wrap::Clamp), 1.25), 1.0);
        assert_eq!(at(&nearest(Wrap::Mirror), 1.25), 1.0);
        assert_eq!(at(&nearest(Wrap::Mirror), 1.75), 0.0);
        assert_eq!(at(&nearest(Wrap::Clamp), -3.0), 0.0);
        assert_eq!(Wrap::Mirror.index(-1, 2), 0);
    }

    #[test]
    fn linear_blends_and_nearest_does_not() {
        let linear = reference(Sampler::default(), None);
        assert!((at(&linear, 0.5) - 0.5).abs() < 1e-6);
        let nearest = reference(
            Sampler {
                nearest: true,
                ..Sampler::default()
            },
            None,
        );
        assert_eq!(at(&nearest, 0.49), 0.0);
        assert_eq!(at(&nearest, 0.51), 1.0);
    }

    #[test]
    fn transform_offsets_scales_and_rotates() {
        let t = UvTransform {
            offset: Vec2::new(0.5, 0.0),
            rotation: 0.0,
            scale: Vec2::ONE,
        };
        assert_eq!(t.apply(Vec2::new(0.25, 0.5)), Vec2::new(0.75, 0.5));
        let r = UvTransform {
            offset: Vec2::ZERO,
            rotation: std::f32::consts::FRAC_PI_2,
            scale: Vec2::new(2.0, 1.0),
        };
        let q = r.apply(Vec2::new(1.0, 0.0));
        assert!((q - Vec2::new(0.0, -2.0)).length() < 1e-6, "{q}");
        assert!(at(&reference(Sampler::default(), Some(t)), 0.25) > 0.9);
    }
}

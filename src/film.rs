//! The image being rendered: linear premultiplied RGBA plus the AOV layers written to EXR.

use crate::cryptomatte::CryptoLayer;
use crate::math::{Vec2, Vec3, Vec4};

/// What the centre ray of one pixel saw, for the depth, normal and id layers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelAov {
    /// Camera-space depth along the view axis; `f32::INFINITY` where the ray missed.
    pub depth: f32,
    /// World-space unit shading normal; zero where missed.
    pub normal: Vec3,
    /// Primitive index, -1 where missed.
    pub prim_id: i32,
    /// Object index, -1 where missed.
    pub object_id: i32,
    /// Diffuse albedo `kd` of the material at the hit (textures evaluated, before lighting);
    /// zero where missed.
    pub albedo: Vec3,
    /// World-space hit point; zero where missed.
    pub position: Vec3,
    /// Surface texture coordinates at the hit (a mesh's first set, a sphere's longitude and
    /// latitude); zero where missed.
    pub uv: Vec2,
}

impl PixelAov {
    /// The value of a pixel whose centre ray hit nothing.
    pub const MISS: PixelAov = PixelAov {
        depth: f32::INFINITY,
        normal: Vec3::ZERO,
        prim_id: -1,
        object_id: -1,
        albedo: Vec3::ZERO,
        position: Vec3::ZERO,
        uv: Vec2::ZERO,
    };
}

/// A `width x height` image, rows top to bottom. Fields are private so the layers always
/// have one entry per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    rgba: Vec<Vec4>,
    aov: Vec<PixelAov>,
    crypto: Vec<CryptoLayer>,
}

impl Film {
    /// A black, transparent film with every AOV at its miss value.
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            rgba: vec![Vec4::ZERO; n],
            aov: vec![PixelAov::MISS; n],
            crypto: Vec::new(),
        }
    }

    /// Scales the colour (not alpha, not the AOV layers) by `2^stops`: the exposure, applied
    /// once before the film is written so that the EXR and the PNG agree. Whole stops scale
    /// by a power of two, exactly.
    pub fn expose(&mut self, stops: f32) {
        let scale = stops.exp2();
        for p in &mut self.rgba {
            *p = (p.truncate() * scale).extend(p.w);
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Linear premultiplied RGBA, row-major from the top-left.
    pub fn rgba(&self) -> &[Vec4] {
        &self.rgba
    }

    /// Per-pixel AOVs, same layout as `rgba`.
    pub fn aov(&self) -> &[PixelAov] {
        &self.aov
    }

    /// RGBA at pixel `(x, y)`.
    pub fn pixel(&self, x: u32, y: u32) -> Vec4 {
        self.rgba[(y * self.width + x) as usize]
    }

    /// AOV at pixel `(x, y)`.
    pub fn pixel_aov(&self, x: u32, y: u32) -> PixelAov {
        self.aov[(y * self.width + x) as usize]
    }

    /// The Cryptomatte layers, in the order they are written (none unless the render asked
    /// for them).
    pub fn crypto(&self) -> &[CryptoLayer] {
        &self.crypto
    }

    /// Mutable Cryptomatte layers, for the renderer to fill.
    pub fn crypto_mut(&mut self) -> &mut [CryptoLayer] {
        &mut self.crypto
    }

    /// Adds a Cryptomatte layer; it must have been made for this film's pixel count.
    pub fn add_crypto(&mut self, layer: CryptoLayer) {
        assert_eq!(
            layer.ranks().len(),
            layer.levels() * self.rgba.len(),
            "Cryptomatte layer {} made for another film size",
            layer.name()
        );
        self.crypto.push(layer);
    }

    /// Stores one finished pixel.
    pub fn set(&mut self, x: u32, y: u32, rgba: Vec4, aov: PixelAov) {
        let i = (y * self.width + x) as usize;
        self.rgba[i] = rgba;
        self.aov[i] = aov;
    }
}

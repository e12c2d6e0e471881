//! The image being rendered: linear premultiplied RGBA plus the AOV layers written to EXR.

mod display;
mod exposure;
mod finite;
mod passes;
mod paste;
mod tile_split;
mod tonemap;

pub use display::{DisplayTransform, linear_to_srgb8};
pub use exposure::{
    AUTO_EXPOSURE_PERCENTILE, AUTO_EXPOSURE_TARGET, auto_exposure, auto_exposure_of,
};
pub use finite::{NonFinite, check_finite};
pub use passes::{PassLayer, SHADOW_PASS, is_colour_pass};
pub use tile_split::{SPLIT_ROWS, TileSpec};
pub use tonemap::Tonemap;

use crate::cryptomatte::CryptoLayer;
use crate::math::{Vec2, Vec3, Vec4};

/// What the centre ray of one pixel saw, for the depth, normal and id layers, and how many
/// samples the pixel took.
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
    /// Index of the instance hit (the scene's instance list), -1 where missed or where the
    /// surface belongs to no instance.
    pub instance_id: i32,
    /// Diffuse albedo `kd` of the material at the hit (textures evaluated, before lighting);
    /// zero where missed.
    pub albedo: Vec3,
    /// World-space hit point; zero where missed.
    pub position: Vec3,
    /// Surface texture coordinates at the hit (a mesh's first set, a sphere's longitude and
    /// latitude); zero where missed.
    pub uv: Vec2,
    /// Pixel samples the render took here (each traced through the lens rays of one sample):
    /// `spp x spp`, or fewer under adaptive supersampling; 0 where no render wrote the pixel.
    pub samples: u32,
}

impl PixelAov {
    /// The value of a pixel whose centre ray hit nothing.
    pub const MISS: PixelAov = PixelAov {
        depth: f32::INFINITY,
        normal: Vec3::ZERO,
        prim_id: -1,
        object_id: -1,
        instance_id: -1,
        albedo: Vec3::ZERO,
        position: Vec3::ZERO,
        uv: Vec2::ZERO,
        samples: 0,
    };
}

/// A rectangle of pixels `[x0, x1) x [y0, y1)` of the full image (pbrt's pixel bounds): the
/// part of the image a render computes and an EXR stores as its data window.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PixelWindow {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelWindow {
    /// The whole `width x height` image.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
        }
    }

    /// The pixels a crop window in normalized device coordinates (`[0,1]`, y down) covers, by
    /// pbrt's rule: each bound is `ceil(resolution * crop)`, so adjacent crops share no pixel
    /// and together cover the image.
    pub fn from_crop(crop: [f32; 4], width: u32, height: u32) -> Self {
        // In f32, as pbrt computes it, so that e.g. 40 x 0.3 is 12, not 12.0000005 -> 13.
        let at = |f: f32, n: u32| ((n as f32 * f).ceil() as u32).min(n);
        Self {
            x0: at(crop[0], width),
            x1: at(crop[1], width),
            y0: at(crop[2], height),
            y1: at(crop[3], height),
        }
    }

    /// Width in pixels (of the window).
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    /// Height in pixels (of the window).
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    /// Why this is no window of a `width x height` image: empty or reaching outside it.
    pub fn check(&self, width: u32, height: u32) -> Result<(), String> {
        if self.x0 >= self.x1 || self.y0 >= self.y1 {
            return Err(format!(
                "pixel bounds x {}..{}, y {}..{} hold no pixel",
                self.x0, self.x1, self.y0, self.y1
            ));
        }
        if self.x1 > width || self.y1 > height {
            return Err(format!(
                "pixel bounds x {}..{}, y {}..{} reach outside the {width}x{height} image",
                self.x0, self.x1, self.y0, self.y1
            ));
        }
        Ok(())
    }
}

/// Scales linear colour (not alpha) by `2^stops`, as [`Film::expose`] does; also used by
/// `lumis merge`, which exposes the tiles' floats after assembling them.
pub fn expose_rgba(rgba: &mut [Vec4], stops: f32) {
    let scale = stops.exp2();
    // Saturating: a bright pixel times a large exposure stays finite (f32::MAX), never inf.
    for p in rgba {
        *p = (p.truncate() * scale)
            .min(Vec3::splat(f32::MAX))
            .extend(p.w);
    }
}

/// The pixels of one window of a `full_width x full_height` image, rows top to bottom
/// (usually the whole image). Fields are private so the layers always have one entry per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    /// Where this film's `(0, 0)` lies in the full image.
    origin: (u32, u32),
    /// The full image the window belongs to (the EXR display window, the camera's frame).
    full: (u32, u32),
    rgba: Vec<Vec4>,
    aov: Vec<PixelAov>,
    crypto: Vec<CryptoLayer>,
    passes: Vec<PassLayer>,
}

impl Film {
    /// A black, transparent film of the whole image with every AOV at its miss value.
    pub fn new(width: u32, height: u32) -> Self {
        Self::window(width, height, PixelWindow::full(width, height))
    }

    /// A black, transparent film of `window` of a `full_width x full_height` image.
    pub fn window(full_width: u32, full_height: u32, window: PixelWindow) -> Self {
        let (width, height) = (window.width(), window.height());
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            origin: (window.x0, window.y0),
            full: (full_width, full_height),
            rgba: vec![Vec4::ZERO; n],
            aov: vec![PixelAov::MISS; n],
            crypto: Vec::new(),
            passes: Vec::new(),
        }
    }

    /// Where this film's pixel `(0, 0)` lies in the full image.
    pub fn origin(&self) -> (u32, u32) {
        self.origin
    }

    /// Size of the full image this film is a window of.
    pub fn full_size(&self) -> (u32, u32) {
        self.full
    }

    /// Scales the colour (not alpha, not the AOV layers) and the radiance passes by
    /// `2^stops`: the exposure, applied once before the film is written so that the EXR and
    /// the PNG agree and the passes still add up to the beauty. Whole stops scale by a power
    /// of two, exactly.
    pub fn expose(&mut self, stops: f32) {
        expose_rgba(&mut self.rgba, stops);
        let scale = stops.exp2();
        for pass in self.passes.iter_mut().filter(|p| p.is_colour()) {
            for v in pass.values_mut() {
                *v = (*v * scale).min(Vec3::splat(f32::MAX));
            }
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

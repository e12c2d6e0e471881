//! Renders one swatch per procedural texture kind to a PNG for a human to look at.
//!
//! Each swatch is the plane z = 0 over [0, 4]^2 at 128x128 pixels. Scales and colours come from
//! the paper's `allMaterials.scn`, rescaled so a swatch spans the diameter of that scene's sphere
//! (the pattern density a viewer of the paper's Fig 1 sees). Layout, left to right:
//! top row checkerboard, turbulence, marble, wood; bottom row criss-cross, raw noise, a Lambert-lit
//! normal map, and the criss-cross of the scene's ground (primaries) over 300 units.
//!
//! `cargo run --example texture_swatches [out.png]` (default `/tmp/texture_swatches.png`).

use lumis_core::math::{Vec2, Vec3};
use lumis_core::texture::{NormalMap, Texture, perlin};

const SIZE: u32 = 128;
const GAP: u32 = 4;
const EXTENT: f32 = 4.0;

/// The texture's `.scn` scale converted to world units, then shrunk so the sphere's diameter
/// fits in one swatch.
fn fit(t: Texture, sphere_diameter: f32) -> Texture {
    let t = t.from_scn_scale();
    let s = t.scale().unwrap_or(1.0) * EXTENT / sphere_diameter;
    match t {
        Texture::Solid(_) | Texture::Image { .. } => t,
        Texture::Checkerboard { a, b, origin, .. } => Texture::Checkerboard {
            a,
            b,
            scale: s,
            // Shrunk with the cells, so the grid keeps its phase.
            origin: origin * EXTENT / sphere_diameter,
        },
        Texture::Turbulence { a, b, .. } => Texture::Turbulence { a, b, scale: s },
        Texture::Marble { a, b, .. } => Texture::Marble { a, b, scale: s },
        Texture::Wood { a, b, .. } => Texture::Wood { a, b, scale: s },
        Texture::CrissCross { a, b, c, .. } => Texture::CrissCross { a, b, c, scale: s },
    }
}

/// Linear [0, 1] to an 8-bit sRGB code value.
fn srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let e = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0 + 0.5) as u8
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "/tmp/texture_swatches.png".into());
    let rgb = Vec3::new;
    let swatches: Vec<Box<dyn Fn(Vec3) -> Vec3>> = {
        let tex =
            |t: Texture| -> Box<dyn Fn(Vec3) -> Vec3> { Box::new(move |p| t.eval(p, Vec2::ZERO)) };
        let bumps = NormalMap {
            scale: 0.25,
            amount: 0.5,
        };
        let light = rgb(1.0, 1.0, 2.0).normalize();
        vec![
            tex(fit(
                Texture::Checkerboard {
                    a: rgb(0.3, 0.2, 0.1),
                    b: rgb(0.7, 0.8, 0.9),
                    scale: 50.0,
                    origin: Vec3::ZERO,
                },
                200.0,
            )),
            tex(fit(
                Texture::Turbulence {
                    a: rgb(0.0509, 0.1803, 0.0509),
                    b: rgb(0.1607, 0.2784, 0.1607),
                    scale: 0.75,
                },
                280.0,
            )),
            tex(fit(
                Texture::Marble {
                    a: rgb(0.4, 0.3, 0.2),
                    b: rgb(0.6, 0.7, 0.8),
                    scale: 0.5,
                },
                300.0,
            )),
            tex(fit(
                Texture::Wood {
                    a: rgb(0.1043, 0.0737, 0.0517),
                    b: rgb(0.4215, 0.2686, 0.1888),
                    scale: 0.01,
                },
                300.0,
            )),
            tex(fit(
                Texture::CrissCross {
                    a: rgb(0.3, 0.35, 0.29),
                    b: rgb(0.25, 0.1, 0.17),
                    c: rgb(0.75, 0.65, 0.82),
                    scale: 0.1,
                },
                250.0,
            )),
            Box::new(|p: Vec3| Vec3::splat(0.5 + 0.5 * perlin::noise(p * 2.0))),
            Box::new(move |p: Vec3| {
                Vec3::splat(0.9 * bumps.perturb(Vec3::Z, p).dot(light).max(0.0))
            }),
            tex(fit(
                Texture::CrissCross {
                    a: Vec3::X,
                    b: Vec3::Y,
                    c: Vec3::Z,
                    scale: 0.05,
                },
                300.0,
            )),
        ]
    };
    let cols = 4;
    let rows = swatches.len().div_ceil(cols) as u32;
    let width = cols as u32 * (SIZE + GAP) + GAP;
    let height = rows * (SIZE + GAP) + GAP;
    let mut img = image::RgbImage::from_pixel(width, height, image::Rgb([40, 40, 40]));
    for (i, f) in swatches.iter().enumerate() {
        let (x0, y0) = (
            GAP + (i % cols) as u32 * (SIZE + GAP),
            GAP + (i / cols) as u32 * (SIZE + GAP),
        );
        for py in 0..SIZE {
            for px in 0..SIZE {
                let u = (px as f32 + 0.5) / SIZE as f32 * EXTENT;
                let v = (1.0 - (py as f32 + 0.5) / SIZE as f32) * EXTENT;
                let c = f(Vec3::new(u, v, 0.0));
                img.put_pixel(
                    x0 + px,
                    y0 + py,
                    image::Rgb([srgb8(c.x), srgb8(c.y), srgb8(c.z)]),
                );
            }
        }
    }
    img.save(&out)?;
    println!("wrote {out} ({width}x{height})");
    Ok(())
}

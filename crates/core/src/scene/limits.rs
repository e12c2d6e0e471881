//! The value limits every scene meets, whatever file it came from: [`super::SceneBuilder`]
//! checks each sphere, mesh, light, material and the camera against them as they are added,
//! so no format can skip the check (docs/robustness.md, "Values").
//!
//! Why these numbers:
//! - **Coordinates, |x| <= [`MAX_COORDINATE`] = 1e18.** A finite `f32` is not enough: the
//!   intersection and shading code squares differences of two points (`|o - c|^2` and `b^2` in
//!   the sphere tests, `|light - p|^2` for a point light, products of two sheared coordinates
//!   in the triangle edge functions). With every point within 1e18 a difference is at most 2e18,
//!   a sum of three squares at most 1.2e37, and the `--precision fast` sphere's `b^2 = 4 (f.d)^2`
//!   at most 4.8e37: seven times below `f32::MAX` (3.4e38). Coordinates of 1e19 would already
//!   overflow it.
//! - **Radiance, <= [`MAX_RADIANCE`] = 1e6** (emission, ambient, background): 15 times the
//!   largest half float (65504), room for a few stops of negative exposure, and far above any
//!   physical scene in lumis's units. **Light power, <= [`MAX_LIGHT_POWER`] = 1e20** (colour x
//!   intensity): a point light's irradiance falls with the squared distance, so realistic
//!   lights far away need large intensities.
//! - **Reflectances in [0, 1]** (diffuse, specular, reflectivity, transmission), shininess at
//!   most [`MAX_SHININESS`]: with them a hit reflects at most what arrives.
//!
//! What the renderer still clamps: a point light's irradiance near its position (`I / d^2` is
//! unbounded as `d -> 0`) at [`MAX_IRRADIANCE`], and every shaded radiance at
//! [`MAX_SAMPLE_RADIANCE`], so sums over many lights and 64 bounces of weight up to 2 stay
//! finite (an `inf` times a zero weight would be a NaN pixel).

use crate::light::Light;
use crate::material::{MAX_SHININESS, Material, Texture};
use crate::math::{Aabb, Vec3};

/// Largest |coordinate| of any geometry bound, light position or camera position.
pub const MAX_COORDINATE: f32 = 1e18;
/// Largest emitted, ambient or background radiance component.
pub const MAX_RADIANCE: f32 = 1e6;
/// Largest light colour x intensity component (W/sr for point and spot lights, W/m^2 for
/// directional and `.scn` lights).
pub const MAX_LIGHT_POWER: f32 = 1e20;
/// Largest exposure, in stops either way: `2^64` times the largest radiance stays finite.
pub const MAX_EXPOSURE: f32 = 64.0;
// The ceiling of a light's irradiance lives beside the light that it limits.
pub use crate::light::MAX_IRRADIANCE;
/// Ceiling of the radiance any shaded hit returns; the EXR stores half floats up to 65504
/// (clamped there) or floats up to this.
pub const MAX_SAMPLE_RADIANCE: f32 = 1e30;

/// A value outside the limits: which element (as the builder was given its name) and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{element}: {message}")]
pub struct LimitError {
    /// The object, material, light or camera.
    pub element: String,
    /// What is out of range, and the limit.
    pub message: String,
}

/// `[x, y, z]` in scientific notation: `1e38`, not 39 digits.
fn sci(p: Vec3) -> String {
    format!("[{:e}, {:e}, {:e}]", p.x, p.y, p.z)
}

/// Why `b` (world-space bounds of one object) is outside the coordinate limit.
pub fn check_bounds(b: &Aabb) -> Result<(), String> {
    if b.is_empty() {
        return Ok(());
    }
    for p in [b.min, b.max] {
        if !p.is_finite() || p.abs().max_element() > MAX_COORDINATE {
            return Err(format!(
                "world-space bounds {} .. {} exceed the coordinate limit |x| <= {MAX_COORDINATE:e} \
                 (a scale, radius or vertex too large)",
                sci(b.min),
                sci(b.max)
            ));
        }
    }
    Ok(())
}

/// Why point `p` (named `what`) is outside the coordinate limit.
pub fn check_point(what: &str, p: Vec3) -> Result<(), String> {
    if p.is_finite() && p.abs().max_element() <= MAX_COORDINATE {
        Ok(())
    } else {
        Err(format!(
            "{what} {} exceeds the coordinate limit |x| <= {MAX_COORDINATE:e}",
            sci(p)
        ))
    }
}

/// Why colour `c` (named `what`) is not finite and within `[0, max]`.
pub fn check_range(what: &str, c: Vec3, max: f32) -> Result<(), String> {
    if c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= max {
        Ok(())
    } else {
        Err(format!(
            "{what} {} must be finite and in [0, {max:e}]",
            sci(c)
        ))
    }
}

/// `c` clamped into `[0, max]` (NaN to 0), and whether that changed it: for the formats whose
/// bad values are warnings (MTL, glTF).
pub fn clamp_range(c: Vec3, max: f32) -> (Vec3, bool) {
    let clamped = Vec3::from_array(c.to_array().map(|x| if x > 0.0 { x.min(max) } else { 0.0 }));
    (clamped, clamped != c)
}

/// The colours a texture can take (their components bound every value it yields).
fn texture_colours(t: &Texture) -> Vec<Vec3> {
    match t {
        Texture::Solid(c) => vec![*c],
        Texture::Checkerboard { a, b, .. }
        | Texture::Turbulence { a, b, .. }
        | Texture::Marble { a, b, .. }
        | Texture::Wood { a, b, .. } => vec![*a, *b],
        Texture::CrissCross { a, b, c, .. } => vec![*a, *b, *c],
        // Image textures hold 8- or 16-bit values in [0, 1] times a checked tint.
        _ => Vec::new(),
    }
}

/// Why material `m` is outside the limits.
pub fn check_material(m: &Material) -> Result<(), String> {
    for c in texture_colours(&m.diffuse) {
        check_range("diffuse", c, 1.0)?;
    }
    check_range("specular", m.specular, 1.0)?;
    check_range("emission", m.emission, MAX_RADIANCE)?;
    for (what, v) in [
        ("reflectivity", m.reflectivity),
        ("transmission", m.transmission),
    ] {
        check_range(what, Vec3::splat(v), 1.0)?;
    }
    check_range("shininess", Vec3::splat(m.shininess), MAX_SHININESS)?;
    if !(m.ior.is_finite() && m.ior > 0.0) {
        return Err(format!("index of refraction {} must be positive", m.ior));
    }
    Ok(())
}

/// Why light `l` is outside the limits.
pub fn check_light(l: &Light) -> Result<(), String> {
    let (position, power) = match l {
        Light::Point {
            position,
            intensity,
        }
        | Light::Spot {
            position,
            intensity,
            ..
        } => (Some(*position), *intensity),
        Light::Unattenuated {
            position,
            irradiance,
        } => (Some(*position), *irradiance),
        Light::Directional { irradiance, .. } => (None, *irradiance),
    };
    if let Some(p) = position {
        check_point("position", p)?;
    }
    check_range("colour x intensity", power, MAX_LIGHT_POWER)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_accept_ordinary_and_refuse_huge_values() {
        let b = |x: f32| Aabb::new(Vec3::splat(-x), Vec3::splat(x));
        assert!(check_bounds(&b(1e18)).is_ok());
        assert!(check_bounds(&b(1.1e18)).is_err());
        assert!(check_bounds(&b(f32::INFINITY)).is_err());
        assert!(check_range("c", Vec3::splat(1.0), 1.0).is_ok());
        assert!(check_range("c", Vec3::new(1.0, -0.1, 0.0), 1.0).is_err());
        assert!(check_range("c", Vec3::new(1.0, f32::NAN, 0.0), 1.0).is_err());
        assert_eq!(
            clamp_range(Vec3::new(5.0, -1.0, f32::NAN), 1.0),
            (Vec3::new(1.0, 0.0, 0.0), true)
        );
        assert_eq!(
            clamp_range(Vec3::splat(0.5), 1.0),
            (Vec3::splat(0.5), false)
        );
        let m = Material {
            specular: Vec3::splat(1e38),
            ..Material::default()
        };
        assert!(check_material(&m).unwrap_err().contains("specular"));
        assert!(check_material(&Material::default()).is_ok());
    }

    #[test]
    fn the_coordinate_limit_keeps_the_squares_finite() {
        // The largest difference of two admissible points, squared and summed over three axes,
        // and the fast sphere test's b^2 = 4 (f.d)^2 of it: all finite in f32.
        let d = 2.0 * MAX_COORDINATE;
        let f = Vec3::splat(d);
        assert!(f.length_squared().is_finite());
        let b = 2.0 * f.dot(Vec3::splat(1.0 / 3f32.sqrt()));
        assert!((b * b).is_finite());
    }
}

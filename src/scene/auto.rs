//! Automatic camera and lights for scenes that bring none (a bare OBJ, a TOML file without
//! `[camera]`): a three-quarter view framing the bounds and a key/fill light rig.

use crate::camera::Camera;
use crate::light::Light;
use crate::math::{Aabb, Vec3};

/// Vertical field of view of the automatic camera, degrees.
const AUTO_FOV: f32 = 40.0;

/// A pinhole camera looking at the centre of `bounds` from the front-right-above, far enough
/// that the bounding sphere fits the vertical field of view of a `width x height` image.
/// Empty or non-finite bounds give a camera at `(0, 0, 5)` looking at the origin.
pub fn framing_camera(bounds: Aabb, width: u32, height: u32) -> Camera {
    let (center, radius) = bounding_sphere(bounds);
    let aspect = (width.max(1) as f32 / height.max(1) as f32).min(1.0);
    // The narrower of the two fields of view decides the distance.
    let half = (AUTO_FOV.to_radians() * 0.5).tan() * aspect;
    let distance = radius * 1.1 * (1.0 + half * half).sqrt() / half;
    let position = center + Vec3::new(0.55, 0.4, 1.0).normalize() * distance;
    Camera::look_at(position, center, Vec3::Y, AUTO_FOV, 0.0, None)
        .or_else(|_| Camera::look_at(Vec3::Z * 5.0, Vec3::ZERO, Vec3::Y, AUTO_FOV, 0.0, None))
        .unwrap_or_else(|_| unreachable!("the fallback camera is valid"))
}

/// A warm key point light above-left of the bounds, bright enough that a white Lambert surface
/// facing it has radiance about 1, plus a cool directional fill from the right.
pub fn default_rig(bounds: Aabb) -> [Light; 2] {
    let (center, radius) = bounding_sphere(bounds);
    let position = center + Vec3::new(-1.2, 2.0, 1.5) * (radius * 1.5);
    let d2 = (position - center).length_squared();
    [
        Light::Point {
            position,
            intensity: Vec3::new(1.0, 0.95, 0.85) * (std::f32::consts::PI * d2),
        },
        Light::Directional {
            direction: Vec3::new(1.0, -0.6, -0.5).normalize(),
            irradiance: Vec3::new(0.6, 0.7, 0.9),
        },
    ]
}

/// Centre and radius of a sphere around `bounds`; the unit sphere when the bounds are unusable.
fn bounding_sphere(bounds: Aabb) -> (Vec3, f32) {
    let radius = 0.5 * (bounds.max - bounds.min).length();
    if bounds.is_empty() || !radius.is_finite() || !bounds.min.is_finite() {
        return (Vec3::ZERO, 1.0);
    }
    (bounds.center(), radius.max(1e-3))
}

//! The domain of ray queries and cameras: which rays and camera values lumis answers, and why.
//! Inside it every query is answered exactly (docs/hard-cases.md states the bounds); outside
//! it every entry point refuses with a message naming the file and the row or key, before
//! anything is traced or written. The scene's own values have their limits beside this, in
//! [`super::limits`].
//!
//! **Rays** (`lumis hits` files; the library's queries assume the same):
//! - the origin: any finite `f32` point. A ray from far away is traced from near the scene
//!   ([`crate::accel::RayFrame`]), so its distance from the geometry costs no precision and no
//!   product can overflow; origins up to `f32::MAX` are answered.
//! - the direction: finite and non-zero, of any length (subnormal components included); `t`
//!   is measured in its units, and a hit whose `t` exceeds `f32::MAX` has no `f32` distance,
//!   so it is no hit.
//! - `t_min`, `t_max`: any numbers, infinities included; hits count in `(t_min, t_max]`, an
//!   empty interval has none. NaN is refused.
//!
//! **Cameras** (every scene format, `-D`, animation keys):
//! - the position, within the coordinate limit (1e18) like all geometry;
//! - the field of view, in `[MIN_FOV_DEG, 180)` degrees: the basis is held in `f64`, which
//!   resolves directions to ~1e-16 rad; at 1e-7 degrees over the largest image side (65536)
//!   neighbouring pixels are 2.7e-14 rad apart, 240 times that;
//! - the lens radius (aperture, or the `.scn` square lens's size), in `[0, MAX_APERTURE]`: a lens
//!   point is a camera position, within the coordinate limit of the eye;
//! - the focus distance, in `(0, MAX_FOCUS_DISTANCE]`: no two points of the world are farther
//!   apart (2 * sqrt(3) * 1e18 < 4e18), and the focus point stays an ordinary `f64`;
//! - an orthographic view height, positive and at least `MIN_ORTHO_HEIGHT` times the largest
//!   coordinate of the camera position (the `f64` image plane then resolves 1/65536 of it with
//!   a margin of 100), and at most `MAX_ORTHO_HEIGHT`.
//!
//! Every ray lumis makes itself stays inside: camera rays by the checks above, secondary rays
//! because they start at surface points within the coordinate limit (offset by a few ulps) and
//! go along unit directions (reflection, refraction) or towards a light at a non-zero distance.

use super::limits::MAX_COORDINATE;
use crate::camera::{Camera, Lens};
use crate::math::Vec3;

/// Smallest field of view, in degrees.
pub const MIN_FOV_DEG: f64 = 1e-7;
/// Largest lens radius or square lens size, in world units.
pub const MAX_APERTURE: f32 = MAX_COORDINATE;
/// Largest focus distance, in world units.
pub const MAX_FOCUS_DISTANCE: f32 = 4.0 * MAX_COORDINATE;
/// Smallest orthographic view height, relative to the camera position's largest coordinate.
pub const MIN_ORTHO_HEIGHT: f64 = 1e-9;
/// Largest orthographic view height: twice the coordinate limit spans the whole world.
pub const MAX_ORTHO_HEIGHT: f32 = 2.0 * MAX_COORDINATE;

/// Why a ray is outside the domain.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum RayError {
    /// A NaN or infinite origin component.
    #[error("origin {} is not finite; origins must be finite (any magnitude)", sci(*.0))]
    Origin(Vec3),
    /// A NaN, infinite or all-zero direction.
    #[error("direction {} is {}; directions must be finite and non-zero (any length)", sci(*.0), what_dir(*.0))]
    Direction(Vec3),
    /// A NaN end of the interval.
    #[error("t_min {0} or t_max {1} is NaN; they must be numbers (infinities allowed)")]
    Interval(f32, f32),
}

/// Why the ray `origin + t dir`, `t` in `(t_min, t_max]`, is outside the domain.
pub fn check_ray(origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Result<(), RayError> {
    if !origin.is_finite() {
        return Err(RayError::Origin(origin));
    }
    if !dir.is_finite() || dir == Vec3::ZERO {
        return Err(RayError::Direction(dir));
    }
    if t_min.is_nan() || t_max.is_nan() {
        return Err(RayError::Interval(t_min, t_max));
    }
    Ok(())
}

/// Why `camera` is outside the domain (the message names the value and its range).
pub fn check_camera(camera: &Camera) -> Result<(), String> {
    let p = camera.position();
    if !p.is_finite() || p.abs().max_element() > MAX_COORDINATE {
        return Err(format!(
            "position {} exceeds the coordinate limit |x| <= {MAX_COORDINATE:e}",
            sci(p)
        ));
    }
    if let Some(height) = camera.ortho_height() {
        let min = MIN_ORTHO_HEIGHT * p.abs().max_element() as f64;
        if !(height as f64 >= min && height > 0.0 && height <= MAX_ORTHO_HEIGHT) {
            return Err(format!(
                "orthographic height {height:e} is outside the supported range \
                 [{min:e} ({MIN_ORTHO_HEIGHT:e} x the position's largest coordinate), \
                 {MAX_ORTHO_HEIGHT:e}]"
            ));
        }
        return Ok(());
    }
    let fov = camera.fov_degrees();
    if !(MIN_FOV_DEG..180.0).contains(&fov) {
        return Err(format!(
            "field of view {:e} degrees is outside the supported range [{MIN_FOV_DEG:e}, 180)",
            fov as f32
        ));
    }
    let (what, size) = match camera.lens() {
        Lens::Pinhole => ("aperture", 0.0),
        Lens::Disk(r) => ("aperture", r),
        Lens::Square(s) => ("lens size", s),
    };
    if !(0.0..=MAX_APERTURE).contains(&size) {
        return Err(format!(
            "{what} {size:e} is outside the supported range [0, {MAX_APERTURE:e}]"
        ));
    }
    let focus = camera.focus_distance();
    if !(focus > 0.0 && focus <= MAX_FOCUS_DISTANCE) {
        return Err(format!(
            "focus distance {focus:e} is outside the supported range (0, {MAX_FOCUS_DISTANCE:e}]"
        ));
    }
    Ok(())
}

/// `[x, y, z]` in scientific notation.
fn sci(p: Vec3) -> String {
    format!("[{:e}, {:e}, {:e}]", p.x, p.y, p.z)
}

fn what_dir(d: Vec3) -> &'static str {
    if d.is_nan() {
        "NaN"
    } else if !d.is_finite() {
        "infinite"
    } else {
        "zero"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_of_any_finite_origin_and_direction_are_in_the_domain() {
        let ok = |o: Vec3, d: Vec3, a: f32, b: f32| check_ray(o, d, a, b).is_ok();
        assert!(ok(Vec3::splat(f32::MAX), Vec3::X, 0.0, f32::INFINITY));
        assert!(ok(
            Vec3::ZERO,
            Vec3::new(f32::from_bits(1), 0.0, 0.0),
            -1e30,
            5.0
        ));
        assert!(ok(
            Vec3::ZERO,
            Vec3::X,
            f32::NEG_INFINITY,
            f32::NEG_INFINITY
        ));
        let err = |o: Vec3, d: Vec3, a: f32, b: f32| check_ray(o, d, a, b).unwrap_err().to_string();
        assert_eq!(
            err(Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::X, 0.0, 1.0),
            "origin [inf, 0e0, 0e0] is not finite; origins must be finite (any magnitude)"
        );
        assert!(err(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0).contains("is zero; directions must be"));
        assert!(err(Vec3::ZERO, Vec3::NAN, 0.0, 1.0).contains("is NaN"));
        assert!(err(Vec3::ZERO, Vec3::X, f32::NAN, 1.0).contains("NaN"));
    }

    #[test]
    fn camera_values_outside_their_ranges_are_refused_with_the_range() {
        let cam = |fov: f32, aperture: f32, focus: Option<f32>| {
            Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, fov, aperture, focus).unwrap()
        };
        assert!(check_camera(&cam(40.0, 0.1, None)).is_ok());
        assert!(check_camera(&cam(1.5e-7, 1e18, Some(4e18))).is_ok());
        let e = check_camera(&cam(40.0, 1e30, None)).unwrap_err();
        assert_eq!(e, "aperture 1e30 is outside the supported range [0, 1e18]");
        assert!(
            check_camera(&cam(5e-8, 0.0, None))
                .unwrap_err()
                .contains("[1e-7, 180)")
        );
        assert!(
            check_camera(&cam(40.0, 0.1, Some(1e19)))
                .unwrap_err()
                .contains("focus")
        );
        let ortho = Camera::orthographic(Vec3::new(0.0, 0.0, 1e10), Vec3::ZERO, Vec3::Y, 10.0);
        assert!(check_camera(&ortho.unwrap()).is_ok());
        let ortho = Camera::orthographic(Vec3::new(0.0, 0.0, 1e10), Vec3::ZERO, Vec3::Y, 9.0);
        assert!(
            check_camera(&ortho.unwrap())
                .unwrap_err()
                .contains("orthographic height")
        );
    }
}

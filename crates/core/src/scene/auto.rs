//! Automatic camera and lights for scenes that bring none (a bare OBJ, a TOML file without
//! `[camera]`, a glTF file without cameras or lights): a three-quarter view framing the bounds,
//! a key/fill light rig placed relative to the camera actually used, and the up axis a model
//! is turned to before either is chosen.

use crate::camera::Camera;
use crate::light::Light;
use crate::math::{Aabb, Mat4, Vec3};

/// Vertical field of view of the automatic camera, degrees.
const AUTO_FOV: f32 = 40.0;

/// Which model axis points up (`--up`). lumis scenes are Y-up; a Z-up model (many CAD and
/// Blender exports to OBJ) is turned so that its +Z becomes +Y.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UpAxis {
    /// +Y is up (glTF's convention, and the default).
    #[default]
    Y,
    /// +Z is up: the model is turned -90 degrees about X, so +Z goes to +Y and -Y (the usual
    /// front of a Z-up model) to +Z.
    Z,
}

impl UpAxis {
    /// Both axes, in documentation order.
    pub const ALL: [UpAxis; 2] = [UpAxis::Y, UpAxis::Z];

    /// The name used on the command line (`--up`) and in Python (`up=`).
    pub fn name(self) -> &'static str {
        match self {
            UpAxis::Y => "y",
            UpAxis::Z => "z",
        }
    }

    /// Model space to lumis's Y-up world.
    pub fn to_y_up(self) -> Mat4 {
        match self {
            UpAxis::Y => Mat4::IDENTITY,
            // Exact: (x, y, z) -> (x, z, -y), no rounding from a sine and cosine.
            UpAxis::Z => Mat4::from_cols(
                Vec3::X.extend(0.0),
                (-Vec3::Z).extend(0.0),
                Vec3::Y.extend(0.0),
                glam::Vec4::W,
            ),
        }
    }
}

impl std::str::FromStr for UpAxis {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        UpAxis::ALL
            .into_iter()
            .find(|a| a.name() == s)
            .ok_or_else(|| format!("unknown up axis {s:?}; expected y or z"))
    }
}

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

/// A warm key point light behind-above-left of `camera` (seen from the bounds), bright enough
/// that a white Lambert surface facing it has radiance about 1, plus a cool directional fill
/// from the camera's right. Placed relative to the camera so that whatever a file's camera
/// looks at is lit on the side it sees.
pub fn default_rig(bounds: Aabb, camera: &Camera) -> [Light; 2] {
    let (center, radius) = bounding_sphere(bounds);
    let (right, up) = (camera.right(), camera.up());
    // Towards the camera from the model; for an orthographic camera the view direction.
    let back = if camera.is_orthographic() {
        -camera.forward()
    } else {
        (camera.position() - center)
            .try_normalize()
            .unwrap_or(-camera.forward())
    };
    let key = (back * 1.5 + up * 2.0 - right * 1.2).normalize_or(back);
    let position = center + key * (radius * 4.0);
    let d2 = (position - center).length_squared();
    let fill = (-back * 0.5 - up * 0.6 - right).normalize_or(-back);
    [
        Light::Point {
            position,
            intensity: Vec3::new(1.0, 0.95, 0.85) * (std::f32::consts::PI * d2),
        },
        Light::Directional {
            direction: fill,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_up_turns_z_to_y_and_front_to_the_viewer() {
        let m = UpAxis::Z.to_y_up();
        assert_eq!(m.transform_vector3(Vec3::Z), Vec3::Y);
        assert_eq!(m.transform_vector3(-Vec3::Y), Vec3::Z);
        assert_eq!(m.transform_vector3(Vec3::X), Vec3::X);
    }

    #[test]
    fn the_key_light_sits_on_the_camera_side() {
        let bounds = Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        for eye in [Vec3::new(0.0, 0.0, -8.0), Vec3::new(6.0, 1.0, 3.0)] {
            let camera = Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 40.0, 0.0, None).unwrap();
            let [Light::Point { position, .. }, _] = default_rig(bounds, &camera) else {
                panic!("the key is a point light");
            };
            assert!(position.dot(eye) > 0.0, "key {position} vs eye {eye}");
        }
    }
}

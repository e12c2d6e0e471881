//! The `.scn` camera statements (`cameraPosition`, `cameraLookAt`, `cameraUp`,
//! `cameraScreenWidth`, `dispersion`) and their defaults, turned into a lumis [`Camera`].

use lumis_core::camera::{Camera, CameraError, FovAxis, Lens};
use lumis_core::math::Vec3;

/// The original's `dispersion` when a scene does not set it (its `RayTracer` constructor): depth
/// of field is on unless a scene turns it off.
pub(super) const DEFAULT_DISPERSION: f32 = 5.0;

/// The camera statements as read, before they are checked and combined.
pub(super) struct CameraSpec {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub screen_width: f32,
    pub dispersion: f32,
}

impl Default for CameraSpec {
    /// The original's camera before any statement: at the origin looking down -z, up +y, and
    /// 1920 wide (its default image width, so one world unit per two pixels).
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            look_at: -Vec3::Z,
            up: Vec3::Y,
            screen_width: 1920.0,
            dispersion: DEFAULT_DISPERSION,
        }
    }
}

impl CameraSpec {
    /// The lens `dispersion` asks for. Positive: origins jitter by `[0, d)` along the camera's
    /// right and up axes (the original moves them along world x and y, which only matches for a
    /// camera looking down -z; lumis does not copy that). Negative: no depth of field, one ray
    /// per sample, as the original. Zero: the original traces `depthComplexity` identical rays,
    /// which average to the pinhole image, so lumis traces one.
    pub fn lens(&self) -> Lens {
        if self.dispersion > 0.0 {
            Lens::Square(self.dispersion)
        } else {
            Lens::Pinhole
        }
    }

    /// The original maps column x of W to `(x - W/2)/2 * (w/W)` on the image plane through the
    /// look-at point: half the visible width there is `w / 4`.
    pub fn build(&self) -> Result<Camera, CameraError> {
        let distance = (self.look_at - self.position).length();
        let half_fov = (self.screen_width * 0.25 / distance.max(f32::MIN_POSITIVE)).atan();
        Ok(Camera::look_at(
            self.position,
            self.look_at,
            self.up,
            2.0 * half_fov.to_degrees(),
            0.0,
            None,
        )?
        .with_fov_axis(FovAxis::Horizontal)
        .with_lens(self.lens()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispersion_sign_picks_the_lens() {
        let spec = |dispersion| CameraSpec {
            dispersion,
            ..CameraSpec::default()
        };
        assert_eq!(CameraSpec::default().lens(), Lens::Square(5.0));
        assert_eq!(spec(2.0).lens(), Lens::Square(2.0));
        assert_eq!(spec(0.0).lens(), Lens::Pinhole);
        assert_eq!(spec(-1.0).lens(), Lens::Pinhole);
        assert!(CameraSpec::default().build().unwrap().has_depth_of_field());
        assert!(!spec(-1.0).build().unwrap().has_depth_of_field());
    }
}

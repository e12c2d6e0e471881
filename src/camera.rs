//! Look-at perspective camera with a thin lens for depth of field.
//!
//! ```toml
//! [camera]
//! position = [0.0, 2.0, 8.0]
//! look_at = [0.0, 1.0, 0.0]
//! up = [0.0, 1.0, 0.0]
//! fov = 40.0            # vertical field of view, degrees
//! aperture = 0.05       # lens radius (0: pinhole)
//! focus_distance = 8.0  # distance to the plane in focus (default: |look_at - position|)
//! ```

use crate::math::{Mat4, Ray, Vec2, Vec3, Vec4};

/// A perspective camera in world space. Image `x` grows right and `y` grows down.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    position: Vec3,
    /// Unit view direction.
    forward: Vec3,
    /// Unit right vector of the image.
    right: Vec3,
    /// Unit up vector of the image.
    up: Vec3,
    /// `tan(fov / 2)` along `fov_axis`.
    tan_half_fov: f32,
    fov_axis: FovAxis,
    lens: Lens,
    focus_distance: f32,
}

/// Which image axis the field of view spans; the other follows from the aspect ratio.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    /// The usual convention (pbrt's for landscape images, Blender's "vertical" fit).
    Vertical,
    /// The `.scn` convention: `cameraScreenWidth` fixes the horizontal extent.
    Horizontal,
}

/// The lens aperture shape, in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lens {
    /// No depth of field.
    Pinhole,
    /// A thin lens of this radius.
    Disk(f32),
    /// The `.scn` "dispersion": the ray origin moves by `[0, size)` along right and up.
    Square(f32),
}

/// Why a camera could not be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CameraError {
    /// `look_at` equals `position`.
    #[error("camera position and look_at coincide")]
    NoViewDirection,
    /// `up` is parallel to the view direction.
    #[error("camera up vector is parallel to the view direction")]
    UpParallel,
    /// Field of view outside (0, 180) degrees.
    #[error("field of view {0} must lie strictly between 0 and 180 degrees")]
    BadFov(f32),
    /// Negative aperture or non-positive focus distance.
    #[error("aperture must be >= 0 and focus distance > 0")]
    BadLens,
}

impl Camera {
    /// A camera at `position` looking at `look_at`, vertical field of view `fov_deg`, lens
    /// radius `aperture` focused at `focus_distance` (`None`: the look-at distance).
    pub fn look_at(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        fov_deg: f32,
        aperture: f32,
        focus_distance: Option<f32>,
    ) -> Result<Self, CameraError> {
        let view = look_at - position;
        let forward = view.try_normalize().ok_or(CameraError::NoViewDirection)?;
        let right = forward
            .cross(up)
            .try_normalize()
            .ok_or(CameraError::UpParallel)?;
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return Err(CameraError::BadFov(fov_deg));
        }
        let focus_distance = focus_distance.unwrap_or(view.length());
        if !(aperture >= 0.0 && focus_distance > 0.0 && focus_distance.is_finite()) {
            return Err(CameraError::BadLens);
        }
        let lens = if aperture > 0.0 {
            Lens::Disk(aperture)
        } else {
            Lens::Pinhole
        };
        Ok(Self {
            position,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov: (fov_deg.to_radians() * 0.5).tan(),
            fov_axis: FovAxis::Vertical,
            lens,
            focus_distance,
        })
    }

    /// The same camera with its field of view measured along `axis`.
    pub fn with_fov_axis(mut self, axis: FovAxis) -> Self {
        self.fov_axis = axis;
        self
    }

    /// The same camera with another lens (the focus distance is kept).
    pub fn with_lens(mut self, lens: Lens) -> Self {
        self.lens = lens;
        self
    }

    /// `tan` of the half field of view along x and y for a `width x height` image.
    fn tan_half_xy(&self, width: u32, height: u32) -> (f32, f32) {
        let aspect = width as f32 / height as f32;
        match self.fov_axis {
            FovAxis::Vertical => (self.tan_half_fov * aspect, self.tan_half_fov),
            FovAxis::Horizontal => (self.tan_half_fov, self.tan_half_fov / aspect),
        }
    }

    /// The lens.
    pub fn lens(&self) -> Lens {
        self.lens
    }

    /// Camera position.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// True when the lens has a non-zero radius.
    pub fn has_depth_of_field(&self) -> bool {
        !matches!(
            self.lens,
            Lens::Pinhole | Lens::Disk(0.0) | Lens::Square(0.0)
        )
    }

    /// The ray through film position `film` (pixels, `(0,0)` = top-left corner of the image,
    /// `(w,h)` = bottom-right) from lens sample `lens` in `[0,1)^2`.
    pub fn ray(&self, film: Vec2, width: u32, height: u32, lens: Vec2) -> Ray {
        let dir = self.pinhole_dir(film, width, height);
        let d = match self.lens {
            Lens::Pinhole => return Ray::new(self.position, dir),
            Lens::Disk(radius) => concentric_disk(lens) * radius,
            Lens::Square(size) => lens * size,
        };
        // Thin lens: every ray through the lens meets the pinhole ray on the focus plane.
        let focus = self.position + dir * (self.focus_distance / dir.dot(self.forward));
        let origin = self.position + self.right * d.x + self.up * d.y;
        Ray::new(origin, (focus - origin).normalize())
    }

    /// Unit direction of the pinhole ray through a film position (see [`Camera::ray`]).
    pub fn pinhole_dir(&self, film: Vec2, width: u32, height: u32) -> Vec3 {
        let (tx, ty) = self.tan_half_xy(width, height);
        let sx = (2.0 * film.x / width as f32 - 1.0) * tx;
        let sy = (1.0 - 2.0 * film.y / height as f32) * ty;
        (self.forward + self.right * sx + self.up * sy).normalize()
    }

    /// OpenEXR `worldToCamera`: world to a left-handed camera space with +x right, +y up and
    /// +z the view direction. Column-vector form; EXR stores it transposed (row vectors).
    pub fn world_to_camera(&self) -> Mat4 {
        let cam_to_world = Mat4::from_cols(
            self.right.extend(0.0),
            self.up.extend(0.0),
            self.forward.extend(0.0),
            self.position.extend(1.0),
        );
        cam_to_world.inverse()
    }

    /// OpenEXR `worldToNDC`: world to normalised device coordinates after the homogeneous divide,
    /// `(0,0)` the top-left and `(1,1)` the bottom-right corner of the display window, `z` the
    /// reciprocal of the camera-space depth. Column-vector form.
    pub fn world_to_ndc(&self, width: u32, height: u32) -> Mat4 {
        let (tx, ty) = self.tan_half_xy(width, height);
        let (sx, sy) = (1.0 / tx, 1.0 / ty);
        // Camera (x, y, z) -> clip (x', y', z', w) with ndc = clip.xyz / z.
        let cam_to_ndc = Mat4::from_cols(
            Vec4::new(0.5 * sx, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -0.5 * sy, 0.0, 0.0),
            Vec4::new(0.5, 0.5, 0.0, 1.0),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
        );
        cam_to_ndc * self.world_to_camera()
    }
}

/// Maps `[0,1)^2` onto the unit disk preserving area (Shirley-Chiu concentric mapping).
fn concentric_disk(u: Vec2) -> Vec2 {
    let o = u * 2.0 - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, std::f32::consts::FRAC_PI_4 * (o.y / o.x))
    } else {
        (
            o.y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (o.x / o.y),
        )
    };
    Vec2::new(theta.cos(), theta.sin()) * r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera::look_at(
            Vec3::new(1.0, 2.0, 5.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::Y,
            50.0,
            0.0,
            None,
        )
        .unwrap()
    }

    #[test]
    fn world_to_ndc_maps_a_ray_point_back_to_its_pixel() {
        let c = cam();
        let (w, h) = (64, 48);
        let m = c.world_to_ndc(w, h);
        for film in [
            Vec2::new(10.5, 7.5),
            Vec2::new(60.25, 40.75),
            Vec2::new(32.0, 24.0),
        ] {
            let p = c.ray(film, w, h, Vec2::ZERO).at(3.7);
            let q = m * p.extend(1.0);
            let ndc = q.truncate() / q.w;
            assert!(
                (ndc.x * w as f32 - film.x).abs() < 1e-3,
                "{ndc:?} vs {film:?}"
            );
            assert!(
                (ndc.y * h as f32 - film.y).abs() < 1e-3,
                "{ndc:?} vs {film:?}"
            );
        }
    }

    #[test]
    fn thin_lens_rays_converge_on_the_focus_plane() {
        let c = Camera::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 40.0, 0.5, Some(4.0)).unwrap();
        let film = Vec2::new(20.0, 10.0);
        let a = c.ray(film, 64, 32, Vec2::new(0.1, 0.9));
        let b = c.ray(film, 64, 32, Vec2::new(0.8, 0.3));
        let pa = a.at((4.0 - 0.0) / -a.dir.z);
        let pb = b.at(4.0 / -b.dir.z);
        assert!((pa - pb).length() < 1e-4, "{pa} vs {pb}");
    }

    #[test]
    fn rejects_degenerate_setups() {
        assert_eq!(
            Camera::look_at(Vec3::ONE, Vec3::ONE, Vec3::Y, 40.0, 0.0, None),
            Err(CameraError::NoViewDirection)
        );
        assert_eq!(
            Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 40.0, 0.0, None),
            Err(CameraError::UpParallel)
        );
        assert_eq!(
            Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 180.0, 0.0, None),
            Err(CameraError::BadFov(180.0))
        );
    }
}

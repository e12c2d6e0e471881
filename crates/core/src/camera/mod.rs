//! Look-at perspective camera with a thin lens for depth of field, and an orthographic camera.
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
//!
//! An orthographic camera sends parallel rays along the view direction from the plane through
//! `position` perpendicular to it; the width it spans follows from the image's aspect ratio. It
//! has no lens.
//!
//! ```toml
//! [camera]
//! type = "orthographic"
//! position = [0.0, 0.0, 10.0]
//! look_at = [0.0, 0.0, 0.0]
//! height = 4.0          # world-space height the image spans
//! ```
//!
//! # Precision
//!
//! The basis (`forward`, `right`, `up`) and `tan(fov / 2)` are built and held in `f64`. A pixel's
//! ray is formed in camera space as `(sx, sy, 1)` in `f64`, taken to world space and normalised
//! in `f64`; thin-lens rays aim from their lens point at the `f64` focus point. What is rounded
//! to `f32`, and where, decides what survives:
//!
//! * **Near the scene** (the eye or lens point inside the scene's near region, see
//!   [`crate::accel::RayFrame`]: every ordinary view) the origin and the direction are rounded
//!   as they are, each component correctly. A unit `f32` direction turns only in steps of
//!   `ulp(d_i)`, `2^-24..2^-23` of a component, which from a few scene sizes away is far below
//!   a pixel.
//! * **Far from the scene** the ray is formed in `f64` and moved along itself to near the
//!   scene's bounds (in double-double) before anything is rounded: the origin is then rounded
//!   on the scene's grid and the direction's rounding acts over the scene's size only, so a
//!   unit sphere seen from 1e8 along an oblique axis with a field of view of 1.4e-6 degrees
//!   (3.8e-10 rad a pixel, where ~150 pixels share each `f32` direction from the eye) is
//!   resolved pixel for pixel (`tests/hard_cases/camera.rs`).
//! * **Limits** ([`crate::scene::domain`]): the field of view is at least 1e-7 degrees, where
//!   neighbouring pixels of the largest image are still 240 times the `f64` basis's resolution
//!   apart; lens radius and focus distance are bounded by the world's size.
//! * **Matrices.** `world_to_camera` / `world_to_ndc` are computed in `f64` but stored as `f32`
//!   (the EXR header's M44f): their translation `-R p` keeps only ~7 digits, so reprojecting
//!   through them far from the origin is good to `ulp(|p|)` in camera space, not to a pixel.

use crate::accel::{Framing, RayFrame};
use crate::math::{Mat4, Ray, Vec2, Vec3};
use glam::{DMat4, DVec3, DVec4};

/// A perspective camera in world space. Image `x` grows right and `y` grows down.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    position: Vec3,
    /// Unit view direction (f64: f32 would quantise tiny fields of view, see the module docs).
    forward: DVec3,
    /// Unit right vector of the image.
    right: DVec3,
    /// Unit up vector of the image.
    up: DVec3,
    /// `tan(fov / 2)` along `fov_axis`.
    tan_half_fov: f64,
    fov_axis: FovAxis,
    lens: Lens,
    focus_distance: f64,
    /// `Some(half height)` of the view in world units for an orthographic camera.
    ortho_half_height: Option<f64>,
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
    /// An orthographic view height that is not a positive finite number.
    #[error("orthographic view height {0} must be a positive finite number")]
    BadHeight(f32),
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
        // f32 inputs differ exactly in f64 (unless their exponents are 29+ apart).
        let view = look_at.as_dvec3() - position.as_dvec3();
        let forward = view.try_normalize().ok_or(CameraError::NoViewDirection)?;
        let right = forward
            .cross(up.as_dvec3())
            .try_normalize()
            .ok_or(CameraError::UpParallel)?;
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return Err(CameraError::BadFov(fov_deg));
        }
        let focus_distance = focus_distance.unwrap_or(view.length() as f32);
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
            tan_half_fov: ((fov_deg as f64).to_radians() * 0.5).tan(),
            fov_axis: FovAxis::Vertical,
            lens,
            focus_distance: focus_distance as f64,
            ortho_half_height: None,
        })
    }

    /// An orthographic camera at `position` looking at `look_at` whose image spans `height`
    /// world units vertically (the width follows from the image's aspect ratio).
    pub fn orthographic(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        height: f32,
    ) -> Result<Self, CameraError> {
        if !(height > 0.0 && height.is_finite()) {
            return Err(CameraError::BadHeight(height));
        }
        let mut c = Self::look_at(position, look_at, up, 90.0, 0.0, None)?;
        c.ortho_half_height = Some(0.5 * height as f64);
        Ok(c)
    }

    /// True for an orthographic camera.
    pub fn is_orthographic(&self) -> bool {
        self.ortho_half_height.is_some()
    }

    /// The same camera with its field of view measured along `axis`.
    pub fn with_fov_axis(mut self, axis: FovAxis) -> Self {
        self.fov_axis = axis;
        self
    }

    /// The same camera with another lens (the focus distance is kept). Orthographic cameras
    /// ignore the lens.
    pub fn with_lens(mut self, lens: Lens) -> Self {
        self.lens = lens;
        self
    }

    /// `tan` of the half field of view along x and y for a `width x height` image.
    /// For an orthographic camera: the half extents of the view in world units.
    fn tan_half_xy(&self, width: u32, height: u32) -> (f64, f64) {
        let aspect = width as f64 / height as f64;
        if let Some(half) = self.ortho_half_height {
            return (half * aspect, half);
        }
        match self.fov_axis {
            FovAxis::Vertical => (self.tan_half_fov * aspect, self.tan_half_fov),
            FovAxis::Horizontal => (self.tan_half_fov, self.tan_half_fov / aspect),
        }
    }

    /// The lens.
    pub fn lens(&self) -> Lens {
        self.lens
    }

    /// The field of view in degrees along its axis (perspective cameras).
    pub fn fov_degrees(&self) -> f64 {
        2.0 * self.tan_half_fov.atan().to_degrees()
    }

    /// The world-space height an orthographic camera's image spans; `None` for perspective.
    pub fn ortho_height(&self) -> Option<f32> {
        self.ortho_half_height.map(|h| (2.0 * h) as f32)
    }

    /// Distance from the lens to the plane in focus (world units).
    pub fn focus_distance(&self) -> f32 {
        self.focus_distance as f32
    }

    /// Camera position.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// Unit view direction, rounded to f32.
    pub fn forward(&self) -> Vec3 {
        self.forward.as_vec3()
    }

    /// Unit up vector of the image, rounded to f32.
    pub fn up(&self) -> Vec3 {
        self.up.as_vec3()
    }

    /// Unit right vector of the image, rounded to f32.
    pub fn right(&self) -> Vec3 {
        self.right.as_vec3()
    }

    /// True when the lens has a non-zero radius.
    pub fn has_depth_of_field(&self) -> bool {
        !self.is_orthographic()
            && !matches!(
                self.lens,
                Lens::Pinhole | Lens::Disk(0.0) | Lens::Square(0.0)
            )
    }

    /// The ray through film position `film` (pixels, `(0,0)` = top-left corner of the image,
    /// `(w,h)` = bottom-right) from lens sample `lens` in `[0,1)^2`, for a scene framed by
    /// `frame` (the accelerator's [`RayFrame`]): when the eye or the lens point lies outside the
    /// scene's near region, the ray is formed in `f64` and starts near the scene instead, so
    /// its direction is rounded to `f32` only there (see the module docs).
    pub fn ray(&self, frame: &RayFrame, film: Vec2, width: u32, height: u32, lens: Vec2) -> Ray {
        if self.is_orthographic() {
            return self.centre_ray(frame, film, width, height);
        }
        let dir = self.pinhole_dir64(film, width, height);
        let d = match self.lens {
            Lens::Pinhole => return framed(frame, self.position.as_dvec3(), dir),
            Lens::Disk(radius) => concentric_disk(lens) * radius,
            Lens::Square(size) => lens * size,
        };
        // Thin lens: every ray through the lens meets the pinhole ray on the focus plane.
        let p = self.position.as_dvec3();
        let focus = p + dir * (self.focus_distance / dir.dot(self.forward));
        let origin = p + self.right * d.x as f64 + self.up * d.y as f64;
        let rounded = origin.as_vec3();
        if frame.holds(rounded) {
            // The direction is aimed from the origin as rounded to f32, so the ray really
            // passes through the focus point.
            let to_focus = (focus - rounded.as_dvec3()).normalize();
            return Ray::new(rounded, to_focus.as_vec3());
        }
        framed(frame, origin, (focus - origin).normalize())
    }

    /// The ray through a film position ignoring the lens: from the eye (perspective) or from the
    /// image plane (orthographic), framed as [`Camera::ray`]. The AOV layers trace it.
    pub fn centre_ray(&self, frame: &RayFrame, film: Vec2, width: u32, height: u32) -> Ray {
        if self.is_orthographic() {
            let (hx, hy) = self.tan_half_xy(width, height);
            let sx = (2.0 * film.x as f64 / width as f64 - 1.0) * hx;
            let sy = (1.0 - 2.0 * film.y as f64 / height as f64) * hy;
            let origin = self.position.as_dvec3() + self.right * sx + self.up * sy;
            return framed(frame, origin, self.forward);
        }
        framed(
            frame,
            self.position.as_dvec3(),
            self.pinhole_dir64(film, width, height),
        )
    }

    /// Unit direction of the pinhole ray through a film position (see [`Camera::ray`]); the
    /// view direction for an orthographic camera.
    /// Formed in f64 and rounded once, so it is the f32 direction nearest to the exact one.
    pub fn pinhole_dir(&self, film: Vec2, width: u32, height: u32) -> Vec3 {
        self.pinhole_dir64(film, width, height).as_vec3()
    }

    /// The camera-space direction `(sx, sy, 1)` taken to world space and normalised, in f64.
    fn pinhole_dir64(&self, film: Vec2, width: u32, height: u32) -> DVec3 {
        if self.is_orthographic() {
            return self.forward;
        }
        let (tx, ty) = self.tan_half_xy(width, height);
        let sx = (2.0 * film.x as f64 / width as f64 - 1.0) * tx;
        let sy = (1.0 - 2.0 * film.y as f64 / height as f64) * ty;
        (self.forward + self.right * sx + self.up * sy).normalize()
    }

    /// OpenEXR `worldToCamera`: world to a left-handed camera space with +x right, +y up and
    /// +z the view direction. Column-vector form; EXR stores it transposed (row vectors).
    /// Computed in f64 (the transpose of the orthonormal basis, translation `-R p`), rounded once.
    pub fn world_to_camera(&self) -> Mat4 {
        self.world_to_camera64().as_mat4()
    }

    fn world_to_camera64(&self) -> DMat4 {
        let (r, u, f, p) = (self.right, self.up, self.forward, self.position.as_dvec3());
        DMat4::from_cols(
            DVec4::new(r.x, u.x, f.x, 0.0),
            DVec4::new(r.y, u.y, f.y, 0.0),
            DVec4::new(r.z, u.z, f.z, 0.0),
            DVec4::new(-r.dot(p), -u.dot(p), -f.dot(p), 1.0),
        )
    }

    /// OpenEXR `worldToNDC`: world to normalised device coordinates after the homogeneous divide,
    /// `(0,0)` the top-left and `(1,1)` the bottom-right corner of the display window, `z` the
    /// reciprocal of the camera-space depth (orthographic: the depth itself, no divide).
    /// Column-vector form.
    pub fn world_to_ndc(&self, width: u32, height: u32) -> Mat4 {
        let (tx, ty) = self.tan_half_xy(width, height);
        let (sx, sy) = (1.0 / tx, 1.0 / ty);
        if self.is_orthographic() {
            let cam_to_ndc = DMat4::from_cols(
                DVec4::new(0.5 * sx, 0.0, 0.0, 0.0),
                DVec4::new(0.0, -0.5 * sy, 0.0, 0.0),
                DVec4::new(0.0, 0.0, 1.0, 0.0),
                DVec4::new(0.5, 0.5, 0.0, 1.0),
            );
            return (cam_to_ndc * self.world_to_camera64()).as_mat4();
        }
        // Camera (x, y, z) -> clip (x', y', z', w) with ndc = clip.xyz / z.
        let cam_to_ndc = DMat4::from_cols(
            DVec4::new(0.5 * sx, 0.0, 0.0, 0.0),
            DVec4::new(0.0, -0.5 * sy, 0.0, 0.0),
            DVec4::new(0.5, 0.5, 0.0, 1.0),
            DVec4::new(0.0, 0.0, 1.0, 0.0),
        );
        (cam_to_ndc * self.world_to_camera64()).as_mat4()
    }
}

/// The `f32` ray for the `f64` ray `origin + t dir` (`t > 0`, `dir` unit): rounded as it is
/// when its origin lies in `frame`'s near region, else moved near the scene before the
/// direction is rounded; a ray whose line misses the scene gets an empty interval.
fn framed(frame: &RayFrame, origin: DVec3, dir: DVec3) -> Ray {
    match frame.frame_f64(origin, dir) {
        Framing::AsGiven => Ray::new(origin.as_vec3(), dir.as_vec3()),
        Framing::Moved(m) => m.ray,
        Framing::Miss => Ray::segment(origin.as_vec3(), dir.as_vec3(), 0.0),
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
mod tests;

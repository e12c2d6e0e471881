//! The camera as the EXR header records it: the standard `worldToCamera` and `worldToNDC`
//! M44f attributes and, with depth of field, the standard `focus` and the lens
//! (`lumis/lensRadius` or `lumis/lensSquareSize`).
//!
//! The writer takes these numbers rather than a [`Camera`], so that a file can be written
//! again from what its header says (`lumis merge` has no scene, hence no camera).

use ::exr::meta::header::Header;
use ::exr::prelude::{AttributeValue, Text};

use super::{ATTR_LENS_RADIUS, ATTR_LENS_SQUARE};
use lumis_core::camera::{Camera, Lens};
use lumis_core::math::Mat4;

/// What the EXR header says of the camera that rendered the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExrCamera {
    /// World to camera space (camera looks down -Z), as [`Camera::world_to_camera`].
    pub world_to_camera: Mat4,
    /// World to normalized device coordinates of the full image, as [`Camera::world_to_ndc`].
    pub world_to_ndc: Mat4,
    /// The distance to the plane in focus (scene units) when the camera has depth of field;
    /// `None` writes no lens attributes at all.
    pub focus: Option<f32>,
    /// The lens aperture, written only with depth of field.
    pub lens: Lens,
}

impl ExrCamera {
    /// The header's view of `camera` for a `full_width x full_height` image (the full image,
    /// also for a crop: the matrices are the display window's).
    pub fn new(camera: &Camera, full_width: u32, full_height: u32) -> Self {
        Self {
            world_to_camera: camera.world_to_camera(),
            world_to_ndc: camera.world_to_ndc(full_width, full_height),
            focus: camera.has_depth_of_field().then(|| camera.focus_distance()),
            lens: camera.lens(),
        }
    }

    /// The camera `header` records; an error names what is missing.
    pub(super) fn read(header: &Header) -> Result<Self, String> {
        let attributes = &header.own_attributes;
        let matrix = |m: Option<[f32; 16]>, name: &str| {
            m.map(|m| Mat4::from_cols_array(&m))
                .ok_or_else(|| format!("no {name} attribute: not an EXR lumis wrote"))
        };
        let float = |name: &str| match attributes.other.get(&Text::from(name)) {
            Some(AttributeValue::F32(v)) => Some(*v),
            _ => None,
        };
        let lens = match (float(ATTR_LENS_RADIUS), float(ATTR_LENS_SQUARE)) {
            (Some(r), None) => Lens::Disk(r),
            (None, Some(s)) => Lens::Square(s),
            _ => Lens::Pinhole,
        };
        Ok(Self {
            world_to_camera: matrix(attributes.world_to_camera, "worldToCamera")?,
            world_to_ndc: matrix(attributes.world_to_normalized_device, "worldToNDC")?,
            focus: attributes.focus,
            lens,
        })
    }
}

/// The OpenEXR/Imath M44f memory layout of a glam column-vector matrix.
///
/// Imath multiplies row vectors (`p' = p * M`) and stores `M` row-major, so the EXR matrix is
/// the transpose of glam's `M`; row-major storage of the transpose is exactly glam's
/// column-major array. The exr crate writes the 16 floats in array order, unchanged, and
/// [`Mat4::from_cols_array`] reads them back bit for bit.
pub fn imath_m44f(m: Mat4) -> [f32; 16] {
    m.to_cols_array()
}

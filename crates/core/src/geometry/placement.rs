//! [`Placement`]: an affine map of a prototype's object space into the world, with what
//! instance queries need of it (see `super::instance` for how rays use it).

use glam::{DAffine3, DMat3, DVec3};

use super::surface::rounded_with_error;
use crate::math::{Aabb, Ray, Vec3, f32_down, f32_up};
use glam::Vec3A;

/// Relative growth of an instance's world box beyond the exact image of its prototype's box:
/// covers the object-space ray's rounding (half an ulp of origin and direction, carried
/// through a placement of moderate condition), which moves the tested point by far less.
const BOX_GROWTH: f64 = 1.0 / (1u64 << 18) as f64;

/// Why a placement cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlacementError {
    /// A matrix or translation entry is NaN or infinite.
    #[error("the transform has a non-finite entry")]
    NonFinite,
    /// The linear part cannot be inverted (a zero scale, or collapsed axes).
    #[error(
        "the transform is singular (determinant {determinant:e}): it flattens the mesh and has no inverse"
    )]
    Singular {
        /// The linear part's determinant.
        determinant: f64,
    },
}

/// True when `to_world` maps every surface onto a line or a point (its linear part has rank 1
/// or 0: every 2x2 minor, so every cross product of two columns, is zero), which no ray can
/// hit: glTF's way of hiding a mesh with a zero scale. Loaders draw nothing for it, instanced
/// or flattened alike.
pub fn leaves_no_area(to_world: &DAffine3) -> bool {
    let m = to_world.matrix3;
    let [x, y, z] = [m.x_axis, m.y_axis, m.z_axis];
    [x.cross(y), y.cross(z), z.cross(x)]
        .iter()
        .all(|c| *c == DVec3::ZERO)
}

/// An affine placement of object space into world space, with what its queries need: the
/// inverse for rays, the inverse transpose for normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    to_world: DAffine3,
    to_object: DAffine3,
    /// Inverse transpose of the linear part, for normals.
    normals: DMat3,
    /// The determinant is negative: the placement mirrors.
    mirrors: bool,
}

impl Placement {
    /// The placement `to_world` (object space to world space), refused when it is not finite
    /// or not invertible in `f64` (a scale of 1e-6 on every axis is fine; zero is not).
    pub fn new(to_world: DAffine3) -> Result<Self, PlacementError> {
        if !to_world.is_finite() {
            return Err(PlacementError::NonFinite);
        }
        let determinant = to_world.matrix3.determinant();
        let to_object = to_world.inverse();
        if determinant == 0.0 || !to_object.is_finite() {
            return Err(PlacementError::Singular { determinant });
        }
        Ok(Self {
            to_world,
            to_object,
            normals: to_object.matrix3.transpose(),
            mirrors: determinant < 0.0,
        })
    }

    /// Object space to world space.
    pub fn to_world(&self) -> DAffine3 {
        self.to_world
    }

    /// World space to object space.
    pub(crate) fn world_to_object(&self) -> DAffine3 {
        self.to_object
    }

    /// True when the placement mirrors (negative determinant).
    pub fn mirrors(&self) -> bool {
        self.mirrors
    }

    /// The object-space ray of world ray `ray`: origin and direction transformed in `f64` and
    /// rounded once; the same interval. `None` when the image is not a usable ray (it
    /// overflows `f32`, or the direction rounds to zero).
    #[inline]
    pub fn object_ray(&self, ray: &Ray) -> Option<Ray> {
        let origin = self
            .to_object
            .transform_point3(ray.origin.as_dvec3())
            .as_vec3();
        let dir = self
            .to_object
            .transform_vector3(ray.dir.as_dvec3())
            .as_vec3();
        // One SIMD test for the three conditions (the short-circuit form was six branches
        // on every instance entered).
        let (o, d) = (Vec3A::from(origin), Vec3A::from(dir));
        let usable = (o.is_finite_mask() & d.is_finite_mask()).all() && d.cmpne(Vec3A::ZERO).any();
        usable.then_some(Ray {
            origin,
            dir,
            ..*ray
        })
    }

    /// The world box around the object-space box `b`: the exact image of its corners, rounded
    /// outwards and grown by [`BOX_GROWTH`] of its size and position.
    pub fn world_bounds(&self, b: &Aabb) -> Aabb {
        if b.is_empty() {
            return Aabb::EMPTY;
        }
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for k in 0..8 {
            let pick =
                |bit: usize, min: f32, max: f32| (if k & bit == 0 { min } else { max }) as f64;
            let corner = DVec3::new(
                pick(1, b.min.x, b.max.x),
                pick(2, b.min.y, b.max.y),
                pick(4, b.min.z, b.max.z),
            );
            let w = self.to_world.transform_point3(corner);
            lo = lo.min(w);
            hi = hi.max(w);
        }
        let grow = ((hi - lo).max_element() + lo.abs().max(hi.abs()).max_element()) * BOX_GROWTH;
        Aabb {
            min: (lo - grow).to_array().map(f32_down).into(),
            max: (hi + grow).to_array().map(f32_up).into(),
        }
    }

    /// A world point and its error bound from an object-space point and its bound.
    pub fn world_point(&self, p: Vec3, p_error: Vec3) -> (Vec3, Vec3) {
        let exact = self.to_world.transform_point3(p.as_dvec3());
        let m = self.to_world.matrix3;
        let abs = DMat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
        // The object point's own error, carried through the linear part, and the f64
        // evaluation's rounding (a few ulps of the terms summed).
        let carried = abs * p_error.as_dvec3();
        let terms = abs * p.as_dvec3().abs() + self.to_world.translation.abs();
        rounded_with_error(
            exact,
            carried * (1.0 + 1e-15) + terms * (8.0 * f64::EPSILON),
        )
    }

    /// A unit world normal from an object-space one (inverse transpose; the orientation the
    /// flattened mesh gets).
    pub fn world_normal(&self, n: Vec3) -> Vec3 {
        let w = self.normals * n.as_dvec3();
        let len = w.length();
        if len > 0.0 && len.is_finite() {
            (w / len).as_vec3()
        } else {
            n
        }
    }

    /// A unit world tangent with its handedness (`w`) from an object-space one.
    pub(super) fn world_tangent(&self, t: crate::math::Vec4) -> crate::math::Vec4 {
        let d = self.to_world.matrix3 * t.truncate().as_dvec3();
        let len = d.length();
        let d = if len > 0.0 {
            (d / len).as_vec3()
        } else {
            Vec3::ZERO
        };
        d.extend(if self.mirrors { -t.w } else { t.w })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn only_maps_onto_a_line_or_a_point_leave_no_area() {
        let turn = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let placed = |scale: [f64; 3]| {
            DAffine3::from_scale_rotation_translation(
                DVec3::from(scale),
                turn,
                DVec3::new(5.0, -2.0, 1e3),
            )
        };
        for (scale, none) in [
            ([0.0, 0.0, 0.0], true),
            ([0.0, 2.0, 0.0], true),
            ([3.0, 0.0, 0.0], true),
            ([0.0, 2.0, 1e-30], false),
            ([1.0, 0.0, 1.0], false),
            ([1e-6, 1e-6, 1e-6], false),
            ([1.0, -1.0, 1.0], false),
        ] {
            assert_eq!(leaves_no_area(&placed(scale)), none, "{scale:?}");
        }
        // A singular map of rank 2 (a shear collapsing z onto x and y) keeps area.
        let shear = DAffine3::from_cols(DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0), DVec3::ZERO);
        assert!(Placement::new(shear).is_err() && !leaves_no_area(&shear));
    }
}

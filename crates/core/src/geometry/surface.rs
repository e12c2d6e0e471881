//! What a hit means geometrically: the surface point, its normals and texture coordinates, a
//! bound on the rounding error of the point, and where a ray leaving it must start.

use super::accuracy::Offset;
use crate::math::{Vec2, Vec3, f32_up, offset_ray_origin};
use glam::DVec3;

/// Differential geometry at a hit, in world space.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// The hit point.
    pub p: Vec3,
    /// Unit geometric normal (outward for spheres; winding order for triangles).
    pub ng: Vec3,
    /// Unit shading normal (interpolated for smooth meshes), on the same side as `ng`.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// Barycentric weights of a triangle's second and third vertex (0 for spheres), for the
    /// attributes beyond `uv` (see [`super::Geometry::hit_attributes`]).
    pub bary: Vec2,
    /// Per-component bound on the absolute error of `p` (pbrt's `pError`): how far the computed
    /// point may lie from a point of the true surface, for offsetting secondary rays.
    pub p_error: Vec3,
}

/// The `f32` point nearest to `exact` and a bound on its distance from the true surface point:
/// the rounding to `f32` (known exactly, since `exact` is at hand) plus `slack`, the error of
/// the `f64` evaluation that produced `exact`. Tight where it matters: a coordinate that lands
/// exactly on an `f32` (an axis-aligned plane's height) gets an error bound of ~0.
pub(crate) fn rounded_with_error(exact: DVec3, slack: DVec3) -> (Vec3, Vec3) {
    let p = exact.as_vec3();
    let err = (p.as_dvec3() - exact).abs() + slack;
    // Rounded up, so the f32 bound still covers the f64 one.
    (p, Vec3::new(f32_up(err.x), f32_up(err.y), f32_up(err.z)))
}

impl SurfacePoint {
    /// Origin for a ray leaving this point along `dir` (to the side of the surface `dir` points
    /// to), by the rule `offset`.
    pub fn spawn_origin(&self, dir: Vec3, offset: Offset) -> Vec3 {
        let n = if self.ng.dot(dir) < 0.0 {
            -self.ng
        } else {
            self.ng
        };
        match offset {
            Offset::ErrorBound => self.past_error_bound(n),
            Offset::Ulp => {
                let past_error = self.p + n * self.ng.abs().dot(self.p_error);
                offset_ray_origin(past_error, n, dir)
            }
            Offset::Epsilon(e) => self.p + n * e,
        }
    }

    /// pbrt-v4's `OffsetRayOrigin`: move along `n` by the error bound projected on the normal,
    /// so the true surface lies behind the new point, then one more ulp in each component the
    /// normal has, so rounding the sum to `f32` cannot fall back onto the surface.
    fn past_error_bound(&self, n: Vec3) -> Vec3 {
        let d = n.abs().dot(self.p_error);
        let moved = self.p + n * d;
        let step = |x: f32, n: f32| {
            if n > 0.0 {
                x.next_up()
            } else if n < 0.0 {
                x.next_down()
            } else {
                x
            }
        };
        Vec3::new(step(moved.x, n.x), step(moved.y, n.y), step(moved.z, n.z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_error_is_exact_and_zero_on_representable_coordinates() {
        let exact = DVec3::new(1e6 + 0.3, 2.0, -1e-3);
        let (p, err) = rounded_with_error(exact, DVec3::ZERO);
        assert_eq!(p.y, 2.0);
        assert_eq!(err.y, 0.0);
        assert!(err.x as f64 >= (p.x as f64 - exact.x).abs());
        assert!(
            err.x <= 0.0625 / 2.0,
            "half an ulp of 1e6 at most: {}",
            err.x
        );
    }

    #[test]
    fn error_bound_offset_is_one_ulp_off_an_exact_plane() {
        let s = SurfacePoint {
            p: Vec3::new(1e6, 0.0, -1e6),
            ng: Vec3::Y,
            ns: Vec3::Y,
            uv: Vec2::ZERO,
            bary: Vec2::ZERO,
            p_error: Vec3::new(0.03, 0.0, 0.03),
        };
        let up = s.spawn_origin(Vec3::new(0.3, 1.0, 0.0), Offset::ErrorBound);
        assert_eq!(up, Vec3::new(1e6, f32::from_bits(1), -1e6));
        let down = s.spawn_origin(-Vec3::Y, Offset::ErrorBound);
        assert_eq!(down.y, -f32::from_bits(1));
        // The old fixed-ulp rule and the epsilon rule for comparison.
        assert!(s.spawn_origin(Vec3::Y, Offset::Epsilon(1e-4)).y == 1e-4);
        assert!(s.spawn_origin(Vec3::Y, Offset::Ulp).y > 0.0);
    }
}

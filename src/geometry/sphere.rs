//! Analytic spheres, intersected in a form that stays exact for huge and distant spheres.
//!
//! ```toml
//! [[sphere]]
//! center = [0.0, 1.0, 0.0]
//! radius = 1.0
//! material = "glass"
//! ```

use crate::math::{Aabb, Ray, Vec3};

/// A sphere in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, world space.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: f32,
}

impl Sphere {
    /// Its bounding box.
    pub fn bounds(&self) -> Aabb {
        Aabb::new(
            self.center - Vec3::splat(self.radius),
            self.center + Vec3::splat(self.radius),
        )
    }

    /// The nearest `t` in `(ray.t_min, ray.t_max]` where the ray meets the surface.
    ///
    /// Uses the precision-preserving form of Ray Tracing Gems ch. 7: the discriminant is
    /// `r^2 - |f - (f.d / d.d) d|^2` (distance of the centre from the ray line, not a difference
    /// of two huge squares), and the roots come from `q = -(b + sign(b) sqrt(disc))`, which never
    /// subtracts nearly equal numbers. It is evaluated in `f64`: the constant term
    /// `|f|^2 - r^2` still cancels for a ray starting on a sphere much larger than the scene
    /// (r = 1e4: ulp(1e8) = 8 in f32), and that error shows as shadow acne on ground spheres
    /// (`tests/hard_cases.rs`). The f64 form is exact enough for the paper's r ~ 1e7 ground.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<f32> {
        let f = ray.origin.as_dvec3() - self.center.as_dvec3();
        let d = ray.dir.as_dvec3();
        let a = d.length_squared();
        let half_b = f.dot(d);
        let perp = f - d * (half_b / a);
        let r = self.radius as f64;
        let disc = a * (r * r - perp.length_squared());
        if disc < 0.0 {
            return None;
        }
        let c = f.length_squared() - r * r;
        let q = -(half_b + disc.sqrt().copysign(half_b));
        let (mut t0, mut t1) = ((c / q) as f32, (q / a) as f32);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        if t0 > ray.t_min && t0 <= ray.t_max {
            Some(t0)
        } else if t1 > ray.t_min && t1 <= ray.t_max {
            Some(t1)
        } else {
            None
        }
    }

    /// TEMPORARY stand-in until the sphere precision variants land.
    pub fn intersect_fast(&self, ray: &Ray) -> Option<f32> {
        self.intersect(ray)
    }

    /// TEMPORARY stand-in until the sphere precision variants land.
    pub fn intersect_double(&self, ray: &Ray) -> Option<f32> {
        self.intersect(ray)
    }

    /// The point of the surface nearest to `p` (computed in f64, then rounded).
    pub fn project(&self, p: Vec3) -> Vec3 {
        let c = self.center.as_dvec3();
        let d = p.as_dvec3() - c;
        let len = d.length();
        if len == 0.0 {
            return p;
        }
        (c + d * (self.radius as f64 / len)).as_vec3()
    }

    /// Outward unit normal at a surface point.
    pub fn normal_at(&self, p: Vec3) -> Vec3 {
        ((p - self.center) / self.radius).normalize_or(Vec3::Y)
    }

    /// Spherical texture coordinates `(phi / 2pi, theta / pi)` of a surface point, y up.
    pub fn uv_at(&self, p: Vec3) -> (f32, f32) {
        let d = self.normal_at(p);
        let phi = d.z.atan2(d.x);
        let u = (phi + std::f32::consts::PI) / std::f32::consts::TAU;
        let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
        (u, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_unit_sphere_front_and_back() {
        let s = Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        assert_eq!(s.intersect(&r), Some(4.0));
        let inside = Ray::new(Vec3::ZERO, Vec3::Z * 2.0);
        assert_eq!(s.intersect(&inside), Some(0.5));
    }

    #[test]
    fn huge_ground_sphere_is_hit_at_the_right_height() {
        // The paper's ground: radius 9,999,899 centred 1e7 below the origin, top at y = -101.
        let s = Sphere {
            center: Vec3::new(0.0, -1e7, 0.0),
            radius: 9_999_899.0,
        };
        let r = Ray::new(Vec3::new(3.0, 50.0, 7.0), Vec3::new(0.01, -1.0, 0.02));
        let t = s.intersect(&r).expect("must hit the ground");
        let y = r.at(t).y;
        assert!((y + 101.0).abs() < 0.05, "hit height {y}");
    }
}

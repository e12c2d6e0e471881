//! Analytic spheres, intersected to within an ulp of the exact root even for huge and distant
//! spheres, grazing rays and unnormalised directions of any finite magnitude.
//!
//! ```toml
//! [[sphere]]
//! center = [0.0, 1.0, 0.0]
//! radius = 1.0
//! material = "glass"
//! ```

use super::twofloat::{Dd, diff_f32, two_prod, two_sum};
use crate::math::{Aabb, Ray, Vec3, f32_down, f32_up};

/// Below this fraction of `|d|^2 r^2` the double-double discriminant's sign is not certain.
const TANGENT_BAND: f64 = 1.0 / (1u128 << 95) as f64;

/// A sphere in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, world space.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: f32,
}

/// What [`Sphere::dd_roots`] finds along a ray.
pub(super) struct DdRoots {
    /// The discriminant lies within its rounding of 0 (or below it).
    pub(super) band: bool,
    /// The two roots rounded to `f32`; `None` when the discriminant is negative.
    pub(super) roots: Option<(f32, f32)>,
}

impl Sphere {
    /// Its bounding box, rounded outwards: `c +- r` in f32 would round a sphere smaller than
    /// `ulp(c)` (r = 1e-3 at 1e5) to a box that misses part of it, or to a flat one. The sum is
    /// taken exactly (`f64` two-sum), since `f64` rounds too when `c` and `r` are more than 2^53
    /// apart: a radius below `ulp(c)` (r = 1e-34 at 38), or a centre below `ulp(r)` (c = 2^-139
    /// beside r = 2^-69, which left the box's top at `r`, under the ball's, and a far ray's
    /// hit outside its sphere's box).
    pub fn bounds(&self) -> Aabb {
        let r = self.radius as f64;
        let below = |x: f32| {
            let s = two_sum(x as f64, -r);
            let down = f32_down(s.hi);
            if down as f64 == s.hi && s.lo < 0.0 {
                down.next_down()
            } else {
                down
            }
        };
        let above = |x: f32| {
            let s = two_sum(x as f64, r);
            let up = f32_up(s.hi);
            if up as f64 == s.hi && s.lo > 0.0 {
                up.next_up()
            } else {
                up
            }
        };
        Aabb::new(self.center.map(below), self.center.map(above))
    }

    /// The nearest `t` in `(ray.t_min, ray.t_max]` where the ray meets the surface; always
    /// finite (a root beyond `f32::MAX` is a miss).
    ///
    /// **Accuracy: the returned `t` is within 1 f32 ulp of the exact root of the `f32` inputs**
    /// (origin, any finite non-zero direction, centre, radius), and hit/miss agrees with the sign
    /// of the exact discriminant except when `|disc| < 2^-95 |d|^2 r^2` (a tangency that close is
    /// below every f32 input's resolution).
    ///
    /// The cancellation-free form of Ray Tracing Gems ch. 7 is evaluated in `f64` first: with
    /// `f = o - c`, the quarter discriminant is `|d|^2 r^2 - |f x d|^2` (Lagrange's identity: no
    /// difference of two huge squares), and the roots are `q / |d|^2` and `c / q` with
    /// `q = -(f.d + sign(f.d) sqrt(disc))`, which never subtracts nearly equal numbers. Alongside,
    /// a first-order bound on the rounding error of each root is accumulated (the rounding of
    /// `f` itself, of `f.d`, of the discriminant and of the constant `|f|^2 - r^2`). When a root
    /// that matters could be off by more than `2^-28` relative (rounded to f32 that is at most
    /// 1/16 ulp extra, hence the 1-ulp bound), or the discriminant's sign is in doubt, the same
    /// formulas are re-evaluated in double-double ([`Sphere::intersect_double`]). That happens for
    /// origins very near a huge sphere (r = 1e7 seen from 1e-4 above: `|f|^2 - r^2` loses 11
    /// digits), for grazing rays and when `o - c` does not fit an `f64` (o.y = 1e-4 against
    /// c.y = -1e7); ordinary camera and shadow rays stay on the f64 path.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<f32> {
        // Unit roundoff of f64; the constants below are generous first-order error counts.
        const U: f64 = f64::EPSILON / 2.0;
        const TOL: f64 = 1.0 / (1u64 << 28) as f64;
        let f = ray.origin.as_dvec3() - self.center.as_dvec3();
        let d = ray.dir.as_dvec3();
        let r = self.radius as f64;
        let r2 = r * r; // exact: 48 bits
        let a = d.length_squared();
        let ff = f.length_squared();
        let cross2 = f.cross(d).length_squared();
        let disc = a * r2 - cross2;
        // |f x d|^2 errs by ~2 |f x d| (|f||d| u) per rounding of f and of the cross product,
        // bounded without a square root by AM-GM: sqrt(cross2 ff a) <= (cross2 + ff a) / 2.
        // (Square roots and divisions dominate this test's time: the checks below use none.)
        let e_disc = 8.0 * U * (a * r2 + 0.5 * (cross2 + ff * a));
        if disc < -e_disc {
            return None;
        }
        if disc <= e_disc {
            return self.intersect_double(ray);
        }
        let b = f.dot(d);
        let e_b = 5.0 * U * f.abs().dot(d.abs());
        let sq = disc.sqrt();
        let q = -(b + sq.copysign(b));
        let c = ff - r2;
        // Relative errors: q's is err_q / (|q| sq) + 2 u (sqrt halves the discriminant's, and
        // |q| >= sqrt(disc) absorbs it), c's is err_c / |c|; each root adds 2 u more.
        let err_q = e_b * sq + e_disc;
        let err_c = 7.0 * U * (ff + r2);
        let (qs, ac) = (q.abs() * sq, c.abs());
        let lim = TOL - 4.0 * U;
        let (t0, t1) = (q / a, c / q);
        if err_q <= lim * qs && err_q * ac + err_c * qs <= lim * qs * ac {
            return nearest_in_range(t0 as f32, t1 as f32, ray);
        }
        let (rel0, rel1) = (err_q / qs + 4.0 * U, err_q / qs + err_c / ac + 4.0 * U);
        // A root needs to be accurate only when it could decide the answer, i.e. when it may lie
        // inside the ray's interval. That depends on `t_max`, which shrinks as a traversal finds
        // hits, so what this path returns must be what the double-double path would: a root
        // counts as outside only if all it may be rounds outside (a tie with `t_max` would be
        // a hit there), and an accurate root is taken only if all it may be rounds alike.
        let settled = |t: f64, rel: f64| {
            let e = t.abs() * rel;
            let outside = ((t + e) as f32) <= ray.t_min || ((t - e) as f32) > ray.t_max;
            (rel <= TOL && (t - e) as f32 == (t + e) as f32) || outside
        };
        if !(settled(t0, rel0) && settled(t1, rel1)) {
            return self.intersect_double(ray);
        }
        nearest_in_range(t0 as f32, t1 as f32, ray)
    }

    /// [`Sphere::intersect`] with every step in double-double arithmetic: `o - c` and `r^2` are
    /// exact, `|d|^2`, `f.d`, `|f x d|^2`, the discriminant and `|f|^2 - r^2` carry ~106 bits,
    /// and each root is rounded once to the nearest f32. Never less accurate than `intersect`
    /// (it is its fallback); about ten times slower. The `--precision double` option.
    pub fn intersect_double(&self, ray: &Ray) -> Option<f32> {
        let DdRoots { band, roots } = self.dd_roots(ray);
        let (t0, t1) = roots?;
        if !band {
            return nearest_in_range(t0, t1, ray);
        }
        let bounds = self.bounds();
        let inside = |t: f32| crate::math::slab::within_box(&bounds, ray, t);
        match (inside(t0), inside(t1)) {
            (true, true) => nearest_in_range(t0, t1, ray),
            (true, false) => nearest_in_range(t0, t0, ray),
            (false, true) => nearest_in_range(t1, t1, ray),
            (false, false) => None,
        }
    }

    /// The roots of `ray` against the sphere in double-double arithmetic (the formulas of
    /// [`Self::intersect_double`]), and whether the discriminant lies in the tangency band,
    /// within its rounding of 0 (a tangency closer than 2^-95 |d|^2 r^2), where its sign is
    /// not known: the line may miss the ball, and its box, by a hair. A root in the band counts
    /// only where it lies inside the sphere's box as the traversals compute it for this ray, so
    /// no hierarchy culls a hit brute force reports (meeting the box somewhere is not enough: a
    /// far ray crosses a tiny box within one ulp of `t`, and the root may round past it). The
    /// all-hits query reads the band as a graze.
    pub(super) fn dd_roots(&self, ray: &Ray) -> DdRoots {
        let o = ray.origin.to_array();
        let c = self.center.to_array();
        let d = ray.dir.as_dvec3().to_array();
        let f: [Dd; 3] = std::array::from_fn(|i| diff_f32(o[i], c[i]));
        let sum3 = |g: &dyn Fn(usize) -> Dd| g(0).add(g(1)).add(g(2));
        let a = sum3(&|i| two_prod(d[i], d[i]));
        let b = sum3(&|i| f[i].mul_f64(d[i]));
        let cross = |i: usize, j: usize| f[i].mul_f64(d[j]).sub(f[j].mul_f64(d[i]));
        let cross2 = cross(1, 2)
            .square()
            .add(cross(2, 0).square())
            .add(cross(0, 1).square());
        let r = self.radius as f64;
        let r2 = Dd::from_f64(r * r); // exact
        let disc = a.mul(r2).sub(cross2);
        let band = disc.hi <= TANGENT_BAND * a.hi * r2.hi;
        if disc.is_negative() {
            return DdRoots { band, roots: None };
        }
        let k = sum3(&|i| f[i].square()).sub(r2);
        let sq = disc.sqrt();
        let q = if b.is_negative() {
            sq.sub(b)
        } else {
            b.add(sq).neg()
        };
        // q == 0 only for an origin exactly at the tangent point: both roots are 0.
        let roots = if q.hi == 0.0 {
            (0.0, 0.0)
        } else {
            (q.div(a).to_f32(), k.div(q).to_f32())
        };
        DdRoots {
            band,
            roots: Some(roots),
        }
    }

    /// The textbook quadratic `b^2 - 4ac` evaluated in `f32`, as many renderers ship it: fast,
    /// but `c = |f|^2 - r^2` and the discriminant cancel catastrophically for huge or distant
    /// spheres (thousands of ulps on a radius-1e7 ground). The `--precision fast` option.
    pub fn intersect_fast(&self, ray: &Ray) -> Option<f32> {
        let f = ray.origin - self.center;
        let d = ray.dir;
        let a = d.dot(d);
        let b = 2.0 * f.dot(d);
        let c = f.dot(f) - self.radius * self.radius;
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        nearest_in_range((-b - s) / (2.0 * a), (-b + s) / (2.0 * a), ray)
    }

    /// The point of the surface nearest to `p`, correctly rounded per component: `p - c`, its
    /// length and `c + (p - c) r / |p - c|` are evaluated in double-double, so a point 1e-4 above
    /// a sphere centred 1e7 away keeps its small coordinates (f64 alone would lose ~1e-9).
    pub fn project(&self, p: Vec3) -> Vec3 {
        let (p, c) = (p.to_array(), self.center.to_array());
        let d: [Dd; 3] = std::array::from_fn(|i| diff_f32(p[i], c[i]));
        let len2 = d[0].square().add(d[1].square()).add(d[2].square());
        if len2.hi == 0.0 {
            return Vec3::from_array(p);
        }
        let s = Dd::from_f64(self.radius as f64).div(len2.sqrt());
        Vec3::from_array(std::array::from_fn(|i| {
            d[i].mul(s).add_f64(c[i] as f64).to_f32()
        }))
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

/// The smaller of two candidate roots in `(t_min, t_max]`, else the larger; never infinite or NaN.
#[inline]
fn nearest_in_range(t0: f32, t1: f32, ray: &Ray) -> Option<f32> {
    let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    let ok = |t: f32| t > ray.t_min && t <= ray.t_max && t.is_finite();
    if ok(lo) {
        Some(lo)
    } else if ok(hi) {
        Some(hi)
    } else {
        None
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
    fn all_variants_agree_on_easy_rays_and_never_return_infinity() {
        let s = Sphere {
            center: Vec3::new(0.5, -0.25, 3.0),
            radius: 1.25,
        };
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.1, -0.05, 1.0));
        let t = s.intersect(&r).unwrap();
        assert_eq!(s.intersect_double(&r), Some(t));
        assert!((s.intersect_fast(&r).unwrap() - t).abs() < 1e-5);
        // A subnormal direction puts the root beyond f32::MAX: a miss, not +inf.
        let tiny = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, f32::from_bits(1)));
        assert_eq!(s.intersect(&tiny), None);
        assert_eq!(s.intersect_fast(&tiny), None);
    }

    /// Every face of the box lies on or beyond the ball, in exact rational arithmetic, for
    /// centres far below `ulp(r)` (2^-139 beside 2^-69: `c + r` rounds to `r` even in `f64`),
    /// far above it, and of either sign.
    #[test]
    fn bounds_contain_the_ball_whatever_the_centre_and_radius_magnitudes() {
        use num_rational::BigRational;
        let q = |x: f32| BigRational::from_float(x).expect("finite");
        let exceeds = |face: f32, c: f32, r: f32| q(face) - q(c) >= q(r);
        let below = |face: f32, c: f32, r: f32| q(c) - q(face) >= q(r);
        let values = [0.0, 1e-45, 2f32.powi(-139), 1e-30, 1.0, 1e5, 3e38];
        for &c in &values {
            for sign in [1.0, -1.0] {
                for r in [2f32.powi(-69), 1e-40, 1e-3, 1.0, 1e18] {
                    let c = sign * c;
                    let s = Sphere {
                        center: Vec3::splat(c),
                        radius: r,
                    };
                    let b = s.bounds();
                    assert!(exceeds(b.max.x, c, r), "max of c = {c:e}, r = {r:e}");
                    assert!(below(b.min.x, c, r), "min of c = {c:e}, r = {r:e}");
                }
            }
        }
    }

    #[test]
    fn bounds_contain_a_sphere_smaller_than_the_ulp_of_its_centre() {
        let s = Sphere {
            center: Vec3::new(1e5, -3e5, 7e4),
            radius: 1e-3,
        };
        let b = s.bounds();
        for i in 0..3 {
            assert!((b.min[i] as f64) <= s.center[i] as f64 - 1e-3);
            assert!((b.max[i] as f64) >= s.center[i] as f64 + 1e-3);
        }
    }

    #[test]
    fn bounds_contain_a_sphere_smaller_than_the_f64_ulp_of_its_centre() {
        // 38 - 1e-34 rounds to 38 even in f64: the box must still be wider than a point.
        let s = Sphere {
            center: Vec3::new(38.0, -5.921568e17, 2.95e-14),
            radius: 1e-34,
        };
        let b = s.bounds();
        for i in 0..3 {
            assert!(b.min[i] < s.center[i] && b.max[i] > s.center[i], "{b:?}");
        }
    }

    #[test]
    fn project_keeps_small_coordinates_next_to_a_huge_sphere() {
        // The top of this sphere is y = 0; f64 alone lands ~1e-9 off.
        let s = Sphere {
            center: Vec3::new(0.0, -1e7, 0.0),
            radius: 1e7,
        };
        let p = s.project(Vec3::new(0.0, 1e-4, 0.0));
        assert!(p.y.abs() < 1e-20, "{p}");
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

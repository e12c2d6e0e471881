//! Ray/box slab tests, chosen once per ray so that every finite non-zero direction, whatever its
//! magnitude (components from 2^-149 to 2^127), culls exactly the boxes brute force would
//! never find a hit in.
//!
//! - [`SlabF32`] is the fast path: one reciprocal per axis in `f32`. With `AXIS_PARALLEL` it also
//!   resolves `0 * inf` for zero direction components (a ray running inside a slab's plane).
//! - [`SlabF64`] takes over when the `f32` reciprocal cannot represent `1 / d`: a subnormal
//!   component overflows to infinity (d = 2e-39 would cull a box entered at t = 5e37) and a huge
//!   one underflows into subnormals that keep too few bits for the widening to cover.

use crate::math::{Aabb, Ray, Vec3A, f32_down, f32_up};
use glam::DVec3;

/// A slab test prepared for one ray: the entry and exit parameters of a box within
/// `[t_min, t_max]` (both conservative), or `None` when the ray misses it.
pub(crate) trait Slab: Copy {
    /// See [`Aabb::hit_range`].
    fn range(&self, b: &Aabb, t_min: f32, t_max: f32) -> Option<(f32, f32)>;
}

/// The `f32` slab test of [`Aabb::hit_range_with`].
#[derive(Clone, Copy)]
pub(crate) struct SlabF32<const AXIS_PARALLEL: bool> {
    origin: Vec3A,
    inv: Vec3A,
}

impl<const AXIS_PARALLEL: bool> SlabF32<AXIS_PARALLEL> {
    /// The test for `ray` whose reciprocal direction is `inv` (see [`with_slab`]).
    #[inline(always)]
    pub(crate) fn with_inverse(ray: &Ray, inv: Vec3A) -> Self {
        Self {
            origin: Vec3A::from(ray.origin),
            inv,
        }
    }
}

impl<const AXIS_PARALLEL: bool> Slab for SlabF32<AXIS_PARALLEL> {
    #[inline(always)]
    fn range(&self, b: &Aabb, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        b.hit_range_with::<AXIS_PARALLEL>(self.origin, self.inv, t_min, t_max)
    }
}

/// The same test in `f64`, where `1 / d` is exact to 1 ulp for every `f32` direction.
#[derive(Clone, Copy)]
pub(crate) struct SlabF64 {
    origin: DVec3,
    inv: DVec3,
}

/// Relative widening of the `f64` exit: the differences, reciprocals and products each round
/// once in `f64`, so a few `f64` ulps cover them; the `f32` conversion is widened separately.
const F64_SCALE: f64 = 1.0 + 8.0 * f64::EPSILON;

impl SlabF64 {
    /// The test for `ray` (see [`with_slab`]).
    #[inline(always)]
    pub(crate) fn for_ray(ray: &Ray) -> Self {
        Self {
            origin: ray.origin.as_dvec3(),
            inv: DVec3::ONE / ray.dir.as_dvec3(),
        }
    }
}

impl Slab for SlabF64 {
    #[inline]
    fn range(&self, b: &Aabb, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        let t0 = (b.min.as_dvec3() - self.origin) * self.inv;
        let t1 = (b.max.as_dvec3() - self.origin) * self.inv;
        let (mut lo, mut hi) = (t0.min(t1), t0.max(t1));
        // As in the f32 test: `0 * inf` marks a ray inside that slab's plane.
        for i in 0..3 {
            if t0[i].is_nan() || t1[i].is_nan() {
                lo[i] = f64::NEG_INFINITY;
                hi[i] = f64::INFINITY;
            }
        }
        let near = lo.max_element().max(t_min as f64);
        let far = hi.min_element();
        let far = far.max(far * F64_SCALE).min(t_max as f64);
        if near > far {
            return None;
        }
        // Rounded outwards to f32, so the interval still holds the exact one.
        Some((f32_down(near), f32_up(far)))
    }
}

/// Direction components above this send a ray to the `f64` test: with `|d| > 2^96`, a box
/// 2^-30 away is entered at `t < 2^-126`, where `f32` keeps fewer bits than the widening covers.
pub(crate) const HUGE_COMPONENT: f32 = 7.922_816e28; // 2^96

/// Which slab test a ray needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SlabKind {
    /// Every reciprocal finite and normal: the fast `f32` test.
    Finite,
    /// Some component exactly zero, the others fine: `f32` with the `0 * inf` handling.
    AxisParallel,
    /// Some non-zero component whose `f32` reciprocal overflows or is subnormal, or so large
    /// that box distances of ordinary scenes fall into `f32` subnormals.
    Wide,
}

impl SlabKind {
    /// The test `ray` needs.
    #[cfg(test)]
    pub(crate) fn of(ray: &Ray) -> Self {
        Self::with_inverse(ray, crate::math::safe_inverse(ray.dir))
    }

    /// The test `ray` needs, given its `f32` reciprocal direction (computed once per ray).
    #[inline(always)]
    pub(crate) fn with_inverse(ray: &Ray, inv: Vec3A) -> Self {
        let d = Vec3A::from(ray.dir);
        let zero = d.cmpeq(Vec3A::ZERO);
        // A non-zero component whose reciprocal is not a normal float, or a huge component.
        let normal = inv.abs().cmpge(Vec3A::splat(f32::MIN_POSITIVE)) & inv.is_finite_mask();
        let wide = (!zero & !normal) | d.abs().cmpgt(Vec3A::splat(HUGE_COMPONENT));
        if wide.any() {
            SlabKind::Wide
        } else if zero.any() {
            SlabKind::AxisParallel
        } else {
            SlabKind::Finite
        }
    }
}

/// True when `t` lies between the entry and the exit of box `b` as the traversals compute them
/// for `ray` (the same slab test, the same widening): a hit at such a `t` is never culled by a
/// box that contains `b`, since box entries and exits are monotone in the box's planes.
#[inline]
pub(crate) fn within_box(b: &Aabb, ray: &Ray, t: f32) -> bool {
    box_range(b, ray).is_some_and(|(near, far)| near <= t && t <= far)
}

/// The entry and exit of box `b` as the traversals compute them for `ray` (over all `t`): the
/// interval [`within_box`] tests against.
#[inline]
pub(crate) fn box_range(b: &Aabb, ray: &Ray) -> Option<(f32, f32)> {
    with_slab!(ray, |slab| slab.range(b, f32::NEG_INFINITY, f32::INFINITY))
}

/// [`box_range`] with its common case inline: a direction whose components are all finite,
/// non-zero and not huge takes the `f32` test here; the others take `box_range` itself. Per
/// instance entered, the out-of-line call with its three kinds of test cost more than the test.
#[inline(always)]
pub(crate) fn box_range_inline(b: &Aabb, ray: &Ray) -> Option<(f32, f32)> {
    let inv = crate::math::safe_inverse(ray.dir);
    if SlabKind::with_inverse(ray, inv) == SlabKind::Finite {
        return SlabF32::<false>::with_inverse(ray, inv).range(b, f32::NEG_INFINITY, f32::INFINITY);
    }
    box_range(b, ray)
}

/// Runs `$body` with `$slab` bound to the slab test `$ray` needs (a macro, because each arm
/// instantiates the traversal for a different test type).
macro_rules! with_slab {
    ($ray:expr, |$slab:ident| $body:expr) => {{
        let inv = $crate::math::safe_inverse($ray.dir);
        match $crate::math::slab::SlabKind::with_inverse($ray, inv) {
            $crate::math::slab::SlabKind::Finite => {
                let $slab = $crate::math::slab::SlabF32::<false>::with_inverse($ray, inv);
                $body
            }
            $crate::math::slab::SlabKind::AxisParallel => {
                let $slab = $crate::math::slab::SlabF32::<true>::with_inverse($ray, inv);
                $body
            }
            $crate::math::slab::SlabKind::Wide => {
                let $slab = $crate::math::slab::SlabF64::for_ray($ray);
                $body
            }
        }
    }};
}
pub(crate) use with_slab;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn subnormal_direction_components_use_the_f64_test_and_keep_far_boxes() {
        // The case: 1 / 2e-39 overflows f32, yet the box is entered at t = 5e37.
        let ray = Ray::new(Vec3::ZERO, Vec3::new(1e-38, 2e-39, 0.0));
        assert_eq!(SlabKind::of(&ray), SlabKind::Wide);
        let b = Aabb::new(Vec3::new(1.0, 0.1, -1.0), Vec3::new(1.0, 0.3, 1.0));
        let (near, far) = SlabF64::for_ray(&ray)
            .range(&b, 0.0, f32::INFINITY)
            .expect("the ray crosses the box");
        assert!(near <= 1e38 && far >= 1e38, "{near} {far}");
        // The f32 test culls it: exactly the bug.
        assert!(
            SlabF32::<true>::with_inverse(&ray, crate::math::safe_inverse(ray.dir))
                .range(&b, 0.0, f32::INFINITY)
                .is_none()
        );
    }

    #[test]
    fn kinds_follow_the_direction() {
        let k = |d: Vec3| SlabKind::of(&Ray::new(Vec3::ZERO, d));
        assert_eq!(k(Vec3::new(1.0, 2.0, 3.0)), SlabKind::Finite);
        assert_eq!(k(Vec3::new(1.0, 0.0, -0.0)), SlabKind::AxisParallel);
        assert_eq!(k(Vec3::new(1.0, 0.0, 1e-45)), SlabKind::Wide);
        assert_eq!(k(Vec3::new(3e38, 1.0, 1.0)), SlabKind::Wide);
        assert_eq!(k(Vec3::new(2f32.powi(90), 1.0, 1.0)), SlabKind::Finite);
        assert_eq!(k(Vec3::new(2f32.powi(100), 1.0, 1.0)), SlabKind::Wide);
    }
}

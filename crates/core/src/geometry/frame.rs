//! Rays from far away: each query is traced from an origin near the scene.
//!
//! The float32 tests lose what the translation `p - o` loses. A ray from 1e19 towards a unit
//! sphere sees every vertex rounded onto the same point (even in `f64`: 1e19 + 1 needs 64
//! bits), and from 1e8 the front and the back of the sphere round to the same `t`, so the tie
//! rule picks whichever comes first in the file. Embree leaves such rays undefined; lumis moves
//! them instead: a ray whose origin lies outside the scene's *near region* (its bounds grown by
//! [`NEAR_FACTOR`] times their largest extent, or by their largest coordinate if that is more)
//! is moved along itself, in double-double
//! arithmetic, to a point near the bounds, rounded to `f32` there; the query runs from that
//! point, and the distance moved is added back to the `t` it reports.
//!
//! What that costs in exactness is stated and small: the moved origin is the exact point of the
//! given line rounded to `f32` at the scene's scale, so the answer is the exact answer of a line
//! displaced by at most half an `f32` ulp of the near region's largest coordinate, ordered by
//! `t` measured from there. An origin is moved only from farther away than the scene's own
//! coordinates reach, where staying would cost more than that rounding. Rays starting inside the near region (every secondary ray, camera
//! rays of ordinary views) are traced exactly as given, after one box test of their origin.
//!
//! The same move serves the camera ([`RayFrame::frame_f64`]): its rays are formed in `f64` and
//! moved before their direction is rounded, so a camera far from a small scene keeps each
//! pixel's own ray (docs/hard-cases.md, "Far cameras").

use glam::DVec3;

use crate::geometry::twofloat::{Dd, two_prod, two_sum};
use crate::math::{Aabb, Ray, Vec3, Vec3A, f32_down, f32_up};

/// The near region is the scene's bounds grown on every side by this many times their
/// largest extent, or by their largest coordinate magnitude if that is more. Within it, hits
/// are ordered by `t` to about `2^-24` of `(1 + 2 * NEAR_FACTOR)` extents or of that magnitude,
/// the resolution of the scene's own coordinates; ordinary camera placements (model viewers
/// frame a model from 1.5 to 3 extents away) stay inside and pay nothing.
pub const NEAR_FACTOR: f32 = 4.0;

/// The near region's margin never exceeds this: with scene coordinates within
/// [`crate::scene::limits::MAX_COORDINATE`] (1e18) the region stays within 2e18, where every
/// product the `f32` triangle test forms of two coordinate differences (at most 4e18 each,
/// 8e18 sheared) is below 7e37 and their sums stay finite.
const MAX_MARGIN: f32 = 1e18;

/// Moves made before giving up on landing in the near region: each move lands within about
/// `2^-50` of the remaining distance, so 3 cover the whole `f32` range; the rest is slack.
const MAX_MOVES: usize = 8;

/// Relative widening of the `f64` slab distances (three roundings of `2^-53` each).
const SLAB_WIDEN: f64 = 1.0 / (1u64 << 48) as f64;

/// The scene's bounds and near region, made once per accelerator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayFrame {
    /// Bounds of every primitive.
    bounds: Aabb,
    /// `bounds` grown by `margin`, rounded outwards: origins inside are traced as given (its
    /// corners kept as SIMD vectors for the test every query makes).
    near_min: Vec3A,
    near_max: Vec3A,
    /// How far outside the bounds (world units) a moved origin is aimed: half the margin.
    backoff: f64,
}

/// How a query's ray is traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Framing {
    /// From its own origin, unchanged.
    AsGiven,
    /// From a point near the scene ([`Moved::ray`]).
    Moved(Moved),
    /// It meets nothing: its line misses the scene's bounds within its interval, or its origin
    /// or direction is not a finite non-zero vector (which every entry point refuses first).
    Miss,
}

impl Framing {
    /// The ray to trace for the caller's `given` ray: itself, the moved one, or none.
    #[inline(always)]
    pub fn ray<'a>(&'a self, given: &'a Ray) -> Option<&'a Ray> {
        match self {
            Framing::AsGiven => Some(given),
            Framing::Moved(m) => Some(&m.ray),
            Framing::Miss => None,
        }
    }

    /// The `t` on [`Framing::ray`] of a hit at the caller's `t` (the inverse of
    /// [`Framing::caller_t`], to within its rounding): where a surface is computed again.
    pub fn local_t(&self, caller: f32) -> f32 {
        match self {
            Framing::Moved(m) => (caller as f64 - m.shift.to_f64()) as f32,
            _ => caller,
        }
    }

    /// The caller's `t` of a hit at `t` on [`Framing::ray`] (see [`Moved::world_t`]).
    #[inline(always)]
    pub fn caller_t(&self, t: f32) -> Option<f32> {
        match self {
            Framing::AsGiven => Some(t),
            Framing::Moved(m) => m.world_t(t),
            Framing::Miss => None,
        }
    }
}

/// A ray moved along itself to near the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moved {
    /// The ray to trace: the moved origin, the same direction, its interval in local `t`.
    pub ray: Ray,
    /// The distance moved, in units of the direction: world `t = shift + local t`.
    shift: Dd,
    /// The caller's interval, which reported distances are kept inside.
    t_min: f32,
    t_max: f32,
}

impl Moved {
    /// The caller's `t` of a hit at local `t`: rounded once to `f32` and kept inside the
    /// caller's `(t_min, t_max]` (the local interval was rounded, so a hit within an ulp of an
    /// end may round just outside). `None` when it lies beyond `f32::MAX` (no `f32` distance).
    #[inline]
    pub fn world_t(&self, local: f32) -> Option<f32> {
        let t = self.shift.add_f64(local as f64).to_f32();
        if !t.is_finite() {
            return None;
        }
        Some(t.min(self.t_max).max(self.t_min.next_up()))
    }
}

impl RayFrame {
    /// The frame of a scene whose primitives lie within `bounds` (empty: nothing to hit).
    pub fn new(bounds: Aabb) -> Self {
        if bounds.is_empty() || !(bounds.min.is_finite() && bounds.max.is_finite()) {
            return Self {
                bounds: Aabb::EMPTY,
                near_min: Aabb::EMPTY.min.into(),
                near_max: Aabb::EMPTY.max.into(),
                backoff: 0.0,
            };
        }
        let scale = bounds.min.abs().max(bounds.max.abs()).max_element();
        // A point-like scene still gets a margin of a few ulps of its position.
        let floor = 4.0 * ulp(scale).max(f32::MIN_POSITIVE);
        let around = (NEAR_FACTOR * bounds.extent().max_element()).max(floor);
        // Moving costs the rounding of the moved origin, half an ulp of the scene's largest
        // coordinate; staying costs `t` resolution, 2^-24 of the distance. So an origin is
        // moved only from farther than the scene's coordinates reach: a small object far from
        // the world's origin, seen from nearby, keeps its exact translation.
        let margin = around.max(scale).min(MAX_MARGIN) as f64;
        let near = Aabb {
            min: bounds.min.map(|x| f32_down(x as f64 - margin)),
            max: bounds.max.map(|x| f32_up(x as f64 + margin)),
        };
        Self {
            bounds,
            near_min: near.min.into(),
            near_max: near.max.into(),
            // Landing a few extents before the bounds keeps `t` on the scene's scale.
            backoff: 0.5 * (around as f64).min(margin),
        }
    }

    /// A frame that traces every finite origin as given: for rays made without a scene
    /// (camera tests), where there are no bounds to move towards.
    pub fn unbounded() -> Self {
        Self {
            bounds: Aabb::EMPTY,
            near_min: Vec3A::NEG_INFINITY,
            near_max: Vec3A::INFINITY,
            backoff: 0.0,
        }
    }

    /// The near region: origins inside it are traced as given.
    pub fn near_region(&self) -> Aabb {
        Aabb {
            min: self.near_min.into(),
            max: self.near_max.into(),
        }
    }

    /// True when a ray from `origin` is traced as given (false for NaN or infinite origins).
    #[inline(always)]
    pub fn holds(&self, origin: Vec3) -> bool {
        let o = Vec3A::from(origin);
        (o.cmpge(self.near_min) & o.cmple(self.near_max)).all()
    }

    /// How `ray` is traced: as given when its origin lies in the near region, else moved.
    #[inline(always)]
    pub fn frame(&self, ray: &Ray) -> Framing {
        if self.holds(ray.origin) {
            Framing::AsGiven
        } else {
            self.frame_far(ray)
        }
    }

    #[cold]
    #[inline(never)]
    fn frame_far(&self, ray: &Ray) -> Framing {
        if !(ray.origin.is_finite() && ray.dir.is_finite()) || ray.dir == Vec3::ZERO {
            return Framing::Miss;
        }
        let origin = ray.origin.to_array().map(|x| Dd::from_f64(x as f64));
        self.move_near(origin, ray.dir.as_dvec3(), ray.dir, ray.t_min, ray.t_max)
    }

    /// How a ray given in `f64` is traced (`origin + t dir`, `t > 0`): the camera's rays, whose
    /// direction must not be rounded before their origin is near the scene. `AsGiven` means:
    /// round the origin and the direction and trace that.
    pub fn frame_f64(&self, origin: DVec3, dir: DVec3) -> Framing {
        if self.holds(origin.as_vec3()) {
            return Framing::AsGiven;
        }
        if !(origin.is_finite() && dir.is_finite()) || dir == DVec3::ZERO {
            return Framing::Miss;
        }
        let o = origin.to_array().map(Dd::from_f64);
        self.move_near(o, dir, dir.as_vec3(), 0.0, f32::INFINITY)
    }

    /// Moves the point `origin` (double-double per axis) along `dir` until its `f32` rounding
    /// lies in the near region, aiming [`Self::backoff`] before the bounds' entry (or before
    /// `t_min`), and returns the ray from there with direction `dir32` (`dir` rounded).
    fn move_near(
        &self,
        origin: [Dd; 3],
        dir: DVec3,
        dir32: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Framing {
        let mut p = origin;
        let mut shift = Dd::ZERO;
        // Moving by `backoff / max |d_i|` changes no coordinate by more than `backoff`.
        let back = self.backoff / dir.abs().max_element();
        for _ in 0..MAX_MOVES {
            if self.holds(round_point(&p)) {
                break;
            }
            let Some((enter, exit)) = slab(&self.bounds, &p, dir) else {
                return Framing::Miss;
            };
            let (lo, hi) = local_interval(shift, t_min, t_max);
            if lo > exit || hi < enter {
                return Framing::Miss;
            }
            let step = enter.max(lo) - back;
            p = advance(p, step, dir);
            shift = shift.add_f64(step);
        }
        // The rounded point is the origin; distances from it are measured on a line displaced
        // by under an ulp of it, which is the stated bound.
        let origin = round_point(&p);
        // The local interval: the caller's, clipped to the near region's range, whose entry
        // lies a margin before any primitive's, so the clip loses no hit whatever the rounding.
        let from = origin.to_array().map(|x| Dd::from_f64(x as f64));
        let Some((enter, exit)) = slab(&self.near_region(), &from, dir) else {
            return Framing::Miss;
        };
        // A hit beyond f32::MAX either way has no f32 distance: it is no hit, for the
        // nearest-hit and the any-hit query alike, so the caps are part of the interval
        // (rounded inwards).
        let (capped_lo, capped) = (t_min < -f32::MAX, t_max > f32::MAX);
        let (lo, hi) = local_interval(shift, t_min, t_max);
        let t_lo = match (lo >= enter, capped_lo) {
            (true, false) => lo as f32,
            (true, true) => f32_up(lo),
            (false, _) => f32_down(enter),
        };
        let t_hi = match (hi <= exit, capped) {
            (true, false) => hi as f32,
            (true, true) => f32_down(hi),
            (false, _) => f32_up(exit),
        };
        if t_lo >= t_hi || t_lo.is_nan() || t_hi.is_nan() {
            return Framing::Miss;
        }
        Framing::Moved(Moved {
            ray: Ray {
                origin,
                dir: dir32,
                t_min: t_lo,
                t_max: t_hi,
            },
            shift,
            t_min,
            t_max,
        })
    }
}

/// The caller's interval `(t_min, t_max]` capped at `-+f32::MAX` (no `f32` distance lies
/// beyond), measured from a point `shift` along the ray.
fn local_interval(shift: Dd, t_min: f32, t_max: f32) -> (f64, f64) {
    (
        local_t(shift, t_min.max(-f32::MAX)),
        local_t(shift, t_max.min(f32::MAX)),
    )
}

/// The caller's `t` measured from a point `shift` along the ray (infinities stay infinite).
fn local_t(shift: Dd, t: f32) -> f64 {
    if t.is_finite() {
        Dd::from_f64(t as f64).sub(shift).hi
    } else {
        t as f64
    }
}

/// `p + s d` per axis, exactly up to the double-double rounding of the result (`s d` is an
/// exact two-product; the sums keep both error terms).
fn advance(p: [Dd; 3], s: f64, d: DVec3) -> [Dd; 3] {
    std::array::from_fn(|i| {
        let prod = two_prod(s, d[i]);
        p[i].add(prod)
    })
}

/// The nearest `f32` point to a double-double point.
fn round_point(p: &[Dd; 3]) -> Vec3 {
    Vec3::from_array(p.map(Dd::to_f32))
}

/// The `f64` slab test of the line `p + t d` against box `b`, widened outwards so that it holds
/// the exact interval: `(enter, exit)`, or `None` when the line misses the box.
fn slab(b: &Aabb, p: &[Dd; 3], d: DVec3) -> Option<(f64, f64)> {
    let (mut enter, mut exit) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..3 {
        let lo = (two_sum(b.min[i] as f64, -p[i].hi).hi) - p[i].lo;
        let hi = (two_sum(b.max[i] as f64, -p[i].hi).hi) - p[i].lo;
        if d[i] == 0.0 {
            // Parallel to this slab: inside it for every t, or never.
            if lo > 0.0 || hi < 0.0 {
                return None;
            }
            continue;
        }
        let (t0, t1) = (lo / d[i], hi / d[i]);
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        enter = enter.max(near - near.abs() * SLAB_WIDEN);
        exit = exit.min(far + far.abs() * SLAB_WIDEN);
    }
    (enter <= exit).then_some((enter, exit))
}

/// The spacing of `f32`s at `x` (the distance to the next one up).
fn ulp(x: f32) -> f32 {
    let x = x.abs();
    if x.is_finite() {
        x.next_up() - x
    } else {
        f32::MAX
    }
}

#[cfg(test)]
mod tests;

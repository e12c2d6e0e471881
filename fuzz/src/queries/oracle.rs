//! The exact oracle: where the exact line `o + t d` of a ray (its `f32` values taken as exact
//! numbers) meets each primitive, and which answers are certain once the line may be displaced
//! by `delta`.
//!
//! lumis promises exactness for a ray whose line is displaced by at most
//! `delta = 4 ulp_f32(S)`, `S` = the largest |coordinate| of the scene's box plus 4 times its
//! largest extent: a far origin is moved along the ray to near the scene and rounded to `f32`
//! there. Seen along the ray, a displacement moves the line's footprint in the plane
//! perpendicular to `d` by at most `delta`. So a primitive is
//! - **clearly hit** when that footprint lies inside the primitive's projection by more than
//!   `delta` (a triangle: every edge function's distance, a sphere: `|f x d| / |d| < r - delta`),
//! - **clearly missed** when it lies outside by more than `delta`,
//! - **ambiguous** otherwise: either answer is right, but a hit's `t` must still be where the
//!   displaced line can meet the primitive.
//!
//! The crossings are exact (big integers, [`super::fixed`]); distances and tolerances are
//! compared in `f64` with a relative slack of 1e-9, far below `delta >= 2^-22 S`.

use super::fixed::{FRAC, IV, fix, fix_up, ratio, to_f64, ulp_f32};
use super::scene::Prim;
use lumis_core::math::{Aabb, Ray, Vec3};
use num_bigint::BigInt;
use num_traits::{Signed, Zero};

/// Relative slack of `f64` comparisons against exactly computed quantities.
const SLACK: f64 = 1e-9;

/// The ray and the scene's displacement bound, in exact and `f64` form.
pub struct Frame {
    pub ray: Ray,
    o: IV,
    d: IV,
    /// `|d|`.
    pub d_len: f64,
    /// The displacement bound, world units.
    pub delta: f64,
    /// `S`, world units.
    pub s: f64,
    delta_fix: BigInt,
    /// The parameter of the point nearest the box's centre, `ref_num / |d|^2`, both scaled
    /// by 2^298.
    ref_num: BigInt,
    d2: BigInt,
    /// That parameter, `ref_num / d2`, rounded: every offset is its crossing's `t` minus it.
    pub t_ref: f64,
    /// The box's centre.
    centre: IV,
}

/// A crossing of the exact line with a primitive.
#[derive(Clone, Copy, Debug)]
pub struct Root {
    /// The ray parameter (exact, rounded to `f64`).
    pub t: f64,
    /// `t` minus the parameter of the point nearest the scene's centre, evaluated exactly
    /// before rounding: crossings `1 -+ 1e-20` of a far ray are both `t = 1.0` in `f64`, but
    /// their offsets keep them apart for the ordering check.
    pub dt: f64,
    /// The size of the terms `dt` was computed from, which its rounding is relative to: a
    /// sphere's offset is the difference `dt_c -+ half`, which cancels to far below both when
    /// the crossing is near the reference point.
    pub dt_scale: f64,
    /// How far the displaced line's crossing may move in `t` (the rounding of the returned `t`
    /// is not included: see [`Frame::tol`]).
    pub shift: f64,
}

/// What the oracle says about one primitive.
#[derive(Clone, Debug)]
pub enum Class {
    /// Every displaced line crosses it, at each root (sorted) within its shift.
    Hit(Vec<Root>),
    /// No displaced line meets it.
    Miss,
    /// Either answer; a hit's `t` lies in `[lo, hi]` (before rounding), its offset (as
    /// [`Root::dt`]) is at least `dt_lo`.
    Ambiguous { lo: f64, hi: f64, dt_lo: f64 },
}

/// A triangle whose plane the line crosses at one point.
#[derive(Clone, Copy, Debug)]
pub struct Crossing {
    /// Signed distances of the footprint from the edges opposite corners 0, 1, 2, in the
    /// plane perpendicular to `d` (positive inside).
    pub dist: [f64; 3],
    /// The plane crossing.
    pub root: Root,
}

impl Frame {
    /// The frame of `ray` (in the domain: finite origin, finite non-zero direction) in a scene
    /// with box `bounds`.
    pub fn new(ray: &Ray, bounds: &Aabb) -> Self {
        let lo = bounds.min.as_dvec3();
        let hi = bounds.max.as_dvec3();
        let s = lo.abs().max(hi.abs()).max_element() + 4.0 * (hi - lo).max_element();
        let delta = 4.0 * ulp_f32(s);
        let d = ray.dir.as_dvec3();
        let m = d.abs().max_element();
        let (o, dv) = (IV::of(ray.origin.to_array()), IV::of(ray.dir.to_array()));
        let centre = IV::of(bounds.center().to_array());
        let (ref_num, d2) = (centre.sub(&o).dot(&dv), dv.dot(&dv));
        Self {
            ray: *ray,
            t_ref: ratio(&ref_num, &d2),
            ref_num,
            d2,
            centre,
            o,
            d: dv,
            d_len: m * (d / m).length(),
            delta,
            s,
            delta_fix: fix_up(delta),
        }
    }

    /// The tolerance of a returned `t` near `root`: its shift and 8 `f32` ulps of rounding.
    pub fn tol(&self, root: &Root) -> f64 {
        root.shift * (1.0 + SLACK) + 8.0 * ulp_f32(root.t)
    }

    /// The `f32` rounding allowed in an ordering decision: 8 ulps of `t` as it is compared
    /// after the origin has been moved near the scene (at most `2 S / |d|` from it).
    pub fn order_ulps(&self, t: f64) -> f64 {
        8.0 * ulp_f32(t.abs().min(2.0 * self.s / self.d_len))
    }

    /// The classification of `p`, with a triangle's crossing when it has one.
    pub fn classify(&self, p: &Prim) -> (Class, Option<Crossing>) {
        match *p {
            Prim::Triangle(c) => self.triangle(c),
            Prim::Sphere { center, radius } => (self.sphere(center, radius), None),
        }
    }

    fn triangle(&self, c: [Vec3; 3]) -> (Class, Option<Crossing>) {
        let p = c.map(|v| IV::of(v.to_array()));
        let n = p[1].sub(&p[0]).cross(&p[2].sub(&p[0]));
        if n.is_zero() {
            // Collinear corners: no area to cross, but a grazing line may touch the segment.
            return (self.near_box(&Aabb::from_points(c)), None);
        }
        let nd = n.dot(&self.d);
        let n_len = n.norm(2 * FRAC);
        if nd.is_zero() {
            // Parallel: off the plane by more than delta is a miss, else anywhere on it.
            let off = to_f64(&n.dot(&self.o.sub(&p[0])), 3 * FRAC).abs() / n_len;
            if off > self.delta * (1.0 + SLACK) {
                return (Class::Miss, None);
            }
            return (self.near_box(&Aabb::from_points(c)), None);
        }
        let num = n.dot(&p[0].sub(&self.o));
        let t = ratio(&num, &nd);
        let dt = ratio(&(&num * &self.d2 - &self.ref_num * &nd), &(&nd * &self.d2));
        // Moving the line by delta moves the plane crossing by delta |n| / |n.d| in t.
        let nd_f = to_f64(&nd, 3 * FRAC).abs();
        let shift = self.delta * n_len / nd_f;
        let rel = p.each_ref().map(|v| v.sub(&self.o));
        let edge = |k: usize| {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            // The edge function: d . ((p_i - o) x (p_j - o)), which sums to n.d over the
            // three edges; divided by |e x d| it is the footprint's distance from the edge.
            let e = self.d.dot(&rel[i].cross(&rel[j]));
            let side = p[j].sub(&p[i]).cross(&self.d).norm(2 * FRAC);
            let dist = to_f64(&e, 3 * FRAC) / side;
            if nd.is_negative() { -dist } else { dist }
        };
        let dist = [edge(0), edge(1), edge(2)];
        let margin = self.delta * (1.0 + SLACK);
        let root = Root {
            t,
            dt,
            dt_scale: dt.abs(),
            shift,
        };
        let class = if dist.iter().all(|&x| x > margin) {
            Class::Hit(vec![root])
        } else if dist.iter().any(|&x| x < -margin) {
            Class::Miss
        } else {
            Class::Ambiguous {
                lo: t - shift,
                hi: t + shift,
                dt_lo: dt - shift,
            }
        };
        (class, Some(Crossing { dist, root }))
    }

    fn sphere(&self, center: Vec3, radius: f32) -> Class {
        let f = self.o.sub(&IV::of(center.to_array()));
        let d = &self.d;
        let (a, b) = (d.dot(d), f.dot(d));
        let r = fix(radius);
        let r2 = &r * &r;
        let cross2 = {
            let x = f.cross(d);
            x.dot(&x)
        };
        // Squared footprint distance |f x d|^2 / |d|^2 against (r -+ delta)^2, exactly.
        let outer = &r + &self.delta_fix;
        if cross2 > &outer * &outer * &a {
            return Class::Miss;
        }
        let inner = &r - &self.delta_fix;
        let clear = inner.is_positive() && cross2 < &inner * &inner * &a;
        let (af, bf) = (to_f64(&a, 2 * FRAC), to_f64(&b, 2 * FRAC));
        let dist = (to_f64(&cross2, 4 * FRAC) / af).sqrt();
        // The closest approach's offset from the reference: (c - centre) . d / |d|^2.
        let dt_c = ratio(&IV::of(center.to_array()).sub(&self.centre).dot(d), &a);
        let (rf, delta) = (radius as f64, self.delta);
        if !clear {
            // Tangent within delta: the displaced line meets the sphere, if at all, within
            // sqrt((r + delta)^2 - dist^2) of the closest approach.
            let tc = -bf / af;
            let half = ((rf + delta).powi(2) - dist * dist).max(0.0).sqrt() / self.d_len;
            let pad = (half + delta / self.d_len) * (1.0 + SLACK) + 8.0 * ulp_f32(tc);
            return Class::Ambiguous {
                lo: tc - pad,
                hi: tc + pad,
                dt_lo: dt_c - pad,
            };
        }
        // The roots, stably: q = -(b + sign(b) sqrt(disc)), t = q / a and c / q, from the
        // exact coefficients (disc = a r^2 - |f x d|^2 by Lagrange's identity).
        let disc = to_f64(&(&a * &r2 - &cross2), 4 * FRAC);
        let c = to_f64(&(f.dot(&f) - &r2), 2 * FRAC);
        let q = -(bf + disc.sqrt().copysign(bf));
        let (t0, t1) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            let (x, y) = (q / af, c / q);
            (x.min(y), x.max(y))
        };
        let half = disc.sqrt() / af;
        // Moving the line by delta moves the closest approach by delta / |d| along it, and the
        // half chord h = sqrt(r^2 - dist^2) by at most (2 dist + delta) delta / (h + h_min).
        let h = (rf * rf - dist * dist).max(0.0).sqrt();
        let h_min = (rf * rf - (dist + delta).powi(2)).max(0.0).sqrt();
        let shift = delta / self.d_len * (1.0 + (2.0 * dist + delta) / (h + h_min)) * 1.01;
        Class::Hit(vec![
            Root {
                t: t0,
                dt: dt_c - half,
                dt_scale: dt_c.abs() + half,
                shift,
            },
            Root {
                t: t1,
                dt: dt_c + half,
                dt_scale: dt_c.abs() + half,
                shift,
            },
        ])
    }

    /// A primitive without a crossing point (collinear corners, or in a plane parallel to the
    /// ray): ambiguous over the parameters where the line is within delta of its box, a miss
    /// when there are none.
    fn near_box(&self, b: &Aabb) -> Class {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for i in 0..3 {
            let bmin = fix(b.min[i]) - &self.delta_fix;
            let bmax = fix(b.max[i]) + &self.delta_fix;
            let (o, d) = (&self.o.0[i], &self.d.0[i]);
            if d.is_zero() {
                if o < &bmin || o > &bmax {
                    return Class::Miss;
                }
                continue;
            }
            let (t1, t2) = (ratio(&(bmin - o), d), ratio(&(bmax - o), d));
            lo = lo.max(t1.min(t2));
            hi = hi.min(t1.max(t2));
        }
        let pad = (hi.abs().max(lo.abs())) * SLACK;
        if lo > hi + pad {
            return Class::Miss;
        }
        // No offset: a primitive without area never decides the order.
        Class::Ambiguous {
            lo: lo - pad,
            hi: hi + pad,
            dt_lo: f64::NEG_INFINITY,
        }
    }

    /// True when the point `o + t d` lies within `delta + 8 ulp(t) |d|` of the sphere's
    /// surface: exactly, for the `f32` value of `t` lumis returned.
    pub fn near_sphere_surface(&self, center: Vec3, radius: f32, t: f32) -> bool {
        let p = self.o.shl(FRAC).add(&self.d.scale(&fix(t)));
        let f = p.sub(&IV::of(center.to_array()).shl(FRAC));
        let eps = (self.delta + 8.0 * ulp_f32(t as f64) * self.d_len) * (1.0 + SLACK);
        let e = fix_up(eps) << FRAC;
        let r = fix(radius) << FRAC;
        let dist2 = f.dot(&f);
        let outer = &r + &e;
        let inner = &r - &e;
        dist2 <= &outer * &outer && (!inner.is_positive() || dist2 >= &inner * &inner)
    }

    /// The sign of `d . ((b - a) x (c - a))`: which side of the projected line `a b` the
    /// projected `c` lies on, seen along the ray.
    pub fn side(&self, a: Vec3, b: Vec3, c: Vec3) -> std::cmp::Ordering {
        let [a, b, c] = [a, b, c].map(|v| IV::of(v.to_array()));
        self.d
            .dot(&b.sub(&a).cross(&c.sub(&a)))
            .cmp(&BigInt::zero())
    }
}

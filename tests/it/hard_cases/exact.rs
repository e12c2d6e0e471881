//! Exact rational arithmetic on `f32` inputs: the oracle of the hard-case suite.
//!
//! Every finite `f32` is a rational number, so a ray/triangle hit, an orientation or a sign of a
//! polynomial can be decided exactly with big rationals, independently of any floating-point
//! code in lumis.

#![allow(dead_code)]

use lumis_core::math::Vec3;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

/// An exact rational.
pub type Q = BigRational;

/// The exact value of a finite `f32`.
pub fn q(x: f32) -> Q {
    BigRational::from_float(x as f64).expect("finite input")
}

/// The exact value of a finite `f64`.
pub fn q64(x: f64) -> Q {
    BigRational::from_float(x).expect("finite input")
}

/// A vector of exact rationals.
#[derive(Clone, Debug, PartialEq)]
pub struct V(pub [Q; 3]);

impl V {
    /// The exact value of an `f32` vector.
    pub fn of(v: Vec3) -> Self {
        V([q(v.x), q(v.y), q(v.z)])
    }

    pub fn sub(&self, o: &V) -> V {
        V([0, 1, 2].map(|i| &self.0[i] - &o.0[i]))
    }

    pub fn add(&self, o: &V) -> V {
        V([0, 1, 2].map(|i| &self.0[i] + &o.0[i]))
    }

    pub fn scale(&self, s: &Q) -> V {
        V([0, 1, 2].map(|i| &self.0[i] * s))
    }

    pub fn dot(&self, o: &V) -> Q {
        &self.0[0] * &o.0[0] + &self.0[1] * &o.0[1] + &self.0[2] * &o.0[2]
    }

    pub fn cross(&self, o: &V) -> V {
        let (a, b) = (&self.0, &o.0);
        V([
            &a[1] * &b[2] - &a[2] * &b[1],
            &a[2] * &b[0] - &a[0] * &b[2],
            &a[0] * &b[1] - &a[1] * &b[0],
        ])
    }

    pub fn is_zero(&self) -> bool {
        self.0.iter().all(Zero::is_zero)
    }
}

/// True when the triangle's area is exactly zero (collinear or coincident corners).
pub fn triangle_is_degenerate(p: [Vec3; 3]) -> bool {
    let [a, b, c] = p.map(V::of);
    b.sub(&a).cross(&c.sub(&a)).is_zero()
}

/// An exact ray/triangle hit: the ray parameter and the barycentrics of corners 1 and 2.
#[derive(Clone, Debug)]
pub struct ExactHit {
    pub t: Q,
    pub u: Q,
    pub v: Q,
}

impl ExactHit {
    /// True when the hit lies on an edge or a vertex of the triangle (a barycentric is 0).
    pub fn on_boundary(&self) -> bool {
        let w = Q::from_integer(BigInt::from(1)) - &self.u - &self.v;
        self.u.is_zero() || self.v.is_zero() || w.is_zero()
    }
}

/// Where the line `o + t d` meets the closed triangle `p` (edges and vertices included), in
/// exact arithmetic; `None` when it misses or is parallel to the plane. No range on `t` applied.
pub fn ray_triangle(o: Vec3, d: Vec3, p: [Vec3; 3]) -> Option<ExactHit> {
    let (o, d) = (V::of(o), V::of(d));
    let [p0, p1, p2] = p.map(V::of);
    // Solve u e1 + v e2 - t d = o - p0 by Cramer's rule.
    let (a, b) = (p1.sub(&p0), p2.sub(&p0));
    let c = V([0, 1, 2].map(|i| -&d.0[i]));
    let s = o.sub(&p0);
    let det = a.dot(&b.cross(&c));
    if det.is_zero() {
        return None;
    }
    let u = s.dot(&b.cross(&c)) / &det;
    let v = a.dot(&s.cross(&c)) / &det;
    let t = a.dot(&b.cross(&s)) / &det;
    let one = Q::from_integer(BigInt::from(1));
    let inside = !u.is_negative() && !v.is_negative() && (&u + &v) <= one;
    inside.then_some(ExactHit { t, u, v })
}

/// `|o + t d - c|^2 - r^2` at an exact `t`: negative inside the sphere, positive outside.
pub fn sphere_value(o: Vec3, d: Vec3, c: Vec3, r: f32, t: &Q) -> Q {
    let p = V::of(o).add(&V::of(d).scale(t)).sub(&V::of(c));
    p.dot(&p) - q(r) * q(r)
}

/// How far `x` lies from the exact value `exact`, in units of the `f32` spacing at `exact`.
pub fn ulps_from(x: f32, exact: &Q) -> f64 {
    let diff = (q(x) - exact).abs();
    let e = exact_to_f64(exact).abs() as f32;
    let ulp = if e == 0.0 {
        f32::from_bits(1)
    } else {
        let next = f32::from_bits(e.to_bits() + 1);
        next - e
    };
    exact_to_f64(&diff) / ulp as f64
}

/// The nearest `f64` to an exact rational (good to a few f64 ulps: enough to report errors).
pub fn exact_to_f64(x: &Q) -> f64 {
    use num_traits::ToPrimitive;
    x.to_f64().unwrap_or(f64::NAN)
}

/// The exact parameter where the line `o + t d` meets the plane of `p` (`None` if parallel).
pub fn plane_t(o: Vec3, d: Vec3, p: [Vec3; 3]) -> Option<Q> {
    let (o, d) = (V::of(o), V::of(d));
    let [p0, p1, p2] = p.map(V::of);
    let n = p1.sub(&p0).cross(&p2.sub(&p0));
    let den = n.dot(&d);
    if den.is_zero() {
        return None;
    }
    Some(n.dot(&p0.sub(&o)) / den)
}

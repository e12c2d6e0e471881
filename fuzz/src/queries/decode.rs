//! Fuzz bytes to a scene and rays. Every byte string decodes (missing bytes read as 0), and
//! the encoding is dense in the cases that matter: a few shared vertices on a lattice (shared
//! edges, duplicates, degenerate and sliver triangles), scenes placed anywhere up to the
//! coordinate limit at any scale, and ray components across the whole `f32` range, aimed at
//! the scene's vertices, edges and poles from any distance.
//!
//! Layout (fuzz/make_corpus.sh writes seeds in it; "value" and "mag" are defined below):
//!
//! ```text
//! scene:  [n] 1 + n % 12 primitives
//!         centre C: 3 x value          scale [l]: l < 128: L = 10^(l % 49 - 30) (1e-30 ..= 1e18)
//!                                      else L = max(|C_i|, 1) * 2^-(l % 24): resolved at C
//!         [m] pool of 3 + m % 6 vertices, each [k] then
//!             k < 0xe0: 3 x [i8] -> C + L * i / 4 (in f64, rounded once)   else 3 x raw f32
//!         n x primitive [k]:
//!             k even: triangle, 3 x [i] pool index i % pool
//!             k odd:  sphere, [i] centre = pool vertex, radius: k & 0x80 ? raw f32
//!                     : [e] L * 2^(e % 96 - 64) * (1 + [f] / 256)
//! rays:   [c] 1 + c % 8 rays, each
//!         origin [k] % 8: 0 raw    3 x raw f32
//!                         1 mags   3 x mag
//!                         2..=4 near  3 x [i8] -> C + L * i / 4
//!                         5..=7 afar  target T, [e][f] D = 10^(e % 39) * (1 + f / 128),
//!                                  3 x [i8] u -> T + D u / |u|
//!         dir    [k] % 8: 0 raw    3 x raw f32
//!                         1 mags   3 x mag
//!                         2 axis   [a] axis a % 3, mag along it, the others 0 or -0 (bits of a)
//!                         3..=7 aimed  target T, [a] tilt 10^-(a % 8 - 3) rad (a % 8 < 4: none)
//!                                  with 3 x [i8] sideways, [s] scale 2^(s as i8):
//!                                  d = (T - o + tilt) * 2^s in f64, rounded once
//!         t_min  [k] % 8: 0..=2 0, 3 -0, 4 -inf, 5 mag, 6 raw f32, 7 L / 1024
//!         t_max  [k] % 8: 0..=2 inf, 3 f32::MAX, 4 mag, 5 raw f32, 6 0,
//!                         7 [e] t_T * (1 +- 2^-(e % 32)) (t_T: the parameter of the last
//!                         target, else of C; - when e >= 128)
//! target: [p] p = 255: C; else primitive p % n and [f]: triangle f % 8: corner 0..=2,
//!         edge midpoint 3..=5, centroid 6, 7; sphere f % 8: centre 0, 7, else 1..=6
//!         centre +- r on an axis
//! value:  [k] % 8: 0, -0, +-10^(b % 37 - 18), +-2^(b - 64) mantissa, raw f32, [i8],
//!         +-1e18 * b / 255 (the coordinate limit)
//! mag:    [s][e][f]: s & 6 == 0: a special value (table), else
//!         +-(1 + f / 256) * 2^((s e as u16) % 277 - 149): every exponent, subnormal to 2^127
//! ```

use super::scene::Prim;
use glam::DVec3;
use lumis_core::math::{Ray, Vec3};

/// The decoded primitives (before the limits are applied) and everything needed to decode
/// the rays against the accepted ones.
pub struct Header {
    pub prims: Vec<Prim>,
    center: DVec3,
    scale: f64,
}

/// Fuzz bytes, read front to back; past the end every byte is 0.
pub struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Reader(data)
    }

    fn byte(&mut self) -> u8 {
        match self.0.split_first() {
            Some((b, rest)) => {
                self.0 = rest;
                *b
            }
            None => 0,
        }
    }

    fn raw(&mut self) -> f32 {
        f32::from_le_bytes([self.byte(), self.byte(), self.byte(), self.byte()])
    }

    fn lattice(&mut self) -> DVec3 {
        DVec3::new(self.i8(), self.i8(), self.i8()) / 4.0
    }

    fn i8(&mut self) -> f64 {
        self.byte() as i8 as f64
    }

    /// A coordinate of the scene's centre: zero, powers of ten and two, raw bits, small
    /// integers, or anywhere up to the coordinate limit.
    fn value(&mut self) -> f32 {
        let (k, b) = (self.byte(), self.byte());
        let sign = if k & 0x80 != 0 { -1.0 } else { 1.0 };
        match k % 8 {
            0 => 0.0,
            1 => -0.0,
            2 | 3 => sign * 10f32.powi(b as i32 % 37 - 18),
            4 => sign * (1.0 + self.byte() as f32 / 256.0) * 2f32.powi(b as i32 - 64),
            5 => self.raw(),
            6 => b as i8 as f32,
            _ => sign * (1e18 * (b as f64 / 255.0)) as f32,
        }
    }

    /// Any magnitude an `f32` can have, subnormal to near `f32::MAX`, either sign, or a special
    /// value.
    fn mag(&mut self) -> f32 {
        const SPECIAL: [f32; 16] = [
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            1e-45,
            f32::MAX,
            -f32::MAX,
            1e-38,
            3.4e38,
            1e30,
            1e19,
            1e18,
            1e6,
            1.0,
            -1.0,
            f32::EPSILON,
            1e-30,
        ];
        let (s, e, f) = (self.byte(), self.byte(), self.byte());
        if s & 6 == 0 {
            return SPECIAL[e as usize % 16];
        }
        let sign = if s & 1 != 0 { -1.0 } else { 1.0 };
        let exp = (u16::from_le_bytes([s, e]) % 277) as i32 - 149;
        (sign * (1.0 + f as f64 / 256.0) * 2f64.powi(exp)) as f32
    }
}

/// Rounds a point computed in `f64` to `f32` once.
fn round(p: DVec3) -> Vec3 {
    p.as_vec3()
}

/// Reads the scene part of the input.
pub fn scene(r: &mut Reader) -> Header {
    let n = 1 + r.byte() as usize % 12;
    let c = Vec3::new(r.value(), r.value(), r.value());
    // A non-finite centre leaves every lattice point non-finite: the primitives are refused.
    let center = c.as_dvec3();
    let l = r.byte();
    let scale = if l < 128 {
        10f64.powi(l as i32 % 49 - 30)
    } else {
        // Fine enough to be resolved at the centre, however far it is.
        center.abs().max_element().max(1.0) * 2f64.powi(-(l as i32 % 24))
    };
    let pool: Vec<Vec3> = (0..3 + r.byte() as usize % 6)
        .map(|_| {
            if r.byte() < 0xe0 {
                round(center + r.lattice() * scale)
            } else {
                Vec3::new(r.raw(), r.raw(), r.raw())
            }
        })
        .collect();
    let pick = |r: &mut Reader| pool[r.byte() as usize % pool.len()];
    let prims = (0..n)
        .map(|_| {
            let k = r.byte();
            if k & 1 == 0 {
                Prim::Triangle([pick(r), pick(r), pick(r)])
            } else {
                let center = pick(r);
                let radius = if k & 0x80 != 0 {
                    r.raw()
                } else {
                    let (e, f) = (r.byte(), r.byte());
                    let m = 1.0 + f as f64 / 256.0;
                    (scale * m * 2f64.powi(e as i32 % 96 - 64)) as f32
                };
                Prim::Sphere { center, radius }
            }
        })
        .collect();
    Header {
        prims,
        center,
        scale,
    }
}

/// Reads the rays against `prims`, the primitives the scene accepted (non-empty).
pub fn rays(r: &mut Reader, h: &Header, prims: &[Prim]) -> Vec<Ray> {
    let count = 1 + r.byte() as usize % 8;
    (0..count).map(|_| ray(r, h, prims)).collect()
}

fn ray(r: &mut Reader, h: &Header, prims: &[Prim]) -> Ray {
    // The last target aimed at: `t_max` may be placed just before or after it.
    let mut aim = h.center;
    let origin = match r.byte() % 8 {
        0 => Vec3::new(r.raw(), r.raw(), r.raw()),
        1 => Vec3::new(r.mag(), r.mag(), r.mag()),
        2..=4 => round(h.center + r.lattice() * h.scale),
        _ => {
            aim = target(r, h, prims);
            let (e, f) = (r.byte(), r.byte());
            let dist = 10f64.powi(e as i32 % 39) * (1.0 + f as f64 / 128.0);
            let u = r.lattice();
            let u = if u == DVec3::ZERO { DVec3::X } else { u };
            round(aim + u.normalize() * dist)
        }
    };
    let dir = match r.byte() % 8 {
        0 => Vec3::new(r.raw(), r.raw(), r.raw()),
        1 => Vec3::new(r.mag(), r.mag(), r.mag()),
        2 => {
            let a = r.byte();
            let mut d = Vec3::new(
                if a & 8 != 0 { -0.0 } else { 0.0 },
                if a & 16 != 0 { -0.0 } else { 0.0 },
                if a & 32 != 0 { -0.0 } else { 0.0 },
            );
            d[a as usize % 3] = r.mag();
            d
        }
        _ => {
            aim = target(r, h, prims);
            let to = aim - origin.as_dvec3();
            let a = r.byte() % 8;
            let side = r.lattice();
            let tilt = if a < 4 || side == DVec3::ZERO {
                DVec3::ZERO
            } else {
                // The sideways part perpendicular to the aim, `10^-a` rad of it.
                let perp = side - to * (side.dot(to) / to.length_squared().max(f64::MIN_POSITIVE));
                let len = perp.length();
                if len > 0.0 && len.is_finite() {
                    perp / len * to.length() * 10f64.powi(3 - a as i32)
                } else {
                    DVec3::ZERO
                }
            };
            round((to + tilt) * 2f64.powi(r.byte() as i8 as i32))
        }
    };
    let t_min = match r.byte() % 8 {
        0..=2 => 0.0,
        3 => -0.0,
        4 => f32::NEG_INFINITY,
        5 => r.mag(),
        6 => r.raw(),
        _ => (h.scale / 1024.0) as f32,
    };
    let t_max = match r.byte() % 8 {
        0..=2 => f32::INFINITY,
        3 => f32::MAX,
        4 => r.mag(),
        5 => r.raw(),
        6 => 0.0,
        _ => {
            let e = r.byte();
            let d = dir.as_dvec3();
            let t = (aim - origin.as_dvec3()).dot(d) / d.length_squared();
            let k = 2f64.powi(-(e as i32 % 32));
            (t * if e & 0x80 != 0 { 1.0 - k } else { 1.0 + k }) as f32
        }
    };
    Ray {
        origin,
        dir,
        t_min,
        t_max,
    }
}

/// A point of the scene to aim at: its centre, or a corner, edge midpoint, centroid, sphere
/// centre or pole of a primitive (in `f64`, rounded only as part of the ray).
fn target(r: &mut Reader, h: &Header, prims: &[Prim]) -> DVec3 {
    let p = r.byte();
    if p == 255 {
        return h.center;
    }
    let f = r.byte() as usize % 8;
    match prims[p as usize % prims.len()] {
        Prim::Triangle(c) => {
            let c = c.map(|v| v.as_dvec3());
            match f {
                0..=2 => c[f],
                3..=5 => (c[f - 3] + c[(f - 2) % 3]) / 2.0,
                _ => (c[0] + c[1] + c[2]) / 3.0,
            }
        }
        Prim::Sphere { center, radius } => {
            let mut t = center.as_dvec3();
            if (1..=6).contains(&f) {
                let sign = if f.is_multiple_of(2) { -1.0 } else { 1.0 };
                t[(f - 1) / 2] += sign * radius as f64;
            }
            t
        }
    }
}

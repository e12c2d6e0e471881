//! An independent check of the fuzz target's exact oracle (fuzz/src/queries/oracle.rs, big
//! integers in fixed point) against plain big rationals (tests/hard_cases/exact.rs), on the
//! scenes and rays the decoder makes of the first seeded inputs: degenerate and sliver
//! triangles, rays parallel to a triangle's plane or tangent to a sphere, scenes from 1e-30
//! to 1e18 and rays from anywhere in the `f32` range.
//!
//! For every primitive and ray in the domain, with `delta` the oracle's displacement bound:
//! - a triangle with a crossing point: Cramer's rule gives the exact `t` and barycentrics;
//!   the footprint's distance from edge `k` is `w_k |n.d| / |e_k x d|`. A clear hit lies
//!   more than `delta` inside every edge (so it is an exact hit, also by `ray_triangle`); a
//!   clear miss more than `delta` outside one (an exact miss); an ambiguous one within
//!   `delta` of an edge, with its exact `t` in the range the oracle allows. The oracle's `t`,
//!   offset and edge distances are the exact ones to [`RATIO_TOL`], [`RATIO_TOL`] and
//!   [`DIST_TOL`].
//! - a triangle without one (collinear corners, or parallel to the ray): never a clear hit;
//!   a clear miss only when the exact line is more than `delta` off its plane or its box.
//! - a sphere: the exact discriminant `b^2 - a c` and the footprint distance `h` from the
//!   centre. A clear hit has `h < r - delta` (so a positive discriminant) and roots that the
//!   exact ones bracket within [`ROOT_TOL`]; a clear miss has `h > r - delta` (a negative
//!   discriminant); an ambiguous one is within `delta` of tangent, its range holding both
//!   exact roots.

use super::exact::{Q, V, q64};
use super::queries::oracle::Frame;
use super::queries::{self, Prim, Scene, scene::ray_lit};
use super::{ray, seeded, sphere, tri};
use lumis_core::math::{Aabb, Ray};
use num_traits::{Signed, Zero};
use std::cmp::Ordering::{self, Less};
use std::collections::BTreeMap;
use std::time::Instant;

/// Seeded inputs checked (the first ones of the seeded run).
const INPUTS: usize = 3000;

/// The oracle's plane-crossing `t` and every crossing's offset are a quotient of exact
/// integers rounded once (a 64-bit quotient, then to `f64`): within this relative error.
const RATIO_TOL: f64 = 1.0 / (1u64 << 52) as f64;

/// A sphere's roots come from the exact coefficients rounded to `f64`, by the stable formula:
/// within this relative error of the exact root (the offsets: of the chord's half and the
/// closest approach's offset).
const ROOT_TOL: f64 = 1.0 / (1u64 << 48) as f64;

/// The oracle's edge distances, relative (it compares them with a slack of 1e-9).
const DIST_TOL: f64 = 1e-12;

/// How far beyond `delta` an ambiguous class may be granted: the oracle's slack of 1e-9 and
/// its rounding.
const LOOSE: f64 = 1.0 + 2e-9;

/// What the check saw: how many (primitive, ray) pairs fell in each case, and the largest
/// errors of the oracle's `t` found.
#[derive(Default)]
struct Seen {
    cases: BTreeMap<String, usize>,
    /// The largest relative error of a plane crossing's `t`.
    plane_t: f64,
    /// The smallest power of two bracketing every sphere root's relative error.
    root: f64,
}

impl Seen {
    fn count(&mut self, case: &str) {
        *self.cases.entry(case.to_string()).or_default() += 1;
    }
}

macro_rules! ensure {
    ($cond:expr, $($what:tt)*) => {
        if !$cond {
            return Err(format!($($what)*));
        }
    };
}

mod spheres;
mod triangles;

/// The ray, the scene's reference parameter and `delta`, exactly.
struct Exact {
    ray: Ray,
    o: V,
    d: V,
    /// `d . d`.
    dd: Q,
    /// The parameter of the point nearest the scene box's centre, `(c - o) . d / d . d`.
    t_ref: Q,
    delta: Q,
}

impl Exact {
    fn new(ray: &Ray, frame: &Frame, bounds: &Aabb) -> Self {
        let (o, d) = (V::of(ray.origin), V::of(ray.dir));
        let dd = d.dot(&d);
        let t_ref = V::of(bounds.center()).sub(&o).dot(&d) / &dd;
        Exact {
            ray: *ray,
            o,
            d,
            dd,
            t_ref,
            delta: q64(frame.delta),
        }
    }
}

/// `|x - exact| <= tol |exact|`, exactly.
fn close(x: f64, exact: &Q, tol: f64) -> bool {
    (q64(x) - exact).abs() <= q64(tol) * exact.abs()
}

/// The order of `sign * sqrt(sq)` against `m` (`sq >= 0`, `sign` the value's sign: `Equal`
/// exactly when `sq` is 0).
fn cmp_signed_sqrt(sign: Ordering, sq: &Q, m: &Q) -> Ordering {
    let m_sign = m.cmp(&Q::zero());
    if sign != m_sign {
        return sign.cmp(&m_sign);
    }
    let by_size = sq.cmp(&(m * m));
    if sign == Less {
        by_size.reverse()
    } else {
        by_size
    }
}

fn check(x: &Exact, frame: &Frame, p: &Prim, seen: &mut Seen) -> Result<(), String> {
    let (class, crossing) = frame.classify(p);
    match *p {
        Prim::Triangle(c) => triangles::triangle(x, c, class, crossing, seen),
        Prim::Sphere { center, radius } => spheres::sphere(x, center, radius, class, seen),
    }
}

/// The size classes of a ray's scene and ray, for the coverage check.
fn scales(frame: &Frame, ray: &Ray, seen: &mut Seen) {
    let (o, d) = (ray.origin.abs().max_element(), ray.dir.abs().max_element());
    for (case, yes) in [
        ("scale: scene within 1e-20", frame.s < 1e-20),
        ("scale: scene beyond 1e15", frame.s > 1e15),
        ("scale: origin beyond 1e20", o > 1e20),
        ("scale: direction below 1e-20", d < 1e-20),
        ("scale: direction beyond 1e20", d > 1e20),
    ] {
        if yes {
            seen.count(case);
        }
    }
}

/// Checks every primitive of every `(name, scene, rays)` case against every ray in the
/// domain; panics with the first disagreements (each with its scene and ray as Rust).
fn run(cases: impl Iterator<Item = (String, Scene, Vec<Ray>)>) -> Seen {
    let start = Instant::now();
    let mut seen = Seen::default();
    let (mut failures, mut rays_checked) = (Vec::new(), 0);
    for (name, scene, rays) in cases {
        let bounds = scene.geometry.bounds();
        for ray in rays.iter().filter(|r| queries::in_domain(r)) {
            rays_checked += 1;
            let frame = Frame::new(ray, &bounds);
            let x = Exact::new(ray, &frame, &bounds);
            scales(&frame, ray, &mut seen);
            for (k, p) in scene.prims.iter().enumerate() {
                if let Err(e) = check(&x, &frame, p, &mut seen) {
                    let (s, r) = (scene.literal(), ray_lit(ray));
                    failures.push(format!("{name}, primitive {k}: {e}\n{s}{r}"));
                }
            }
        }
    }
    let pairs: usize = seen
        .cases
        .iter()
        .filter(|(k, _)| !k.starts_with("scale"))
        .map(|c| c.1)
        .sum();
    println!(
        "{rays_checked} rays, {pairs} (primitive, ray) pairs in {:.1?}; largest relative error \
         of a plane crossing's t {:e}, of a sphere root <= {:e}",
        start.elapsed(),
        seen.plane_t,
        seen.root
    );
    for (case, n) in &seen.cases {
        println!("  {case}: {n}");
    }
    assert!(
        failures.is_empty(),
        "{} disagreements; the first:\n{}",
        failures.len(),
        failures[..failures.len().min(3)].join("\n")
    );
    seen
}

/// Asserts that each of `cases` was seen at least `min` times.
fn covered(seen: &Seen, cases: &[&str], min: usize) {
    for case in cases {
        let n = seen.cases.get(*case).copied().unwrap_or(0);
        assert!(n >= min, "{case}: {n} cases, fewer than {min}");
    }
}

#[test]
fn the_oracle_agrees_with_rational_arithmetic_on_decoded_scenes() {
    let cases = seeded::inputs(INPUTS).enumerate().filter_map(|(i, data)| {
        let (scene, rays) = queries::decode_input(&data)?;
        Some((format!("seeded input {i}"), scene, rays))
    });
    let seen = run(cases);
    let cases = [
        "triangle: clear hit",
        "triangle: clear miss",
        "triangle: ambiguous, an exact hit",
        "triangle: ambiguous, an exact miss",
        "degenerate triangle: clear miss",
        "degenerate triangle: ambiguous",
        "parallel triangle: clear miss",
        "parallel triangle: ambiguous",
        "sphere: clear hit",
        "sphere: clear miss",
        "sphere: ambiguous, an exact hit",
        "sphere: ambiguous, an exact miss",
        "scale: scene within 1e-20",
        "scale: scene beyond 1e15",
        "scale: origin beyond 1e20",
        "scale: direction below 1e-20",
        "scale: direction beyond 1e20",
    ];
    covered(&seen, &cases, 5);
}

/// Exact tangents are rare in decoded scenes: rays in the plane `x = 4 s` tangent to the
/// sphere of radius `s` at `(3 s, 0, 0)` (and passing within an `f32` ulp of the spheres of
/// the next radii up and down), lying in a triangle's plane, parallel to another's, along a
/// degenerate triangle, with `s` from `2^-140` (subnormal) to `2^57`, origins from `4 s` to
/// `2^100` away and directions from `2^-120` to `2^100` long.
#[test]
fn the_oracle_agrees_with_rational_arithmetic_on_tangent_and_parallel_rays() {
    let mut cases = Vec::new();
    for e in [-140, -126, -90, -40, 0, 30, 57] {
        // In f64: `2f32.powi(-140)` is 0 (a reciprocal of 2^140).
        let pow2 = |k: i32| 2f64.powi(k) as f32;
        let s = pow2(e);
        let prims = [
            sphere([3.0 * s, 0.0, 0.0], s),
            sphere([3.0 * s, 0.0, 0.0], s.next_up()),
            sphere([3.0 * s, 0.0, 0.0], s.next_down()),
            tri([4.0 * s, -s, -s], [4.0 * s, s, -s], [4.0 * s, 0.0, 2.0 * s]),
            tri([5.0 * s, -s, -s], [5.0 * s, s, -s], [5.0 * s, 0.0, 2.0 * s]),
            tri(
                [4.0 * s, s, s],
                [4.0 * s, 2.0 * s, 2.0 * s],
                [4.0 * s, 3.0 * s, 3.0 * s],
            ),
            tri(
                [0.0, s, s],
                [0.0, 2.0 * s, 2.0 * s],
                [0.0, 3.0 * s, 3.0 * s],
            ),
        ];
        let mut rays = Vec::new();
        for (dy, dz) in [(1.0, 1.0), (1.0, 0.0), (0.0, 1.0), (1.0, 3.0)] {
            for away in [4.0 * s, pow2(e + 30), pow2(100)] {
                for k in [-120, 0, 100] {
                    let d = pow2(k);
                    rays.push(ray(
                        [4.0 * s, -away * dy, -away * dz],
                        [0.0, dy * d, dz * d],
                    ));
                }
            }
        }
        cases.push((format!("s = 2^{e}"), super::scene(&prims), rays));
    }
    let seen = run(cases.into_iter());
    let cases = [
        "sphere: ambiguous, exactly tangent",
        "sphere: ambiguous, an exact hit",
        "sphere: ambiguous, an exact miss",
        "parallel triangle: ambiguous",
        "parallel triangle: clear miss",
        "degenerate triangle: ambiguous",
        "degenerate triangle: clear miss",
    ];
    covered(&seen, &cases, 50);
}

//! What a query may answer, from the oracle's classification of every primitive
//! ([`super::oracle`]), and the check of one answer against it.
//!
//! - A returned hit's primitive is never clearly missed, its `t` lies within tolerance of that
//!   primitive's exact crossing (a sphere: of a root, and the point near the surface).
//! - When a primitive is clearly hit at a `t` clearly inside `(t_min, min(t_max, f32::MAX)]`
//!   (a `t` beyond `f32::MAX` is a miss), the query hits, at most that `t` plus tolerance, and
//!   the returned primitive's exact crossing is not beyond it either (the front face of a far
//!   sphere mesh, not the back one whose `t` rounds to the same `f32`).
//! - Two triangles sharing an edge, on opposite sides of it as seen along the ray, with the
//!   footprint clearly inside both of their other edges: every displaced line crosses one of
//!   them, so the pair counts as a clear hit (watertightness).
//! - `occluded` is true whenever a hit is certain, false when every primitive is clearly
//!   missed or crossed only clearly out of range.

use super::oracle::{Class, Crossing, Frame, Root};
use super::scene::Prim;
use lumis_core::accel::Hit;
use std::fmt::Write;

/// How a crossing lies relative to the ray's range, given its tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Range {
    In,
    Out,
    Edge,
}

/// A hit the query must return.
#[derive(Clone, Debug)]
struct Must {
    /// The returned `t` may not exceed this.
    bound: f64,
    why: String,
}

/// The oracle's expectations for one ray.
pub struct Expect {
    classes: Vec<(Class, Option<Crossing>)>,
    must: Option<Must>,
    /// The clear crossing in range with the smallest exact offset ([`Root::dt`]), and its
    /// primitive: no other primitive may be returned whose exact crossing lies beyond it
    /// (compared by offset, since `f64` may not tell the `t` of far crossings apart).
    nearest: Option<(u32, Root)>,
    /// True when no primitive can be hit in range.
    none: bool,
    /// The oracle contradicting itself (a checker bug, not a lumis one), if it does.
    broken: Option<String>,
}

impl Expect {
    /// Classifies every primitive of the scene for the ray of `frame`.
    pub fn new(frame: &Frame, prims: &[Prim]) -> Self {
        let classes: Vec<_> = prims.iter().map(|p| frame.classify(p)).collect();
        let mut must: Option<Must> = None;
        let mut offer = |m: Must| {
            if must.as_ref().is_none_or(|b| m.bound < b.bound) {
                must = Some(m);
            }
        };
        let mut nearest: Option<(u32, Root)> = None;
        let mut none = true;
        for (i, (class, _)) in classes.iter().enumerate() {
            match class {
                Class::Miss => {}
                Class::Hit(roots) => {
                    for r in roots {
                        let range = range(frame, r.t, frame.tol(r));
                        none &= range == Range::Out;
                        if range == Range::In {
                            offer(Must {
                                bound: r.t + frame.tol(r),
                                why: format!("primitive {i} is clearly hit at t = {:e}", r.t),
                            });
                            if nearest.is_none_or(|(_, n)| r.dt < n.dt) {
                                nearest = Some((i as u32, *r));
                            }
                        }
                    }
                }
                Class::Ambiguous { lo, hi, .. } => {
                    let u = 8.0 * fixed_ulp(lo.abs().max(hi.abs()));
                    none &= hi + u < t_lo(frame) || lo - u > t_hi(frame);
                }
            }
        }
        for (i, j, bound) in watertight_pairs(frame, prims, &classes) {
            offer(Must {
                bound,
                why: format!(
                    "triangles {i} and {j} share an edge the ray crosses: one of them is hit"
                ),
            });
        }
        let broken = inconsistent_offset(frame, &classes);
        Self {
            classes,
            must,
            nearest,
            none,
            broken,
        }
    }

    /// Whether a hit is certain, and whether none is possible.
    pub fn certain(&self) -> (bool, bool) {
        (self.must.is_some(), self.none)
    }

    /// Checks one query's nearest hit and occlusion answers.
    pub fn check(
        &self,
        frame: &Frame,
        prims: &[Prim],
        hit: Option<&Hit>,
        occluded: bool,
    ) -> Result<(), String> {
        if let Some(b) = &self.broken {
            return Err(format!("oracle: {b}"));
        }
        if let Some(h) = hit {
            self.check_hit(frame, prims, h)?;
        } else if let Some(m) = &self.must {
            return Err(format!("lost hit: {}", m.why));
        }
        if let (Some(m), false) = (&self.must, occluded) {
            return Err(format!("occluded is false, but {}", m.why));
        }
        if self.none && occluded {
            return Err(
                "occluded is true, but every primitive is clearly missed or crossed \
                        clearly out of range"
                    .into(),
            );
        }
        Ok(())
    }

    fn check_hit(&self, frame: &Frame, prims: &[Prim], h: &Hit) -> Result<(), String> {
        let (p, t) = (h.prim as usize, h.hit.t);
        let tf = t as f64;
        // The returned primitive's exact crossing (as an offset, `Root::dt`) and how far it
        // may move.
        let (exact, shift) = match &self.classes[p].0 {
            Class::Miss => return Err(format!("false hit: primitive {p} is clearly missed")),
            Class::Hit(roots) => {
                // Of two roots within tolerance (a far small sphere), the front one.
                let r = roots
                    .iter()
                    .find(|r| (tf - r.t).abs() <= frame.tol(r))
                    .ok_or_else(|| {
                        let list: Vec<String> = roots.iter().map(|r| format!("{:e}", r.t)).collect();
                        format!("t = {t:e} is not within tolerance of primitive {p}'s exact crossing(s) {list:?}")
                    })?;
                (r.dt, r.shift)
            }
            Class::Ambiguous { lo, hi, dt_lo } => {
                let u = 8.0 * fixed_ulp(tf);
                if tf < lo - u || tf > hi + u {
                    return Err(format!(
                        "t = {t:e} is outside [{lo:e}, {hi:e}], where a displaced ray can meet \
                         primitive {p}"
                    ));
                }
                (*dt_lo, 0.0)
            }
        };
        if let Prim::Sphere { center, radius } = prims[p]
            && !frame.near_sphere_surface(center, radius, t)
        {
            return Err(format!(
                "o + t d at t = {t:e} is not within delta + 8 ulp(t) |d| of sphere {p}'s surface"
            ));
        }
        let Some(m) = &self.must else { return Ok(()) };
        if tf > m.bound {
            return Err(format!(
                "wrong order: t = {t:e} on primitive {p} is beyond {:e}, but {}",
                m.bound, m.why
            ));
        }
        if let Some((q, r)) = self.nearest {
            let limit = r.dt + (r.shift + shift) * 1.01 + frame.order_ulps(r.t);
            if exact > limit && q as usize != p {
                return Err(format!(
                    "wrong primitive: {p}, whose exact crossing lies {:e} beyond primitive \
                     {q}'s clear crossing t = {:e} (more than the displacement allows, {:e}; \
                     as offsets from t_ref = {:e}: {exact:e} against {:e})",
                    exact - r.dt,
                    r.t,
                    limit - r.dt,
                    frame.t_ref,
                    r.dt
                ));
            }
        }
        Ok(())
    }

    /// The classification, one line per primitive, for a failure report.
    pub fn describe(&self) -> String {
        let mut s = String::new();
        for (i, (class, crossing)) in self.classes.iter().enumerate() {
            let _ = write!(s, "  prim {i}: {class:?}");
            if let Some(c) = crossing {
                let _ = write!(s, ", edge distances {:?}", c.dist.map(|d| format!("{d:e}")));
            }
            s.push('\n');
        }
        s
    }
}

/// The first crossing whose offset ([`Root::dt`]) is not its `t` minus the reference
/// parameter `t_ref`, beyond the rounding of the three: the ordering check compares offsets,
/// so an offset with a wrong sign or scale (as the spheres' once had) would blame a correct
/// answer while every printed `t` looks right. A sphere's offset is a difference that may
/// cancel (its crossing at the reference point): its rounding counts against the size of the
/// terms ([`Root::dt_scale`]), not of the result.
fn inconsistent_offset(frame: &Frame, classes: &[(Class, Option<Crossing>)]) -> Option<String> {
    let t_ref = frame.t_ref;
    // `width`: the magnitude of a pad subtracted from both (an ambiguous range's).
    let bad = |what: &str, t: f64, dt: f64, width: f64| {
        let err = (t - dt - t_ref).abs();
        let scale = t.abs() + dt.abs() + t_ref.abs() + width;
        (scale.is_finite() && err > 1e-12 * scale).then(|| {
            format!(
                "{what} t = {t:e} has the offset {dt:e}, but t - t_ref = {:e}",
                t - t_ref
            )
        })
    };
    classes
        .iter()
        .enumerate()
        .find_map(|(i, (class, _))| match class {
            Class::Hit(roots) => roots.iter().find_map(|r| {
                let what = format!("primitive {i}'s crossing");
                bad(&what, r.t, r.dt, r.dt_scale)
            }),
            Class::Ambiguous { lo, hi, dt_lo } if dt_lo.is_finite() => {
                let what = format!("primitive {i}'s earliest crossing");
                bad(&what, *lo, *dt_lo, hi - lo)
            }
            _ => None,
        })
}

/// The start of the range: `t_min`, or `-f32::MAX` (a `t` beyond is no `f32`).
fn t_lo(frame: &Frame) -> f64 {
    frame.ray.t_min.max(-f32::MAX) as f64
}

/// The end of the range: `t_max`, or `f32::MAX` (a larger `t` is no `f32`).
fn t_hi(frame: &Frame) -> f64 {
    frame.ray.t_max.min(f32::MAX) as f64
}

fn range(frame: &Frame, t: f64, tol: f64) -> Range {
    let (lo, hi) = (t_lo(frame), t_hi(frame));
    if t - tol > lo && t + tol < hi {
        Range::In
    } else if t + tol < lo || t - tol > hi {
        Range::Out
    } else {
        Range::Edge
    }
}

fn fixed_ulp(t: f64) -> f64 {
    super::fixed::ulp_f32(t)
}

/// Pairs of triangles that share an edge the footprint lies on (within delta), on opposite
/// sides of it along the ray, with the footprint clearly inside both triangles' other edges
/// and both crossings clearly in range: with the bound on the returned `t`.
fn watertight_pairs(
    frame: &Frame,
    prims: &[Prim],
    classes: &[(Class, Option<Crossing>)],
) -> Vec<(usize, usize, f64)> {
    let margin = frame.delta * 1.000_001;
    let mut out = Vec::new();
    let tri = |i: usize| match (&prims[i], &classes[i].1) {
        (Prim::Triangle(c), Some(x)) => Some((*c, *x)),
        _ => None,
    };
    for i in 0..prims.len() {
        let Some((ci, xi)) = tri(i) else { continue };
        for j in i + 1..prims.len() {
            let Some((cj, xj)) = tri(j) else { continue };
            for ki in 0..3 {
                let (a, b) = (ci[(ki + 1) % 3], ci[(ki + 2) % 3]);
                let Some(kj) = (0..3).find(|&k| {
                    let (c, d) = (cj[(k + 1) % 3], cj[(k + 2) % 3]);
                    (c == a && d == b) || (c == b && d == a)
                }) else {
                    continue;
                };
                let others_inside =
                    |x: &Crossing, k: usize| (0..3).all(|e| e == k || x.dist[e] > margin);
                if !(others_inside(&xi, ki) && others_inside(&xj, kj)) {
                    continue;
                }
                let (si, sj) = (frame.side(a, b, ci[ki]), frame.side(a, b, cj[kj]));
                if si.is_eq() || sj.is_eq() || si == sj {
                    continue;
                }
                let (ri, rj) = (xi.root, xj.root);
                let (ti, tj) = (frame.tol(&ri), frame.tol(&rj));
                if range(frame, ri.t, ti) == Range::In && range(frame, rj.t, tj) == Range::In {
                    out.push((i, j, (ri.t + ti).max(rj.t + tj)));
                }
            }
        }
    }
    out
}

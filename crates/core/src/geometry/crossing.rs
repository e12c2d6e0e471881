//! What one primitive contributes to an all-hits query ([`crate::accel::Accel::all_hits_geometry`]):
//! its [`Contact`]s with a ray, each a surface crossing, a graze, or a touch of a triangle's
//! boundary that the query resolves together with the other triangles touched there.
//!
//! ## The rule
//!
//! The watertight test ([`super::intersect_triangle`]) is inclusive: its edge decisions are the
//! exact signs of the sheared edge functions, and a ray through an edge shared by two triangles
//! hits both (through a vertex, every triangle around it that it touches). Counting each of
//! those as a crossing breaks inside/outside parity. Here a hit whose exact edge functions are
//! all non-zero is a plain crossing; a hit with a zero edge function (on an edge) or two (on a
//! vertex) is decided by *symbolic perturbation*: the ray is displaced by the infinitesimal
//! `(eps, eps^2)` in the test's sheared 2-D plane (its origin moved by `eps` along world axis
//! `kx` and `eps^2` along `ky`), so a zero edge function `E` of the directed edge `p -> q`
//! takes the sign of
//!
//! ```text
//! dE/d(eps)   = Y(q) - Y(p) = (q - p)[ky] - (d[ky] / d[kz]) (q - p)[kz]
//! dE/d(eps^2) = X(p) - X(q) = (q - p)[kz] (d[kx] / d[kz]) - (q - p)[kx]
//! ```
//!
//! the first where it is non-zero, else the second (both zero only for an edge parallel to the
//! ray, whose triangle is edge-on and never hit). Both are evaluated exactly from the `f32`
//! inputs with the *exact* shear ratios, multiplied out by `d[kz]` (the `f32` shear is rounded
//! and is not used), and depend only on the edge's two vertices and the direction: the two
//! triangles sharing an edge traverse it in opposite directions, so they get opposite signs and
//! exactly one of them *claims* the perturbed ray when it crosses the edge from one to the
//! other, none or both when the edge is a silhouette. A triangle claims the ray when every
//! perturbed sign agrees with its non-zero ones.
//!
//! The perturbed ray meets every surface generically, so the claims count its crossings. To
//! also report the touches that are not crossings, the touches of one mesh at one place are
//! grouped ([`Seam`]: the same edge, or the same vertex, by exact position) and the group gives
//! one hit: a crossing when an odd number of its members claims the ray, else a graze.
//!
//! Spheres: two roots are two crossings; a root inside the tangency band of
//! [`super::Sphere::intersect_double`] (`|disc| <= 2^-95 |d|^2 r^2`) is one graze.

use std::cmp::Ordering;

use super::conditioning::Shear64;
use super::exact::edge_sign;
use super::twofloat::{two_prod, two_sum};
use super::{Geometry, PrimHit, Primitive, Sphere, WatertightRay};
use crate::geometry::Precision;
use crate::math::{Ray, Vec3};

/// A place on a mesh's surface where a ray touched the boundary of one or more triangles: an
/// edge (its end points in increasing order) or a vertex, as exact `f32` bit patterns (`-0` as
/// `+0`), so triangles of a mesh whose vertices were not welded still meet at one seam.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Seam {
    /// Through the inside of an edge.
    Edge { mesh: u32, ends: [[u32; 3]; 2] },
    /// Through a vertex.
    Vertex { mesh: u32, at: [u32; 3] },
}

/// How a ray meets a primitive at one point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Touch {
    /// Through a triangle's interior or at a simple root of a sphere.
    Crossing,
    /// A tangent sphere root.
    Graze,
    /// On a triangle's boundary: `claims` when the perturbed ray crosses this triangle.
    Boundary { seam: Seam, claims: bool },
}

/// One meeting of a ray with a primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The primitive index.
    pub prim: u32,
    /// Distance (on the ray tested) and barycentrics, as the nearest-hit test reports them.
    pub hit: PrimHit,
    /// Crossing, graze, or a boundary touch to resolve with the rest of its seam.
    pub touch: Touch,
}

impl Geometry {
    /// Pushes onto `out` every contact of `ray` with primitive `index` in `(t_min, t_max]`:
    /// none, one, or a sphere's two. A triangle is touched exactly where the nearest-hit test
    /// hits it (the watertight test, or the double one for [`Precision::Double`]; the
    /// non-exact `Fast` test is not used: it would break the rule), so every distance is one
    /// that test reports. `wr` is the ray's shear.
    pub fn contacts(
        &self,
        index: u32,
        ray: &Ray,
        wr: &WatertightRay,
        precision: Precision,
        out: &mut Vec<Contact>,
    ) {
        let double = precision == Precision::Double;
        match self.prims[index as usize] {
            Primitive::Triangle { mesh, tri } => {
                let hit = if double {
                    self.intersect_double(index, ray)
                } else {
                    self.intersect(index, ray, wr)
                };
                let Some(hit) = hit else { return };
                let corners = self.meshes[mesh as usize].corners(tri);
                out.extend(triangle_contact(index, hit, ray, wr, corners, mesh));
            }
            Primitive::Sphere { sphere } => {
                let s = &self.spheres[sphere as usize];
                let test = |r: &Ray| {
                    if double {
                        s.intersect_double(r)
                    } else {
                        s.intersect(r)
                    }
                };
                let Some(first) = test(ray) else { return };
                let contact = |t: f32, touch| Contact {
                    prim: index,
                    hit: PrimHit {
                        t,
                        u: 0.0,
                        v: 0.0,
                        inner: 0,
                    },
                    touch,
                };
                let census = root_census(s, ray);
                if census.tangent {
                    out.push(contact(first, Touch::Graze));
                    return;
                }
                out.push(contact(first, Touch::Crossing));
                let second = test(&Ray {
                    t_min: first,
                    ..*ray
                });
                match second {
                    Some(t) => out.push(contact(t, Touch::Crossing)),
                    // Both roots in range but rounded to one `f32`: two crossings at one `t`.
                    None if census.in_range == 2 => out.push(contact(first, Touch::Crossing)),
                    None => {}
                }
            }
            Primitive::Instance { instance } => {
                self.instance_contacts(instance, index, ray, precision, out)
            }
        }
    }
}

/// The contact of a triangle (primitive `index` of mesh `mesh`, corners `corners`) that the
/// triangle test hit at `hit` (see [`Geometry::contacts`]); `wr` is the ray's shear.
#[inline]
pub(crate) fn triangle_contact(
    index: u32,
    hit: PrimHit,
    ray: &Ray,
    wr: &WatertightRay,
    corners: [Vec3; 3],
    mesh: u32,
) -> Option<Contact> {
    let touch = triangle_touch(ray, [wr.kx, wr.ky, wr.kz], corners, mesh)?;
    Some(Contact {
        prim: index,
        hit,
        touch,
    })
}

/// How a touched triangle is met: `None` when the exact edge signs say it is not touched at
/// all (only where the caller's hit came from elsewhere; the triangle tests never do that).
fn triangle_touch(ray: &Ray, k: [usize; 3], p: [Vec3; 3], mesh: u32) -> Option<Touch> {
    let shear = Shear64::new(ray, k);
    // Edge i runs from corner i + 1 to corner i + 2, as in the triangle test.
    let ends = |i: usize| (p[(i + 1) % 3], p[(i + 2) % 3]);
    let signs: [Ordering; 3] = std::array::from_fn(|i| {
        let (a, b) = ends(i);
        let (e, bound) = shear.edge(a, b);
        if e.abs() > bound {
            e.total_cmp(&0.0)
        } else {
            edge_sign(ray.origin, ray.dir, a, b, k)
        }
    });
    let side = *signs.iter().find(|s| s.is_ne())?;
    if signs.iter().any(|s| *s == side.reverse()) {
        return None;
    }
    let mut zero = [0; 3];
    let mut zeros = 0;
    for (i, s) in signs.iter().enumerate() {
        if s.is_eq() {
            zero[zeros] = i;
            zeros += 1;
        }
    }
    let zero = &zero[..zeros];
    let claims = zero.iter().all(|&i| {
        let (a, b) = ends(i);
        perturbed_sign(ray.dir, a, b, k) == side
    });
    let seam = match *zero {
        [] => return Some(Touch::Crossing),
        [i] => {
            let (a, b) = ends(i);
            let (a, b) = (position_key(a), position_key(b));
            Seam::Edge {
                mesh,
                ends: [a.min(b), a.max(b)],
            }
        }
        // Two zero edges meet at the corner neither leaves out.
        [i, j] => Seam::Vertex {
            mesh,
            at: position_key(p[3 - i - j]),
        },
        _ => return None,
    };
    Some(Touch::Boundary { seam, claims })
}

/// A position as the bits of its coordinates, `-0` taken as `+0`.
fn position_key(v: Vec3) -> [u32; 3] {
    (v + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// The sign a zero edge function of the directed edge `p -> q` takes when the ray is displaced
/// by `(eps, eps^2)` in the sheared plane of axes `k` (see the module docs): exact, from the
/// edge and the direction only. `Equal` only for an edge parallel to `d`.
pub(crate) fn perturbed_sign(d: Vec3, p: Vec3, q: Vec3, k: [usize; 3]) -> Ordering {
    let [kx, ky, kz] = k;
    let dz = d[kz] as f64;
    // Multiplying by d[kz] scales both derivatives by it: undo its sign.
    let unscale = |s: Ordering| if dz < 0.0 { s.reverse() } else { s };
    // (q - p)[ky] d[kz] - d[ky] (q - p)[kz]: d/d(eps) of the edge function, times d[kz].
    let first = cross_of_difference(p[ky], q[ky], d[kz], p[kz], q[kz], d[ky]);
    if first.is_ne() {
        return unscale(first);
    }
    // -((q - p)[kx] d[kz] - d[kx] (q - p)[kz]): d/d(eps^2), times d[kz].
    let second = cross_of_difference(p[kx], q[kx], d[kz], p[kz], q[kz], d[kx]);
    unscale(second.reverse())
}

/// Sign of `(b1 - a1) s1 - (b2 - a2) s2` in exact arithmetic on the `f32` inputs: each
/// difference split into its rounded value and error (two-sum), every product of those with
/// `s` expanded exactly (two-product), the eight terms summed as a non-overlapping expansion.
fn cross_of_difference(a1: f32, b1: f32, s1: f32, a2: f32, b2: f32, s2: f32) -> Ordering {
    let (h1, l1) = two_sum(b1 as f64, -(a1 as f64)).parts();
    let (h2, l2) = two_sum(b2 as f64, -(a2 as f64)).parts();
    // Eight terms: the expansion never holds more.
    let mut e = [0.0; 8];
    let mut len = 0;
    for (x, s) in [
        (h1, s1 as f64),
        (l1, s1 as f64),
        (-h2, s2 as f64),
        (-l2, s2 as f64),
    ] {
        let (hi, lo) = two_prod(x, s).parts();
        len = grow(&mut e, len, lo);
        len = grow(&mut e, len, hi);
    }
    e[..len]
        .last()
        .map_or(Ordering::Equal, |x| x.total_cmp(&0.0))
}

/// Adds `b` to the expansion `e[..len]` (non-overlapping, increasing magnitude, no zeros),
/// keeping it so, and returns its new length: Shewchuk's GROW-EXPANSION with zero
/// elimination (as in [`super::exact`]). `e` has room for one more term than `len`.
fn grow(e: &mut [f64; 8], len: usize, b: f64) -> usize {
    let mut q = b;
    let mut out = 0;
    for i in 0..len {
        let (s, h) = two_sum(q, e[i]).parts();
        q = s;
        if h != 0.0 {
            e[out] = h;
            out += 1;
        }
    }
    if q != 0.0 {
        e[out] = q;
        out += 1;
    }
    out
}

/// A sphere's roots along a ray, as [`Sphere::intersect_double`] computes them.
struct RootCensus {
    /// The double-double discriminant lies in the tangency band.
    tangent: bool,
    /// How many of the two roots (rounded to `f32`) lie in `(t_min, t_max]`.
    in_range: usize,
}

/// The census of `s`'s roots along `ray`, from [`Sphere::dd_roots`] (the formulas of
/// [`Sphere::intersect_double`]): a discriminant in the tangency band is a tangent, with no
/// root in range.
fn root_census(s: &Sphere, ray: &Ray) -> RootCensus {
    let super::sphere::DdRoots { band, roots } = s.dd_roots(ray);
    let in_range = match roots {
        Some((t0, t1)) if !band => {
            let ok = |t: f32| t > ray.t_min && t <= ray.t_max && t.is_finite();
            ok(t0) as usize + ok(t1) as usize
        }
        _ => 0,
    };
    RootCensus {
        tangent: band,
        in_range,
    }
}

#[cfg(test)]
mod tests;

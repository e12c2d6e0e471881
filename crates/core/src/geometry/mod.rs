//! Primitives: analytic spheres and triangles of indexed meshes, both first-class.
//!
//! [`Geometry`] owns the shapes and a flat list of [`Primitive`]s; accelerators refer to
//! primitives by their index in that list and see only their bounding boxes.

mod accuracy;
mod conditioning;
pub(crate) mod crossing;
pub(crate) mod edge_bound;
mod exact;
mod exact3d;
pub mod frame;
mod instance;
mod instance_entries;
mod mesh;
mod mesh_attributes;
mod placement;
mod polygon;
mod sphere;
mod surface;
pub(crate) mod triangle;
pub(crate) mod twofloat;

pub use accuracy::{DEFAULT_EPSILON, Offset, Precision, check_cutoff, check_epsilon};
pub use crossing::{Contact, Seam, Touch};
pub use exact::{cross_sign, orient2d, triangle_area_is_zero};
pub use exact3d::{ball_contains, normal_dot_sign, on_triangle, orient3d};
pub use instance::{Instance, PrototypeQueries};
pub(crate) use instance_entries::{ENTRY_BLOCK, Entries, Entry};
pub use mesh::{Mesh, MeshError};
pub use mesh_attributes::{AlphaTest, HitAttributes, MeshAttributes, SharedAlphaTest};
pub use placement::{Placement, PlacementError, leaves_no_area};
pub use polygon::{Triangulation, newell_normal, triangulate_polygon};
pub use sphere::Sphere;
pub use surface::SurfacePoint;
pub use triangle::{
    TriangleHit, WatertightRay, face_normal, intersect_triangle, intersect_triangle_double,
    intersect_triangle_fast, unit_face_normal,
};

use crate::math::{Aabb, Ray, Vec2, Vec3};
use glam::DVec3;
use surface::rounded_with_error;

/// Runs `$body` with `$test` bound to the primitive test `$precision` selects, as a closure
/// `Fn(u32, &Ray) -> Option<PrimHit>` over `$geometry` (a macro, because each arm gives the
/// traversal a different closure type: the choice is made once per ray, not per primitive).
macro_rules! with_prim_test {
    ($geometry:expr, $precision:expr, $ray:expr, |$test:ident| $body:expr) => {{
        let g = $geometry;
        match $precision {
            $crate::geometry::Precision::Watertight => {
                let wr = $crate::geometry::WatertightRay::new($ray.dir);
                let $test = |p: u32, r: &$crate::math::Ray| g.intersect(p, r, &wr);
                $body
            }
            $crate::geometry::Precision::Fast => {
                let $test = |p: u32, r: &$crate::math::Ray| g.intersect_fast(p, r);
                $body
            }
            $crate::geometry::Precision::Double => {
                let $test = |p: u32, r: &$crate::math::Ray| g.intersect_double(p, r);
                $body
            }
        }
    }};
}
pub(crate) use with_prim_test;

/// One intersectable primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Primitive {
    /// `Geometry::spheres()[index]`.
    Sphere { sphere: u32 },
    /// Triangle `tri` of `Geometry::meshes()[mesh]`.
    Triangle { mesh: u32, tri: u32 },
    /// `Geometry::instances()[instance]`: a prototype placed by a transform.
    Instance { instance: u32 },
}

/// A ray/primitive hit before shading: the distance and the barycentrics (0 for spheres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimHit {
    /// Ray parameter.
    pub t: f32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
    /// For a hit on an instance, the primitive of its prototype that was hit (0 otherwise).
    pub inner: u32,
}

/// All shapes of a scene and the flat primitive list the accelerators index.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    spheres: Vec<Sphere>,
    meshes: Vec<Mesh>,
    prims: Vec<Primitive>,
    /// Some mesh has an alpha test: lets intersection skip the look-up otherwise.
    any_alpha: bool,
    /// What instances place, and the placements.
    prototypes: Vec<std::sync::Arc<dyn PrototypeQueries>>,
    instances: Vec<Instance>,
    /// Some primitive is an instance: lets hit records skip the look-up otherwise.
    any_instances: bool,
}

impl Geometry {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a sphere; returns its primitive index.
    pub fn add_sphere(&mut self, s: Sphere) -> u32 {
        self.spheres.push(s);
        self.prims.push(Primitive::Sphere {
            sphere: self.spheres.len() as u32 - 1,
        });
        self.prims.len() as u32 - 1
    }

    /// Adds a mesh; returns the primitive index range of its triangles.
    pub fn add_mesh(&mut self, m: Mesh) -> std::ops::Range<u32> {
        let mesh = self.meshes.len() as u32;
        let first = self.prims.len() as u32;
        self.prims
            .extend((0..m.triangle_count() as u32).map(|tri| Primitive::Triangle { mesh, tri }));
        self.any_alpha |= m.alpha_test().is_some();
        self.meshes.push(m);
        first..self.prims.len() as u32
    }

    /// Bytes of the shapes and the primitive list (what the scene holds before any hierarchy).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.spheres.as_slice())
            + self.meshes.iter().map(Mesh::bytes).sum::<usize>()
            + std::mem::size_of_val(self.prims.as_slice())
            + self.prototypes.iter().map(|p| p.bytes()).sum::<usize>()
            + std::mem::size_of_val(self.instances.as_slice())
    }

    /// The primitive list.
    pub fn prims(&self) -> &[Primitive] {
        &self.prims
    }

    /// The spheres.
    pub fn spheres(&self) -> &[Sphere] {
        &self.spheres
    }

    /// The meshes.
    pub fn meshes(&self) -> &[Mesh] {
        &self.meshes
    }

    /// Bounding box of every primitive, in primitive order: all an accelerator builder sees.
    pub fn prim_bounds(&self) -> Vec<Aabb> {
        self.prims.iter().map(|p| self.bounds_of(*p)).collect()
    }

    /// Bounding box of one primitive.
    pub fn bounds_of(&self, p: Primitive) -> Aabb {
        match p {
            Primitive::Sphere { sphere } => self.spheres[sphere as usize].bounds(),
            Primitive::Triangle { mesh, tri } => self.meshes[mesh as usize].triangle_bounds(tri),
            Primitive::Instance { instance } => self.instances[instance as usize].bounds,
        }
    }

    /// Bounds of everything.
    pub fn bounds(&self) -> Aabb {
        let s = self
            .spheres
            .iter()
            .fold(Aabb::EMPTY, |b, s| b.union(s.bounds()));
        let i = self.instances.iter().fold(s, |b, i| b.union(i.bounds));
        self.meshes.iter().fold(i, |b, m| b.union(m.bounds()))
    }

    /// Intersects primitive `index` with `ray` in `(t_min, t_max]` with the default
    /// (watertight) tests; `wr` is the ray's shear.
    #[inline]
    pub fn intersect(&self, index: u32, ray: &Ray, wr: &WatertightRay) -> Option<PrimHit> {
        self.intersect_by(
            index,
            |s| s.intersect(ray),
            |[p0, p1, p2]| intersect_triangle(ray, wr, p0, p1, p2),
            |i| self.intersect_instance(i, ray, Precision::Watertight),
        )
    }

    /// [`Geometry::intersect`] with the `--precision fast` tests.
    ///
    /// Their `t` can be off by thousands of ulps, or land far from the primitive (catastrophic
    /// cancellation in `f32`), where a hierarchy's box tests would never look for it. So a hit
    /// counts only where the ray is inside the primitive's own box, as the traversals compute
    /// that box's entry and exit for this ray: then every box around the primitive is entered
    /// at that `t` too, and every accelerator finds exactly the hits brute force finds.
    #[inline]
    pub fn intersect_fast(&self, index: u32, ray: &Ray) -> Option<PrimHit> {
        self.intersect_by(
            index,
            |s| s.intersect_fast(ray),
            |[p0, p1, p2]| intersect_triangle_fast(ray, p0, p1, p2),
            |i| self.intersect_instance(i, ray, Precision::Fast),
        )
        .filter(|h| {
            crate::math::slab::within_box(&self.bounds_of(self.prims[index as usize]), ray, h.t)
        })
    }

    /// [`Geometry::intersect`] with the `--precision double` tests.
    #[inline]
    pub fn intersect_double(&self, index: u32, ray: &Ray) -> Option<PrimHit> {
        self.intersect_by(
            index,
            |s| s.intersect_double(ray),
            |[p0, p1, p2]| intersect_triangle_double(ray, p0, p1, p2),
            |i| self.intersect_instance(i, ray, Precision::Double),
        )
    }

    /// Primitive `index` through the sphere, the triangle or the instance test given.
    #[inline(always)]
    fn intersect_by(
        &self,
        index: u32,
        sphere: impl FnOnce(&Sphere) -> Option<f32>,
        triangle: impl FnOnce([Vec3; 3]) -> Option<TriangleHit>,
        instance: impl FnOnce(u32) -> Option<PrimHit>,
    ) -> Option<PrimHit> {
        match self.prims[index as usize] {
            Primitive::Sphere { sphere: i } => sphere(&self.spheres[i as usize]).map(|t| PrimHit {
                t,
                u: 0.0,
                v: 0.0,
                inner: 0,
            }),
            Primitive::Triangle { mesh, tri } => {
                let m = &self.meshes[mesh as usize];
                // The alpha test is part of the one per-primitive test every accelerator
                // shares, so a cut-out hole is the same hole for all of them.
                triangle(m.corners(tri))
                    .filter(|h| !self.any_alpha || m.alpha_passes(tri, h.u, h.v))
                    .map(PrimHit::from)
            }
            // Its own alpha tests and box check are inside.
            Primitive::Instance { instance: i } => instance(i),
        }
    }

    /// False when primitive `index`'s alpha test cuts the triangle point `(u, v)` away (the
    /// packed leaves' exact test applies it after the same triangle test).
    #[inline(always)]
    pub(crate) fn alpha_passes(&self, index: u32, u: f32, v: f32) -> bool {
        if !self.any_alpha {
            return true;
        }
        match self.prims[index as usize] {
            Primitive::Triangle { mesh, tri } => self.meshes[mesh as usize].alpha_passes(tri, u, v),
            Primitive::Sphere { .. } | Primitive::Instance { .. } => true,
        }
    }

    /// The attributes of a hit on primitive `index` whose surface is `s` (a sphere's are its
    /// `uv` in both sets, colour 1 and no tangent); `inner` is [`PrimHit::inner`].
    pub fn hit_attributes(&self, index: u32, inner: u32, s: &SurfacePoint) -> HitAttributes {
        match self.prims[index as usize] {
            Primitive::Instance { instance } => self.instance_attributes(instance, inner, s),
            Primitive::Triangle { mesh, tri } => {
                self.meshes[mesh as usize].hit_attributes(tri, s.bary.x, s.bary.y)
            }
            Primitive::Sphere { .. } => HitAttributes {
                uvs: [s.uv; 2],
                color: crate::math::Vec4::ONE,
                tangent: None,
            },
        }
    }

    /// Intersects primitive `index` with the test `precision` selects.
    #[inline]
    pub fn intersect_with(
        &self,
        precision: Precision,
        index: u32,
        ray: &Ray,
        wr: &WatertightRay,
    ) -> Option<PrimHit> {
        match precision {
            Precision::Fast => self.intersect_fast(index, ray),
            Precision::Watertight => self.intersect(index, ray, wr),
            Precision::Double => self.intersect_double(index, ray),
        }
    }

    /// The unit geometric normal of a hit: [`SurfacePoint::ng`] of [`Geometry::surface`],
    /// without the rest of the surface (for hit records).
    pub fn geometric_normal(&self, index: u32, ray: &Ray, hit: &PrimHit) -> Vec3 {
        match self.prims[index as usize] {
            Primitive::Sphere { sphere } => {
                let (d, len) = sphere_offset(&self.spheres[sphere as usize], ray, hit);
                sphere_normal(d, len)
            }
            Primitive::Triangle { mesh, tri } => {
                unit_face_normal(self.meshes[mesh as usize].corners(tri))
            }
            Primitive::Instance { instance } => self.instance_normal(instance, ray, hit),
        }
    }

    /// Surface geometry of a hit on primitive `index` at `ray.at(hit.t)`; texture coordinates
    /// only `with_uv` (else 0).
    pub fn surface(&self, index: u32, ray: &Ray, hit: &PrimHit, with_uv: bool) -> SurfacePoint {
        match self.prims[index as usize] {
            Primitive::Instance { instance } => self.instance_surface(instance, ray, hit, with_uv),
            Primitive::Sphere { sphere } => {
                let s = &self.spheres[sphere as usize];
                // `o + t d` in f32 can cancel badly (o.z = 25, t d.z = -25); projecting onto
                // the sphere in f64 leaves only the final rounding to f32 as error, and that
                // rounding is known exactly.
                let c = s.center.as_dvec3();
                let (d, len) = sphere_offset(s, ray, hit);
                let exact = if len > 0.0 {
                    c + d * (s.radius as f64 / len)
                } else {
                    c + DVec3::new(0.0, s.radius as f64, 0.0)
                };
                // The f64 projection itself: a few f64 ulps of the centre and the radius.
                let slack = (c.abs() + DVec3::splat(s.radius as f64)) * (8.0 * f64::EPSILON);
                let (p, p_error) = rounded_with_error(exact, slack);
                let n = sphere_normal(d, len);
                let (u, v) = if with_uv { s.uv_at(p) } else { (0.0, 0.0) };
                SurfacePoint {
                    p,
                    ng: n,
                    ns: n,
                    uv: Vec2::new(u, v),
                    bary: Vec2::ZERO,
                    p_error,
                }
            }
            Primitive::Triangle { mesh, tri } => {
                let m = &self.meshes[mesh as usize];
                let [p0, p1, p2] = m.corners(tri);
                // Interpolating the corners in f64 is far more accurate than o + t d: whatever
                // the rounding of (u, v), the exact interpolation lies in the triangle's plane,
                // so the point's error is its rounding to f32 plus the f64 evaluation's.
                let (a, b, c) = (p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
                let (u, v) = (hit.u as f64, hit.v as f64);
                let (e1, e2) = (b - a, c - a);
                let exact = a + e1 * u + e2 * v;
                let slack = (a.abs() + (e1 * u).abs() + (e2 * v).abs()) * (8.0 * f64::EPSILON);
                let (p, p_error) = rounded_with_error(exact, slack);
                let ng = unit_face_normal([p0, p1, p2]);
                let ns = m
                    .shading_normal(tri, hit.u, hit.v)
                    .map_or(ng, |ns| if ns.dot(ng) < 0.0 { -ns } else { ns });
                SurfacePoint {
                    p,
                    ng,
                    ns,
                    uv: if with_uv {
                        m.uv(tri, hit.u, hit.v)
                    } else {
                        Vec2::ZERO
                    },
                    bary: Vec2::new(hit.u, hit.v),
                    p_error,
                }
            }
        }
    }
}

/// The hit point's offset from a sphere's centre in f64, and its length.
fn sphere_offset(s: &Sphere, ray: &Ray, hit: &PrimHit) -> (DVec3, f64) {
    let q = ray.origin.as_dvec3() + ray.dir.as_dvec3() * hit.t as f64;
    let d = q - s.center.as_dvec3();
    (d, d.length())
}

/// The unit normal along a sphere hit's f64 offset: `p - center` in f32 loses digits on huge
/// spheres.
fn sphere_normal(d: DVec3, len: f64) -> Vec3 {
    if len > 0.0 {
        (d / len).as_vec3()
    } else {
        Vec3::Y
    }
}

impl From<TriangleHit> for PrimHit {
    fn from(h: TriangleHit) -> Self {
        PrimHit {
            t: h.t,
            u: h.u,
            v: h.v,
            inner: 0,
        }
    }
}

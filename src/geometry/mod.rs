//! Primitives: analytic spheres and triangles of indexed meshes, both first-class.
//!
//! [`Geometry`] owns the shapes and a flat list of [`Primitive`]s; accelerators refer to
//! primitives by their index in that list and see only their bounding boxes.

mod mesh;
mod polygon;
mod sphere;
mod triangle;
mod twofloat;

pub use mesh::{Mesh, MeshError};
pub use polygon::{Triangulation, newell_normal, triangulate_polygon};
pub use sphere::Sphere;
pub use triangle::{TriangleHit, WatertightRay, face_normal, intersect_triangle};

use crate::math::{Aabb, Ray, Vec2, Vec3, gamma, offset_ray_origin};

/// One intersectable primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Primitive {
    /// `Geometry::spheres()[index]`.
    Sphere { sphere: u32 },
    /// Triangle `tri` of `Geometry::meshes()[mesh]`.
    Triangle { mesh: u32, tri: u32 },
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
}

/// Differential geometry at a hit, in world space.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// The hit point.
    pub p: Vec3,
    /// Unit geometric normal (outward for spheres; winding order for triangles).
    pub ng: Vec3,
    /// Unit shading normal (interpolated for smooth meshes), on the same side as `ng`.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// Per-component bound on the absolute error of `p` (pbrt's `pError`): how far the computed
    /// point may lie from the true surface, for offsetting secondary rays.
    pub p_error: Vec3,
}

impl SurfacePoint {
    /// Origin for a ray leaving this point along `dir`: pushed off the surface past the error
    /// bound of `p` along the geometric normal, then a few ulps more
    /// ([`crate::math::offset_ray_origin`]), to the side `dir` points to.
    pub fn spawn_origin(&self, dir: Vec3) -> Vec3 {
        let n = if self.ng.dot(dir) < 0.0 {
            -self.ng
        } else {
            self.ng
        };
        let past_error = self.p + n * self.ng.abs().dot(self.p_error);
        offset_ray_origin(past_error, n, dir)
    }
}

/// All shapes of a scene and the flat primitive list the accelerators index.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    spheres: Vec<Sphere>,
    meshes: Vec<Mesh>,
    prims: Vec<Primitive>,
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
        self.meshes.push(m);
        first..self.prims.len() as u32
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
        }
    }

    /// Bounds of everything.
    pub fn bounds(&self) -> Aabb {
        let s = self
            .spheres
            .iter()
            .fold(Aabb::EMPTY, |b, s| b.union(s.bounds()));
        self.meshes.iter().fold(s, |b, m| b.union(m.bounds()))
    }

    /// Intersects primitive `index` with `ray` in `(t_min, t_max]`; `wr` is the ray's shear.
    #[inline]
    pub fn intersect(&self, index: u32, ray: &Ray, wr: &WatertightRay) -> Option<PrimHit> {
        match self.prims[index as usize] {
            Primitive::Sphere { sphere } => self.spheres[sphere as usize]
                .intersect(ray)
                .map(|t| PrimHit { t, u: 0.0, v: 0.0 }),
            Primitive::Triangle { mesh, tri } => {
                let [p0, p1, p2] = self.meshes[mesh as usize].corners(tri);
                intersect_triangle(ray, wr, p0, p1, p2).map(|h| PrimHit {
                    t: h.t,
                    u: h.u,
                    v: h.v,
                })
            }
        }
    }

    /// Surface geometry of a hit on primitive `index` at `ray.at(hit.t)`.
    pub fn surface(&self, index: u32, ray: &Ray, hit: &PrimHit) -> SurfacePoint {
        match self.prims[index as usize] {
            Primitive::Sphere { sphere } => {
                let s = &self.spheres[sphere as usize];
                // `o + t d` in f32 can cancel badly (o.z = 25, t d.z = -25); projecting onto
                // the sphere in f64 leaves only the final rounding to f32 as error.
                let p = s.project(ray.at(hit.t));
                let n = s.normal_at(p);
                let (u, v) = s.uv_at(p);
                SurfacePoint {
                    p,
                    ng: n,
                    ns: n,
                    uv: Vec2::new(u, v),
                    p_error: p.abs() * gamma(2),
                }
            }
            Primitive::Triangle { mesh, tri } => {
                let m = &self.meshes[mesh as usize];
                let [p0, p1, p2] = m.corners(tri);
                // Interpolating the corners is more accurate than o + t d far from the origin;
                // its error bound is pbrt's for the barycentric sum.
                let b0 = 1.0 - hit.u - hit.v;
                let p = p0 * b0 + p1 * hit.u + p2 * hit.v;
                let p_error =
                    ((p0 * b0).abs() + (p1 * hit.u).abs() + (p2 * hit.v).abs()) * gamma(7);
                let ng = face_normal(p0, p1, p2).normalize_or(Vec3::Y);
                let ns = m
                    .shading_normal(tri, hit.u, hit.v)
                    .map_or(ng, |ns| if ns.dot(ng) < 0.0 { -ns } else { ns });
                SurfacePoint {
                    p,
                    ng,
                    ns,
                    uv: m.uv(tri, hit.u, hit.v),
                    p_error,
                }
            }
        }
    }
}

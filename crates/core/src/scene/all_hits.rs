//! [`World::all_hits`]: every surface crossing and graze along a ray, each crossing counted
//! once (the rule is stated in [`crate::accel::AllHits`]'s module and in docs/hard-cases.md).

use super::World;
use crate::accel::{AllHit, AllHitsScratch, TraversalStats};
use crate::geometry::{Primitive, unit_face_normal};
use crate::math::{Ray, Vec3};

/// One hit of [`World::all_hits`]: the nearest-hit record's fields and a graze flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the caller's ray.
    pub t: f32,
    /// Primitive index.
    pub prim: u32,
    /// Object index (the scene's object list).
    pub object: u32,
    /// The instance hit, if the primitive is one (the scene's instance list).
    pub instance: Option<u32>,
    /// The prototype's primitive, for a hit on an instance (0 otherwise).
    pub inner: u32,
    /// Barycentric weight of the triangle's second vertex (0 for spheres).
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex (0 for spheres).
    pub v: f32,
    /// Unit geometric normal: outward for spheres, by winding for triangles.
    pub normal: Vec3,
    /// Which primitive: a sphere or a mesh's triangle (a prototype's, for an instance).
    pub primitive: Primitive,
    /// True for a touch that does not cross the surface (a silhouette edge or vertex, a
    /// tangent sphere), false for a crossing.
    pub graze: bool,
}

impl World {
    /// Every surface crossing of `ray` in `(t_min, t_max]`, each counted once, and every graze,
    /// sorted by `t` (ties by primitive index); with the scene's `precision`, except that
    /// `fast` uses the watertight tests ([`crate::accel::Accel::all_hits_geometry`]).
    pub fn all_hits(&self, ray: &Ray, stats: &mut TraversalStats) -> Vec<SurfaceHit> {
        let scene = self.scene();
        let g = scene.geometry();
        let mut buffers = AllHitsBuffers::default();
        let Some((traced, hits)) = self.all_hits_found(ray, stats, &mut buffers) else {
            return Vec::new();
        };
        hits.iter()
            .map(|h| SurfaceHit {
                t: h.t,
                prim: h.prim,
                object: scene.object_at(h.prim, h.hit.inner),
                instance: g.instance_of(h.prim),
                inner: h.hit.inner,
                u: h.hit.u,
                v: h.hit.v,
                normal: self.all_hit_normal(&traced, h),
                primitive: g.leaf_primitive(h.prim, h.hit.inner),
                graze: h.graze,
            })
            .collect()
    }

    /// The hits of [`World::all_hits`] as the accelerator finds them, on the ray it returns
    /// (`None`: the ray misses the scene), in buffers kept by the caller from ray to ray: for
    /// batches, which turn them into records without a [`SurfaceHit`]'s look-ups.
    pub fn all_hits_found<'b>(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        buffers: &'b mut AllHitsBuffers,
    ) -> Option<(Ray, &'b [AllHit])> {
        let scene = self.scene();
        let AllHitsBuffers { scratch, hits } = buffers;
        let traced = self.accel().all_hits_into(
            scene.geometry(),
            scene.settings().precision,
            ray,
            stats,
            scratch,
            hits,
        )?;
        Some((traced, hits))
    }

    /// The unit geometric normal of an all-hits hit found on `traced`: from the packed leaves'
    /// copy of the triangle when the hit was found there (the same bits, without the dependent
    /// reads of the primitive list, the index buffer and the vertices), else computed on
    /// `traced`, the caller's ray as given.
    pub fn all_hit_normal(&self, traced: &Ray, h: &AllHit) -> Vec3 {
        h.slot
            .and_then(|slot| self.accel().packed_corners(slot))
            .map_or_else(
                || {
                    let g = self.scene().geometry();
                    g.geometric_normal(h.prim, traced, &h.hit)
                },
                unit_face_normal,
            )
    }
}

/// What [`World::all_hits_found`] reuses from one ray to the next.
#[derive(Clone, Debug, Default)]
pub struct AllHitsBuffers {
    scratch: AllHitsScratch,
    hits: Vec<AllHit>,
}

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
        let mut out = Vec::new();
        self.all_hits_into(ray, stats, &mut AllHitsBuffers::default(), &mut out);
        out
    }

    /// [`World::all_hits`] appended to `out`, with the buffers of `buffers` (kept from ray to
    /// ray by a batch, so a ray allocates nothing once they have grown).
    pub fn all_hits_into(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        buffers: &mut AllHitsBuffers,
        out: &mut Vec<SurfaceHit>,
    ) {
        let scene = self.scene();
        let g = scene.geometry();
        let AllHitsBuffers { scratch, hits } = buffers;
        let Some(traced) =
            self.accel()
                .all_hits_into(g, scene.settings().precision, ray, stats, scratch, hits)
        else {
            return;
        };
        out.extend(hits.iter().map(|h| {
            SurfaceHit {
                t: h.t,
                prim: h.prim,
                object: scene.object_at(h.prim, h.hit.inner),
                instance: g.instance_of(h.prim),
                inner: h.hit.inner,
                u: h.hit.u,
                v: h.hit.v,
                // From the packed leaves' copy of the triangle when the hit was found there (the
                // same bits, without the dependent reads of the index buffer and the vertices),
                // else on the ray the hit was found on: the caller's, traced as given.
                normal: h
                    .slot
                    .and_then(|slot| self.accel().packed_corners(slot))
                    .map_or_else(
                        || g.geometric_normal(h.prim, &traced, &h.hit),
                        unit_face_normal,
                    ),
                primitive: g.leaf_primitive(h.prim, h.hit.inner),
                graze: h.graze,
            }
        }))
    }
}

/// What [`World::all_hits_into`] reuses from one ray to the next.
#[derive(Clone, Debug, Default)]
pub struct AllHitsBuffers {
    scratch: AllHitsScratch,
    hits: Vec<AllHit>,
}

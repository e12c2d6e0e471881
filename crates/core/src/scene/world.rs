//! [`World`]: a scene together with the accelerator built over its own primitives.
//!
//! An accelerator only answers for the geometry it was built over (its leaves hold primitive
//! indices, its packed leaves copies of the triangles). Owning both in one value, built in one
//! place, makes pairing a scene with another scene's accelerator impossible to write.

use std::sync::{Arc, OnceLock};

use super::contains::ContainmentIndex;
use super::{Interaction, Scene, Settings};
use crate::accel::{
    Accel, AccelKind, BuildOptions, Hit, PACKET, PackedLeaves, Traced, Traversal, TraversalStats,
};
use crate::camera::Camera;
use crate::geometry::triangle::unit_face_normal;
use crate::geometry::with_prim_test;
use crate::instancing::{build_instances, prototype_build};
use crate::math::{Ray, Vec3};

/// A scene and the accelerator over its primitives: what renders and ray queries take.
#[derive(Clone, Debug)]
pub struct World {
    scene: Scene,
    accel: Accel,
    /// Each prototype's packed leaves, if it has them: a hit record inside an instance reads
    /// its triangle here, not through the prototype's opaque hierarchy.
    prototype_leaves: Vec<Option<Arc<PackedLeaves>>>,
    /// What point containment queries need, built on the first one (`World::contains`).
    containment: OnceLock<Arc<ContainmentIndex>>,
}

impl World {
    /// Builds accelerator `kind` over `scene`'s primitives.
    pub fn build(mut scene: Scene, kind: AccelKind, opts: &BuildOptions) -> Self {
        // Two levels of one kind: brute force over instances is brute force inside them.
        if scene.geometry().has_instances() {
            build_instances(scene.geometry_mut(), kind, opts, Traversal::Ordered);
        }
        let accel = Accel::build_for(kind, scene.geometry(), opts);
        let prototype_leaves = Accel::prototype_leaves(scene.geometry());
        Self {
            scene,
            accel,
            prototype_leaves,
            containment: OnceLock::new(),
        }
    }

    /// The same world walked with `traversal` (see [`Accel::with_traversal`]), inside its
    /// instances too.
    pub fn with_traversal(mut self, traversal: Traversal) -> Self {
        if self.scene.geometry().has_instances() {
            let kind = self.accel.kind();
            if let Some(opts) = prototype_build(self.scene.geometry()) {
                build_instances(self.scene.geometry_mut(), kind, &opts, traversal);
            }
        }
        Self {
            accel: self.accel.with_traversal(traversal),
            prototype_leaves: Accel::prototype_leaves(self.scene.geometry()),
            scene: self.scene,
            containment: self.containment,
        }
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The point containment index, built on first use.
    pub(super) fn containment_index(&self) -> &ContainmentIndex {
        self.containment
            .get_or_init(|| Arc::new(ContainmentIndex::build(&self.scene)))
    }

    /// The accelerator (built over [`Self::scene`]'s primitives).
    pub fn accel(&self) -> &Accel {
        &self.accel
    }

    /// Render settings to change after the build (no setting changes the geometry).
    pub fn settings_mut(&mut self) -> &mut Settings {
        self.scene.settings_mut()
    }

    /// Replaces the camera (the geometry, and so the accelerator, stay).
    pub fn set_camera(&mut self, camera: Camera) {
        self.scene.set_camera(camera);
    }

    /// Gives the scene back.
    pub fn into_scene(self) -> Scene {
        self.scene
    }

    /// Nearest hit of `ray`, with its surface.
    pub fn intersect(&self, ray: &Ray, stats: &mut TraversalStats) -> Option<Interaction> {
        let traced = self.trace(ray, stats)?;
        Some(self.surface_of(&traced))
    }

    /// The interaction at a traced hit, with texture coordinates only where a texture reads
    /// them (a sphere's cost two inverse trigonometric calls); elsewhere they stay 0, which
    /// nothing reads.
    fn surface_of(&self, traced: &Traced) -> Interaction {
        let object = self.scene.object_at(traced.hit.prim, traced.hit.hit.inner);
        let uv = self.scene.material_of(object).reads_uv();
        self.interaction(traced, uv)
    }

    /// [`World::intersect`] of each of `rays` (up to [`PACKET`]) into `out`: walked together
    /// when they can be (the samples of a pixel from a pinhole camera), else one at a time;
    /// the same answers either way.
    pub fn intersect_packet(
        &self,
        rays: &[Ray],
        stats: &mut TraversalStats,
        out: &mut [Option<Interaction>],
    ) {
        let mut traced = [None; PACKET];
        if !self.trace_packet(rays, stats, &mut traced) {
            for (o, ray) in out.iter_mut().zip(rays) {
                *o = self.intersect(ray, stats);
            }
            return;
        }
        for (o, traced) in out.iter_mut().zip(&traced[..rays.len()]) {
            *o = traced.map(|traced| self.surface_of(&traced));
        }
    }

    /// [`World::trace`] of up to [`PACKET`] rays walked together into `out` (the same answers),
    /// or `false` with nothing written when they cannot share a walk
    /// ([`Accel::trace_packet`]).
    pub fn trace_packet(
        &self,
        rays: &[Ray],
        stats: &mut TraversalStats,
        out: &mut [Option<Traced>],
    ) -> bool {
        let precision = self.scene.settings().precision;
        rays.len() > 1
            && self
                .accel
                .trace_packet(self.scene.geometry(), precision, rays, stats, out)
    }

    /// The nearest hit of `ray` with the ray it was found on, before any surface is computed
    /// (a ray from far away is traced from near the scene: see [`crate::accel::RayFrame`]).
    pub fn trace(&self, ray: &Ray, stats: &mut TraversalStats) -> Option<Traced> {
        let precision = self.scene.settings().precision;
        self.accel
            .trace_geometry(self.scene.geometry(), precision, ray, stats)
    }

    /// [`World::trace`] of every ray `rays` yields, with up to `K` rays walked at once on this
    /// thread (see [`Accel::trace_geometry_each`]); each answer goes to `answer` with its
    /// ray's id, in the order the rays finish.
    pub fn trace_each<const K: usize, Id: Copy>(
        &self,
        stats: &mut TraversalStats,
        rays: impl FnMut() -> Option<(Id, Ray)>,
        answer: impl FnMut(Id, Option<Traced>),
    ) {
        let precision = self.scene.settings().precision;
        self.accel.trace_geometry_each::<K, Id>(
            self.scene.geometry(),
            precision,
            stats,
            rays,
            answer,
        )
    }

    /// The unit geometric normal of a traced hit (see `Geometry::geometric_normal`): from the
    /// packed leaves' copy of the triangle when the hit was found there, the same bits, without
    /// the dependent reads of the primitive list, the index buffer and the vertices.
    /// A hit inside an instance walked in place carries the slot in its prototype's packed
    /// leaves: the object-space normal from there, mapped as the instance maps normals.
    pub fn geometric_normal(&self, traced: &Traced) -> Vec3 {
        let instance = self.scene.geometry().instance_of(traced.hit.prim);
        self.geometric_normal_in(traced, instance)
    }

    /// [`World::geometric_normal`] of a hit on `instance` (`None`: not on an instance), for
    /// callers that know it already.
    #[inline(always)]
    pub(crate) fn geometric_normal_in(&self, traced: &Traced, instance: Option<u32>) -> Vec3 {
        let g = self.scene.geometry();
        let packed = traced.slot.and_then(|slot| match instance {
            None => self.accel.packed_corners(slot).map(unit_face_normal),
            Some(instance) => {
                let inst = g.instances().get(instance as usize)?;
                let leaves = self
                    .prototype_leaves
                    .get(inst.prototype as usize)?
                    .as_ref()?;
                // Mapped as `Geometry::geometric_normal` maps an instance's normals.
                let n = unit_face_normal(leaves.corners(slot)?);
                Some(inst.placement.world_normal(n))
            }
        });
        packed.unwrap_or_else(|| g.geometric_normal(traced.hit.prim, &traced.ray, &traced.hit.hit))
    }

    /// The interaction of a traced hit: its surface computed on the ray it was found on, with
    /// texture coordinates only `with_uv`.
    pub fn interaction(&self, traced: &Traced, with_uv: bool) -> Interaction {
        let Hit { prim, hit } = traced.hit;
        let g = self.scene.geometry();
        Interaction {
            t: traced.t,
            prim,
            inner: hit.inner,
            instance: g.instance_of(prim),
            object: self.scene.object_at(prim, hit.inner),
            surface: self
                .scene
                .geometry()
                .surface(prim, &traced.ray, &hit, with_uv),
        }
    }

    /// The nearest primitive hit of `ray` (its caller's `t`), before any surface is computed.
    pub fn intersect_hit(&self, ray: &Ray, stats: &mut TraversalStats) -> Option<Hit> {
        self.trace(ray, stats).map(|t| t.caller_hit())
    }

    /// True when something blocks `ray` within `(t_min, t_max]`.
    pub fn occluded(&self, ray: &Ray, stats: &mut TraversalStats) -> bool {
        let precision = self.scene.settings().precision;
        self.accel
            .occluded_geometry(self.scene.geometry(), precision, ray, stats)
    }

    /// The distance to the blocker an any-hit query of `ray` stops at (some blocker within
    /// `(t_min, t_max]`, not necessarily the nearest), or `None` when nothing blocks it. The
    /// primitives are tested one at a time with the scene's precision (the choice made once per
    /// ray), so cross-checks can compare the blocker itself, not only the yes or no.
    pub fn first_blocker(&self, ray: &Ray, stats: &mut TraversalStats) -> Option<f32> {
        // The blocker's `t` is measured on the ray the query traces: a far ray's is mapped back.
        let framing = self.accel.frame().frame(ray);
        let local = framing.ray(ray)?;
        let g = self.scene.geometry();
        let mut blocker = None;
        with_prim_test!(g, self.scene.settings().precision, local, |test| {
            self.accel.occluded(local, stats, |p, r| match test(p, r) {
                Some(h) => {
                    blocker = Some(h.t);
                    true
                }
                None => false,
            })
        });
        framing.caller_t(blocker?)
    }
}

//! The bottom level of instancing: a prototype's shapes with a hierarchy of their own
//! ([`Prototype`]), built once however many instances place it, and rebuilt as the kind a
//! world is built with ([`build_instances`]: brute force over instances is brute force inside
//! them too). The geometry traces instances through [`PrototypeQueries`]; this module sits
//! above both the geometry and the accelerators.

use std::sync::Arc;

use crate::accel::{Accel, AccelKind, BuildOptions, Traversal, TraversalStats};
use crate::geometry::{Geometry, Precision, PrimHit, PrototypeQueries};
use crate::math::{Aabb, Ray};

/// A prototype: its shapes and the hierarchy over them.
#[derive(Clone, Debug)]
pub struct Prototype {
    geometry: Arc<Geometry>,
    accel: Arc<Accel>,
    /// What `accel` was built as (rebuilt when a world asks for another).
    built: (AccelKind, BuildOptions),
    /// Bounds of the shapes (a mesh's are a pass over its vertices: once, not per placement).
    bounds: Aabb,
}

impl Prototype {
    /// A prototype over `geometry` (which must hold no instances: two levels), with the
    /// default wide hierarchy until a world asks for another ([`build_instances`]).
    pub fn shared(geometry: Geometry) -> Arc<dyn PrototypeQueries> {
        debug_assert!(
            !geometry.has_instances(),
            "a prototype holds shapes, not instances (two levels)"
        );
        let built = (AccelKind::Sah, BuildOptions::default());
        let accel = Accel::build_for(built.0, &geometry, &built.1);
        Arc::new(Self {
            bounds: geometry.bounds(),
            geometry: Arc::new(geometry),
            accel: Arc::new(accel),
            built,
        })
    }

    /// The hierarchy over the shapes.
    pub fn accel(&self) -> &Accel {
        &self.accel
    }
}

impl PrototypeQueries for Prototype {
    fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    #[inline]
    fn nearest(&self, ray: &Ray, precision: Precision) -> Option<PrimHit> {
        let mut stats = TraversalStats::default();
        let traced = self
            .accel
            .trace_geometry(&self.geometry, precision, ray, &mut stats)?;
        Some(PrimHit {
            t: traced.t,
            inner: traced.hit.prim,
            ..traced.hit.hit
        })
    }

    #[inline]
    fn blocks(&self, ray: &Ray, precision: Precision) -> bool {
        let mut stats = TraversalStats::default();
        self.accel
            .occluded_geometry(&self.geometry, precision, ray, &mut stats)
    }

    fn all_hits(&self, ray: &Ray, precision: Precision) -> Vec<(PrimHit, bool)> {
        let mut stats = TraversalStats::default();
        let found = self
            .accel
            .all_hits_geometry(&self.geometry, precision, ray, &mut stats);
        found
            .hits
            .into_iter()
            .map(|h| {
                let hit = PrimHit {
                    t: h.t,
                    inner: h.prim,
                    ..h.hit
                };
                (hit, h.graze)
            })
            .collect()
    }

    fn bytes(&self) -> usize {
        self.geometry.bytes() + self.accel.bytes()
    }

    fn hierarchy(&self) -> &dyn std::any::Any {
        &*self.accel
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// Rebuilds every prototype of `geometry` as `kind` with `opts` walked by `traversal`, where
/// it was built otherwise (the shapes are shared, not copied).
pub fn build_instances(
    geometry: &mut Geometry,
    kind: AccelKind,
    opts: &BuildOptions,
    traversal: Traversal,
) {
    for slot in geometry.prototypes_mut() {
        let Some(p) = slot.as_any().downcast_ref::<Prototype>() else {
            continue;
        };
        if p.built == (kind, *opts) && p.accel.traversal() == traversal {
            continue;
        }
        let mut p = p.clone();
        if p.built != (kind, *opts) {
            p.accel = Arc::new(Accel::build_for(kind, &p.geometry, opts));
            p.built = (kind, *opts);
        }
        if p.accel.traversal() != traversal {
            p.accel = Arc::new(Accel::clone(&p.accel).with_traversal(traversal));
        }
        *slot = Arc::new(p);
    }
}

/// The build options `geometry`'s prototypes were last built with (`None` without any).
pub fn prototype_build(geometry: &Geometry) -> Option<BuildOptions> {
    geometry
        .prototypes()
        .iter()
        .find_map(|p| p.as_any().downcast_ref::<Prototype>())
        .map(|p| p.built.1)
}

//! Every accelerator x traversal x leaf size over one geometry, answering each query only after
//! checking that all of them agree bit for bit with brute force.

#![allow(dead_code)]

use super::common::all_kinds;
use lumis_core::accel::{
    Accel, AccelKind, BuildOptions, Hit, SegmentParams, Traversal, TraversalStats,
};
use lumis_core::geometry::{Geometry, Precision, WatertightRay};
use lumis_core::math::Ray;
use lumis_core::scene::World;

/// The traversals every hierarchy is walked with: ordered, the paper's exhaustive recursion, and
/// segment marching with short (many segment boundaries) and the paper's segment lengths.
pub fn traversals() -> Vec<Traversal> {
    vec![
        Traversal::Ordered,
        Traversal::Exhaustive,
        Traversal::Segments(SegmentParams {
            init: 0.05,
            max: 1.6,
        }),
        Traversal::Segments(SegmentParams {
            init: 2.0,
            max: lumis_core::accel::PAPER_SEGMENT_MAX,
        }),
    ]
}

/// One geometry with every accelerator configuration built over it.
pub struct Everywhere<'a> {
    pub geometry: &'a Geometry,
    brute: Accel,
    configs: Vec<(String, Accel)>,
}

impl<'a> Everywhere<'a> {
    /// Builds every kind with its default leaf size and with leaves of 1, under every traversal.
    pub fn new(geometry: &'a Geometry) -> Self {
        let bounds = geometry.prim_bounds();
        let brute = Accel::build(AccelKind::Brute, &bounds, &BuildOptions::default());
        let mut configs = Vec::new();
        for kind in all_kinds() {
            for leaf in [kind.default_leaf_size(), 1] {
                let opts = BuildOptions {
                    max_leaf_size: leaf,
                    ..Default::default()
                };
                let built = Accel::build_for(kind, geometry, &opts);
                if let Some(bvh) = built.bvh() {
                    bvh.validate(&bounds).expect("valid hierarchy");
                }
                if let Some(wide) = built.wide() {
                    wide.validate(&bounds).expect("valid wide hierarchy");
                }
                for t in traversals() {
                    configs.push((
                        format!("{kind:?} leaf {leaf} {t:?}"),
                        built.clone().with_traversal(t),
                    ));
                }
            }
        }
        Self {
            geometry,
            brute,
            configs,
        }
    }

    /// The brute-force nearest hit, after asserting every configuration returns it exactly.
    pub fn closest(&self, ray: &Ray) -> Option<Hit> {
        self.closest_with(Precision::default(), ray)
    }

    /// [`Everywhere::closest`] with the primitive tests of `precision`.
    pub fn closest_with(&self, precision: Precision, ray: &Ray) -> Option<Hit> {
        let wr = WatertightRay::new(ray.dir);
        let g = self.geometry;
        let query = |a: &Accel| {
            a.intersect(ray, &mut TraversalStats::default(), |p, r| {
                g.intersect_with(precision, p, r, &wr)
            })
        };
        let reference = query(&self.brute);
        for (name, a) in &self.configs {
            assert_eq!(
                query(a),
                reference,
                "{name} differs from brute force on {ray:?}"
            );
        }
        reference
    }

    /// Whether anything blocks the ray, after asserting every configuration agrees.
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_with(Precision::default(), ray)
    }

    /// [`Everywhere::occluded`] with the primitive tests of `precision`.
    pub fn occluded_with(&self, precision: Precision, ray: &Ray) -> bool {
        let wr = WatertightRay::new(ray.dir);
        let g = self.geometry;
        let query = |a: &Accel| {
            a.occluded(ray, &mut TraversalStats::default(), |p, r| {
                g.intersect_with(precision, p, r, &wr).is_some()
            })
        };
        let reference = query(&self.brute);
        for (name, a) in &self.configs {
            assert_eq!(query(a), reference, "{name} occlusion differs on {ray:?}");
        }
        reference
    }
}

/// Renders `scene` through every accelerator kind under every traversal, asserts that all
/// films (colour and every AOV) are bit-identical to brute force's, and returns that film:
/// the rendered hard cases hold for every configuration, not just the default.
pub fn render_everywhere(scene: &lumis_core::scene::Scene) -> lumis_core::film::Film {
    let opts = lumis_core::render::RenderOptions::default();
    let film = |world: &World| {
        lumis_core::render::render(world, &opts)
            .expect("renders")
            .film
    };
    let reference = film(&World::build(
        scene.clone(),
        AccelKind::Brute,
        &BuildOptions::default(),
    ));
    for kind in all_kinds() {
        let opts = BuildOptions {
            max_leaf_size: kind.default_leaf_size(),
            ..Default::default()
        };
        let built = World::build(scene.clone(), kind, &opts);
        for t in traversals() {
            let f = film(&built.clone().with_traversal(t));
            assert!(
                f.rgba() == reference.rgba() && f.aov() == reference.aov(),
                "{kind:?} {t:?} renders a different image than brute force"
            );
        }
    }
    reference
}

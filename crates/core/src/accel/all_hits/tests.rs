use super::*;
use crate::accel::{AccelKind, BuildOptions, SegmentParams, Traversal};
use crate::geometry::{Mesh, Primitive, Sphere};
use crate::math::Vec3;

fn contact(prim: u32, t: f32, touch: Touch) -> Contact {
    Contact {
        prim,
        hit: PrimHit {
            t,
            u: 0.5,
            v: 0.25,
            inner: 0,
        },
        touch,
    }
}

#[test]
fn a_seam_gives_one_hit_crossing_on_an_odd_claim_count_else_graze() {
    let edge = Seam::Edge {
        mesh: 0,
        ends: [[0; 3], [1; 3]],
    };
    let vertex = Seam::Vertex {
        mesh: 0,
        at: [2; 3],
    };
    let b = |seam, claims| Touch::Boundary { seam, claims };
    // The edge: prim 7 claims; prim 3 reports the smaller t, which the hit takes.
    // The vertex: two claims, a graze from the first member (t, index).
    let mut hits = Vec::new();
    resolve(
        &[
            contact(3, 1.0, b(edge, false)),
            contact(5, 2.0, b(vertex, true)),
            contact(7, 1.0000001, b(edge, true)),
            contact(8, 2.0, b(vertex, true)),
            contact(9, 3.0, Touch::Crossing),
            contact(4, 2.0, b(vertex, false)),
        ],
        &[NO_SLOT; 6],
        &mut Vec::new(),
        &mut hits,
    );
    let got: Vec<(u32, f32, bool)> = hits.iter().map(|h| (h.prim, h.t, h.graze)).collect();
    // Seams come out in seam order (edges before vertices); the caller sorts by t.
    assert_eq!(got, [(9, 3.0, false), (7, 1.0, false), (4, 2.0, true)]);
}

/// A closed octahedron (integer vertices), a sphere through it and a far-off cube corner.
fn scene() -> Geometry {
    let mut g = Geometry::new();
    let p = vec![
        Vec3::new(2., 0., 0.),
        Vec3::new(-2., 0., 0.),
        Vec3::new(0., 2., 0.),
        Vec3::new(0., -2., 0.),
        Vec3::new(0., 0., 2.),
        Vec3::new(0., 0., -2.),
    ];
    let mut idx = Vec::new();
    for (a, b) in [(0, 2), (2, 1), (1, 3), (3, 0)] {
        idx.push([a, b, 4]);
        idx.push([b, a, 5]);
    }
    g.add_mesh(Mesh::new(p, None, None, idx).unwrap());
    g.add_sphere(Sphere {
        center: Vec3::new(1., 1., 0.),
        radius: 1.,
    });
    g
}

#[test]
fn every_accelerator_and_traversal_returns_brute_forces_hits() {
    let g = scene();
    let bounds = g.prim_bounds();
    let brute = Accel::build(AccelKind::Brute, &bounds, &BuildOptions::default());
    let mut rays = Vec::new();
    for o in [-3i32, -1, 0, 2, 3] {
        for d in [[1, 0, 0], [1, 1, 0], [1, 1, 1], [0, -1, 2], [2, 1, -1]] {
            let origin = Vec3::new(o as f32, -3.0, (o % 2) as f32);
            let dir = Vec3::new(d[0] as f32, d[1] as f32 + 1.0, d[2] as f32);
            rays.push(Ray::new(origin, dir));
            rays.push(Ray::new(
                Vec3::splat(o as f32 * 1e9),
                -dir - Vec3::splat(o as f32),
            ));
        }
    }
    let mut found = 0;
    for kind in AccelKind::ALL {
        for leaf in [1, kind.default_leaf_size()] {
            let built = Accel::build_for(
                kind,
                &g,
                &BuildOptions {
                    max_leaf_size: leaf,
                    ..Default::default()
                },
            );
            for traversal in [
                Traversal::Ordered,
                Traversal::Exhaustive,
                Traversal::Segments(SegmentParams {
                    init: 0.5,
                    max: 4.0,
                }),
            ] {
                let a = built.clone().with_traversal(traversal);
                for r in &rays {
                    let s = &mut TraversalStats::default();
                    let want = brute.all_hits_geometry(&g, Precision::Watertight, r, s);
                    let mut got = a.all_hits_geometry(&g, Precision::Watertight, r, s);
                    // Only the packed leaves give slots; a slot holds the hit's triangle.
                    for h in &mut got.hits {
                        if let Some(slot) = h.slot.take() {
                            let Primitive::Triangle { mesh, tri } = g.prims()[h.prim as usize]
                            else {
                                panic!("a slot for a primitive that is no triangle");
                            };
                            let corners = a.packed_corners(slot);
                            assert_eq!(corners, Some(g.meshes()[mesh as usize].corners(tri)));
                        }
                    }
                    assert_eq!(format!("{got:?}"), format!("{want:?}"), "{kind:?} {r:?}");
                    found += want.hits.len();
                }
            }
        }
    }
    assert!(found > 100, "{found}");
}

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

/// The surface of the box `[0, n]^3`, every face in unit squares of two triangles whose
/// diagonals alternate, so rays through its lattice points meet edges and vertices shared by
/// two to eight triangles, coplanar and across the box's edges and corners.
fn split_box(n: i32) -> Geometry {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    // Each face: a fixed axis at 0 or n, the other two running over the unit squares.
    for axis in 0..3 {
        for side in [0, n] {
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n {
                for j in 0..n {
                    let mut corner = |di: i32, dj: i32| {
                        let mut p = [0.0f32; 3];
                        p[axis] = side as f32;
                        p[a] = (i + di) as f32;
                        p[b] = (j + dj) as f32;
                        let k = positions.len() as u32;
                        positions.push(Vec3::from_array(p));
                        k
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    if (i + j) % 2 == 0 {
                        indices.push([q[0], q[1], q[2]]);
                        indices.push([q[0], q[2], q[3]]);
                    } else {
                        indices.push([q[0], q[1], q[3]]);
                        indices.push([q[1], q[2], q[3]]);
                    }
                }
            }
        }
    }
    let mut g = Geometry::new();
    g.add_mesh(Mesh::new(positions, None, None, indices).unwrap());
    g
}

#[test]
fn the_packed_leaf_test_gives_the_per_primitive_hits_on_edges_and_vertices() {
    // The SIMD leaf path (sah's packed leaves) against brute force's per-primitive contacts,
    // on rays through the split box's lattice points: through vertices and edge points (seams
    // of several triangles), in the faces' planes (edge-on triangles), from nearby and from
    // far away, and cut short at a hit's `t` (`t_max` exactly on a surface).
    let g = split_box(3);
    let brute = Accel::build_for(AccelKind::Brute, &g, &BuildOptions::default());
    let packed = Accel::build_for(AccelKind::Sah, &g, &BuildOptions::default());
    assert!(packed.packed().is_some());
    let lattice: Vec<Vec3> = (0..7 * 7 * 7)
        .map(|k| Vec3::new((k % 7) as f32, (k / 7 % 7) as f32, (k / 49) as f32) * 0.5)
        .collect();
    let origins = [
        Vec3::new(-1.5, 0.5, 4.0),
        Vec3::new(1.5, 1.5, 1.5),
        Vec3::new(0.0, -2.0, 0.0),
        Vec3::new(3.0, 3.0, 5.0),
        Vec3::new(-7e5, 2e5, 3e5),
    ];
    let (mut rays, mut slots, mut seams) = (0, 0, 0);
    for &o in &origins {
        for (k, &target) in lattice.iter().enumerate() {
            let dir = target - o;
            if dir == Vec3::ZERO {
                continue;
            }
            let mut ray = Ray::new(o, dir);
            if k % 3 == 0 {
                ray.t_max = 1.0;
            }
            let s = &mut TraversalStats::default();
            let want = brute.all_hits_geometry(&g, Precision::Watertight, &ray, s);
            let mut got = packed.all_hits_geometry(&g, Precision::Watertight, &ray, s);
            for h in &mut got.hits {
                let slot = h
                    .slot
                    .take()
                    .expect("every triangle hit comes from a packed leaf");
                let Primitive::Triangle { mesh, tri } = g.prims()[h.prim as usize] else {
                    panic!("a triangle's slot on another primitive");
                };
                assert_eq!(
                    packed.packed_corners(slot),
                    Some(g.meshes()[mesh as usize].corners(tri))
                );
                slots += 1;
            }
            // Bit for bit: the debug form tells -0 from +0.
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "{ray:?}");
            rays += 1;
            let mut contacts = Vec::new();
            let wr = WatertightRay::new(ray.dir);
            for p in 0..g.prims().len() as u32 {
                g.contacts(p, &ray, &wr, Precision::Watertight, &mut contacts);
            }
            seams += contacts
                .iter()
                .filter(|c| matches!(c.touch, Touch::Boundary { .. }))
                .count();
        }
    }
    // The rays are awkward: most meet the surface on its edges and vertices.
    assert!(
        rays > 1500 && slots > 2000 && seams > 3000,
        "{rays} {slots} {seams}"
    );
}

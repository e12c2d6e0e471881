use glam::DVec3;

use super::shape::MeshShape;
use super::*;
use crate::accel::{AccelKind, BuildOptions};
use crate::camera::Camera;
use crate::geometry::{Mesh, Sphere};
use crate::material::Material;
use crate::scene::SceneBuilder;

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The cube `[0, s]^3`, two triangles per face, outward; `skip` leaves out one face.
fn cube(s: f32, skip: Option<usize>) -> Mesh {
    let p: Vec<Vec3> = (0..8)
        .map(|i| {
            v(
                (i & 1) as f32 * s,
                ((i >> 1) & 1) as f32 * s,
                (i >> 2) as f32 * s,
            )
        })
        .collect();
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let idx = faces
        .iter()
        .enumerate()
        .filter(|(f, _)| Some(*f) != skip)
        .flat_map(|(_, &[a, b, c, d])| [[a, b, c], [a, c, d]])
        .collect();
    Mesh::new(p, None, None, idx).unwrap()
}

/// A unit sphere of `8 * 4^level` triangles (a subdivided octahedron), outward.
fn sphere_mesh(level: u32) -> Mesh {
    let mut tris: Vec<[DVec3; 3]> = Vec::new();
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    for s in 0..8 {
        let sign = |k: usize| if s >> k & 1 == 1 { -1.0 } else { 1.0 };
        let [a, b, c] = [0, 1, 2].map(|k| axes[k] * sign(k));
        let flip = sign(0) * sign(1) * sign(2) < 0.0;
        tris.push(if flip { [a, c, b] } else { [a, b, c] });
    }
    for _ in 0..level {
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    let positions = tris
        .iter()
        .flatten()
        .map(|p| p.normalize().as_vec3())
        .collect();
    let idx = (0..tris.len() as u32)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    Mesh::new(positions, None, None, idx).unwrap()
}

fn world(meshes: Vec<Mesh>, spheres: &[Sphere]) -> World {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    for (i, mesh) in meshes.into_iter().enumerate() {
        b.add_mesh(format!("mesh{i}"), mesh, m);
    }
    for (i, s) in spheres.iter().enumerate() {
        b.add_sphere(format!("sphere{i}"), *s, m);
    }
    let cam = Camera::look_at(v(0., 0., 20.), Vec3::ZERO, Vec3::Y, 40.0, 0.0, None).unwrap();
    World::build(
        b.build(cam).unwrap(),
        AccelKind::Sah,
        &BuildOptions::default(),
    )
}

/// Seeded points in `[lo, hi]^3`.
fn points(n: usize, lo: f32, hi: f32, mut seed: u64) -> Vec<Vec3> {
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((seed >> 40) as f32 / (1u64 << 24) as f32)
    };
    (0..n).map(|_| v(next(), next(), next())).collect()
}

#[test]
fn closedness_counts_edges_by_exact_position() {
    assert!(MeshShape::build(&cube(2.0, None)).closed);
    assert!(!MeshShape::build(&cube(2.0, Some(3))).closed);
    // Unwelded: every triangle with its own three vertices.
    let sphere = sphere_mesh(2);
    assert_eq!(sphere.positions().len(), 3 * sphere.triangle_count());
    assert!(MeshShape::build(&sphere).closed);
    // A T-junction: the top face of the cube split at an edge's midpoint on one side only,
    // the crack filled by a zero-area face. Closed with the filler, open without it.
    let c = cube(2.0, None);
    let mut p = c.positions().to_vec();
    p.push(v(1.0, 2.0, 2.0)); // the midpoint of the edge (0,2,2)-(2,2,2)
    let mut idx: Vec<[u32; 3]> = c.indices().to_vec();
    // Face z = 2 is [4, 5, 7, 6]: triangles [4, 5, 7], [4, 7, 6]. Split [4, 7, 6] at 8,
    // which lies on its edge 7-6.
    let top = idx.iter().position(|t| *t == [4, 7, 6]).unwrap();
    idx[top] = [4, 7, 8];
    idx.push([4, 8, 6]);
    let open = Mesh::new(p.clone(), None, None, idx.clone()).unwrap();
    assert!(!MeshShape::build(&open).closed, "edge 7-6 is now single");
    // The face y = 2 ([2, 6, 7, 3]) still uses edge 6-7; the filler 6-8-7 has zero area.
    idx.push([6, 8, 7]);
    let filled = Mesh::new(p, None, None, idx).unwrap();
    assert!(MeshShape::build(&filled).closed);
}

#[test]
fn closed_cube_holds_its_surface_and_nothing_outside() {
    let w = world(vec![cube(2.0, None)], &[]);
    assert_eq!(w.containment_methods(), [ContainmentMethod::Exact]);
    // Every point of the lattice of quarter units over [-1, 3]^3: inside exactly when in
    // [0, 2]^3, faces, edges and corners included.
    let mut pts = Vec::new();
    for i in -4..=12 {
        for j in -4..=12 {
            for k in -4..=12 {
                pts.push(v(i as f32, j as f32, k as f32) * 0.25);
            }
        }
    }
    let got = w.containment(&pts).unwrap();
    for (p, c) in pts.iter().zip(&got) {
        let want = p.cmpge(Vec3::ZERO).all() && p.cmple(Vec3::splat(2.0)).all();
        assert_eq!(c.inside, want, "{p}");
        assert_eq!(c.method, ContainmentMethod::Exact);
    }
    // Just off a face: one ulp either way.
    let off = |x: f32| w.contains_point(v(x, 1.0, 1.0)).inside;
    assert!(off(2.0) && !off(2.0f32.next_up()) && off(2.0f32.next_down()));
    assert!(off(0.0) && !off(-1e-30) && off(1e-30));
}

#[test]
fn spheres_hold_their_closed_ball_exactly() {
    let s = Sphere {
        center: v(10.0, 0.0, 0.0),
        radius: 0.5,
    };
    let w = world(vec![], &[s]);
    let at = |p: Vec3| w.contains_point(p).inside;
    assert!(at(v(10.5, 0.0, 0.0)) && at(v(10.0, -0.5, 0.0)) && at(s.center));
    assert!(!at(v(10.5f32.next_up(), 0.0, 0.0)));
    assert!(
        !at(v(10.5, 1e-30, 0.0)),
        "beyond the ball by 1e-60 in |p - c|^2"
    );
    let near = v(10.0, 0.3, 0.4);
    let exact = (0.3f32 as f64).powi(2) + (0.4f32 as f64).powi(2) <= 0.25;
    assert_eq!(at(near), exact);
}

#[test]
fn non_finite_points_are_refused_by_index() {
    let w = world(vec![cube(1.0, None)], &[]);
    let err = w
        .contains(&[v(0.5, 0.5, 0.5), v(f32::NAN, 0.0, 0.0)])
        .unwrap_err();
    assert_eq!(err.index, 1);
    assert!(err.to_string().starts_with("point 1: [NaN"), "{err}");
}

/// The hierarchy's winding number against the triangle-by-triangle sum, on open and closed
/// spheres and an open cube, at points all around, on vertices and on edge midpoints.
#[test]
fn far_field_winding_number_is_close_to_the_exact_sum() {
    let mut open_sphere = sphere_mesh(4);
    let keep: Vec<[u32; 3]> = open_sphere
        .indices()
        .iter()
        .copied()
        .filter(|t| {
            let c = t.map(|i| open_sphere.positions()[i as usize]);
            (c[0] + c[1] + c[2]).z < 2.4 // a cap cut off the top
        })
        .collect();
    open_sphere = Mesh::new(open_sphere.positions().to_vec(), None, None, keep).unwrap();
    let mut worst = 0.0f64;
    for mesh in [open_sphere, cube(2.0, Some(1)), sphere_mesh(3)] {
        // The far field of the closed sphere too, for the comparison.
        let shape = MeshShape::build_open(&mesh);
        let bounds = shape.bounds;
        let (lo, hi) = (
            bounds.min.min_element() - 1.0,
            bounds.max.max_element() + 1.0,
        );
        let mut pts = points(3000, lo, hi, 5);
        for t in 0..mesh.triangle_count() as u32 {
            let c = mesh.corners(t);
            pts.extend([c[0], (c[0] + c[1]) * 0.5, (c[0] + c[1] + c[2]) / 3.0]);
        }
        for p in pts {
            let fast = shape.winding(&mesh, p).unwrap();
            let exact = shape.winding_exact_sum(&mesh, p.as_dvec3());
            worst = worst.max((fast - exact).abs());
        }
    }
    // Measured: 0.0246 (docs/hard-cases.md states it).
    eprintln!("max |hierarchy - exact sum| = {worst:e}");
    assert!(worst < 0.03, "{worst:e}");
}

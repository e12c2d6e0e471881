//! Point containment (`World::contains`; the rules: docs/hard-cases.md, "Point containment"),
//! against oracles written independently of it:
//!
//! - boxes made of unit squares (a box with a box-shaped cavity, welded and unwelded, placed
//!   by exact instance transforms; tens of thousands of half-unit lattice points, thousands
//!   exactly on faces, edges and corners): the analytic answer, compared exactly;
//! - non-convex and slanted closed meshes (dented cube, octahedron, tetrahedron): the exact
//!   rational ray-casting oracle of the all-hits tests (`all_hits/oracle.rs`);
//! - several objects with a sphere: the union, the ball decided in integer arithmetic;
//! - an open box (one face removed): answered by the winding number, which agrees with a
//!   brute-force `f64` solid-angle sum wherever that sum is 0.1 or more from 1/2, and says so.

use crate::all_hits::oracle::{Side, classify};
use glam::{DAffine3, DMat3, DVec3};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::camera::Camera;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::material::Material;
use lumis_core::math::Vec3;
use lumis_core::scene::{ContainmentMethod, Part, SceneBuilder, Shape, World};
use num_rational::BigRational;
use num_traits::Zero;
use std::collections::HashMap;

type Tri = [[i32; 3]; 3];

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The faces of the box `[lo, hi]` as unit squares, two triangles each, wound outwards (or
/// inwards, for a cavity).
fn box_faces(lo: [i32; 3], hi: [i32; 3], outward: bool, out: &mut Vec<Tri>) {
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        for (plane, positive) in [(lo[k], false), (hi[k], true)] {
            for a in lo[i]..hi[i] {
                for b in lo[j]..hi[j] {
                    let corner = |da: i32, db: i32| {
                        let mut p = [0; 3];
                        (p[k], p[i], p[j]) = (plane, a + da, b + db);
                        p
                    };
                    // Counter-clockwise in (i, j) faces +k.
                    let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    if positive != outward {
                        quad.reverse();
                    }
                    out.push([quad[0], quad[1], quad[2]]);
                    out.push([quad[0], quad[2], quad[3]]);
                }
            }
        }
    }
}

/// A mesh of integer triangles: shared vertices (`weld`) or three of its own per triangle.
fn mesh(tris: &[Tri], weld: bool) -> Mesh {
    let mut positions = Vec::new();
    let mut ids: HashMap<[i32; 3], u32> = HashMap::new();
    let mut idx = Vec::new();
    for t in tris {
        idx.push(t.map(|p| {
            let new = positions.len() as u32;
            let id = if weld {
                *ids.entry(p).or_insert(new)
            } else {
                new
            };
            if id == new {
                positions.push(Vec3::from_array(p.map(|x| x as f32)));
            }
            id
        }));
    }
    Mesh::new(positions, None, None, idx).expect("valid mesh")
}

fn camera() -> Camera {
    Camera::look_at(v(0., 0., 40.), Vec3::ZERO, Vec3::Y, 40.0, 0.0, None).unwrap()
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
    World::build(
        b.build(camera()).unwrap(),
        AccelKind::Sah,
        &BuildOptions::default(),
    )
}

/// Every point `lo + step * (i, j, k)` up to `hi`.
fn lattice(lo: f32, hi: f32, step: f32) -> Vec<Vec3> {
    let n = ((hi - lo) / step) as i32;
    let mut pts = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            for k in 0..=n {
                pts.push(Vec3::new(i as f32, j as f32, k as f32) * step + Vec3::splat(lo));
            }
        }
    }
    pts
}

/// `[0, 8]^3` without the open cavity `(2, 5) x (3, 6) x (2, 6)`.
const OUTER: ([i32; 3], [i32; 3]) = ([0, 0, 0], [8, 8, 8]);
const CAVITY: ([i32; 3], [i32; 3]) = ([2, 3, 2], [5, 6, 6]);

fn box_with_cavity() -> Vec<Tri> {
    let mut tris = Vec::new();
    box_faces(OUTER.0, OUTER.1, true, &mut tris);
    box_faces(CAVITY.0, CAVITY.1, false, &mut tris);
    tris
}

/// The analytic answer for the box with its cavity, `offset` added to it: the closed outer
/// box minus the open cavity (its walls are surface, so inside).
fn in_box_with_cavity(p: Vec3, offset: Vec3) -> bool {
    let p = p - offset;
    let within = |lo: [i32; 3], hi: [i32; 3], strict: bool| {
        (0..3).all(|k| {
            let (l, h) = (lo[k] as f32, hi[k] as f32);
            if strict {
                l < p[k] && p[k] < h
            } else {
                l <= p[k] && p[k] <= h
            }
        })
    };
    within(OUTER.0, OUTER.1, false) && !within(CAVITY.0, CAVITY.1, true)
}

#[test]
fn box_with_a_cavity_on_a_half_unit_lattice_has_no_wrong_answer() {
    let pts = lattice(-3.0, 11.0, 0.5);
    assert!(pts.len() > 24_000);
    let on_surface = pts
        .iter()
        .filter(|p| {
            let outside = |x: Vec3| !in_box_with_cavity(x, Vec3::ZERO);
            in_box_with_cavity(**p, Vec3::ZERO)
                && [Vec3::X, Vec3::Y, Vec3::Z]
                    .iter()
                    .any(|&e| outside(**p + e * 0.25) || outside(**p - e * 0.25))
        })
        .count();
    assert!(on_surface > 1_500, "{on_surface} points on the surface");
    for weld in [true, false] {
        let w = world(vec![mesh(&box_with_cavity(), weld)], &[]);
        assert_eq!(w.containment_methods(), [ContainmentMethod::Exact]);
        let got = w.containment(&pts).unwrap();
        let wrong: Vec<Vec3> = pts
            .iter()
            .zip(&got)
            .filter(|(p, c)| c.inside != in_box_with_cavity(**p, Vec3::ZERO))
            .map(|(p, _)| *p)
            .collect();
        assert!(
            wrong.is_empty(),
            "weld {weld}: {} wrong, e.g. {:?}",
            wrong.len(),
            &wrong[..wrong.len().min(5)]
        );
        assert!(got.iter().all(|c| c.method == ContainmentMethod::Exact));
        // The same answers from one thread and from four.
        let single = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let again = single.install(|| w.contains(&pts).unwrap());
        assert_eq!(again, got.iter().map(|c| c.inside).collect::<Vec<_>>());
    }
}

/// The dented cube (a pyramid pushed into one face), the octahedron and a tetrahedron, at
/// every quarter-unit point around them, against the exact ray-casting oracle.
#[test]
fn slanted_and_non_convex_meshes_match_the_rational_oracle() {
    let dented = {
        let mut tris = Vec::new();
        box_faces([-2, -2, -2], [2, 2, 2], true, &mut tris);
        // Replace the face x = 2 (its unit squares) by a pyramid dented to the centre, fanned
        // over the unit segments of the face's rim (which its neighbours share).
        tris.retain(|t| !t.iter().all(|p| p[0] == 2));
        for ([y, z], [dy, dz]) in [
            ([-2, -2], [1, 0]),
            ([2, -2], [0, 1]),
            ([2, 2], [-1, 0]),
            ([-2, 2], [0, -1]),
        ] {
            for k in 0..4 {
                let a = [2, y + k * dy, z + k * dz];
                let b = [2, y + (k + 1) * dy, z + (k + 1) * dz];
                tris.push([a, b, [0, 0, 0]]);
            }
        }
        tris
    };
    let octahedron: Vec<Tri> = [
        ([3, 0, 0], [0, 3, 0]),
        ([0, 3, 0], [-3, 0, 0]),
        ([-3, 0, 0], [0, -3, 0]),
        ([0, -3, 0], [3, 0, 0]),
    ]
    .iter()
    .flat_map(|&(a, b)| [[a, b, [0, 0, 3]], [b, a, [0, 0, -3]]])
    .collect();
    let tetrahedron: Vec<Tri> = {
        let p = [[-1, -1, -1], [4, 0, 0], [0, 4, 0], [0, 0, 4]];
        [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
            .iter()
            .map(|t| t.map(|i| p[i]))
            .collect()
    };
    let zero = BigRational::zero();
    for (name, tris) in [
        ("dented cube", dented),
        ("octahedron", octahedron),
        ("tetrahedron", tetrahedron),
    ] {
        let m = mesh(&tris, true);
        let corners: Vec<[Vec3; 3]> = (0..m.triangle_count() as u32)
            .map(|t| m.corners(t))
            .collect();
        let w = world(vec![m], &[]);
        assert_eq!(
            w.containment_methods(),
            [ContainmentMethod::Exact],
            "{name}"
        );
        let pts = lattice(-4.0, 4.5, 0.5);
        let got = w.contains(&pts).unwrap();
        let mut surface = 0;
        for (p, inside) in pts.iter().zip(got) {
            let side = classify(*p, Vec3::ZERO, &zero, &corners);
            surface += (side == Side::Surface) as usize;
            assert_eq!(inside, side != Side::Outside, "{name}: {p} is {side:?}");
        }
        assert!(surface > 50, "{name}: {surface} points on the surface");
    }
}

#[test]
fn several_objects_answer_inside_any_of_them_spheres_included() {
    let sphere = Sphere {
        center: v(12.0, 4.0, 4.0),
        radius: 2.5,
    };
    let mut open = Vec::new();
    box_faces([20, 0, 0], [24, 4, 4], true, &mut open);
    open.retain(|t| !t.iter().all(|p| p[2] == 4));
    let w = world(
        vec![mesh(&box_with_cavity(), true), mesh(&open, true)],
        &[sphere],
    );
    use ContainmentMethod::{Exact, WindingNumber};
    assert_eq!(w.containment_methods(), [Exact, WindingNumber, Exact]);
    let pts = lattice(-1.0, 16.0, 0.5);
    let got = w.containment(&pts).unwrap();
    // In units of 1/2: |2p - 2c|^2 <= (2r)^2 in integers.
    let in_ball = |p: Vec3| {
        let d = (p - sphere.center) * 2.0;
        let d = d.to_array().map(|x| x as i64);
        d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= 25
    };
    let mut ball_points = 0;
    for (p, c) in pts.iter().zip(&got) {
        ball_points += in_ball(*p) as usize;
        assert_eq!(
            c.inside,
            in_box_with_cavity(*p, Vec3::ZERO) || in_ball(*p),
            "{p}"
        );
        assert_eq!(c.method, Exact, "the open box is far from these points");
    }
    assert!(ball_points > 300);
}

/// The box with its cavity placed by exact maps (integer translations, a quarter turn, a
/// mirror): the answers are the exact world-space ones.
#[test]
fn instanced_closed_meshes_answer_exactly_under_exact_placements() {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    let proto = b.add_prototype(vec![Part {
        name: "solid".into(),
        shape: Shape::Mesh(mesh(&box_with_cavity(), true)),
        material: m,
    }]);
    // A quarter turn about z then a shift: (x, y, z) -> (-y + 30, x, z), so the copy spans
    // [22, 30] x [0, 8] x [0, 8]; and a mirror x -> -x shifted to [-20, -12].
    let turn = DAffine3::from_mat3_translation(
        DMat3::from_cols(DVec3::Y, -DVec3::X, DVec3::Z),
        DVec3::new(30.0, 0.0, 0.0),
    );
    let mirror = DAffine3::from_mat3_translation(
        DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)),
        DVec3::new(-12.0, 0.0, 0.0),
    );
    b.add_instance(proto, "turned", turn);
    b.add_instance(proto, "mirrored", mirror);
    let w = World::build(
        b.build(camera()).unwrap(),
        AccelKind::Sah,
        &BuildOptions::default(),
    );
    assert_eq!(w.containment_methods(), [ContainmentMethod::Exact; 2]);
    let back = |a: &DAffine3, p: Vec3| a.inverse().transform_point3(p.as_dvec3()).as_vec3();
    for (placement, lo) in [(turn, v(21.0, -1.0, -1.0)), (mirror, v(-21.0, -1.0, -1.0))] {
        let pts: Vec<Vec3> = lattice(0.0, 10.0, 0.5).iter().map(|p| *p + lo).collect();
        let got = w.contains(&pts).unwrap();
        for (p, inside) in pts.iter().zip(got) {
            assert_eq!(
                inside,
                in_box_with_cavity(back(&placement, *p), Vec3::ZERO),
                "{p}"
            );
        }
    }
}

/// The solid angle of triangle `abc` at `q`, by the half-angle formula of Eriksson (1990)
/// over unit vectors: written here apart from the library's.
fn solid_angle(t: &Tri, q: DVec3) -> f64 {
    let [a, b, c] = t.map(|p| (DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) - q).normalize());
    let triple = a.dot(b.cross(c));
    2.0 * triple.atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a))
}

#[test]
fn an_open_box_answers_by_winding_number_and_says_so() {
    let mut open = Vec::new();
    box_faces([0, 0, 0], [4, 4, 4], true, &mut open);
    open.retain(|t| !t.iter().all(|p| p[2] == 4));
    let w = world(vec![mesh(&open, true)], &[]);
    assert_eq!(w.containment_methods(), [ContainmentMethod::WindingNumber]);
    let pts = lattice(-1.0, 5.0, 0.25);
    let got = w.containment(&pts).unwrap();
    let on_surface = |p: Vec3| {
        let inside = p.cmpge(Vec3::ZERO).all() && p.cmple(Vec3::splat(4.0)).all();
        inside && (p.min_element() == 0.0 || p.x == 4.0 || p.y == 4.0)
    };
    let (mut compared, mut surface) = (0, 0);
    for (p, c) in pts.iter().zip(&got) {
        let in_bounds = p.cmpge(Vec3::ZERO).all() && p.cmple(Vec3::splat(4.0)).all();
        let want_method = if in_bounds {
            ContainmentMethod::WindingNumber
        } else {
            ContainmentMethod::Exact
        };
        assert_eq!(c.method, want_method, "{p}");
        if on_surface(*p) {
            assert!(c.inside, "{p} is on the surface");
            surface += 1;
            continue;
        }
        let q = p.as_dvec3();
        let w: f64 =
            open.iter().map(|t| solid_angle(t, q)).sum::<f64>() / (4.0 * std::f64::consts::PI);
        if (w - 0.5).abs() > 0.1 {
            assert_eq!(c.inside, w > 0.5, "{p}: brute-force winding number {w}");
            compared += 1;
        }
    }
    assert!(
        compared > 10_000 && surface > 1_000,
        "{compared} compared, {surface} on the surface"
    );
}

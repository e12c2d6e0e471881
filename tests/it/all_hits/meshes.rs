//! The closed integer meshes the all-hits tests aim at, the scenes made of them, and the exact
//! points (vertices, edge midpoints, face points) rays are aimed through.

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::camera::Camera;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::material::Material;
use lumis_core::math::Vec3;
use lumis_core::scene::{Scene, SceneBuilder, World};

pub fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// A scene of the given meshes and spheres.
pub fn scene(meshes: Vec<Mesh>, spheres: &[Sphere]) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    for (i, mesh) in meshes.into_iter().enumerate() {
        b.add_mesh(format!("mesh{i}"), mesh, m);
    }
    for (i, s) in spheres.iter().enumerate() {
        b.add_sphere(format!("sphere{i}"), *s, m);
    }
    let cam = Camera::look_at(v(0., 0., 20.), Vec3::ZERO, Vec3::Y, 40.0, 0.0, None).unwrap();
    b.build(cam).expect("scene within the value limits")
}

pub fn world(meshes: Vec<Mesh>, spheres: &[Sphere]) -> World {
    World::build(
        scene(meshes, spheres),
        AccelKind::Sah,
        &BuildOptions::default(),
    )
}

pub fn mesh(p: Vec<Vec3>, idx: Vec<[u32; 3]>) -> Mesh {
    Mesh::new(p, None, None, idx).expect("valid mesh")
}

/// The cube [-2, 2]^3, each face split along one of its diagonals (`alt` picks which); with
/// `dent` the face x = 2 is replaced by a pyramid dented in to the centre.
pub fn cube(alt: bool, dent: bool) -> Mesh {
    let mut p: Vec<Vec3> = (0..8)
        .map(|i| {
            let c = |bit: u32| if i & bit != 0 { 2.0 } else { -2.0 };
            v(c(1), c(2), c(4))
        })
        .collect();
    let quads = [
        [0, 2, 6, 4],
        [1, 5, 7, 3],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 6, 7, 5],
    ];
    let mut idx = Vec::new();
    for (f, [a, b, c, d]) in quads.into_iter().enumerate() {
        if dent && f == 1 {
            p.push(Vec3::ZERO);
            for (x, y) in [(a, b), (b, c), (c, d), (d, a)] {
                idx.push([x, y, 8]);
            }
        } else if alt ^ (f % 2 == 0) {
            idx.extend([[a, b, c], [a, c, d]]);
        } else {
            idx.extend([[a, b, d], [b, c, d]]);
        }
    }
    mesh(p, idx)
}

/// |x| + |y| + |z| <= 3.
pub fn octahedron() -> Mesh {
    let p = vec![
        v(3., 0., 0.),
        v(-3., 0., 0.),
        v(0., 3., 0.),
        v(0., -3., 0.),
        v(0., 0., 3.),
        v(0., 0., -3.),
    ];
    let mut idx = Vec::new();
    for (a, b) in [(0, 2), (2, 1), (1, 3), (3, 0)] {
        idx.extend([[a, b, 4], [b, a, 5]]);
    }
    mesh(p, idx)
}

pub fn tetrahedron() -> Mesh {
    let p = vec![
        v(-1., -1., -1.),
        v(4., 0., 0.),
        v(0., 4., 0.),
        v(0., 0., 4.),
    ];
    mesh(p, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
}

/// Two fans of eight triangles around the apexes (0, 0, +-3) over an integer octagon.
pub fn bipyramid() -> Mesh {
    let ring = [
        (3, 0),
        (2, 2),
        (0, 3),
        (-2, 2),
        (-3, 0),
        (-2, -2),
        (0, -3),
        (2, -2),
    ];
    let mut p: Vec<Vec3> = ring
        .iter()
        .map(|&(x, y)| v(x as f32, y as f32, 0.))
        .collect();
    p.extend([v(0., 0., 3.), v(0., 0., -3.)]);
    let idx = (0..8u32)
        .flat_map(|i| [[i, (i + 1) % 8, 8], [(i + 1) % 8, i, 9]])
        .collect();
    mesh(p, idx)
}

pub fn triangles(m: &Mesh) -> Vec<[Vec3; 3]> {
    (0..m.triangle_count() as u32)
        .map(|t| m.corners(t))
        .collect()
}

/// Vertices, edge midpoints and one exact point inside every face: where rays are aimed.
pub fn targets(m: &Mesh) -> Vec<Vec3> {
    let p = m.positions();
    let mut t = p.to_vec();
    for &[a, b, c] in m.indices() {
        let (a, b, c) = (p[a as usize], p[b as usize], p[c as usize]);
        t.extend([
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (a + b + c * 2.0) * 0.25,
        ]);
    }
    t
}

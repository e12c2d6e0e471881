//! The examples of issue 24 through the whole checker (every accelerator, traversal and
//! precision, brute force and the exact oracle): far origins must neither lose hits nor
//! report false ones, and the front face of a far mesh is the answer.

use super::queries::{self, Prim};
use super::{octahedron, ray, scene, sphere, tri};
use lumis_core::math::Ray;

/// The unit-sphere mesh seen from `(x, x, x)` with `d = -o` exactly: the exact answer is the
/// front face (0) near `t = 1`.
#[test]
fn a_unit_sphere_mesh_from_1e19_is_hit_on_its_front_face() {
    let mesh = octahedron();
    for x in [1e6f32, 1e19, 1e30, 1e38] {
        queries::check(&scene(&mesh), &[ray([x; 3], [-x; 3])]);
    }
}

/// From 1e30, 1e-3 rad off a triangle: the exact answer is a miss.
#[test]
fn rays_from_1e30_aimed_off_a_mesh_miss_it() {
    let prims = [tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])];
    let rays: Vec<Ray> = [[1e-3f32, 0.0, -1.0], [0.0, -1e-3, -1.0], [1e-3, 1e-3, -1.0]]
        .iter()
        .map(|d| ray([0.25, 0.25, 1e30], *d))
        .collect();
    queries::check(&scene(&prims), &rays);
}

/// Straight at a unit sphere and a triangle from 1e6 up to 3e38, and back out along the
/// other side (the sphere's front, not its back).
#[test]
fn origins_from_1e6_to_3e38_see_the_front_of_a_sphere() {
    let prims: [Prim; 2] = [
        sphere([0.0, 0.0, 0.0], 1.0),
        tri([-4.0, -4.0, -3.0], [4.0, -4.0, -3.0], [0.0, 4.0, -3.0]),
    ];
    let rays: Vec<Ray> = [1e6f32, 1e10, 1e19, 1e30, 3e38]
        .iter()
        .flat_map(|&x| {
            [
                ray([0.0, 0.0, x], [0.0, 0.0, -1.0]),
                ray([0.1, 0.2, x], [0.0, 0.0, -x]),
            ]
        })
        .collect();
    queries::check(&scene(&prims), &rays);
}

/// Two concentric spheres seen from 1e19: both fronts are `t = 1e19` in `f32`, but the outer
/// one (primitive 1) is in front; the lower index is no tie-breaker for distinct exact hits.
#[test]
fn a_far_ray_sees_the_outer_of_two_concentric_spheres() {
    let prims = [sphere([0.0; 3], 1.0), sphere([0.0; 3], 10.0)];
    queries::check(&scene(&prims), &[ray([0.0, 0.0, 1e19], [0.0, 0.0, -1.0])]);
}

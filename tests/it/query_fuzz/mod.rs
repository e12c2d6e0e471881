//! The `queries` fuzz target's checker (fuzz/src/queries/, included by path in `main.rs`) in stable
//! `cargo test`: its oracle on hand-made cases with known answers and against the hard-case
//! suite's rational arithmetic ([`oracle_cases`]), the oracle's classification of decoded
//! scenes against plain big rationals ([`oracle_crosscheck`]), the issue's examples
//! ([`issue_cases`]), and a seeded run over pseudo-random inputs ([`seeded`]), so the checker
//! runs without nightly.

use crate::hard_cases::exact;
use crate::queries;

mod issue_cases;
mod oracle_cases;
mod oracle_crosscheck;
mod seeded;
mod survey_cases;

use lumis_core::math::{Ray, Vec3};
use queries::{Prim, Scene};

/// The scene of `prims` (all must be accepted).
fn scene(prims: &[Prim]) -> Scene {
    let s = Scene::build(prims).expect("a valid scene");
    assert_eq!(s.prims.len(), prims.len(), "every primitive accepted");
    s
}

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Prim {
    Prim::Triangle([a, b, c].map(Vec3::from_array))
}

fn sphere(c: [f32; 3], r: f32) -> Prim {
    Prim::Sphere {
        center: Vec3::from_array(c),
        radius: r,
    }
}

fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
    Ray::new(Vec3::from_array(o), Vec3::from_array(d))
}

/// The octahedron with corners on the unit axes: the coarsest unit-sphere mesh, its faces
/// in octant order (face `i` has outward normal signs from the bits of `i`, 0 = positive).
fn octahedron() -> Vec<Prim> {
    (0..8)
        .map(|i| {
            let s = |bit: u32| if i & (1 << bit) == 0 { 1.0 } else { -1.0 };
            tri([s(0), 0.0, 0.0], [0.0, s(1), 0.0], [0.0, 0.0, s(2)])
        })
        .collect()
}

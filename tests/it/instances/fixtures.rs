//! Scenes of instances and their flattened twins.

use crate::common::{Rng, scenes};
use glam::{DAffine3, DQuat, DVec3};
use lumis_core::camera::Camera;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::material::Material;
use lumis_core::math::{Mat4, Vec3};
use lumis_core::scene::{Part, Scene, SceneBuilder, Shape};

/// Placements that cover the transform classes: identity, rotation, uniform and non-uniform
/// scale, mirrors (one and three axes), a shear and a far translation.
pub fn placements() -> Vec<DAffine3> {
    let rot = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
    vec![
        DAffine3::IDENTITY,
        DAffine3::from_scale_rotation_translation(
            DVec3::splat(1.5),
            rot,
            DVec3::new(4.0, 0.5, -1.0),
        ),
        DAffine3::from_scale_rotation_translation(
            DVec3::new(0.5, 2.0, 1.0),
            DQuat::from_rotation_y(0.7),
            DVec3::new(-4.0, 1.0, 2.0),
        ),
        DAffine3::from_scale_rotation_translation(
            DVec3::new(-1.0, 1.0, 1.0),
            DQuat::IDENTITY,
            DVec3::new(0.0, 4.0, 0.0),
        ),
        DAffine3::from_scale_rotation_translation(
            DVec3::splat(-0.75),
            rot,
            DVec3::new(0.0, -4.0, 1.0),
        ),
        DAffine3::from_cols_array(&[1.0, 0.0, 0.0, 0.4, 1.0, 0.0, 0.0, 0.3, 1.0, 3.0, -3.0, 3.0]),
    ]
}

/// The prototype: a jittered closed icosphere and a sphere beside it.
pub fn prototype_parts() -> (Mesh, Sphere) {
    let mesh = scenes::icosphere(2, 0.02, &mut Rng::new(3));
    let sphere = Sphere {
        center: Vec3::new(1.6, 0.0, 0.0),
        radius: 0.5,
    };
    (mesh, sphere)
}

/// A camera looking at the origin from `+z`.
pub fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 0.0, 18.0),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        0.0,
        None,
    )
    .expect("valid camera")
}

/// The two-part prototype ([`prototype_parts`], named `ball` and `moon`) of material `m`.
pub fn add_prototype(b: &mut SceneBuilder, m: u32) -> u32 {
    let (mesh, sphere) = prototype_parts();
    b.add_prototype(vec![
        Part {
            name: "ball".into(),
            shape: Shape::Mesh(mesh),
            material: m,
        },
        Part {
            name: "moon".into(),
            shape: Shape::Sphere(sphere),
            material: m,
        },
    ])
}

/// The placements as instances of one two-part prototype, after a plain triangle of the top
/// level (so primitives of both levels meet).
pub fn instanced(placements: &[DAffine3]) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    b.add_mesh("ground", ground(), m);
    let proto = add_prototype(&mut b, m);
    for (i, p) in placements.iter().enumerate() {
        b.add_instance(proto, format!("copy{i}"), *p);
    }
    b.build(camera()).expect("within the limits")
}

/// The same placements flattened: each a transformed copy of the mesh (spheres only where
/// the placement keeps them spheres: a uniform scale without shear).
pub fn flattened(placements: &[DAffine3]) -> Scene {
    let (mesh, _) = prototype_parts();
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    b.add_mesh("ground", ground(), m);
    for (i, p) in placements.iter().enumerate() {
        let m4: Mat4 = glam::DMat4::from(*p).as_mat4();
        b.add_mesh(format!("copy{i}"), mesh.clone().transformed(&m4), m);
    }
    b.build(camera()).expect("within the limits")
}

/// A large triangle behind everything.
fn ground() -> Mesh {
    scenes::soup(&[[
        Vec3::new(-30.0, -30.0, -8.0),
        Vec3::new(30.0, -30.0, -8.0),
        Vec3::new(0.0, 30.0, -8.0),
    ]])
}

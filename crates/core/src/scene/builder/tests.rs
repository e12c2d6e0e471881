//! The builder's object bookkeeping and light names.

use super::*;
use crate::geometry::{Mesh, Sphere};
use crate::math::Vec3;

fn two_triangles() -> Mesh {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
    Mesh::new(p, None, None, vec![[0, 1, 2], [0, 2, 3]]).expect("valid mesh")
}

#[test]
fn each_primitive_belongs_to_the_object_that_added_it() {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    let tri = |x: f32| {
        let p = vec![
            Vec3::new(x, 0., 0.),
            Vec3::new(x + 1., 0., 0.),
            Vec3::new(x, 1., 0.),
        ];
        Mesh::new(p, None, None, vec![[0, 1, 2]]).expect("valid mesh")
    };
    let empty = Mesh::new(vec![], None, None, vec![]).expect("an empty mesh is valid");
    // Objects 0..5 own primitives [0], [1, 2], [], [3], [] (an empty object in the middle
    // and one at the end).
    let sphere = Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    };
    b.add_sphere("s", sphere, m);
    b.add_mesh("two", two_triangles(), m);
    b.add_mesh("empty", empty.clone(), m);
    b.add_mesh("one", tri(2.0), m);
    b.add_mesh("empty at the end", empty, m);
    let cam = Camera::look_at(Vec3::Z * 10.0, Vec3::ZERO, Vec3::Y, 40.0, 0.0, None)
        .expect("valid camera");
    let scene = b.build(cam).expect("within the limits");
    let owners: Vec<u32> = (0..4).map(|p| scene.object_of(p)).collect();
    assert_eq!(owners, [0, 1, 1, 3]);
}

#[test]
fn a_scene_of_one_object_owns_every_primitive() {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    b.add_mesh("two", two_triangles(), m);
    let cam = Camera::look_at(Vec3::Z * 10.0, Vec3::ZERO, Vec3::Y, 40.0, 0.0, None)
        .expect("valid camera");
    let scene = b.build(cam).expect("within the limits");
    assert_eq!([scene.object_of(0), scene.object_of(1)], [0, 0]);
}

#[test]
fn light_names_are_exr_safe_and_unique() {
    let taken = vec!["key".to_string(), "key_2".to_string()];
    assert_eq!(unique_light_name(&taken, "key"), "key_3");
    assert_eq!(unique_light_name(&taken, "fill light.1"), "fill_light_1");
    assert_eq!(unique_light_name(&taken, ""), "light");
}

mod singular {
    use super::*;
    use glam::{DAffine3, DVec3};

    fn camera() -> Camera {
        Camera::look_at(Vec3::Z * 10.0, Vec3::ZERO, Vec3::Y, 40.0, 0.0, None).expect("valid camera")
    }

    fn scaled(x: f64, y: f64, z: f64) -> DAffine3 {
        DAffine3::from_scale(DVec3::new(x, y, z))
    }

    /// A prototype of a two-triangle mesh.
    fn mesh_prototype() -> (SceneBuilder, u32) {
        let mut b = SceneBuilder::new();
        let m = b.add_material(Material::default());
        let mesh = Part {
            name: "mesh".into(),
            shape: Shape::Mesh(two_triangles()),
            material: m,
        };
        let p = b.add_prototype(vec![mesh]);
        (b, p)
    }

    /// A prototype of a two-triangle mesh and a sphere.
    fn builder() -> (SceneBuilder, u32) {
        let mut b = SceneBuilder::new();
        let m = b.add_material(Material::default());
        let sphere = Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let parts = vec![
            Part {
                name: "mesh".into(),
                shape: Shape::Mesh(two_triangles()),
                material: m,
            },
            Part {
                name: "ball".into(),
                shape: Shape::Sphere(sphere),
                material: m,
            },
        ];
        let p = b.add_prototype(parts);
        (b, p)
    }

    #[test]
    fn a_placement_onto_a_line_or_a_point_keeps_empty_objects_and_copies_nothing() {
        let (mut b, p) = builder();
        b.add_instance(p, "seen", DAffine3::IDENTITY);
        assert_eq!(b.add_instance(p, "point", scaled(0.0, 0.0, 0.0)), 2);
        b.add_instance(p, "line", scaled(0.0, 4.0, 0.0));
        b.add_instance(p, "after", DAffine3::from_translation(DVec3::X * 3.0));
        let scene = b.build(camera()).expect("hidden placements are fine");
        let names: Vec<&str> = scene.objects().iter().map(|o| o.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "seen/mesh",
                "seen/ball",
                "point/mesh",
                "point/ball",
                "line/mesh",
                "line/ball",
                "after/mesh",
                "after/ball"
            ]
        );
        assert_eq!(scene.geometry().instances().len(), 2);
        assert!(scene.geometry().meshes().is_empty());
        // The instance after them still names its own objects.
        assert_eq!(scene.instance_objects(), [0, 6]);
    }

    #[test]
    fn a_placement_onto_a_plane_copies_its_meshes_but_refuses_its_spheres() {
        let (mut b, p) = builder();
        b.add_instance(p, "flat", scaled(2.0, 2.0, 0.0));
        let e = b.build(camera()).expect_err("an elliptic disc");
        assert_eq!(e.element, "instance \"flat\"");
        assert!(e.message.contains("elliptic disc"), "{}", e.message);

        let (mut b, p) = mesh_prototype();
        b.add_instance(p, "flat", scaled(2.0, 2.0, 0.0));
        let scene = b.build(camera()).expect("a flat mesh is fine");
        assert_eq!(scene.geometry().instances().len(), 0);
        let copy = &scene.geometry().meshes()[0];
        assert_eq!(copy.triangle_count(), 2);
        assert_eq!(copy.bounds().max, Vec3::new(2.0, 2.0, 0.0));
        assert_eq!(scene.objects()[0].name, "flat");
    }

    #[test]
    fn flattened_copies_stop_at_their_budget_naming_the_placement() {
        let (mut b, p) = mesh_prototype();
        b.singular_budget = 5;
        for k in 0..3 {
            b.add_instance(p, format!("flat{k}"), scaled(1.0, 0.0, 1.0));
        }
        let e = b.build(camera()).expect_err("6 triangles > 5");
        assert_eq!(e.element, "instance \"flat2\"");
        assert!(e.message.contains("zero scale"), "{}", e.message);
    }
}

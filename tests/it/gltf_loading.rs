//! glTF 2.0 loading on the assets `tools/gen_gltf_assets.py` writes to `assets/gltf/`: the three
//! containers agree pixel for pixel, and counts, bounds, materials, lights and cameras match what
//! the generator put in.

use crate::common;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::geometry::Mesh;
use lumis_core::light::Light;
use lumis_core::material::Texture;
use lumis_core::math::{Aabb, Vec3};
use lumis_core::scene::Scene;
use lumis_core::texture::srgb_to_linear;
use lumis_io::formats::{self, LoadOptions};

use common::files::gltf_asset as asset;

fn load(name: &str) -> Scene {
    common::render::load(&asset(name))
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

fn assert_bounds(b: Aabb, min: [f32; 3], max: [f32; 3]) {
    assert!(
        close(b.min, Vec3::from(min)) && close(b.max, Vec3::from(max)),
        "bounds {b:?}, expected {min:?}..{max:?}"
    );
}

/// True when every triangle of `m` faces away from `centre` (outward winding of a convex mesh).
fn faces_outward(m: &Mesh, centre: Vec3) -> bool {
    (0..m.triangle_count() as u32).all(|t| {
        let [a, b, c] = m.corners(t);
        (b - a).cross(c - a).dot((a + b + c) / 3.0 - centre) > 0.0
    })
}

#[test]
fn gltf_bin_data_uri_and_glb_render_identical_depth_and_ids() {
    let names = ["cube.gltf", "cube_embedded.gltf", "cube.glb"];
    let films: Vec<_> = names
        .iter()
        .map(|name| {
            let mut s = load(name);
            assert_eq!(s.geometry().prims().len(), 12, "{name}");
            assert_bounds(s.geometry().bounds(), [-0.5; 3], [0.5; 3]);
            let cam = lumis_core::camera::Camera::look_at(
                Vec3::new(1.5, 1.2, 2.5),
                Vec3::ZERO,
                Vec3::Y,
                40.0,
                0.0,
                None,
            )
            .unwrap();
            s.set_camera(cam);
            common::render::film(
                s,
                (48, 32),
                AccelKind::Sah,
                &BuildOptions {
                    max_leaf_size: 4,
                    ..Default::default()
                },
            )
        })
        .collect();
    let hits = films[0].aov().iter().filter(|a| a.prim_id >= 0).count();
    assert!(
        hits > 100,
        "the cube should cover part of the image ({hits} pixels)"
    );
    for (name, film) in names.iter().zip(&films).skip(1) {
        for (a, b) in films[0].aov().iter().zip(film.aov()) {
            assert_eq!(a.depth.to_bits(), b.depth.to_bits(), "{name}");
            assert_eq!((a.prim_id, a.object_id), (b.prim_id, b.object_id), "{name}");
        }
        assert_eq!(films[0].rgba(), film.rgba(), "{name}");
    }
}

#[test]
fn cube_material_uvs_and_normals_are_read() {
    let s = load("cube.glb");
    let m = &s.geometry().meshes()[0];
    assert!(m.normals().is_some() && m.uvs().is_some());
    assert!(faces_outward(m, Vec3::ZERO));
    let red = s.material_of(0);
    // metallic 0: kd is the base colour; roughness 0.5: n = 2 / 0.5^4 - 2 = 30.
    assert_eq!(red.diffuse, Texture::Solid(Vec3::new(0.8, 0.1, 0.1)));
    assert!((red.shininess - 30.0).abs() < 1e-3);
    assert_eq!((red.reflectivity, red.transmission), (0.0, 0.0));
    assert!(close(red.specular, Vec3::splat(0.04)));
    // No lights in the file: the default rig.
    assert_eq!(s.lights().len(), 2);
    // The material keeps its glTF name (what Cryptomatte's material mattes are called); a
    // primitive without a material gets the specification's default material, "default".
    assert_eq!(s.material_names()[s.objects()[0].material as usize], "red");
    let plain = load("hierarchy.gltf");
    assert!(
        plain
            .objects()
            .iter()
            .all(|o| plain.material_names()[o.material as usize] == "default")
    );
}

#[test]
fn sparse_accessor_overrides_two_corners() {
    let s = load("sparse.gltf");
    let m = &s.geometry().meshes()[0];
    let ys: Vec<f32> = m.positions().iter().map(|p| p.y).collect();
    assert_eq!(ys, [0.0, 0.0, 1.0, 1.0]);
    assert_bounds(s.geometry().bounds(), [-1.0, 0.0, -1.0], [1.0, 1.0, 1.0]);
}

#[test]
fn strips_and_fans_keep_front_faces_and_points_are_skipped_with_a_warning() {
    let s = load("strip_fan.gltf");
    let meshes = s.geometry().meshes();
    assert_eq!(meshes.len(), 2);
    assert_eq!(meshes[0].triangle_count(), 4);
    assert_eq!(meshes[1].triangle_count(), 3);
    for m in meshes {
        for t in 0..m.triangle_count() as u32 {
            let [a, b, c] = m.corners(t);
            assert!((b - a).cross(c - a).z > 0.0, "triangle {t} faces away");
        }
    }
    assert_eq!(s.objects()[0].name, "strip_fan/0");
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.contains("primitives[2]") && w.contains("Points")),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn hierarchy_composes_parent_and_child_and_negative_scale_keeps_faces_outward() {
    // Flattened, the two placements of the shared cube are world-space meshes to measure.
    let options = LoadOptions {
        flatten_instances: true,
        ..LoadOptions::default()
    };
    let s = formats::load_with(&asset("hierarchy.gltf"), &options).unwrap();
    let names: Vec<&str> = s.objects().iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["stretched", "mirrored"]);
    let meshes = s.geometry().meshes();
    // Parent: +90 degrees about Y ((x, y, z) -> (z, y, -x)), then z + 10.
    assert_bounds(meshes[0].bounds(), [-0.25, -0.5, 7.0], [0.25, 0.5, 9.0]);
    assert_bounds(meshes[1].bounds(), [-0.5, 2.5, 9.5], [0.5, 3.5, 10.5]);
    assert!(faces_outward(&meshes[0], Vec3::new(0.0, 0.0, 8.0)));
    assert!(faces_outward(&meshes[1], Vec3::new(0.0, 3.0, 10.0)));
}

#[test]
fn one_mesh_placed_by_three_nodes_makes_three_objects() {
    // Three instances of one 12-triangle prototype, one top-level primitive each.
    let s = load("instancing.gltf");
    assert_eq!(s.objects().len(), 3);
    assert_eq!(s.geometry().instances().len(), 3);
    assert_eq!(s.geometry().prims().len(), 3);
    assert_eq!(s.geometry().prototypes()[0].geometry().prims().len(), 12);
    // Instance boxes are padded for the transform's rounding (a few 1e-5 here).
    let b = s.geometry().bounds();
    assert!(b.min.x <= -3.5 && b.min.x > -3.5001 && b.max.x >= 3.5 && b.max.x < 3.5001);
    let options = LoadOptions {
        flatten_instances: true,
        ..LoadOptions::default()
    };
    let flat = formats::load_with(&asset("instancing.gltf"), &options).unwrap();
    assert_eq!(flat.objects().len(), 3);
    assert_eq!(flat.geometry().prims().len(), 36);
    assert_bounds(
        flat.geometry().bounds(),
        [-3.5, -0.5, -0.5],
        [3.5, 0.5, 0.5],
    );
}

#[test]
fn missing_normals_mean_flat_shading() {
    let s = load("no_normals.gltf");
    let m = &s.geometry().meshes()[0];
    assert_eq!(m.triangle_count(), 1);
    assert!(m.normals().is_none());
    // A primitive without a material gets lumis's default grey.
    assert_eq!(s.material_of(0), &lumis_core::material::Material::default());
}

#[test]
fn textured_quad_loads_uvs_and_applies_its_base_colour_texture() {
    let s = load("textured_quad.gltf");
    let m = &s.geometry().meshes()[0];
    assert_eq!(m.uvs().map(<[_]>::len), Some(4));
    assert_eq!(m.uvs().unwrap()[1], lumis_core::math::Vec2::new(1.0, 1.0));
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    // checker.png is 2x2: sRGB 230 on the diagonal from the top-left, 20 elsewhere.
    let material = s.material_of(0);
    let image = &material
        .textured
        .as_ref()
        .unwrap()
        .base_texture
        .as_ref()
        .unwrap()
        .image;
    assert_eq!((image.width(), image.height()), (2, 2));
    let (light, dark) = (srgb_to_linear(230.0 / 255.0), srgb_to_linear(20.0 / 255.0));
    let at = |u: f32, v: f32| {
        let uv = lumis_core::math::Vec2::new(u, v);
        let attrs = lumis_core::geometry::HitAttributes {
            uvs: [uv; 2],
            color: lumis_core::math::Vec4::ONE,
            tangent: None,
        };
        let hit = material.at_hit(&attrs, Vec3::Z, Vec3::Z).unwrap();
        hit.material.diffuse.eval(Vec3::ZERO, uv).x
    };
    assert!((at(0.25, 0.25) - light).abs() < 1e-6 && (at(0.75, 0.75) - light).abs() < 1e-6);
    assert!((at(0.75, 0.25) - dark).abs() < 1e-6 && (at(0.25, 0.75) - dark).abs() < 1e-6);
}

#[test]
fn lights_and_camera_take_their_node_transforms() {
    let s = load("lights_camera.gltf");
    assert_eq!(s.lights().len(), 3);
    // Candela and lux to W/sr and W/m^2: divided by 683 lm/W.
    let watts = |v: Vec3| v / lumis_core::light::LUMENS_PER_WATT;
    assert_eq!(
        s.lights()[0],
        Light::Point {
            position: Vec3::new(-2.0, 4.0, 2.0),
            intensity: watts(Vec3::new(40.0, 20.0, 10.0)),
        }
    );
    let Light::Spot {
        position,
        direction,
        intensity,
        cos_inner,
        cos_outer,
    } = s.lights()[1]
    else {
        panic!("{:?}", s.lights()[1]);
    };
    assert!(close(position, Vec3::new(0.0, 4.0, 0.0)));
    assert!(close(direction, -Vec3::Y));
    assert_eq!(intensity, watts(Vec3::splat(100.0)));
    assert!((cos_inner - 0.2f32.cos()).abs() < 1e-6 && (cos_outer - 0.4f32.cos()).abs() < 1e-6);
    let Light::Directional {
        direction,
        irradiance,
    } = s.lights()[2]
    else {
        panic!("{:?}", s.lights()[2]);
    };
    assert!(close(direction, -Vec3::Y));
    assert_eq!(irradiance, watts(Vec3::new(1.0, 1.0, 2.0)));
    let cam = s.camera();
    assert!(close(cam.position(), Vec3::new(0.0, 1.0, 6.0)));
    assert!(close(cam.forward(), -Vec3::Z));
    // aspectRatio 1.5 sets the height for the default width.
    assert_eq!((s.settings().width, s.settings().height), (640, 427));
}

#[test]
fn camera_and_scene_choices_are_checked() {
    let path = asset("lights_camera.gltf");
    let pick = |scene, camera| {
        let options = LoadOptions {
            scene,
            camera,
            ..LoadOptions::default()
        };
        formats::load_with(&path, &options)
    };
    assert!(pick(Some(0), Some(0)).is_ok());
    let e = format!(
        "{:#}",
        anyhow::Error::from(pick(None, Some(1)).unwrap_err())
    );
    assert!(
        e.contains("camera 1") && e.contains("lights_camera.gltf"),
        "{e}"
    );
    let e = pick(Some(3), None).unwrap_err().to_string();
    assert!(e.contains("scene 3"), "{e}");
    // Files without a camera are framed automatically.
    let framed = load("instancing.gltf");
    assert!(framed.camera().position().z > 1.0);
}

#[test]
fn pbr_materials_map_by_the_documented_rules() {
    let s = load("materials.gltf");
    let by_name = |n: &str| {
        let o = s.objects().iter().position(|o| o.name == n).unwrap();
        s.material_of(o as u32).clone()
    };
    let gold = by_name("gold");
    assert_eq!(gold.reflectivity, 1.0);
    assert_eq!(gold.diffuse, Texture::Solid(Vec3::ZERO));
    assert!(close(gold.specular, Vec3::new(1.0, 0.8, 0.3)));
    assert_eq!(gold.shininess, 10_000.0);
    let glass = by_name("glass");
    assert_eq!((glass.transmission, glass.ior), (1.0, 1.45));
    assert_eq!(glass.diffuse, Texture::Solid(Vec3::ZERO));
    let lamp = by_name("lamp");
    assert!(close(lamp.emission, Vec3::new(2.0, 1.0, 0.5)));
    let ghost = by_name("ghost");
    assert_eq!((ghost.transmission, ghost.ior), (0.75, 1.0));
    assert_eq!(ghost.shininess, 0.0);
    let Texture::Solid(kd) = ghost.diffuse else {
        panic!()
    };
    assert!(close(kd, Vec3::new(0.05, 0.1, 0.15)));
}

#[test]
fn cli_renders_a_glb_directly_and_chooses_cameras() {
    let dir = tempfile::tempdir().unwrap();
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lumis"))
            .current_dir(dir.path())
            .arg("render")
            .arg(asset("lights_camera.gltf"))
            .args(["--width", "24", "--height", "16", "--spp", "1", "--quiet"])
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run(&["-o", "a.png", "--camera", "0", "--gltf-scene", "0"]);
    common::cli::assert_ok(&out);
    assert!(dir.path().join("a.png").exists());
    let out = run(&["-o", "b.png", "--camera", "4"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("camera 4"),
        "{stderr}"
    );
    assert!(!dir.path().join("b.png").exists());
}

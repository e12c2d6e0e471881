//! glTF files the `gltf` crate alone would refuse (custom attributes, a scene without nodes,
//! POSITION without min/max), orthographic cameras (glTF and TOML), photometric light units and
//! the default rig following the file's camera; on the assets `tools/gen_gltf_assets.py` writes.

use crate::common;

use std::path::Path;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::Film;
use lumis_core::light::Light;
use lumis_core::scene::Scene;
use lumis_io::formats;

use common::files::gltf_asset as asset;

fn load(name: &str) -> Scene {
    common::render::load(&asset(name))
}

fn render_at(s: Scene, width: u32, height: u32) -> Film {
    let build = BuildOptions {
        max_leaf_size: 4,
        ..Default::default()
    };
    common::render::film(s, (width, height), AccelKind::Sah, &build)
}

fn warned(s: &Scene, pieces: &[&str]) -> bool {
    s.warnings()
        .iter()
        .any(|w| pieces.iter().all(|p| w.contains(p)))
}

#[test]
fn custom_vertex_attributes_are_ignored_with_a_warning_naming_them() {
    let s = load("custom_attribute.gltf");
    assert_eq!(s.geometry().prims().len(), 12);
    assert!(
        warned(&s, &["meshes[0].primitives[0]", "_BARYCENTRIC", "ignored"]),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn a_scene_without_nodes_renders_the_background_and_warns() {
    let s = load("empty_scene.gltf");
    assert_eq!(s.geometry().prims().len(), 0);
    assert!(
        warned(&s, &["no triangles", "background"]),
        "{:?}",
        s.warnings()
    );
    let film = render_at(s, 8, 6);
    assert!(
        film.rgba()
            .iter()
            .all(|p| p.w == 0.0 && p.truncate().max_element() == 0.0)
    );
}

#[test]
fn position_without_min_max_loads_with_bounds_from_the_data() {
    let s = load("no_minmax.gltf");
    let b = s.geometry().bounds();
    assert_eq!((b.min.to_array(), b.max.to_array()), ([-0.5; 3], [0.5; 3]));
    assert!(warned(&s, &["POSITION", "min/max"]), "{:?}", s.warnings());
}

/// Pixels whose centre ray hits object `object`: count and bounding box width, height.
fn footprint(film: &Film, object: i32) -> (usize, u32, u32) {
    let (mut n, mut x0, mut x1, mut y0, mut y1) = (0, u32::MAX, 0, u32::MAX, 0);
    for y in 0..film.height() {
        for x in 0..film.width() {
            if film.pixel_aov(x, y).object_id == object {
                n += 1;
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
    }
    (n, x1.saturating_sub(x0) + 1, y1.saturating_sub(y0) + 1)
}

#[test]
fn orthographic_gltf_camera_shows_near_and_far_cubes_at_equal_size() {
    let s = load("ortho_cubes.gltf");
    assert!(s.camera().is_orthographic());
    // xmag / ymag = 2 sets the aspect ratio of the default size.
    assert_eq!((s.settings().width, s.settings().height), (640, 320));
    // 8 x 4 world units over 128 x 64 pixels: each unit cube covers 16 x 16 pixels.
    let film = render_at(s, 128, 64);
    let (near, far) = (footprint(&film, 0), footprint(&film, 1));
    assert_eq!(near, (256, 16, 16), "near cube");
    assert_eq!(far, near, "far cube");
}

#[test]
fn orthographic_toml_camera_matches_the_gltf_one() {
    let toml = format!(
        r#"
        [render]
        width = 128
        height = 64
        [camera]
        type = "orthographic"
        position = [0.0, 0.0, 5.0]
        look_at = [0.0, 0.0, 0.0]
        height = 4.0
        [[mesh]]
        file = "{}"
        "#,
        asset("ortho_cubes.gltf").display()
    );
    let s = formats::toml::load_toml_str(&toml, Path::new("ortho.toml"), &|p| std::fs::read(p))
        .unwrap_or_else(|e| panic!("{e:#}"));
    assert!(s.camera().is_orthographic());
    let film = render_at(s, 128, 64);
    let sizes: Vec<_> = (0..2).map(|o| footprint(&film, o)).collect();
    assert!(sizes[0].0 > 0, "{sizes:?}");
    assert_eq!(sizes[0], sizes[1]);
    for bad in [
        "type = \"orthographic\"\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]",
        "type = \"orthographic\"\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nheight = 2.0\nfov = 30.0",
        "type = \"fisheye\"\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]",
    ] {
        let text = format!("[camera]\n{bad}\n");
        let e = formats::toml::load_toml_str(&text, Path::new("bad.toml"), &|p| std::fs::read(p))
            .unwrap_err();
        assert!(format!("{e:#}").contains("camera"), "{e:#}");
    }
}

#[test]
fn a_68300_lux_sun_becomes_100_watts_per_square_metre() {
    let s = load("sun.gltf");
    let Light::Directional { irradiance, .. } = s.lights()[0] else {
        panic!("{:?}", s.lights());
    };
    assert!((irradiance.x - 100.0).abs() < 1e-3, "{irradiance}");
}

#[test]
fn the_default_rig_lights_the_side_a_camera_behind_the_model_sees() {
    let s = load("back_camera.gltf");
    assert!(
        s.camera().forward().z > 0.99,
        "the file camera looks along +Z"
    );
    let film = render_at(s, 32, 32);
    // The centre pixel shows the cube's -Z face (red 0.8 albedo): lit by the key, not only by
    // the 0.05 ambient term.
    let centre = film.pixel(16, 16);
    assert_eq!(film.pixel_aov(16, 16).object_id, 0);
    assert!(centre.x > 0.3, "visible face is dark: {centre}");
}

#[test]
fn up_z_turns_a_gltf_scene_with_its_cameras_and_lights() {
    let options = formats::LoadOptions {
        up: lumis_core::scene::UpAxis::Z,
        ..formats::LoadOptions::default()
    };
    let s = formats::load_with(&asset("lights_camera.gltf"), &options).unwrap();
    // (x, y, z) -> (x, z, -y): the ground quad at y = -0.5 now lies at z = +0.5.
    let b = s.geometry().bounds();
    assert_eq!(b.min.to_array(), [-5.0, -5.0, -0.5]);
    assert_eq!(b.max.to_array(), [5.0, 5.0, 0.5]);
    let p = s.camera().position();
    assert!(
        (p - lumis_core::math::Vec3::new(0.0, 6.0, -1.0)).length() < 1e-5,
        "{p}"
    );
    let Light::Point { position, .. } = s.lights()[0] else {
        panic!("{:?}", s.lights());
    };
    assert!((position - lumis_core::math::Vec3::new(-2.0, 2.0, -4.0)).length() < 1e-5);
}

#[test]
fn an_accessor_without_a_buffer_view_reads_as_zeros() {
    // The same quad with and without its TEXCOORD_0 data: without, every corner is (0, 0).
    let uvs = |name: &str| -> Vec<[f32; 2]> {
        let s = load(name);
        let mesh = &s.geometry().meshes()[0];
        (0..mesh.triangle_count() as u32)
            .flat_map(|t| [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].map(|(u, v)| (t, u, v)))
            .map(|(t, u, v)| mesh.uv(t, u, v).to_array())
            .collect()
    };
    let given = uvs("textured_quad.gltf");
    assert!(given.iter().any(|uv| *uv != [0.0, 0.0]), "{given:?}");
    let zeros = uvs("no_view_uv.gltf");
    assert_eq!(zeros.len(), given.len());
    assert!(zeros.iter().all(|uv| *uv == [0.0, 0.0]), "{zeros:?}");
    // And it renders: the whole quad shows the texel at (0, 0), lit.
    let film = render_at(load("no_view_uv.gltf"), 16, 16);
    assert!(film.pixel(8, 8).x > 0.0);
}

#[test]
fn a_texture_without_a_source_loads_untextured_with_a_warning() {
    // `source` is optional (an extension may name the only image); lumis cannot read that
    // image, so the material keeps its factors and says why.
    let s = load("no_source.gltf");
    assert!(
        warned(
            &s,
            &["baseColorTexture not applied", "textures[0] has no source"]
        ),
        "{:?}",
        s.warnings()
    );
    assert!(warned(&s, &["EXT_texture_webp", "not supported"]));
    let film = render_at(s, 16, 16);
    let p = film.pixel(8, 8);
    assert!(p.x > 0.0 && p.x.is_finite(), "{p}");
}

#[test]
fn a_spot_light_without_its_spot_object_gets_the_default_cone() {
    let s = load("spot_defaults.gltf");
    assert!(
        warned(&s, &["lights[1]", "default cone"]),
        "{:?}",
        s.warnings()
    );
    let cones: Vec<(f32, f32)> = s
        .lights()
        .iter()
        .filter_map(|l| match l {
            Light::Spot {
                cos_inner,
                cos_outer,
                ..
            } => Some((*cos_inner, *cos_outer)),
            _ => None,
        })
        .collect();
    // Inner angle 0, outer pi/4.
    assert_eq!(cones.len(), 1);
    assert_eq!(cones[0].0, 1.0);
    assert!(
        (cones[0].1 - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6,
        "{cones:?}"
    );
}

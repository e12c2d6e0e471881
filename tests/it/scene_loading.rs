//! Scene loading: the shipped default scene, TOML inline meshes and transforms, OBJ files, and
//! every kind of bad input returning an error that names the file and the line or element.

use std::error::Error;
use std::path::{Path, PathBuf};

use glam::Vec3;
use lumis_core::light::Light;
use lumis_core::scene::Scene;
use lumis_io::formats::{self, SceneError};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

/// The whole error chain, as `main` prints it.
fn chain(e: &SceneError) -> String {
    let mut s = e.to_string();
    let mut cur: Option<&dyn Error> = e.source();
    while let Some(c) = cur {
        s += &format!(": {c}");
        cur = c.source();
    }
    s
}

/// Loads `text` as if it were `tests/fixtures/bad.toml`, with files read from disk.
fn load(text: &str) -> Result<Scene, SceneError> {
    formats::toml::load_toml_str(text, &fixture("bad.toml"), &|p| std::fs::read(p))
}

/// Loads `text`, expects an error, and checks it names the file and contains every `needle`.
fn expect_err(text: &str, needles: &[&str]) -> String {
    let msg = match load(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => chain(&e),
    };
    assert!(msg.contains("bad.toml"), "no file name in: {msg}");
    for n in needles {
        assert!(msg.contains(n), "{n:?} missing from: {msg}");
    }
    msg
}

const CAMERA: &str = "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n";

#[test]
fn default_scene_loads_with_every_effect() {
    let s = formats::default_scene().unwrap_or_else(|e| panic!("{}", chain(&e)));
    assert_eq!(s.geometry().spheres().len(), 6);
    assert_eq!(s.geometry().meshes().len(), 1);
    assert_eq!(s.geometry().meshes()[0].triangle_count(), 1920);
    assert!(s.geometry().meshes()[0].normals().is_some());
    assert_eq!(s.objects().len(), 7);
    assert_eq!(s.materials().len(), 7);
    assert_eq!(s.lights().len(), 2);
    assert!(matches!(s.lights()[0], Light::Point { .. }));
    assert!(matches!(s.lights()[1], Light::Directional { .. }));
    let st = s.settings();
    assert_eq!(
        (st.width, st.height, st.spp, st.max_depth),
        (640, 360, 2, 5)
    );
    let fx = lumis_core::effects::Analysis::new(&s, lumis_core::effects::EffectMode::Auto, true);
    assert!(fx.shadows.on && fx.reflection.on && fx.refraction.on && fx.depth_of_field.on);
    assert!(s.materials().iter().any(|m| m.emission != Vec3::ZERO));
}

#[test]
fn default_scene_file_on_disk_matches_the_embedded_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/default.toml");
    let disk = formats::load(&path).unwrap_or_else(|e| panic!("{}", chain(&e)));
    let embedded = formats::default_scene().unwrap_or_else(|e| panic!("{}", chain(&e)));
    assert_eq!(disk.objects(), embedded.objects());
    assert_eq!(disk.geometry().meshes(), embedded.geometry().meshes());
    assert_eq!(disk.camera(), embedded.camera());
}

#[test]
fn inline_mesh_is_scaled_rotated_then_translated() {
    let text = format!(
        "{CAMERA}
[materials.m]
diffuse = [0.5, 0.5, 0.5]

[[mesh]]
name = \"tri\"
material = \"m\"
positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
indices = [[0, 1, 2]]
scale = [2.0, 3.0, 1.0]
rotate = [0.0, 0.0, 90.0]
translate = [10.0, 0.0, 0.0]
"
    );
    let s = load(&text).unwrap_or_else(|e| panic!("{}", chain(&e)));
    let m = &s.geometry().meshes()[0];
    // (1,0,0) -> scaled (2,0,0) -> rotated 90 deg about Z (0,2,0) -> (10,2,0).
    let expect = [
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(10.0, 2.0, 0.0),
        Vec3::new(7.0, 0.0, 0.0),
    ];
    for (p, e) in m.positions().iter().zip(expect) {
        assert!((*p - e).length() < 1e-5, "{p} vs {e}");
    }
    let b = s.geometry().bounds();
    assert!((b.min - Vec3::new(7.0, 0.0, 0.0)).length() < 1e-5);
    assert!((b.max - Vec3::new(10.0, 2.0, 0.0)).length() < 1e-5);
    assert_eq!(s.objects()[0].name, "tri");
    assert!(m.normals().is_none());
}

#[test]
fn obj_fixture_loads_objects_with_quads_triangulated() {
    let path = fixture("cube.obj");
    let bytes = std::fs::read(&path).unwrap();
    let meshes = formats::obj::load_obj_meshes(&mut bytes.as_slice(), &path).unwrap();
    assert_eq!(meshes.len(), 2);
    assert_eq!(meshes[0].0, "bottom_half");
    let tris: usize = meshes.iter().map(|(_, m)| m.triangle_count()).sum();
    assert_eq!(tris, 12);
    let merged = formats::obj::load_obj_merged(&mut bytes.as_slice(), &path).unwrap();
    assert_eq!(merged.triangle_count(), 12);
    assert_eq!(merged.bounds().min, Vec3::new(-1.0, 0.0, -1.0));
    assert_eq!(merged.bounds().max, Vec3::new(1.0, 2.0, 1.0));
    assert!(merged.normals().is_none(), "no vn lines: flat shading");
}

#[test]
fn scene_references_obj_relative_to_its_folder() {
    let s = formats::load(&fixture("with_obj.toml")).unwrap_or_else(|e| panic!("{}", chain(&e)));
    let m = &s.geometry().meshes()[0];
    assert_eq!(m.triangle_count(), 12);
    assert!(
        m.normals().is_some(),
        "smooth = true computes vertex normals"
    );
    let b = m.bounds();
    assert_eq!(b.min, Vec3::new(9.0, 0.0, -2.0));
    assert_eq!(b.max, Vec3::new(11.0, 1.0, 2.0));
}

#[test]
fn bare_obj_gets_a_camera_and_lights() {
    let s = formats::load(&fixture("cube.obj")).unwrap_or_else(|e| panic!("{}", chain(&e)));
    assert_eq!(s.objects().len(), 2);
    assert_eq!(s.lights().len(), 2);
    let to_center = (Vec3::new(0.0, 1.0, 0.0) - s.camera().position()).normalize();
    assert!(to_center.dot(s.camera().forward()) > 0.999);
}

#[test]
fn syntax_error_names_line_and_column() {
    let msg = expect_err("[render]\nwidth = 100\nheight = = 3\n", &["line 3"]);
    assert!(msg.contains("column"), "{msg}");
}

#[test]
fn wrong_type_names_line_and_expectation() {
    let msg = expect_err(
        "[render]\nwidth = 100\n\n[camera]\nposition = \"here\"\nlook_at = [0.0, 0.0, 0.0]\n",
        &["line 5"],
    );
    assert!(msg.contains("expected"), "{msg}");
    expect_err("[render]\nwidth = -3\n", &["line 2"]);
}

#[test]
fn unknown_field_is_an_error() {
    expect_err("[render]\nwidht = 100\n", &["line 2", "widht", "width"]);
    expect_err(&format!("{CAMERA}fvo = 3.0\n"), &["line 4", "fvo"]);
    expect_err(
        "[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\ncolour = 1\n",
        &["colour"],
    );
    expect_err(
        "[[light]]\ntype = \"spot\"\nposition = [0.0, 0.0, 0.0]\n",
        &["spot"],
    );
}

#[test]
fn unknown_material_names_the_sphere() {
    expect_err(
        &format!(
            "{CAMERA}[materials.red]\n\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\
             material = \"red\"\n\n[[sphere]]\nname = \"ball\"\ncenter = [0.0, 0.0, 0.0]\n\
             radius = 1.0\nmaterial = \"blue\"\n"
        ),
        &["sphere[1] \"ball\"", "unknown material \"blue\"", "red"],
    );
}

#[test]
fn missing_obj_file_names_it() {
    let msg = expect_err(
        &format!("{CAMERA}[[mesh]]\nname = \"teapot\"\nfile = \"nowhere/teapot.obj\"\n"),
        &["mesh[0] \"teapot\"", "nowhere/teapot.obj"],
    );
    assert!(
        msg.contains("fixtures"),
        "path resolved against the scene folder: {msg}"
    );
}

#[test]
fn index_out_of_range_names_the_mesh() {
    expect_err(
        &format!(
            "{CAMERA}[[mesh]]\nname = \"tri\"\npositions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], \
             [0.0, 1.0, 0.0]]\nindices = [[0, 1, 3]]\n"
        ),
        &["mesh[0] \"tri\"", "vertex 3"],
    );
    expect_err(
        &format!("{CAMERA}[[mesh]]\npositions = [[0.0, 0.0, 0.0]]\n"),
        &["mesh[0]", "indices"],
    );
}

#[test]
fn nan_and_inf_are_rejected() {
    expect_err(
        "[[sphere]]\ncenter = [nan, 0.0, 0.0]\nradius = 1.0\n",
        &["sphere[0]", "center"],
    );
    expect_err(
        "[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = inf\n",
        &["sphere[0]", "radius"],
    );
    expect_err(
        "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, -inf, 0.0]\n",
        &["camera", "look_at"],
    );
    expect_err(
        "[[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity = nan\n",
        &["light[0]", "intensity"],
    );
    expect_err(
        &format!(
            "{CAMERA}[[mesh]]\npositions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, nan, 0.0]]\nindices = [[0, 1, 2]]\n"
        ),
        &["mesh[0]"],
    );
    expect_err("[materials.x]\nior = nan\n", &["materials.x", "ior"]);
}

#[test]
fn bad_values_name_their_element() {
    expect_err(
        "[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 0.0\n",
        &["sphere[0]", "radius"],
    );
    expect_err(
        "[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = -2.0\n",
        &["sphere[0]", "radius"],
    );
    expect_err("[render]\nwidth = 0\n", &["render", "width 0"]);
    expect_err("[render]\nspp = 0\n", &["render", "spp"]);
    expect_err(
        "[camera]\nposition = [1.0, 1.0, 1.0]\nlook_at = [1.0, 1.0, 1.0]\n",
        &["camera", "coincide"],
    );
    expect_err(&format!("{CAMERA}fov = 200.0\n"), &["camera", "200"]);
    expect_err(
        "[materials.m]\ntransmission = 1.5\n",
        &["materials.m", "transmission"],
    );
    expect_err(
        "[[light]]\ntype = \"directional\"\ndirection = [0.0, 0.0, 0.0]\nintensity = 1.0\n",
        &["light[0]", "direction"],
    );
    expect_err(
        "[[light]]\ntype = \"point\"\nintensity = 1.0\n",
        &["light[0]", "position"],
    );
    expect_err(
        "[[light]]\ntype = \"point\"\nposition = [0.0, 0.0, 0.0]\n",
        &["line 1", "intensity"],
    );
    expect_err(
        &format!("{CAMERA}[[mesh]]\nfile = \"x.obj\"\npositions = [[0.0, 0.0, 0.0]]\n"),
        &["mesh[0]"],
    );
    expect_err(
        &format!(
            "{CAMERA}[[mesh]]\npositions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]\n\
             indices = [[0, 1, 2]]\nscale = 0.0\n"
        ),
        &["mesh[0]", "scale"],
    );
}

#[test]
fn malformed_obj_returns_errors_not_panics() {
    let path = Path::new("broken.obj");
    for text in [
        "",
        "v 1 2\nf 1 2 3\n",
        "v 0 0 0\nv 1 0 0\nf 1 2 9\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -7 2 3\n",
        "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "f 1//1 2//2 3//3\n",
        "\u{0}\u{ff}garbage\n",
    ] {
        if let Err(e) = formats::obj::load_obj_meshes(&mut text.as_bytes(), path) {
            assert!(chain(&e).contains("broken.obj"), "{}", chain(&e));
        }
    }
}

#[test]
fn arbitrary_text_never_panics() {
    for text in [
        "",
        "[",
        "]]",
        "[[mesh]]",
        "[[light]]",
        "light = 3",
        "[materials]\nx = 1\n",
    ] {
        let _ = load(text);
    }
    // No camera and no geometry: an automatic camera, not a failure.
    assert!(load("").is_ok());
}

#[test]
fn unknown_extension_is_an_error() {
    let e = formats::load(Path::new("scene.blend"))
        .err()
        .map(|e| chain(&e));
    assert!(e.is_some_and(|m| m.contains("scene.blend")));
}

#[test]
fn render_display_key_picks_the_png_encoding() {
    use lumis_core::film::DisplayTransform;
    let display = |text: &str| load(&format!("{text}{CAMERA}")).unwrap().settings().display;
    assert_eq!(display(""), DisplayTransform::Srgb);
    assert_eq!(
        display("[render]\ndisplay = \"srgb\"\n"),
        DisplayTransform::Srgb
    );
    assert_eq!(
        display("[render]\ndisplay = \"clamp\"\n"),
        DisplayTransform::Clamp
    );
    expect_err(
        "[render]\ndisplay = \"linear\"\n",
        &["render", "display", "srgb or clamp"],
    );
}

#[test]
fn documented_example_loads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/scene-format.md")).unwrap();
    let example = doc
        .split("## A complete example")
        .nth(1)
        .and_then(|s| s.split("```toml\n").nth(1))
        .and_then(|s| s.split("```").next())
        .expect("docs/scene-format.md has a complete example");
    // As if it lived in scenes/, so its `../assets/knot.obj` resolves.
    let s = formats::toml::load_toml_str(example, &root.join("scenes/example.toml"), &|p| {
        std::fs::read(p)
    })
    .unwrap_or_else(|e| panic!("{}", chain(&e)));
    assert_eq!(s.geometry().meshes().len(), 2);
    assert_eq!(s.lights().len(), 2);
}

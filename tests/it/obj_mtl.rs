//! OBJ + MTL loading against the assets made by `tools/gen_assets.py` (triangle counts, bounds,
//! material values), bad input through the CLI binary, and a textured quad rendered with
//! `ambient = 1` and no lights, so every pixel's radiance is the texture's colour.

use std::path::{Path, PathBuf};
use std::process::Command;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::material::{Material, Texture};
use lumis_core::math::{Vec2, Vec3};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, World};
use lumis_core::texture::srgb_to_linear;
use lumis_io::formats;

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

fn load(path: &Path) -> Scene {
    formats::load(path).unwrap_or_else(|e| panic!("{e:#?}"))
}

fn triangles(s: &Scene) -> usize {
    s.geometry()
        .meshes()
        .iter()
        .map(|m| m.triangle_count())
        .sum()
}

fn material_named<'a>(s: &'a Scene, object: &str) -> &'a Material {
    let id = s.objects().iter().position(|o| o.name == object);
    s.material_of(id.unwrap_or_else(|| panic!("no object {object}")) as u32)
}

/// Texel (x, y) of assets/quad_texture.png, linear.
fn texel(x: u32, y: u32) -> Vec3 {
    let b = [40 + 25 * x, 40 + 25 * y, 90 + 60 * ((x + y) % 2)];
    Vec3::from(b.map(|c| srgb_to_linear(c as f32 / 255.0)))
}

#[test]
fn textured_quad_has_flipped_uvs_and_an_image_material() {
    let s = load(&asset("textured_quad.obj"));
    assert_eq!((s.objects().len(), triangles(&s)), (1, 2));
    let b = s.geometry().bounds();
    assert_eq!(
        (b.min, b.max),
        (Vec3::new(-1., -1., 0.), Vec3::new(1., 1., 0.))
    );
    let m = &s.geometry().meshes()[0];
    // OBJ's v = 0 is the bottom; lumis's uv (0, 0) is the image's top-left.
    for (p, uv) in m.positions().iter().zip(m.uvs().unwrap()) {
        let expect = Vec2::new((p.x + 1.0) / 2.0, (1.0 - p.y) / 2.0);
        assert!((*uv - expect).length() < 1e-6, "{p} -> {uv}");
    }
    let Texture::Image { image, tint } = &material_named(&s, "quad").diffuse else {
        panic!("map_Kd should give an image texture");
    };
    assert_eq!((image.width(), image.height(), *tint), (8, 8, Vec3::ONE));
    for (x, y) in [(0, 0), (7, 0), (3, 5), (7, 7)] {
        assert!((image.texel(x, y) - texel(x as u32, y as u32)).length() < 1e-6);
    }
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
}

#[test]
fn concave_l_face_is_four_triangles_inside_the_l() {
    let s = load(&asset("l_polygon.obj"));
    assert_eq!(triangles(&s), 4);
    let m = &s.geometry().meshes()[0];
    let b = m.bounds();
    assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::new(2., 2., 0.)));
    let area: f32 = (0..4)
        .map(|t| {
            let [a, b, c] = m.corners(t);
            0.5 * (b - a).cross(c - a).z
        })
        .sum();
    assert!((area - 3.0).abs() < 1e-6, "area {area}");
    // No triangle reaches into the notch [1, 2]^2.
    for t in 0..4 {
        let [a, b, c] = m.corners(t);
        let centroid = (a + b + c) / 3.0;
        assert!(
            !(centroid.x > 1.0 && centroid.y > 1.0),
            "triangle {t} in the notch"
        );
    }
}

#[test]
fn every_illum_mode_maps_to_the_documented_material() {
    let s = load(&asset("illum_modes.obj"));
    assert_eq!((s.objects().len(), triangles(&s)), (10, 20));
    let b = s.geometry().bounds();
    assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::new(14.5, 1., 0.)));
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    // (illum, kd, specular, reflectivity, transmission, ior)
    let table: [(u32, f32, f32, f32, f32, f32); 10] = [
        (0, 0.8, 0.0, 0.0, 0.0, 1.5),
        (1, 0.2, 0.0, 0.0, 0.0, 1.5),
        (2, 0.2, 0.5, 0.0, 0.0, 1.5),
        (3, 0.1, 0.9, 0.9, 0.0, 1.5),
        (4, 0.0, 1.0, 0.0, 0.9, 1.5),
        (5, 0.05, 0.6, 0.7, 0.0, 1.5),
        (6, 0.0, 0.0, 0.0, 1.0, 1.33),
        (7, 0.0, 0.0, 0.0, 0.25, 1.7),
        (8, 0.0, 0.5, 0.5, 0.0, 1.5),
        (9, 0.0, 0.0, 0.0, 1.0, 2.4),
    ];
    for (illum, kd, ks, refl, trans, ior) in table {
        let m = material_named(&s, &format!("illum{illum}"));
        let Texture::Solid(d) = m.diffuse else {
            panic!("illum{illum}: solid diffuse expected")
        };
        let ok = close(d.x, kd)
            && close(m.specular.x, ks)
            && close(m.reflectivity, refl)
            && close(m.transmission, trans)
            && close(m.ior, ior);
        assert!(ok, "illum{illum}: {m:?}");
    }
    let emitter = material_named(&s, "illum1");
    assert_eq!(emitter.emission, Vec3::new(2.0, 1.0, 0.5));
    assert_eq!(material_named(&s, "illum2").shininess, 64.0);
    // Materials keep their `newmtl` names (Cryptomatte's material mattes are called by them).
    for o in s.objects() {
        let name = &s.material_names()[o.material as usize];
        assert_eq!(name, &o.name.replace("illum", "mode"), "object {}", o.name);
    }
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
}

#[test]
fn mixed_faces_negative_indices_and_ignored_points_and_lines() {
    let s = load(&asset("mixed_faces.obj"));
    let names: Vec<&str> = s.objects().iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["mixed", "quad"]);
    let meshes = s.geometry().meshes();
    assert_eq!(
        (meshes[0].triangle_count(), meshes[1].triangle_count()),
        (4, 2)
    );
    let b = s.geometry().bounds();
    assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::new(2., 3., 0.)));
    // Some corners of "mixed" lack normals and UVs: the whole object is flat and UV-less.
    assert!(meshes[0].normals().is_none() && meshes[0].uvs().is_none());
    assert!(meshes[1].normals().is_some() && meshes[1].uvs().is_some());
    // Every triangle faces +z and together they tile [0, 2] x [0, 1] and [0, 1] x [2, 3].
    let area: f32 = meshes
        .iter()
        .flat_map(|m| (0..m.triangle_count() as u32).map(move |t| m.corners(t)))
        .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).z)
        .sum();
    assert!((area - 3.0).abs() < 1e-6);
    let w = s.warnings().join("\n");
    assert!(
        w.contains("mixed_faces.obj") && w.contains("1 point (p) and 2 line (l)"),
        "{w}"
    );
}

#[test]
fn obj_without_normals_is_flat_shaded() {
    let s = load(&asset("no_normals.obj"));
    assert_eq!(triangles(&s), 6);
    let m = &s.geometry().meshes()[0];
    assert!(m.normals().is_none());
    let b = m.bounds();
    assert_eq!(
        (b.min, b.max),
        (Vec3::new(-1., 0., -1.), Vec3::new(1., 1., 1.))
    );
}

/// A TOML scene in `dir` showing `obj` head-on from far away with `ambient = 1`, no lights.
fn flat_view_scene(dir: &Path, obj: &Path, size: u32, material: Option<&str>) -> PathBuf {
    let extra = material.map_or(String::new(), |m| {
        format!("material = \"{m}\"\n[materials.{m}]\ndiffuse = [0.5, 0.5, 0.5]\n")
    });
    let text = format!(
        "[render]\nwidth = {size}\nheight = {size}\nspp = 1\nambient = [1.0, 1.0, 1.0]\n\
         [camera]\nposition = [0.0, 0.0, 100.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 1.4323\n\
         [[mesh]]\nname = \"quad\"\nfile = {:?}\n{extra}",
        obj.display().to_string()
    );
    let path = dir.join("view.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn textured_quad_renders_its_texels() {
    let dir = tempfile::tempdir().unwrap();
    // fov 1.4323 degrees at distance 100: the view is 2.5 units high, the quad 2 of them, so
    // 120 of the 150 pixels: texels are 15 pixels wide and their centres fall on pixel centres.
    let s = load(&flat_view_scene(
        dir.path(),
        &asset("textured_quad.obj"),
        150,
        None,
    ));
    let world = World::build(s.clone(), AccelKind::Sah, &BuildOptions::default());
    let opts = RenderOptions {
        seed: 3,
        threads: Some(2),
        ..RenderOptions::default()
    };
    let film = render(&world, &opts).unwrap().film;
    let (w, h) = (s.settings().width, s.settings().height);
    let to_ndc = s.camera().world_to_ndc(w, h);
    // A pixel's sample lies within half a pixel (1/30 texel) of the texel centre, where
    // bilinear filtering moves the colour by at most 1/30 of the largest neighbour difference
    // (0.66 linear, where the texture wraps from texel 7 to texel 0): 0.022, so 0.025 holds.
    for y in 0..8 {
        for x in 0..8 {
            let uv = Vec2::new((x as f32 + 0.5) / 8.0, (y as f32 + 0.5) / 8.0);
            let p = Vec3::new(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, 0.0);
            let q = to_ndc * p.extend(1.0);
            let (px, py) = ((q.x / q.w * w as f32) as u32, (q.y / q.w * h as f32) as u32);
            let got = film.pixel(px, py).truncate();
            let want = texel(x, y);
            assert!(
                (got - want).abs().max_element() < 0.025,
                "texel ({x}, {y}) at pixel ({px}, {py}): {got} vs {want}"
            );
        }
    }
}

#[test]
fn toml_mesh_uses_mtl_materials_unless_a_material_is_given() {
    let dir = tempfile::tempdir().unwrap();
    let obj = asset("illum_modes.obj");
    let s = load(&flat_view_scene(dir.path(), &obj, 8, None));
    assert_eq!(s.objects().len(), 10);
    assert_eq!(s.objects()[3].name, "quad/illum3");
    assert!((s.material_of(3).reflectivity - 0.9).abs() < 1e-6);
    let s = load(&flat_view_scene(dir.path(), &obj, 8, Some("grey")));
    assert_eq!((s.objects().len(), triangles(&s)), (1, 20));
    assert_eq!(s.material_of(0).diffuse, Texture::Solid(Vec3::splat(0.5)));
}

/// Runs `lumis render OBJ -o out.png` at a small size in `dir`.
fn render_cli(dir: &Path, obj_text: &str) -> std::process::Output {
    let obj = dir.join("model.obj");
    std::fs::write(&obj, obj_text).unwrap();
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .args([
            "render",
            "model.obj",
            "-o",
            "out.png",
            "--width",
            "16",
            "--height",
            "16",
        ])
        .output()
        .unwrap()
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn bad_face_indices_fail_with_file_and_line_and_write_nothing() {
    for (face, what) in [
        ("f 0 1 2", "vertex 0"),
        ("f 1 2 4", "vertex 4"),
        ("f 1 2 -4", "vertex -4"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = render_cli(dir.path(), &format!("{TRI}# a comment\n{face}\n"));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{face}: {stderr}");
        assert!(
            stderr.contains("model.obj") && stderr.contains("line 5"),
            "{stderr}"
        );
        assert!(
            stderr.contains(what) && !stderr.contains("panicked"),
            "{stderr}"
        );
        assert!(!dir.path().join("out.png").exists());
    }
}

#[test]
fn nan_vertex_is_an_error_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = render_cli(dir.path(), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("model.obj") && stderr.contains("line 2"),
        "{stderr}"
    );
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn missing_mtl_warns_and_renders_with_the_default_material() {
    let dir = tempfile::tempdir().unwrap();
    let out = render_cli(
        dir.path(),
        &format!("mtllib gone.mtl\n{TRI}usemtl red\nf 1 2 3\n"),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("gone.mtl"),
        "{stderr}"
    );
    assert!(dir.path().join("out.png").exists());
}

#[test]
fn missing_texture_warns_and_renders_with_the_plain_colour() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl tex\nKd 0.5 0.25 1\nmap_Kd gone.png\n";
    std::fs::write(dir.path().join("m.mtl"), mtl).unwrap();
    let out = render_cli(
        dir.path(),
        &format!("mtllib m.mtl\n{TRI}usemtl tex\nf 1 2 3\n"),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("gone.png"),
        "{stderr}"
    );
    assert!(dir.path().join("out.png").exists());
    let s = load(&dir.path().join("model.obj"));
    assert_eq!(
        s.materials()[0].diffuse,
        Texture::Solid(Vec3::new(0.5, 0.25, 1.0))
    );
}

//! The reported huge-value inputs, one by one: each is refused naming the element and
//! the limit, or (MTL, whose bad values are warnings) clamped and rendered with finite pixels.

use std::path::Path;
use std::process::Command;

use super::seeds;

/// Runs `lumis render scene` in `dir`; exit code and stderr.
fn render(dir: &Path, scene: &str) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args([
            "render", scene, "--width", "16", "--height", "12", "--spp", "1", "-o", "out.exr",
        ])
        .current_dir(dir)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A directory holding every seed, with `name` replaced by `edit` applied to its text.
fn seeded(name: &str, edit: impl Fn(&str) -> String) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for s in seeds::seeds(Path::new(env!("CARGO_MANIFEST_DIR"))) {
        let bytes = if s.name == name {
            edit(&String::from_utf8(s.bytes).unwrap()).into_bytes()
        } else {
            s.bytes
        };
        std::fs::write(dir.path().join(s.name), bytes).unwrap();
    }
    dir
}

/// How a case changes its seed's text.
type Edit<'a> = &'a dyn Fn(&str) -> String;

#[test]
fn huge_finite_geometry_and_light_values_are_refused_naming_the_element() {
    let cases: [(&str, Edit, &str); 7] = [
        (
            "scene.toml",
            &|t| t.replace("scale = 3.0", "scale = 1e38"),
            "mesh[0] \"quad\": model.obj: world-space bounds",
        ),
        (
            "scene.toml",
            &|t| t.replace("radius = 0.8", "radius = 1e38"),
            "sphere \"ball\": world-space bounds",
        ),
        (
            "scene.toml",
            &|t| t.replace("intensity = 120.0", "intensity = 1e38"),
            "light[0]: colour x intensity",
        ),
        (
            "cube.gltf",
            &|t| {
                t.replace(
                    "\"name\": \"cube\"",
                    "\"name\": \"cube\", \"scale\": [1e30, 1e30, 1e30]",
                )
            },
            "mesh \"cube\": world-space bounds",
        ),
        (
            "scene.scn",
            &|t| t.replace("triangle -80", "triangle 3e38"),
            "triangle",
        ),
        (
            "scene.scn",
            &|t| t.replace("80 0.9 null", "80 5 null"),
            "scene.scn:7: reflectivity 5 must be in [0, 1]",
        ),
        (
            "scene.scn",
            &|t| t.replace("FlatColor 0.9 0.5 0.1", "FlatColor -0.9 0.5 0.1"),
            "must have components in [0, 1]",
        ),
    ];
    let mut failures = Vec::new();
    for (file, edit, expected) in cases {
        let dir = seeded(file, edit);
        let (code, stderr) = render(dir.path(), file);
        let exr = dir.path().join("out.exr");
        if code != Some(1) || !stderr.contains(expected) || !stderr.contains(file) || exr.exists() {
            failures.push(format!("{file} ({expected}): exit {code:?}, {stderr}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn huge_mtl_colours_are_clamped_with_a_warning_and_render_finite() {
    let dir = seeded("model.mtl", |t| {
        t.replace("Ks 0.5 0.5 0.5", "Ks 1e38 1e38 1e38")
    });
    let (code, stderr) = render(dir.path(), "model.obj");
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains("model.mtl") && stderr.contains("Ks") && stderr.contains("clamped"),
        "{stderr}"
    );
    super::run::finite_exr(&dir.path().join("out.exr")).unwrap();
}

#[test]
fn gltf_only_flags_are_refused_on_other_formats() {
    let dir = seeded("", |t| t.to_string());
    for (scene, flag) in [
        ("scene.toml", "--camera"),
        ("scene.scn", "--gltf-scene"),
        ("model.obj", "--camera"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
            .args(["render", scene, flag, "0", "-o", "out.exr"])
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{scene} {flag}: {stderr}");
        assert!(
            stderr.contains(scene) && stderr.contains("applies to glTF files only"),
            "{stderr}"
        );
    }
}

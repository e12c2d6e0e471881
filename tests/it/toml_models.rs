//! TOML scenes place model files (glTF/GLB, `.m`, OBJ) with transforms and material overrides
//! beside spheres.

use lumis_core::math::Vec3;
use lumis_io::formats::load;
use std::path::Path;

fn root(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .to_string_lossy()
        .replace('\\', "/")
}

#[test]
fn gltf_and_m_models_are_placed_with_transforms_and_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let cube = lumis_io::formats::load(Path::new(&root("assets/gltf/cube.glb"))).unwrap();
    let cube_bounds = cube.geometry().bounds();
    let scene = dir.path().join("models.toml");
    let text = format!(
        r#"
[camera]
position = [0.0, 2.0, 12.0]
look_at = [0.0, 0.0, 0.0]

[materials.red]
diffuse = [0.8, 0.1, 0.1]

[[sphere]]
center = [0.0, -101.0, 0.0]
radius = 100.0

[[mesh]]
name = "cube_as_is"
file = "{cube}"
translate = [10.0, 0.0, 0.0]

[[mesh]]
name = "cube_red"
file = "{cube}"
material = "red"
scale = 2.0

[[mesh]]
name = "tetra"
file = "{tetra}"
material = "red"
translate = [0.0, 5.0, 0.0]
"#,
        cube = root("assets/gltf/cube.glb"),
        tetra = root("tests/fixtures/scn/tetra.m"),
    );
    std::fs::write(&scene, text).unwrap();
    let s = load(&scene).unwrap();
    assert_eq!(s.objects().len(), 4, "{:?}", s.objects());
    assert_eq!(s.geometry().meshes().len(), 3);
    let bounds = |i: usize| s.geometry().meshes()[i].bounds();
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-5;
    assert!(
        close(bounds(0).min, cube_bounds.min + Vec3::X * 10.0),
        "{:?}",
        bounds(0)
    );
    assert!(
        close(bounds(1).max, cube_bounds.max * 2.0),
        "{:?}",
        bounds(1)
    );
    // The .m tetrahedron spans [-1, 1] on every axis, moved up by 5.
    assert!(
        close(bounds(2).min, Vec3::new(-1.0, 4.0, -1.0))
            && close(bounds(2).max, Vec3::new(1.0, 6.0, 1.0))
    );
    // The first cube keeps its glTF material; the override replaces it on the second.
    let red = s.material_of(2).clone();
    assert_eq!(s.material_of(3), &red);
    assert_ne!(s.material_of(1), &red);
    assert_eq!(s.material_of(1), cube.material_of(0));
}

#[test]
fn unknown_model_extension_and_broken_m_name_the_element() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.m"), "Vertex 1 0 0 0\nFace 1 1 1 5\n").unwrap();
    for (file, needle) in [
        ("model.fbx", "expected a .obj, .gltf, .glb or .m"),
        ("bad.m", "bad.m:2"),
    ] {
        let scene = dir.path().join("s.toml");
        std::fs::write(
            &scene,
            format!("[[mesh]]\nname = \"x\"\nfile = \"{file}\"\n"),
        )
        .unwrap();
        let err = match load(&scene) {
            Ok(_) => panic!("{file} accepted"),
            Err(e) => format!("{:#}", anyhow::Error::new(e)),
        };
        assert!(
            err.contains("mesh[0]") && err.contains(needle),
            "{file}: {err}"
        );
    }
}

//! Input that used to panic inside a dependency (issue 14, item 1): a short MTL colour inside
//! tobj, glTF images without a source or a MIME type inside the gltf crate. lumis now checks
//! these before calling the crates: an MTL problem is a warning naming the MTL file and line
//! (docs/obj-mtl.md), a glTF problem an error naming the element; no panic text either way.

use crate::common;

use common::hostile::{assert_clean, gltf_with, lumis};
use serde_json::json;

/// Writes an OBJ whose triangle uses material `m` of `lib.mtl` = `mtl`, runs `lumis info`.
fn info_with_mtl(mtl: &str) -> common::hostile::Run {
    let dir = tempfile::tempdir().unwrap();
    let obj = "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
    std::fs::write(dir.path().join("model.obj"), obj).unwrap();
    std::fs::write(dir.path().join("lib.mtl"), mtl).unwrap();
    lumis(dir.path(), &["info", "model.obj"], None)
}

#[test]
fn malformed_mtl_statements_are_warnings_naming_the_mtl_file_and_line() {
    let cases = [
        ("Kd 1 0.5", "a colour is 1 or 3 numbers"),
        ("Ks 0.5 x 1", "a colour is 1 or 3 numbers"),
        ("Ka", "a colour is 1 or 3 numbers"),
        ("Ke spectral e.rfl", "spectral colours are not supported"),
        ("Ns", "expected one number"),
        ("Ni 1.5 2", "expected one number"),
        ("d half", "is not a number"),
        ("illum 999", "illum needs an integer"),
        ("map_Kd", "map_Kd needs a file name"),
    ];
    for (statement, why) in cases {
        let run = info_with_mtl(&format!("newmtl m\n{statement}\nKd 0.2 0.3 0.4\n"));
        let text = run.text();
        assert!(run.output.status.success(), "{statement}: {text}");
        assert_clean(&text);
        assert!(
            text.contains("lib.mtl: line 2:") && text.contains(why),
            "{statement}: expected a warning for line 2 with {why:?}: {text}"
        );
    }
    // A nameless newmtl is a warning too, and the statements after it are not applied.
    let run = info_with_mtl("newmtl\nKd 1 1 1\nnewmtl m\n");
    assert!(run.output.status.success());
    assert!(
        run.text()
            .contains("lib.mtl: line 1: newmtl without a name")
    );
}

#[test]
fn a_one_number_mtl_colour_is_a_grey_as_the_specification_allows() {
    let run = info_with_mtl("newmtl m\nKd 1\n");
    let text = run.text();
    assert!(run.output.status.success(), "{text}");
    assert_clean(&text);
    assert!(
        !text.contains("lib.mtl: line"),
        "no warning expected: {text}"
    );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lib.mtl"), "newmtl m\nKd 0.25\n").unwrap();
    let obj = "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
    let path = dir.path().join("model.obj");
    std::fs::write(&path, obj).unwrap();
    let scene = lumis_io::formats::load(&path).unwrap();
    let material = &scene.materials()[0];
    assert_eq!(
        material.diffuse,
        lumis_core::material::Texture::Solid(lumis_core::math::Vec3::splat(0.25))
    );
}

/// Writes `gltf` as `scene.gltf` and runs `lumis info` on it.
fn info_gltf(gltf: &str) -> common::hostile::Run {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.gltf"), gltf).unwrap();
    lumis(dir.path(), &["info", "scene.gltf"], None)
}

#[test]
fn gltf_images_without_a_usable_source_are_errors_naming_the_image() {
    let view = json!([{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteLength": 4}]);
    let cases = [
        (
            json!({"images": [{}]}),
            "has neither `uri` nor `bufferView`",
        ),
        (
            json!({"images": [{"uri": "a.png"}, {"bufferView": 1}], "bufferViews": view}),
            "has a `bufferView` but no `mimeType`",
        ),
        (
            json!({"images": [{"uri": "a.png", "bufferView": 1, "mimeType": "image/png"}],
                   "bufferViews": view}),
            "has both `uri` and `bufferView`",
        ),
    ];
    for (k, (extra, why)) in cases.into_iter().enumerate() {
        let element = if k == 1 { "images[1]" } else { "images[0]" };
        info_gltf(&gltf_with(extra)).assert_refused(&["scene.gltf", element, why]);
    }
}

#[test]
fn a_gltf_buffer_of_zero_bytes_is_an_error_naming_the_buffer() {
    let extra = json!({"buffers": [{"byteLength": 0, "uri": "data:application/octet-stream;base64,"}],
                       "bufferViews": [], "accessors": [], "meshes": [], "nodes": []});
    info_gltf(&gltf_with(extra)).assert_refused(&["scene.gltf", "buffers[0]", "byteLength is 0"]);
}

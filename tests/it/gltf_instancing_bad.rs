//! Broken `EXT_mesh_gpu_instancing` data: `assets/gltf/gpu_instancing.gltf` edited one way at
//! a time (extra accessors in a second, data-URI buffer). `lumis render` exits 1 naming the
//! file, the node's attribute and what was expected, without a panic or an image.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

use crate::common;
use common::files::gltf_asset as asset;
use common::hostile::{assert_clean, data_uri};

/// The `swarm` node (50 instances) and its attributes' element.
const SWARM: &str = "nodes[2].extensions.EXT_mesh_gpu_instancing.attributes";

pub(crate) fn original() -> Value {
    let text = std::fs::read_to_string(asset("gpu_instancing.gltf")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Adds an accessor of `kind` over `floats` (as f32, or as i16 when `shorts`) in a new
/// buffer; returns its index.
pub(crate) fn add_accessor(doc: &mut Value, kind: &str, values: &[f32], shorts: bool) -> usize {
    let mut bytes = Vec::new();
    for v in values {
        if shorts {
            bytes.extend((*v as i16).to_le_bytes());
        } else {
            bytes.extend(v.to_le_bytes());
        }
    }
    let width = match kind {
        "VEC3" => 3,
        _ => 4,
    };
    let buffers = doc["buffers"].as_array_mut().unwrap();
    buffers.push(json!({"byteLength": bytes.len(), "uri": data_uri(&bytes)}));
    let buffer = buffers.len() - 1;
    let views = doc["bufferViews"].as_array_mut().unwrap();
    views.push(json!({"buffer": buffer, "byteLength": bytes.len()}));
    let view = views.len() - 1;
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(json!({
        "bufferView": view,
        "componentType": if shorts { 5122 } else { 5126 },
        "normalized": shorts,
        "type": kind,
        "count": values.len() / width,
    }));
    accessors.len() - 1
}

pub(crate) fn swarm_attributes(doc: &mut Value) -> &mut Value {
    &mut doc["nodes"][2]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]
}

/// Writes `doc` as `dir/name` beside a copy of the original's buffer; returns its path.
pub(crate) fn write_beside_buffer(doc: &Value, dir: &Path, name: &str) -> PathBuf {
    std::fs::copy(asset("gpu_instancing.bin"), dir.join("gpu_instancing.bin")).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, doc.to_string()).unwrap();
    file
}

/// Renders `doc` (beside a copy of the original's buffer) and asserts the refusal.
fn assert_refused(doc: &Value, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let file = write_beside_buffer(doc, dir.path(), "broken.gltf");
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(&out_dir)
        .arg("render")
        .arg(&file)
        .args(["--width", "16", "--height", "8", "--spp", "1", "--quiet"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_clean(&stderr);
    for piece in std::iter::once("broken.gltf").chain(expected.iter().copied()) {
        assert!(stderr.contains(piece), "expected {piece:?} in: {stderr}");
    }
    assert_eq!(std::fs::read_dir(&out_dir).unwrap().count(), 0, "{stderr}");
}

#[test]
fn the_unedited_asset_renders() {
    // The harness itself: the copy beside its buffer loads (so the refusals below are the
    // edits').
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        asset("gpu_instancing.bin"),
        dir.path().join("gpu_instancing.bin"),
    )
    .unwrap();
    let file = dir.path().join("copy.gltf");
    std::fs::write(&file, original().to_string()).unwrap();
    let s = lumis_io::formats::load(&file).unwrap();
    assert_eq!(s.geometry().instances().len(), 58);
}

#[test]
fn attribute_counts_must_agree() {
    let mut doc = original();
    // The flock's SCALE: 8 elements against the swarm's 50.
    let flock_scale =
        doc["nodes"][3]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"].clone();
    swarm_attributes(&mut doc)["SCALE"] = flock_scale;
    assert_refused(&doc, &[&format!("{SWARM}.SCALE"), "8 elements", "50"]);
}

#[test]
fn component_types_and_dimensions_are_checked() {
    let mut doc = original();
    // The swarm's rotation as UNSIGNED_SHORT: not among the rotation's types.
    let r = swarm_attributes(&mut doc)["ROTATION"].as_u64().unwrap() as usize;
    doc["accessors"][r]["componentType"] = json!(5123);
    assert_refused(
        &doc,
        &[
            &format!("{SWARM}.ROTATION"),
            "U16",
            "normalized BYTE or SHORT",
        ],
    );
    // SHORT without `normalized`: the integers would be read as they are.
    let mut doc = original();
    doc["accessors"][r]["normalized"] = json!(false);
    assert_refused(
        &doc,
        &[&format!("{SWARM}.ROTATION"), "I16", "expected FLOAT"],
    );
    // A VEC4 as TRANSLATION.
    let mut doc = original();
    swarm_attributes(&mut doc)["TRANSLATION"] = json!(r);
    assert_refused(&doc, &[&format!("{SWARM}.TRANSLATION"), "Vec4", "VEC3"]);
    // SHORT scales: float only.
    let mut doc = original();
    let a = add_accessor(&mut doc, "VEC3", &[1.0; 150], true);
    swarm_attributes(&mut doc)["SCALE"] = json!(a);
    assert_refused(&doc, &[&format!("{SWARM}.SCALE"), "expected FLOAT"]);
}

#[test]
fn non_finite_translations_and_scales_and_non_unit_rotations_name_the_instance() {
    let mut doc = original();
    let mut t = vec![0.0f32; 150];
    t[7 * 3 + 1] = f32::INFINITY;
    let a = add_accessor(&mut doc, "VEC3", &t, false);
    swarm_attributes(&mut doc)["TRANSLATION"] = json!(a);
    assert_refused(
        &doc,
        &[&format!("{SWARM}.TRANSLATION"), "instance 7", "not finite"],
    );

    // A zero scale is allowed (it hides the entry: `gltf_instancing_hidden`); NaN is not.
    let mut doc = original();
    let mut s = vec![1.0f32; 150];
    s[3 * 3 + 1] = f32::NAN;
    let a = add_accessor(&mut doc, "VEC3", &s, false);
    swarm_attributes(&mut doc)["SCALE"] = json!(a);
    assert_refused(
        &doc,
        &[&format!("{SWARM}.SCALE"), "instance 3", "not finite"],
    );

    let mut doc = original();
    let mut q: Vec<f32> = [0.0, 0.0, 0.0, 1.0].repeat(50);
    q[9 * 4 + 3] = 2.0;
    let a = add_accessor(&mut doc, "VEC4", &q, false);
    swarm_attributes(&mut doc)["ROTATION"] = json!(a);
    assert_refused(
        &doc,
        &[&format!("{SWARM}.ROTATION"), "instance 9", "length 2"],
    );
}

#[test]
fn missing_and_out_of_range_accessors_are_named() {
    let mut doc = original();
    swarm_attributes(&mut doc)["ROTATION"] = json!(999);
    assert_refused(
        &doc,
        &[&format!("{SWARM}.ROTATION"), "accessor 999 does not exist"],
    );
    // An accessor whose count runs past its buffer view: refused before it is read.
    let mut doc = original();
    let r = swarm_attributes(&mut doc)["ROTATION"].as_u64().unwrap() as usize;
    doc["accessors"][r]["count"] = json!(5000);
    assert_refused(&doc, &[&format!("accessors[{r}]")]);
    let mut doc = original();
    doc["nodes"][2]["extensions"]["EXT_mesh_gpu_instancing"] = json!({"attributes": {}});
    assert_refused(
        &doc,
        &[
            "nodes[2].extensions.EXT_mesh_gpu_instancing.attributes",
            "none of TRANSLATION",
        ],
    );
}

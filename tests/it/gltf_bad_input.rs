//! Broken glTF files (written by `tools/gen_gltf_assets.py` to `assets/gltf/bad/`): each fails
//! to load with a message naming the file and the element, without a panic, and the CLI exits
//! non-zero without writing any image.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bad(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/gltf/bad")
        .join(name)
}

/// The whole error chain of loading `name`, which must fail.
fn error_of(name: &str) -> String {
    match lumis_io::formats::load(&bad(name)) {
        Ok(_) => panic!("{name} loaded"),
        Err(e) => format!("{:#}", anyhow::Error::from(e)),
    }
}

/// Asserts that loading `name` fails naming the file and every piece of `expected`, and that
/// the CLI fails the same way and leaves the output folder empty.
fn check(name: &str, expected: &[&str]) {
    let e = error_of(name);
    assert!(e.contains(name), "{name}: {e}");
    for piece in expected {
        assert!(e.contains(piece), "{name}: expected {piece:?} in {e}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir.path())
        .arg("render")
        .arg(bad(name))
        .args(["--width", "16", "--height", "16", "--spp", "1", "--quiet"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
    assert!(
        stderr.contains(name) && !stderr.contains("panicked"),
        "{name}: {stderr}"
    );
    for piece in expected {
        assert!(
            stderr.contains(piece),
            "{name}: expected {piece:?} in {stderr}"
        );
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "{name}");
}

#[test]
fn truncated_glb_names_the_header() {
    check("truncated.glb", &["GLB header", "truncated"]);
}

#[test]
fn invalid_json_names_the_line() {
    check("invalid_json.gltf", &["JSON", "line 2"]);
}

#[test]
fn accessor_out_of_bounds_names_the_accessor_and_view() {
    check(
        "accessor_out_of_bounds.gltf",
        &["accessors[0]", "bufferViews[0]", "2400 elements"],
    );
}

#[test]
fn index_out_of_range_names_the_primitive_and_accessor() {
    check(
        "index_out_of_range.gltf",
        &["meshes[0].primitives[0]", "accessors[3]", "vertex 99"],
    );
}

#[test]
fn nan_position_names_the_accessor_and_vertex() {
    check(
        "nan_position.gltf",
        &["POSITION accessors[0]", "vertex 5", "non-finite"],
    );
}

#[test]
fn missing_buffer_file_names_the_buffer_and_file() {
    check(
        "missing_buffer.gltf",
        &["buffers[0]", "does_not_exist.bin", "cannot read"],
    );
}

#[test]
fn unsupported_required_extension_is_named() {
    check(
        "draco.gltf",
        &["extensionsRequired[0]", "KHR_draco_mesh_compression"],
    );
}

#[test]
fn empty_mesh_is_named() {
    check("empty_mesh.gltf", &["meshes[0]", "no primitives"]);
}

#[test]
fn arbitrary_truncations_and_byte_flips_never_panic() {
    // Every prefix of the GLB and a sweep of single-byte corruptions: each loads or fails
    // cleanly (a panic inside the loader would surface as the catch-all message).
    let glb =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/gltf/cube.glb")).unwrap();
    let origin = Path::new("fuzz.glb");
    let no_files = |_: &Path| Err(std::io::Error::other("no files here"));
    let options = lumis_io::formats::LoadOptions::default();
    let mut variants: Vec<Vec<u8>> = (0..glb.len())
        .step_by(7)
        .map(|n| glb[..n].to_vec())
        .collect();
    for i in 0..glb.len() {
        for v in [0u8, 0xff, 0x7f] {
            let mut g = glb.clone();
            g[i] = v;
            variants.push(g);
        }
    }
    for (k, bytes) in variants.iter().enumerate() {
        if let Err(e) = lumis_io::formats::gltf::load_gltf_bytes(bytes, origin, &no_files, &options)
        {
            let msg = e.to_string();
            assert!(msg.contains("fuzz.glb"), "variant {k}: {msg}");
            assert!(
                !msg.contains("reader failed"),
                "variant {k} panicked: {msg}"
            );
        }
    }
}

//! Size bombs (issue 14, item 2): files of a few hundred bytes that declare sizes they do not
//! contain. Each must fail (or, for a texture, warn) cleanly in well under a second with the
//! binary's address space capped at 100 MB, which an up-front allocation from the declared
//! size would exceed by orders of magnitude. Needs `prlimit` (util-linux); skips, saying so,
//! without it.

use crate::common;

use std::path::Path;
use std::time::Duration;

use common::hostile::{
    TRIANGLE_OBJ, assert_clean, f32_header, gltf_with, have_prlimit, lumis, npy,
};
use serde_json::json;

/// The address-space cap: the binary needs about 30 MB to start and load a small scene.
const CAP: u64 = 100_000_000;
const QUICK: Duration = Duration::from_secs(1);

fn capped(dir: &Path, args: &[&str]) -> Option<common::hostile::Run> {
    if !have_prlimit() {
        eprintln!("skipped: prlimit (util-linux) is not installed, so memory cannot be capped");
        return None;
    }
    let run = lumis(dir, args, Some(CAP));
    assert!(run.elapsed < QUICK, "{args:?} took {:?}", run.elapsed);
    Some(run)
}

#[test]
fn the_cap_leaves_room_for_a_small_valid_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.obj"), TRIANGLE_OBJ).unwrap();
    if let Some(run) = capped(dir.path(), &["info", "tri.obj"]) {
        assert!(run.output.status.success(), "{}", run.stderr());
    }
}

/// An accessor with no buffer view, only one sparse element, and `count` 2^31.
fn sparse_bomb(as_indices: bool) -> String {
    let mut data = Vec::new();
    for v in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        data.extend(v.to_le_bytes());
    }
    data.extend(0u32.to_le_bytes()); // sparse index
    data.extend([0u8; 12]); // sparse value (a VEC3, or a u32 index)
    let sparse = json!({"count": 1, "indices": {"bufferView": 1, "componentType": 5125},
                        "values": {"bufferView": 2}});
    let (kind, component) = if as_indices {
        ("SCALAR", 5125)
    } else {
        ("VEC3", 5126)
    };
    let mut bomb = json!({"componentType": component, "type": kind, "count": 1u64 << 31,
                          "sparse": sparse});
    if !as_indices {
        bomb["min"] = json!([0, 0, 0]);
        bomb["max"] = json!([1, 1, 1]);
    }
    let prim = if as_indices {
        json!({"attributes": {"POSITION": 0}, "indices": 1})
    } else {
        json!({"attributes": {"POSITION": 1}})
    };
    gltf_with(json!({
        "buffers": [{"byteLength": data.len(), "uri": common::hostile::data_uri(&data)}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 4},
                        {"buffer": 0, "byteOffset": 40, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 3,
                       "min": [0, 0, 0], "max": [1, 1, 0]}, bomb],
        "meshes": [{"primitives": [prim]}],
    }))
}

#[test]
fn gltf_accessors_without_a_buffer_view_cannot_declare_billions_of_elements() {
    for as_indices in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("bomb.gltf"), sparse_bomb(as_indices)).unwrap();
        if let Some(run) = capped(dir.path(), &["info", "bomb.gltf"]) {
            run.assert_refused(&["bomb.gltf", "accessors[1]", "count 2147483648"]);
        }
    }
}

/// Runs `lumis hits` on `rays` (a triangle scene beside it) under the cap.
fn hits(rays: &[u8]) -> Option<common::hostile::Run> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.obj"), TRIANGLE_OBJ).unwrap();
    std::fs::write(dir.path().join("rays.npy"), rays).unwrap();
    let run = capped(
        dir.path(),
        &["hits", "tri.obj", "--rays", "rays.npy", "--out", "hits.npy"],
    )?;
    let written = dir.path().join("hits.npy").exists();
    assert_eq!(written, run.output.status.success(), "output iff accepted");
    Some(run)
}

#[test]
fn npy_sizes_are_checked_against_the_bytes_present() {
    let header = f32_header("(2, 8)");
    let two_rays: Vec<u8> = (0..16)
        .flat_map(|i| [0f32, 0., 5., 0., 0., -1., 0., f32::INFINITY][i % 8].to_le_bytes())
        .collect();
    // Version 2 with a header length of 0xFFFFFFFF, followed by two bytes.
    let mut long_header = b"\x93NUMPY\x02\x00".to_vec();
    long_header.extend(u32::MAX.to_le_bytes());
    long_header.extend(b"{}");
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (
            long_header,
            "header length field is 4294967295 bytes, but only 2",
        ),
        // 2^61 rows of 32 bytes overflow a 64-bit byte count (this used to load as 0 rays).
        (
            npy(1, &f32_header("(2305843009213693952, 8)"), &two_rays),
            "the row count overflows",
        ),
        (
            npy(1, &f32_header("(1099511627776, 8)"), &two_rays),
            "truncated data",
        ),
        (
            npy(1, &header, &[two_rays.as_slice(), &[0; 3]].concat()),
            "3 trailing bytes",
        ),
        (npy(3, &header, &two_rays[..40]), "truncated data"),
    ];
    for (bytes, expected) in cases {
        if let Some(run) = hits(&bytes) {
            run.assert_refused(&["rays.npy", expected]);
        }
    }
    // The same header with exactly its data is accepted.
    if let Some(run) = hits(&npy(1, &header, &two_rays)) {
        assert!(run.output.status.success(), "{}", run.stderr());
    }
}

/// A PNG signature, a header declaring `w x h` RGBA texels and an empty image data chunk:
/// enough for a decoder to learn the size, with no pixels behind it.
fn png_header(w: u32, h: u32) -> Vec<u8> {
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 6, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for (kind, data) in [(b"IHDR", ihdr), (b"IDAT", Vec::new())] {
        let body = [&kind[..], &data].concat();
        let crc = body.iter().fold(!0u32, |mut c, &b| {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    (c >> 1) ^ 0xEDB8_8320
                } else {
                    c >> 1
                };
            }
            c
        });
        png.extend((data.len() as u32).to_be_bytes());
        png.extend(&body);
        png.extend((!crc).to_be_bytes());
    }
    png
}

#[test]
fn image_headers_cannot_ask_for_more_than_their_file_can_hold() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("big.png"), png_header(16_000, 16_000)).unwrap();
    std::fs::write(d.join("lib.mtl"), "newmtl m\nmap_Kd big.png\n").unwrap();
    let obj = "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl m\nf 1/1 2/1 3/1\n";
    std::fs::write(d.join("model.obj"), obj).unwrap();
    if let Some(run) = capped(d, &["info", "model.obj"]) {
        let text = run.text();
        assert!(run.output.status.success(), "{text}");
        assert_clean(&text);
        assert!(
            text.contains("big.png") && text.contains("far more than the file"),
            "{text}"
        );
    }
}

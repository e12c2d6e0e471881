//! Hostile inputs for the robustness tests (tests/bad_input_deps.rs, tests/memory_bombs.rs,
//! tests/fuzz_regressions.rs): small glTF, `.npy` and PNG files built in memory, and a way to
//! run the binary on them (optionally under an address-space cap) and check its promises.

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// A glTF document with one triangle (positions in buffer 0 as a base64 data URI), merged
/// with the top-level members of `extra` (which replace the defaults of the same name).
pub fn gltf_with(extra: serde_json::Value) -> String {
    let mut data = Vec::new();
    for v in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        data.extend(v.to_le_bytes());
    }
    let mut doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": data.len(), "uri": data_uri(&data)}],
        "bufferViews": [{"buffer": 0, "byteLength": data.len()}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 3,
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    });
    for (k, v) in extra.as_object().expect("an object") {
        doc[k] = v.clone();
    }
    doc.to_string()
}

/// `bytes` as an `application/octet-stream` base64 data URI.
pub fn data_uri(bytes: &[u8]) -> String {
    const ABC: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::from("data:application/octet-stream;base64,");
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().fold(0u32, |n, &b| n << 8 | u32::from(b)) << (8 * (3 - chunk.len()));
        for k in 0..=chunk.len() {
            s.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
        }
        s.push_str(&"=".repeat(3 - chunk.len()));
    }
    s
}

/// An `.npy` file of `version` whose header is the dict literal `dict`, then `data`.
pub fn npy(version: u8, dict: &str, data: &[u8]) -> Vec<u8> {
    let mut b = b"\x93NUMPY".to_vec();
    b.extend([version, 0]);
    if version == 1 {
        b.extend((dict.len() as u16).to_le_bytes());
    } else {
        b.extend((dict.len() as u32).to_le_bytes());
    }
    b.extend(dict.as_bytes());
    b.extend(data);
    b
}

/// The header dict of a float32 C-order array of `shape`.
pub fn f32_header(shape: &str) -> String {
    format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {shape}, }}\n")
}

/// A triangle OBJ file for scenes that need some geometry (`lumis hits`).
pub const TRIANGLE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// What one run of the binary did.
pub struct Run {
    pub output: Output,
    pub elapsed: Duration,
}

impl Run {
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }

    /// Everything printed (warnings go to stderr, `lumis info` reports to stdout).
    pub fn text(&self) -> String {
        format!(
            "{}{}",
            String::from_utf8_lossy(&self.output.stdout),
            self.stderr()
        )
    }

    /// Asserts a clean refusal: exit code 1 (not a signal or an abort), no panic text, and
    /// every piece of `expected` in the message.
    pub fn assert_refused(&self, expected: &[&str]) {
        let err = self.stderr();
        assert_eq!(self.output.status.code(), Some(1), "{err}");
        assert_clean(&err);
        for piece in expected {
            assert!(err.contains(piece), "expected {piece:?} in: {err}");
        }
    }
}

/// No panic text and no allocator abort in `text`.
pub fn assert_clean(text: &str) {
    assert!(!text.contains("panicked"), "panic text printed: {text}");
    assert!(
        !text.contains("memory allocation"),
        "allocation failed: {text}"
    );
}

/// Runs `lumis args...` in `dir`; under an address-space cap of `cap` bytes when given
/// (through `prlimit`, which the caller has checked exists).
pub fn lumis(dir: &Path, args: &[&str], cap: Option<u64>) -> Run {
    let bin = super::cli::binary();
    let mut cmd = match cap {
        Some(bytes) => {
            let mut c = Command::new("prlimit");
            c.arg(format!("--as={bytes}")).arg(bin);
            c
        }
        None => Command::new(bin),
    };
    let start = Instant::now();
    let output = cmd.current_dir(dir).args(args).output().expect("run lumis");
    Run {
        output,
        elapsed: start.elapsed(),
    }
}

/// Whether `prlimit` (util-linux) can run here.
pub fn have_prlimit() -> bool {
    Command::new("prlimit")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

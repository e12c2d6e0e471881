//! The EXR passes of issue 13 checked on pixels, end to end through the binary: `--aov
//! albedo,position,uv` against the analytic values of small generated scenes, `--transparent`
//! against the over-composite a compositor does, `--layout blender` against Blender's names,
//! and what is written only on request.

mod albedo;
mod flags;
mod layout;
mod position;
mod transparent;
mod uv;

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::exr::{FlatImage, read_exr};

/// Image size of every test scene: small, and even so that the image centre is a pixel corner.
pub const W: usize = 32;
pub const H: usize = 24;

/// `lumis render` run in `dir`.
pub fn lumis(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_lumis"));
    c.current_dir(dir).arg("render");
    c
}

/// Panics with lumis's stderr unless it succeeded.
pub fn ok(out: Output) {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Writes `scene` (TOML) as `dir/name`, renders it to `dir/out` with FLOAT RGBA at
/// `W x H` plus `args`, and reads the EXR back.
pub fn render(dir: &Path, name: &str, scene: &str, out: &str, args: &[&str]) -> FlatImage {
    std::fs::write(dir.join(name), scene).unwrap();
    ok(lumis(dir)
        .arg(name)
        .args([
            "-o", out, "--float", "--quiet", "--width", "32", "--height", "24",
        ])
        .args(args)
        .output()
        .unwrap());
    read_exr(&dir.join(out))
}

/// Index of pixel `(x, y)` in a row-major channel.
pub fn at(x: usize, y: usize) -> usize {
    y * W + x
}

/// The channel names of the first layer, sorted (as EXR stores them).
pub use crate::common::exr::channel_names as names;

/// Row vector `p` times an Imath row-major M44f, as a compositor applies the header matrices.
pub fn row_times_m44f(p: [f32; 4], m: &[f32; 16]) -> [f32; 4] {
    std::array::from_fn(|j| (0..4).map(|i| p[i] * m[i * 4 + j]).sum())
}

/// A camera on +z looking at the origin, 40 degrees vertical field of view, no ambient
/// light: the `[render]` and `[camera]` sections every scene here starts with.
pub const CAMERA: &str = r#"
[render]
spp = 1
ambient = [0.0, 0.0, 0.0]

[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0
"#;

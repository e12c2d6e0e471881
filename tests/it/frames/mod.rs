//! Frame sequences (issue 15) end to end through the binary: `--frame F` poses a TOML scene's
//! `[animation]` at frame F. The camera is checked through the header's `worldToCamera` and
//! `worldToNDC`, which must be those of the camera the keys give (exact on a key and halfway
//! between keys whose values are short binary fractions); a frame equals, byte for byte, a
//! still with the posed values written by hand; `#` runs in the outputs become the frame
//! number; the header records the frame; bad animations fail naming the file and the key; and
//! `tools/slurm/render_frames.sbatch` renders one frame per array task.

mod errors;
mod outputs;
mod slurm;

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use exr::prelude::{AttributeValue, Text};
use lumis_core::camera::Camera;
use lumis_core::math::Vec3;
use lumis_io::output::{ATTR_FRAME, imath_m44f};

use common::exr::{FlatImage, read_exr};

/// Image size of every render here.
const W: u32 = 16;
const H: u32 = 12;

/// A still: one sphere, one triangle, one light, a `[camera]`. Tests append `[animation]`.
pub const STILL: &str = r#"
[render]
width = 16
height = 12
spp = 1
max_depth = 2

[camera]
position = [0.0, 0.0, 8.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0

[[light]]
type = "point"
position = [4.0, 4.0, 8.0]
intensity = 100.0

[[sphere]]
name = "ball"
center = [0.0, 0.0, 0.0]
radius = 1.0

[[mesh]]
name = "tri"
positions = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]
indices = [[0, 1, 2]]
translate = [-2.0, 0.0, 0.0]
"#;

/// Camera keys at frames 2 and 6 (the later one first in the file: keys are sorted on load).
/// Frame 4 is halfway: position [2, 1, 8], fov 30.
const CAMERA_KEYS: &str = r#"
[[animation.camera]]
frame = 6
position = [4.0, 2.0, 8.0]
fov = 20.0

[[animation.camera]]
frame = 2
position = [0.0, 0.0, 8.0]
fov = 40.0
"#;

/// `lumis render` in `dir`.
pub fn lumis(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_lumis"));
    c.current_dir(dir).arg("render");
    c
}

/// Writes `scene` as `dir/name` and renders it with `args` to `dir/out` (FLOAT RGBA, quiet);
/// returns stderr (warnings) after checking that it succeeded.
pub fn render(dir: &Path, name: &str, scene: &str, out: &str, args: &[&str]) -> String {
    std::fs::write(dir.join(name), scene).unwrap();
    let run = lumis(dir)
        .args([name, "-o", out, "--float", "--threads", "2"])
        .args(args)
        .output()
        .unwrap();
    common::cli::assert_ok(&run);
    String::from_utf8_lossy(&run.stderr).into_owned()
}

/// The stderr of a run that must fail cleanly.
pub fn failure(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "succeeded; stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// The animated scene: [`STILL`] with `[animation]` of `frames` frames and `keys`.
fn animated(frames: u32, keys: &str) -> String {
    format!("{STILL}\n[animation]\nframes = {frames}\n{keys}")
}

/// `worldToCamera` and `worldToNDC` of the camera at `position` with `fov` looking at the
/// origin, as lumis writes them.
fn camera_matrices(position: [f32; 3], look_at: [f32; 3], fov: f32) -> ([f32; 16], [f32; 16]) {
    let c = Camera::look_at(
        Vec3::from(position),
        Vec3::from(look_at),
        Vec3::Y,
        fov,
        0.0,
        None,
    )
    .unwrap();
    (
        imath_m44f(c.world_to_camera()),
        imath_m44f(c.world_to_ndc(W, H)),
    )
}

/// The header's camera matrices.
fn header_matrices(image: &FlatImage) -> ([f32; 16], [f32; 16]) {
    let a = &image.layer_data[0].attributes;
    (
        a.world_to_camera.expect("worldToCamera"),
        a.world_to_normalized_device.expect("worldToNDC"),
    )
}

/// Renders frame `frame` of `scene` and returns the header's camera matrices.
fn camera_at(dir: &Path, scene: &str, frame: u32, args: &[&str]) -> ([f32; 16], [f32; 16]) {
    let out = format!("f{frame}.exr");
    let f = frame.to_string();
    render(
        dir,
        "anim.toml",
        scene,
        &out,
        &[&["--frame", &f][..], args].concat(),
    );
    header_matrices(&read_exr(&dir.join(out)))
}

#[test]
fn the_camera_is_exact_on_keys_halfway_between_and_held_outside() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = animated(9, CAMERA_KEYS);
    let o = [0.0; 3];
    for (frame, position, fov) in [
        (0, [0.0, 0.0, 8.0], 40.0),
        (2, [0.0, 0.0, 8.0], 40.0),
        (3, [1.0, 0.5, 8.0], 35.0),
        (4, [2.0, 1.0, 8.0], 30.0),
        (6, [4.0, 2.0, 8.0], 20.0),
        (8, [4.0, 2.0, 8.0], 20.0),
    ] {
        assert_eq!(
            camera_at(d, &scene, frame, &[]),
            camera_matrices(position, o, fov),
            "frame {frame}"
        );
    }
    // Step keys hold their value up to the next key; a key's own interpolation wins over the
    // table's.
    let table_step = scene.replace("frames = 9", "frames = 9\ninterpolation = \"step\"");
    let key_step = scene.replace("frame = 2\n", "frame = 2\ninterpolation = \"step\"\n");
    for step in [table_step, key_step] {
        assert_eq!(
            camera_at(d, &step, 5, &[]),
            camera_matrices([0.0, 0.0, 8.0], o, 40.0)
        );
        assert_eq!(
            camera_at(d, &step, 6, &[]),
            camera_matrices([4.0, 2.0, 8.0], o, 20.0)
        );
    }
}

#[test]
fn a_frame_is_byte_identical_to_the_still_written_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let objects = r#"
[[animation.sphere]]
name = "ball"
frame = 0
center = [0.0, -1.0, 0.0]

[[animation.sphere]]
name = "ball"
frame = 8
center = [1.0, 1.0, 0.0]
radius = 1.5

[[animation.mesh]]
name = "tri"
frame = 0
translate = [-2.0, 0.0, 0.0]
rotate = [0.0, 0.0, 0.0]

[[animation.mesh]]
name = "tri"
frame = 8
translate = [-3.0, 1.0, 0.0]
rotate = [0.0, 0.0, 90.0]
"#;
    let anim_scene = animated(9, &format!("{CAMERA_KEYS}{objects}"));
    render(d, "anim.toml", &anim_scene, "anim.exr", &["--frame", "4"]);
    render(d, "anim.toml", &anim_scene, "anim0.exr", &["--frame", "0"]);
    // Frame 4: the camera halfway from frame 2 to 6, the objects halfway from frame 0 to 8;
    // the radius has a single key, whose value holds at every frame.
    let by_hand = STILL
        .replace("position = [0.0, 0.0, 8.0]", "position = [2.0, 1.0, 8.0]")
        .replace("fov = 40.0", "fov = 30.0")
        .replace("center = [0.0, 0.0, 0.0]", "center = [0.5, 0.0, 0.0]")
        .replace("radius = 1.0", "radius = 1.5")
        .replace(
            "translate = [-2.0, 0.0, 0.0]",
            "translate = [-2.5, 0.5, 0.0]\nrotate = [0.0, 0.0, 45.0]",
        );
    // A motionless animation of the same length: the same pixels and header, but for the
    // scene hash, which tells the two files apart.
    let held_scene = format!("{by_hand}\n[animation]\nframes = 9\n");
    render(d, "held.toml", &held_scene, "held.exr", &["--frame", "4"]);
    let (anim, held) = (d.join("anim.exr"), d.join("held.exr"));
    let (mut a, mut h) = (read_exr(&anim), read_exr(&held));
    assert_ne!(without_scene_hash(&mut a), without_scene_hash(&mut h));
    assert!(a == h, "frame 4 and the held pose differ");
    // Not because nothing moves: frame 0 of the animation is another image than the held
    // pose (any frame of the motionless one).
    render(d, "held.toml", &held_scene, "held0.exr", &["--frame", "0"]);
    let anim0 = read_exr(&d.join("anim0.exr"));
    assert!(anim0 != read_exr(&d.join("held0.exr")));
    // The plain still: the same pixels and header but for the frame's attributes.
    render(d, "still.toml", &by_hand, "still.exr", &[]);
    let mut frame = read_exr(&anim);
    let mut still = read_exr(&d.join("still.exr"));
    without_scene_hash(&mut frame);
    without_scene_hash(&mut still);
    assert_eq!(frame.attributes.time_code.map(|t| t.frame), Some(4));
    frame.attributes.time_code = None;
    let layer = &mut frame.layer_data[0].attributes;
    assert_eq!(layer.frames_per_second, Some((24, 1)));
    layer.frames_per_second = None;
    assert_eq!(
        layer.other.remove(&Text::from(ATTR_FRAME)),
        Some(AttributeValue::I32(4))
    );
    assert!(frame == still, "frame 4 and the still differ");
}

/// Removes and returns `lumis/sceneHash` (a hash of the scene file, which differs between two
/// files that describe the same frame), and removes `lumis/replay` (which names the file).
fn without_scene_hash(image: &mut FlatImage) -> Option<AttributeValue> {
    let other = &mut image.layer_data[0].attributes.other;
    other.remove(&Text::from(lumis_io::output::ATTR_REPLAY));
    other.remove(&Text::from(lumis_io::output::ATTR_SCENE_HASH))
}

#[test]
fn defines_change_the_keys_before_the_frame_is_posed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = animated(9, CAMERA_KEYS);
    let o = [0.0; 3];
    // animation.camera.0 is the first key in the file: frame 6.
    let moved = ["-D", "animation.camera.0.position=[8.0, 4.0, 8.0]"];
    assert_eq!(
        camera_at(d, &scene, 4, &moved),
        camera_matrices([4.0, 2.0, 8.0], o, 30.0)
    );
    // A field no key animates comes from [camera], -D included.
    let look = ["-D", "camera.look_at=[0.0, 1.0, 0.0]"];
    assert_eq!(
        camera_at(d, &scene, 4, &look),
        camera_matrices([2.0, 1.0, 8.0], [0.0, 1.0, 0.0], 30.0)
    );
    // An override of an animated field would change nothing: it is a warning.
    std::fs::write(d.join("anim.toml"), &scene).unwrap();
    let out = lumis(d)
        .args([
            "anim.toml",
            "-D",
            "camera.fov=60",
            "--frame",
            "4",
            "-o",
            "w.exr",
        ])
        .output()
        .unwrap();
    common::cli::assert_ok(&out);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "warning: anim.toml: -D camera.fov=60: keys in [[animation.camera]] animate this field"
        ),
        "{stderr}"
    );
    // -D can shorten the animation; --frame is checked against the result.
    let out = lumis(d)
        .args([
            "anim.toml",
            "-D",
            "animation.frames=4",
            "--frame",
            "4",
            "-o",
            "x.exr",
        ])
        .output()
        .unwrap();
    let stderr = failure(&out);
    assert!(
        stderr.contains("anim.toml: --frame 4: out of range: [animation] frames = 4"),
        "{stderr}"
    );
}

#[test]
fn the_example_orbit_renders_every_frame_on_its_circle() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/orbit.toml");
    let scene = scene.to_str().unwrap();
    for frame in ["0", "13", "23"] {
        let out = lumis(dir.path())
            .args([scene, "--quick", "-q", "--frame", frame, "-o", "o_##.exr"])
            .output()
            .unwrap();
        common::cli::assert_ok(&out);
    }
    for (name, degrees) in [
        ("o_00.exr", 0.0f32),
        ("o_13.exr", 97.5),
        ("o_23.exr", 172.5),
    ] {
        let (w2c, _) = header_matrices(&read_exr(&dir.path().join(name)));
        // The camera position is -R^T t of the row-vector matrix; on the circle of radius 6
        // within the chord's 0.9% of 15 degrees.
        let m = glam::Mat4::from_cols_array(&w2c);
        let eye = m.inverse().transform_point3(glam::Vec3::ZERO);
        let (s, c) = degrees.to_radians().sin_cos();
        let on_circle = glam::Vec3::new(6.0 * s, 2.0, 6.0 * c);
        assert!(
            (eye - on_circle).length() < 0.06,
            "{name}: {eye} vs {on_circle}"
        );
    }
}

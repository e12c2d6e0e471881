//! Bad animations and bad frames fail before rendering, naming the file, the table or key and
//! what was expected, and write nothing.

use super::{STILL, failure, lumis};

/// Writes `scene` as `dir/scene.toml`, runs it with `args`, and returns the error.
fn error(dir: &std::path::Path, scene: &str, args: &[&str]) -> String {
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let out = lumis(dir)
        .args(["scene.toml", "-o", "x.exr", "-q"])
        .args(args)
        .output()
        .unwrap();
    let stderr = failure(&out);
    assert!(!dir.join("x.exr").exists(), "{stderr}");
    stderr
}

/// A camera key at frame 1 of 9 frames, with `fields`.
fn key(fields: &str) -> String {
    format!("{STILL}\n[animation]\nframes = 9\n[[animation.camera]]\nframe = 1\n{fields}\n")
}

#[test]
fn frames_outside_the_animation_and_frames_of_a_still_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let nine = key("fov = 30.0");
    for (scene, frame, want) in [
        (
            nine.as_str(),
            "9",
            "scene.toml: --frame 9: out of range: [animation] frames = 9 numbers them 0..=8",
        ),
        (
            STILL,
            "0",
            "scene.toml: --frame 0: the scene has no [animation] table, so it has no frames",
        ),
    ] {
        let e = error(d, scene, &["--frame", frame]);
        assert!(e.contains(want), "{e}");
    }
    for bad in ["--frame=-1", "--frame=1.5"] {
        let e = error(d, &nine, &[bad]);
        assert!(e.contains("for '--frame <F>'"), "{e}");
    }
    // Other formats have no frames; the built-in default scene is a still.
    std::fs::write(d.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = lumis(d)
        .args(["tri.obj", "--frame", "0", "-o", "x.exr"])
        .output()
        .unwrap();
    let e = failure(&out);
    assert!(
        e.contains("tri.obj: --frame 0: only TOML scenes have frames"),
        "{e}"
    );
    let out = lumis(d)
        .args(["--frame", "0", "-o", "x.exr"])
        .output()
        .unwrap();
    let e = failure(&out);
    assert!(
        e.contains("--frame 0: the scene has no [animation] table"),
        "{e}"
    );
}

#[test]
fn bad_keys_fail_naming_the_key_and_what_was_expected() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let twice = format!(
        "{}[[animation.camera]]\nframe = 1\nfov = 20.0\n",
        key("fov = 30.0")
    );
    let camera = "[camera]\nposition = [0.0, 0.0, 8.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n";
    let no_camera = key("fov = 30.0").replace(camera, "");
    let sphere = |fields: &str| {
        format!("{STILL}\n[animation]\nframes = 9\n[[animation.sphere]]\nframe = 2\n{fields}\n")
    };
    // Keys at frames 0 and 2 that pass through look_at at frame 1.
    let through = format!(
        "{STILL}\n[animation]\nframes = 3\n[[animation.camera]]\nframe = 0\n\
         position = [0.0, 0.0, -2.0]\n[[animation.camera]]\nframe = 2\nposition = [0.0, 0.0, 2.0]\n"
    );
    let cases: Vec<(String, &str)> = vec![
        (
            twice,
            "scene.toml: animation.camera[1] (frame 1): frame 1 is keyed twice (also by \
             animation.camera[0] (frame 1))",
        ),
        (
            key("fov = 30.0").replace("frame = 1", "frame = 9"),
            "animation.camera[0] (frame 9): frame 9 is outside the animation: [animation] \
             frames = 9 numbers them 0..=8",
        ),
        (
            key("fov = 200.0"),
            "animation.camera[0] (frame 1): fov 200 must lie strictly between 0 and 180 degrees",
        ),
        (
            key("position = [1e19, 0.0, 0.0]"),
            "animation.camera[0] (frame 1): position [1e19, 0e0, 0e0] exceeds the coordinate \
             limit",
        ),
        (
            key("look_at = [nan, 0.0, 0.0]"),
            "animation.camera[0] (frame 1): look_at [NaN, 0.0, 0.0] must be finite",
        ),
        (key("up = [0.0, 0.0, 0.0]"), "up must be non-zero"),
        (
            key("aperture = -1.0"),
            "aperture -1 must be finite and >= 0",
        ),
        (key("height = 2.0"), "height is for orthographic cameras"),
        (
            key(""),
            "animation.camera[0] (frame 1): the key animates nothing",
        ),
        (
            key("fovv = 3.0"),
            "scene.toml: line 33, column 1: unknown field `fovv`",
        ),
        (
            key("fov = 30.0").replace("frame = 1", "frame = -1"),
            "scene.toml: line 32, column 9: invalid value",
        ),
        (
            key("interpolation = \"cubic\""),
            "unknown variant `cubic`, expected `linear` or `step`",
        ),
        (
            key("fov = 30.0").replace("frames = 9", "frames = 9\nfps = 23.976"),
            "a whole number of frames per second or [numerator, denominator]",
        ),
        (
            key("fov = 30.0").replace("frames = 9", "frames = 9\nfps = [0, 1]"),
            "scene.toml: animation: fps [0, 1]: numerator and denominator must be in",
        ),
        (
            key("fov = 30.0").replace("frames = 9", "frames = 0"),
            "scene.toml: animation: frames = 0: expected 1..=1000000",
        ),
        (
            no_camera,
            "animation.camera[0] (frame 1): camera keys animate the [camera] table, and the \
             scene has none",
        ),
        (
            sphere("name = \"nope\"\ncenter = [0.0, 0.0, 0.0]"),
            "animation.sphere[0] \"nope\" (frame 2): no [[sphere]] is named \"nope\" (named: \
             [\"ball\"])",
        ),
        (
            sphere("name = \"ball\"\nradius = 0.0"),
            "animation.sphere[0] \"ball\" (frame 2): radius 0 must be > 0",
        ),
        // The camera of every frame is built on load: frame 1's fails the render of frame 0.
        (
            through,
            "scene.toml: animation.camera at frame 1: camera position and look_at coincide",
        ),
    ];
    for (scene, want) in cases {
        let e = error(d, &scene, &[]);
        assert!(e.contains(want), "want {want:?} in:\n{e}");
    }
}

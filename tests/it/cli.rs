//! End to end through the built binary: the default scene renders; a broken scene fails with
//! its path and line and leaves no output file behind.

use crate::common;

use std::process::Command;

fn lumis() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
}

#[test]
fn default_scene_renders_small_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = lumis()
        .current_dir(dir.path())
        .args(["--width", "64", "--height", "36", "--spp", "1", "--quiet"])
        .output()
        .unwrap();
    common::cli::assert_ok(&out);
    assert_eq!(
        common::files::dir_entries(dir.path()),
        ["out.exr", "out.png"]
    );
    let png = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((png.width(), png.height()), (64, 36));
}

#[test]
fn render_subcommand_writes_the_requested_format_and_prints_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = lumis()
        .current_dir(dir.path())
        .args([
            "render",
            "-o",
            "a.png",
            "--width",
            "32",
            "--height",
            "18",
            "--spp",
            "1",
            "--stats",
            "--threads",
            "2",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stderr: {stderr}");
    assert_eq!(common::files::dir_entries(dir.path()), ["a.png"]);
    for needle in [
        "time: load",
        "rays:",
        "camera",
        "shadow",
        "reflection",
        "refraction",
        "Mrays/s",
        "nodes visited/ray",
    ] {
        assert!(
            stderr.contains(needle),
            "summary lacks {needle:?}: {stderr}"
        );
    }
}

#[test]
fn broken_scene_exits_non_zero_names_path_and_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("broken.toml");
    std::fs::write(&scene, "[render]\nwidth = 64\nheight = \"tall\"\n").unwrap();
    let out = lumis()
        .current_dir(dir.path())
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("broken.toml"), "no path in: {stderr}");
    assert!(stderr.contains("line 3"), "no line in: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        common::files::dir_entries(dir.path()),
        ["broken.toml"],
        "no output may be left behind"
    );
}

#[test]
fn missing_scene_and_bad_output_extension_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let out = lumis()
        .current_dir(dir.path())
        .arg("nope.toml")
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope.toml"));
    let out = lumis()
        .current_dir(dir.path())
        .args(["-o", "x.jpg", "--width", "8", "--height", "8"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("x.jpg"));
    assert!(common::files::dir_entries(dir.path()).is_empty());
}

#[test]
fn png_bytes_do_not_depend_on_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    for (threads, name) in [("1", "t1.png"), ("2", "t2.png")] {
        let out = lumis()
            .current_dir(dir.path())
            .args([
                "-q",
                "--width",
                "40",
                "--height",
                "24",
                "--spp",
                "2",
                "--seed",
                "9",
                "--threads",
                threads,
                "-o",
                name,
            ])
            .output()
            .unwrap();
        common::cli::assert_ok(&out);
    }
    let a = std::fs::read(dir.path().join("t1.png")).unwrap();
    let b = std::fs::read(dir.path().join("t2.png")).unwrap();
    assert_eq!(a, b, "PNG bytes differ between --threads 1 and --threads 2");
}

#[test]
fn out_of_range_flags_fail_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 3] = [
        (
            &["--max-depth", "100000"],
            "max_depth 100000 must be in 0..=64",
        ),
        (&["--spp", "100000"], "spp 100000 must be in 1..=64"),
        (
            &["--width", "100000", "--height", "20000"],
            "width 100000 must be in 1..=65536",
        ),
    ];
    for (args, message) in cases {
        let out = lumis()
            .current_dir(dir.path())
            .args(args)
            .arg("-q")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(message) && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
    }
    assert!(common::files::dir_entries(dir.path()).is_empty());
}

#[test]
fn info_describes_a_scene_without_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/default.toml");
    let out = lumis()
        .current_dir(dir.path())
        .args(["info", scene])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    common::cli::assert_ok(&out);
    for needle in [
        "objects: 7 (6 spheres, 1 meshes with 1920 triangles",
        "materials: 7",
        "lights: 2",
        "  light0: ",
        "environment: off",
        "bounds:",
        "warnings: 0",
    ] {
        assert!(stdout.contains(needle), "missing {needle:?} in {stdout}");
    }
    assert!(
        common::files::dir_entries(dir.path()).is_empty(),
        "info must not write files"
    );
}

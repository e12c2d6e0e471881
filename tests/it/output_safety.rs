//! Outputs never clobber: a run that fails leaves every existing file byte for byte as it was
//! and no temporary file behind; no output may be a file the run reads or another output;
//! `hits` arrays must be named `.npy`; stale temporary files of killed runs are cleaned up.

use crate::support_io as support;

use std::path::Path;
use support::{lumis, names, rays_npy, temps_under, toml_scene};

/// Writes `files` (name, bytes) under `dir`, creating folders.
fn write_all(dir: &Path, files: &[(&str, &[u8])]) {
    for (name, bytes) in files {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    }
}

/// Fails unless every file of `files` still has its bytes and there is no temporary file.
fn assert_unchanged(dir: &Path, files: &[(&str, &[u8])]) {
    for (name, bytes) in files {
        assert_eq!(
            std::fs::read(dir.join(name)).unwrap(),
            *bytes,
            "{name} changed"
        );
    }
    assert_eq!(temps_under(dir), Vec::<std::path::PathBuf>::new());
}

fn scene_files() -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("s.toml", toml_scene("").into_bytes()),
        ("out/img.exr", b"old exr".to_vec()),
        ("out/img.png", b"old png".to_vec()),
        ("out/stats.json", b"old json".to_vec()),
    ]
}

fn as_refs<'a>(files: &'a [(&'static str, Vec<u8>)]) -> Vec<(&'static str, &'a [u8])> {
    files.iter().map(|(n, b)| (*n, b.as_slice())).collect()
}

/// The case: `--png` into a missing folder used to replace `-o` first.
#[test]
fn a_failing_output_keeps_every_existing_one() {
    let dir = tempfile::tempdir().unwrap();
    let owned = scene_files();
    let files = as_refs(&owned);
    write_all(dir.path(), &files);
    let bad = [
        // A missing folder for one of them.
        vec!["-o", "out/img.exr", "--png", "nodir/img.png"],
        vec!["-o", "out/img.exr", "--stats-json", "nodir/s.json"],
        // An existing directory as an output.
        vec!["-o", "out/img.exr", "--png", "out/sub.png"],
        // The same file twice, however spelt.
        vec![
            "-o",
            "out/img.exr",
            "--png",
            "out/img.png",
            "--stats-json",
            "./out/img.png",
        ],
        vec!["-o", "out/img.exr", "--stats-json", "out/../out/img.exr"],
    ];
    std::fs::create_dir(dir.path().join("out/sub.png")).unwrap();
    for args in bad {
        let mut all = vec!["render", "s.toml"];
        all.extend(&args);
        let run = lumis(dir.path(), &all);
        run.assert_error(&[]);
        assert!(run.stderr.contains("error:"), "{}", run.stderr);
        assert_unchanged(dir.path(), &files);
    }
    assert_eq!(names(dir.path()), ["out", "s.toml"]);
}

/// The directory checks happen before the render, so a long render cannot end in them: a
/// render of 4096x4096 at 64 samples per pixel would take minutes, the refusal is immediate.
#[test]
fn output_problems_are_found_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), toml_scene("")).unwrap();
    let slow = ["--width", "4096", "--height", "4096", "--spp", "8"];
    for out in [["-o", "nodir/a.exr"], ["--png", "nodir/a.png"]] {
        let mut args = vec!["render", "s.toml"];
        args.extend(out);
        args.extend(slow);
        let run = support::lumis_in(dir.path(), &args, std::time::Duration::from_secs(5));
        run.assert_error(&["nodir", "does not exist"]);
    }
}

#[test]
fn success_writes_every_output_and_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let owned = scene_files();
    write_all(dir.path(), &as_refs(&owned));
    let run = lumis(
        dir.path(),
        &[
            "render",
            "s.toml",
            "-o",
            "out/img.exr",
            "--png",
            "out/img.png",
            "--stats-json",
            "out/stats.json",
        ],
    );
    run.assert_ok();
    for name in ["out/img.exr", "out/img.png", "out/stats.json"] {
        let bytes = std::fs::read(dir.path().join(name)).unwrap();
        assert!(!bytes.starts_with(b"old"), "{name} not replaced");
    }
    assert!(temps_under(dir.path()).is_empty());
}

/// A texture, the scene itself (as the stats report), the mesh: none may be overwritten.
#[test]
fn an_input_is_never_an_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let png =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/default.png")).unwrap();
    let obj = b"mtllib m.mtl\nv 0 0 -3\nv 1 0 -3\nv 0 1 -3\nvt 0 0\nvt 1 0\nvt 0 1\n\
                usemtl m\nf 1/1 2/2 3/3\n";
    let mesh = "[[mesh]]\nname = \"tri\"\nfile = \"m.obj\"\nmaterial = \"m\"\n";
    let scene = toml_scene(mesh);
    let files: Vec<(&str, &[u8])> = vec![
        ("s.toml", scene.as_bytes()),
        ("m.obj", obj),
        ("m.mtl", b"newmtl m\nKd 1 1 1\nmap_Kd tex.png\n"),
        ("tex.png", &png),
    ];
    write_all(d, &files);
    std::fs::hard_link(d.join("tex.png"), d.join("alias.png")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("tex.png", d.join("link.png")).unwrap();
    let cases: Vec<Vec<&str>> = vec![
        vec!["render", "m.obj", "--png", "tex.png"],
        vec!["render", "m.obj", "--png", "./tex.png"],
        vec!["render", "m.obj", "--png", "alias.png"],
        #[cfg(unix)]
        vec!["render", "m.obj", "--png", "link.png"],
        vec!["render", "s.toml", "-o", "a.exr", "--stats-json", "s.toml"],
        vec!["render", "s.toml", "-o", "a.exr", "--stats-json", "m.obj"],
        vec!["render", "m.obj", "-o", "a.exr", "--stats-json", "m.mtl"],
    ];
    for args in cases {
        let run = lumis(d, &args);
        run.assert_error(&["is an input of this run"]);
        assert_unchanged(d, &files);
        assert!(!d.join("a.exr").exists() && !d.join("out.exr").exists());
    }
}

fn hits_setup() -> (tempfile::TempDir, Vec<(&'static str, Vec<u8>)>) {
    let dir = tempfile::tempdir().unwrap();
    let files = vec![
        ("hits.toml", toml_scene("").into_bytes()),
        ("rays.npy", rays_npy(&[0.0, 5.0])),
        ("old.npy", b"old hits".to_vec()),
    ];
    write_all(dir.path(), &as_refs(&files));
    (dir, files)
}

/// The cases: `--out hits.toml` replaced the scene, `--out rays.npy` the rays.
#[test]
fn hits_refuses_inputs_and_non_npy_names() {
    let (dir, owned) = hits_setup();
    let files = as_refs(&owned);
    let base = ["hits", "hits.toml", "--rays", "rays.npy"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--out", "hits.toml"], "must end in .npy"),
        (vec!["--out", "rays.npy"], "is an input of this run"),
        (vec!["--out", "./rays.npy"], "is an input of this run"),
        (
            vec!["--out", "old.npy", "--spawn-out", "x.txt"],
            "must end in .npy",
        ),
        (
            vec!["--out", "old.npy", "--spawn-out", "rays.npy"],
            "is an input",
        ),
        (
            vec!["--out", "old.npy", "--spawn-out", "./old.npy"],
            "same file",
        ),
        (
            vec!["--out", "old.npy", "--timings", "hits.toml"],
            "is an input",
        ),
        (
            vec!["--out", "old.npy", "--spawn-out", "nodir/s.npy"],
            "does not exist",
        ),
    ];
    for (extra, says) in cases {
        let mut args = base.to_vec();
        args.extend(&extra);
        let run = lumis(dir.path(), &args);
        run.assert_error(&[says]);
        assert_unchanged(dir.path(), &files);
        assert_eq!(names(dir.path()), ["hits.toml", "old.npy", "rays.npy"]);
    }
    let run = lumis(dir.path(), &[&base[..], &["--out", "old.npy"]].concat());
    run.assert_ok();
    assert_ne!(
        std::fs::read(dir.path().join("old.npy")).unwrap(),
        b"old hits"
    );
}

/// Temporary files of a killed run (its pid gone, older than a minute) are removed by the next
/// run that writes to the same directory; a live process's and fresh ones are kept.
#[cfg(target_os = "linux")]
#[test]
fn stale_temporaries_of_killed_runs_are_removed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), toml_scene("")).unwrap();
    // pid_max is at most 2^22 on Linux: these pids cannot be running.
    let stale = d.join(".lumis-4194999-AbCdEf.tmp");
    let fresh = d.join(".lumis-4194998-AbCdEf.tmp");
    let alive = d.join(format!(".lumis-{}-AbCdEf.tmp", std::process::id()));
    for p in [&stale, &fresh, &alive] {
        std::fs::write(p, b"").unwrap();
    }
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(120);
    for p in [&stale, &alive] {
        let f = std::fs::File::options().write(true).open(p).unwrap();
        f.set_modified(old).unwrap();
    }
    lumis(d, &["render", "s.toml", "-o", "a.exr"]).assert_ok();
    assert!(!stale.exists(), "stale temporary kept");
    assert!(
        fresh.exists() && alive.exists(),
        "a live or fresh temporary removed"
    );
}

/// A second Ctrl-C quits at once (exit 130) and still leaves no temporary file; the existing
/// output is either untouched or the complete partial image, never torn.
#[cfg(unix)]
#[test]
fn a_second_ctrl_c_quits_without_leaving_temporaries() {
    use std::process::{Command, Stdio};
    use std::time::Duration;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("part.exr"), b"old exr").unwrap();
    // Far longer than the waits below on any machine.
    let child = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args(["--width", "1600", "--height", "1600", "--spp", "12"])
        .args(["-o", "part.exr", "--quiet"])
        .current_dir(dir.path())
        .stdin(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let interrupt = || {
        let pid = child.id().to_string();
        assert!(
            Command::new("kill")
                .args(["-INT", &pid])
                .status()
                .unwrap()
                .success()
        );
    };
    std::thread::sleep(Duration::from_millis(1500));
    interrupt();
    std::thread::sleep(Duration::from_millis(30));
    interrupt();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        temps_under(dir.path()).is_empty(),
        "{:?}",
        names(dir.path())
    );
    let bytes = std::fs::read(dir.path().join("part.exr")).unwrap();
    assert!(
        bytes == b"old exr" || bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]),
        "torn output"
    );
}

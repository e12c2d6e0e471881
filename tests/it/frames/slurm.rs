//! `tools/slurm/render_frames.sbatch` run as Slurm runs an array task (the variables it sets,
//! without a cluster): each task renders its frame to the numbered name, through a staging
//! file that never remains, byte-identical to `lumis render --frame`; a frame outside the
//! animation fails the task and leaves nothing.

use std::path::Path;
use std::process::{Command, Output};

use super::{CAMERA_KEYS, animated, failure, render};

/// Runs the script as array task `task` of job 42 with `env` and lumis flags `args`.
fn task(dir: &Path, task: u32, env: &[(&str, &str)], args: &[&str]) -> Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/slurm/render_frames.sbatch");
    Command::new("bash")
        .arg(script)
        .args(args)
        .current_dir(dir)
        .env("LUMIS", env!("CARGO_BIN_EXE_lumis"))
        .env("SLURM_ARRAY_TASK_ID", task.to_string())
        .env("SLURM_JOB_ID", "42")
        .env("SLURM_CPUS_PER_TASK", "2")
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn each_array_task_renders_its_frame_to_the_numbered_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("frames")).unwrap();
    let scene = animated(9, CAMERA_KEYS);
    std::fs::write(d.join("anim.toml"), &scene).unwrap();
    let out_pattern = d.join("frames/frame_####.exr");
    let env = [
        // As the direct render below names it: the header records the path as given.
        ("SCENE", "anim.toml"),
        ("OUT", out_pattern.to_str().unwrap()),
    ];
    for t in [0, 4] {
        let out = task(d, t, &env, &["--float"]);
        common_ok(&out);
        let log = String::from_utf8_lossy(&out.stdout);
        assert!(
            log.contains(&format!("lumis-slurm: task=frame frame={t} "))
                && log.contains("status=0"),
            "{log}"
        );
    }
    assert_eq!(
        super::common::files::dir_entries(&d.join("frames")),
        ["frame_0000.exr", "frame_0004.exr"]
    );
    render(d, "anim.toml", &scene, "direct.exr", &["--frame", "4"]);
    assert!(
        std::fs::read(d.join("frames/frame_0004.exr")).unwrap()
            == std::fs::read(d.join("direct.exr")).unwrap(),
        "the task's frame differs from lumis render --frame 4"
    );
    // Out of the animation: the task fails with lumis's status, and leaves no file.
    let out = task(d, 9, &env, &[]);
    let stderr = failure(&out);
    assert!(stderr.contains("--frame 9: out of range"), "{stderr}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("status=1"));
    assert_eq!(
        super::common::files::dir_entries(&d.join("frames")).len(),
        2
    );
    // SKIP_EXISTING leaves a finished frame alone; without SCENE or a # nothing runs.
    let before = std::fs::metadata(d.join("frames/frame_0004.exr"))
        .unwrap()
        .modified()
        .unwrap();
    common_ok(&task(d, 4, &[env[0], env[1], ("SKIP_EXISTING", "1")], &[]));
    let after = std::fs::metadata(d.join("frames/frame_0004.exr"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after);
    let e = failure(&task(d, 1, &[env[1]], &[]));
    assert!(e.contains("SCENE is not set"), "{e}");
    let e = failure(&task(d, 1, &[env[0], ("OUT", "frame.exr")], &[]));
    assert!(e.contains("has no # for the frame number"), "{e}");
}

fn common_ok(out: &Output) {
    super::common::cli::assert_ok(out);
}

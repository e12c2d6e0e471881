//! Running the lumis binary from a test: one check that a run succeeded, which shows the
//! run's stderr when it did not (the message a user would have seen), and a run under a time
//! limit.

use std::ffi::OsStr;
use std::io::Read;
use std::path::Path;
use std::process::{Command, ExitStatus, Output, Stdio};
use std::time::{Duration, Instant};

/// Panics with the exit code and stderr of `out` unless the run exited 0.
#[track_caller]
pub fn assert_ok(out: &Output) {
    assert!(
        out.status.success(),
        "exit code {:?}; stderr:\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// What a run of the binary under a time limit did.
pub struct LimitedRun {
    /// How it ended.
    pub status: ExitStatus,
    /// Everything it wrote to stderr.
    pub stderr: String,
    /// Wall time from start to exit.
    pub elapsed: Duration,
}

/// The binary under test: `lumis`, or `lumis-lab` where these helpers serve lab's tests.
pub fn binary() -> &'static str {
    option_env!("CARGO_BIN_EXE_lumis")
        .or(option_env!("CARGO_BIN_EXE_lumis-lab"))
        .expect("built as a test of the lumis or lumis-lab package")
}

/// Runs `lumis ARGS` in `dir` with no stdin and stdout discarded. `None` when it was still
/// running after `limit` (it is then killed): a hang is a test failure, not a stuck test run.
pub fn run_limited<S: AsRef<OsStr>>(dir: &Path, args: &[S], limit: Duration) -> Option<LimitedRun> {
    let start = Instant::now();
    let mut child = Command::new(binary())
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read stderr on a thread so a chatty child cannot block on a full pipe.
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = pipe.read_to_string(&mut s);
        s
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Some(LimitedRun {
        status,
        stderr: reader.join().unwrap(),
        elapsed: start.elapsed(),
    })
}

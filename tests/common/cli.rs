//! Running the lumis binary from a test: one check that a run succeeded, which shows the
//! run's stderr when it did not (the message a user would have seen).

use std::process::Output;

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

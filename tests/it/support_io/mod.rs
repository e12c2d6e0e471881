//! Shared by `non_regular_files` and `output_safety`: running the binary with a time limit (a
//! hang is a failure, not a stuck test run), small scene files, and listings and snapshots of
//! directories.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};
use std::time::Duration;

/// What a run of the binary did.
pub struct Run {
    pub status: ExitStatus,
    pub stderr: String,
    pub elapsed: Duration,
}

impl Run {
    /// Fails unless the run failed cleanly with a message containing every one of `parts`.
    pub fn assert_error(&self, parts: &[&str]) {
        assert!(!self.status.success(), "accepted; stderr: {}", self.stderr);
        self.assert_says(parts);
    }

    /// Fails unless stderr contains every one of `parts` and no panic.
    pub fn assert_says(&self, parts: &[&str]) {
        assert!(!self.stderr.contains("panicked"), "{}", self.stderr);
        for p in parts {
            assert!(self.stderr.contains(p), "no {p:?} in: {}", self.stderr);
        }
    }

    /// Fails unless the run succeeded.
    pub fn assert_ok(&self) {
        assert!(self.status.success(), "failed: {}", self.stderr);
        assert!(!self.stderr.contains("panicked"), "{}", self.stderr);
    }
}

/// Runs `lumis ARGS` in `dir` with no stdin; kills it and fails the test after `limit`.
pub fn lumis_in(dir: &Path, args: &[&str], limit: Duration) -> Run {
    let run = crate::common::cli::run_limited(dir, args, limit)
        .unwrap_or_else(|| panic!("lumis {args:?} hung: killed after {limit:?}"));
    Run {
        status: run.status,
        stderr: run.stderr,
        elapsed: run.elapsed,
    }
}

/// [`lumis_in`] with a 10 s limit (a render of the scenes here takes well under a second).
pub fn lumis(dir: &Path, args: &[&str]) -> Run {
    lumis_in(dir, args, Duration::from_secs(10))
}

/// Makes a FIFO at `path` with coreutils' `mkfifo` (no FFI in the tests).
pub fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
    assert!(ok, "mkfifo {}", path.display());
}

/// A tiny TOML scene: one sphere, 8x8 pixels, one sample; `extra` appended.
pub fn toml_scene(extra: &str) -> String {
    format!(
        "[render]\nwidth = 8\nheight = 8\nspp = 1\n\n[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\n\
         [[sphere]]\ncenter = [0.0, 0.0, -3.0]\nradius = 1.0\nmaterial = \"m\"\n\n{extra}"
    )
}

/// The names in `dir`, sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The temporary files lumis leaves (it must leave none) under `dir`, recursively.
pub fn temps_under(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if e.file_type().unwrap().is_dir() {
            found.extend(temps_under(&p));
        } else if e.file_name().to_string_lossy().starts_with(".lumis-") {
            found.push(p);
        }
    }
    found
}

/// An `(N, 8)` float32 `.npy` of rays along -z from z = 5, one per x offset.
pub fn rays_npy(xs: &[f32]) -> Vec<u8> {
    let mut header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({}, 8), }}",
        xs.len()
    );
    // Magic, version 1.0, header length; the header is padded to a multiple of 64 with '\n'.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    for &x in xs {
        for v in [x, 0.0, 5.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY] {
            bytes.extend(v.to_le_bytes());
        }
    }
    bytes
}

/// Everything under `dir`: each entry's kind, a link's target, a file's bytes.
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, String> {
    let mut all = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        let t = e.file_type().unwrap();
        let what = if t.is_symlink() {
            format!("-> {}", std::fs::read_link(&p).unwrap().display())
        } else if t.is_fifo() {
            "FIFO".to_string()
        } else if t.is_dir() {
            all.extend(snapshot(&p));
            "directory".to_string()
        } else {
            format!("{:?}", std::fs::read(&p).unwrap())
        };
        all.insert(p, what);
    }
    all
}

//! `lumis render --tile I/N` and `lumis merge` (issue 15), end to end through the binary: the
//! merge of every split is the single render's file byte for byte (channels and header), for
//! several tile counts, thread counts, scenes and layers; and tiles that do not belong
//! together are refused with an error naming the tile.

mod hostile;
mod identical;
mod refused;

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::cli::assert_ok;

/// `lumis ARGS` run in `dir`.
pub fn lumis(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// Renders `scene_args` in one go to `NAME_full.exr`.
pub fn render_full(dir: &Path, name: &str, scene_args: &[&str]) -> PathBuf {
    let full = format!("{name}_full.exr");
    let mut args = vec!["render", "-q", "--threads", "2", "-o", &full];
    args.extend_from_slice(scene_args);
    assert_ok(&lumis(dir, &args));
    dir.join(full)
}

/// Renders `scene_args` as `n` tiles `NAME_I.exr`, the thread count varying from tile to tile;
/// returns the tile paths in reverse order, so that the merge cannot rely on the order given.
pub fn render_tiles(dir: &Path, name: &str, n: u32, scene_args: &[&str]) -> Vec<PathBuf> {
    let mut tiles = Vec::new();
    for i in 0..n {
        let spec = format!("{i}/{n}");
        let out = format!("{name}_{i}.exr");
        let threads = (i % 3 + 1).to_string();
        let mut args = vec![
            "render",
            "-q",
            "--tile",
            &spec,
            "--threads",
            &threads,
            "-o",
            &out,
        ];
        args.extend_from_slice(scene_args);
        assert_ok(&lumis(dir, &args));
        tiles.push(dir.join(out));
    }
    tiles.reverse();
    tiles
}

/// `lumis merge TILES -o out`.
pub fn merge(dir: &Path, tiles: &[PathBuf], out: &str) -> Output {
    let mut args: Vec<&str> = vec!["merge", "-q", "-o", out];
    args.extend(tiles.iter().map(|p| p.to_str().unwrap()));
    lumis(dir, &args)
}

/// Stderr of a run that must have failed cleanly: exit code 1, no panic.
#[track_caller]
pub fn refused(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

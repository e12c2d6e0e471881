//! `lumis-lab load`: load time and peak memory of a generated large OBJ and GLB, each load
//! in a fresh child process (`lumis-lab load-one`) so that every peak belongs to one load.

pub mod files;

#[cfg(test)]
mod tests;

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::Path;

/// Options of `lumis-lab load`.
#[derive(Args, Debug)]
pub struct LoadArgs {
    /// Triangles in the generated meshes (rounded to a square grid).
    #[arg(long, default_value_t = 1_000_000)]
    triangles: u32,
    /// Loads per format; the median time and the largest peak memory are reported.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
}

/// Generates a large OBJ and GLB, then loads each in fresh child processes (`bench load-one`)
/// so that every peak-memory reading belongs to one load alone.
pub fn run(args: &LoadArgs) -> Result<()> {
    let n = ((args.triangles as f64 / 2.0).sqrt().ceil() as u32).max(1);
    let dir = tempfile::tempdir().context("creating a temporary folder")?;
    let exe = std::env::current_exe().context("finding the lumis-lab executable")?;
    let tiny = dir.path().join("tiny.obj");
    files::write_obj(&tiny, 1)?;
    let baseline = load_in_child(&exe, &tiny)?;
    println!(
        "{} triangles per mesh; baseline process (a 2-triangle OBJ): {:.1} MiB peak\n",
        2 * n * n,
        baseline.1 as f64 / (1 << 20) as f64
    );
    println!(
        "| format | file size | load time (median of {}) | triangles/s | peak memory | peak over baseline |",
        args.repeat
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for (ext, write) in [
        (
            "obj",
            files::write_obj as fn(&Path, u32) -> std::io::Result<()>,
        ),
        ("glb", files::write_glb),
    ] {
        let file = dir.path().join(format!("grid.{ext}"));
        write(&file, n).with_context(|| format!("writing {}", file.display()))?;
        let size = std::fs::metadata(&file)?.len();
        let mut runs = (0..args.repeat.max(1))
            .map(|_| load_in_child(&exe, &file))
            .collect::<Result<Vec<_>>>()?;
        runs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let median = runs[runs.len() / 2].0;
        let peak = runs.iter().map(|r| r.1).max().unwrap_or(0);
        let mib = |b: u64| b as f64 / (1 << 20) as f64;
        println!(
            "| {ext} | {:.1} MiB | {median:.3} s | {:.2} M | {:.1} MiB | {:.1} MiB |",
            mib(size),
            2.0 * (n as f64).powi(2) / median / 1e6,
            mib(peak),
            mib(peak.saturating_sub(baseline.1))
        );
    }
    Ok(())
}

/// Runs `lumis-lab load-one FILE`; returns (seconds, peak bytes).
fn load_in_child(exe: &Path, file: &Path) -> Result<(f64, u64)> {
    let out = std::process::Command::new(exe)
        .args(["load-one"])
        .arg(file)
        .output()?;
    if !out.status.success() {
        bail!(
            "loading {} failed: {}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let mut words = text.split_whitespace();
    let seconds = words.next().and_then(|w| w.parse().ok());
    let peak = words.next().and_then(|w| w.parse().ok());
    match (seconds, peak) {
        (Some(s), Some(p)) => Ok((s, p)),
        _ => bail!("unexpected output from load-one: {text}"),
    }
}

/// `bench load-one FILE`: loads one file and prints "seconds peak_bytes".
pub fn run_one(file: &Path) -> Result<()> {
    let start = std::time::Instant::now();
    let scene = lumis_io::formats::load(file)?;
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(&scene);
    println!("{seconds} {}", files::peak_rss_bytes().unwrap_or(0));
    Ok(())
}

//! `lumis-lab instances`: memory, load+build time and render time of one model placed 1 to
//! 100,000 times, flattened into copies (where they fit) against instanced (one mesh, one
//! hierarchy, a top level over the placements). Each measurement runs in a fresh child process
//! (`lumis-lab instances-one`) so that every peak-memory reading belongs to one scene alone.

mod one;

pub use one::{InstancesOneArgs, run_one};

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::{Path, PathBuf};

/// Options of `lumis-lab instances`.
#[derive(Args, Debug)]
pub struct InstancesArgs {
    /// Model files to place (any format lumis loads; every mesh of the file is placed).
    #[arg(required = true)]
    models: Vec<PathBuf>,
    /// Placement counts.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 100, 10_000, 100_000])]
    counts: Vec<usize>,
    /// Flattened scenes above this many triangles are not built (they would not fit).
    #[arg(long, default_value_t = 40_000_000)]
    max_flat_triangles: u64,
    /// Render size for the render-time column (`WxH`); renders only for counts up to
    /// `--render-up-to`.
    #[arg(long, default_value = "320x180")]
    render: String,
    /// Largest count that is also rendered.
    #[arg(long, default_value_t = 100)]
    render_up_to: usize,
    /// Measurements per cell; the median time and the largest peak are reported.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
}

/// One child's measurement.
#[derive(Clone, Copy, Debug)]
struct Measured {
    build: f64,
    bytes: u64,
    peak: u64,
    render: f64,
    triangles: u64,
}

/// Runs every (model, count, mode) cell in interleaved rounds of child processes and prints
/// the markdown table.
pub fn run(args: &InstancesArgs) -> Result<()> {
    let exe = std::env::current_exe().context("finding the lumis-lab executable")?;
    println!(
        "| model | placements | mode | triangles traced | load+build (median of {}) | scene bytes | bytes per placement | peak RSS | render {} (median) |",
        args.repeat, args.render
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|");
    for model in &args.models {
        let mesh_triangles = one::model_triangles(model)?;
        for &count in &args.counts {
            let mut modes = vec!["instanced"];
            if mesh_triangles * count as u64 <= args.max_flat_triangles {
                modes.push("flattened");
            }
            let render = (count <= args.render_up_to).then_some(args.render.as_str());
            let mut runs: Vec<Vec<Measured>> = vec![Vec::new(); modes.len()];
            for round in 0..args.repeat.max(1) {
                // Alternate which mode goes first, so drift favours neither.
                for k in 0..modes.len() {
                    let i = if round % 2 == 0 {
                        k
                    } else {
                        modes.len() - 1 - k
                    };
                    runs[i].push(child(&exe, model, count, modes[i], render)?);
                }
            }
            for (mode, mut r) in modes.iter().zip(runs) {
                let median = |f: fn(&Measured) -> f64, r: &mut Vec<Measured>| {
                    r.sort_by(|a, b| f(a).total_cmp(&f(b)));
                    f(&r[r.len() / 2])
                };
                let build = median(|m| m.build, &mut r);
                let render_s = median(|m| m.render, &mut r);
                let m = r[0];
                let peak = r.iter().map(|m| m.peak).max().unwrap_or(0);
                let per = m.bytes as f64 / count as f64;
                let mib = |b: u64| b as f64 / (1 << 20) as f64;
                println!(
                    "| {} | {count} | {mode} | {} | {build:.3} s | {:.1} MiB | {} | {:.0} MiB | {} |",
                    crate::file_name(model),
                    m.triangles,
                    mib(m.bytes),
                    if per >= 1e4 {
                        format!("{:.1} KiB", per / 1024.0)
                    } else {
                        format!("{per:.0} B")
                    },
                    mib(peak),
                    if render.is_some() {
                        format!("{render_s:.3} s")
                    } else {
                        "-".into()
                    }
                );
            }
        }
    }
    Ok(())
}

/// Runs `lumis-lab instances-one` once.
fn child(
    exe: &Path,
    model: &Path,
    count: usize,
    mode: &str,
    render: Option<&str>,
) -> Result<Measured> {
    let mut cmd = std::process::Command::new(exe);
    cmd.arg("instances-one")
        .arg(model)
        .args(["--count", &count.to_string(), "--mode", mode]);
    if let Some(r) = render {
        cmd.args(["--render", r]);
    }
    let out = cmd.output()?;
    if !out.status.success() {
        bail!(
            "{} x{count} {mode} failed: {}",
            model.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let v: Vec<f64> = text
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    let [build, bytes, peak, render, triangles] = v[..] else {
        bail!("unexpected output from instances-one: {text}");
    };
    Ok(Measured {
        build,
        bytes: bytes as u64,
        peak: peak as u64,
        render,
        triangles: triangles as u64,
    })
}

//! `lumis-lab accuracy`: what each accuracy knob (samples, depth, cutoff, precision, offset)
//! buys in error for what it costs in time, one axis at a time from the defaults.
//!
//! Every point is rendered in the same run as the defaults and the converged reference, so
//! time ratios and errors are comparable within a scene whatever the machine's speed.

pub mod metrics;
pub mod plot;
pub mod report;
pub mod scenes;
pub mod sweep;

use super::outputs::BenchOutputs;
use anyhow::{Result, bail};
use clap::Args;
use report::{csv, markdown, summarise};
use std::path::{Path, PathBuf};

/// Options of `lumis-lab accuracy`.
#[derive(Args, Debug)]
pub struct AccuracyArgs {
    /// Scenes: files, paper scene names (looked up in --paper-scenes), or the built-ins
    /// `default`, `far-occluder`, `far-spheres`. Default: the default scene, allMaterials,
    /// texturesInYoFace, tumbledStones, assets/knot.obj, far-occluder and far-spheres.
    scenes: Vec<String>,
    /// Folder holding the paper's .scn files.
    #[arg(long, default_value = "../shared/paper-scenes/scenes")]
    paper_scenes: PathBuf,
    /// Image width of every render.
    #[arg(long, default_value_t = 160)]
    width: u32,
    /// Image height of every render.
    #[arg(long, default_value_t = 90)]
    height: u32,
    /// Timed rounds (the outer loop; each renders every point once); the median is kept.
    #[arg(long, default_value_t = 3)]
    rounds: usize,
    /// Render threads (default, and 0: one per core; more than 4 per core are capped).
    #[arg(long)]
    threads: Option<usize>,
    /// Write every scene's rows here as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the error-vs-time plot here (.png or .svg).
    #[arg(long)]
    plot: Option<PathBuf>,
}

/// Sweeps every accuracy knob on every scene, prints the summary table and writes CSV/plot.
pub fn run(args: &AccuracyArgs) -> Result<()> {
    if args.width == 0 || args.height == 0 || args.rounds == 0 {
        bail!("--width, --height and --rounds must be at least 1");
    }
    let outputs = BenchOutputs::prepare(&[
        ("--csv", args.csv.as_deref()),
        ("--plot", args.plot.as_deref()),
    ])?;
    let plot_format = args.plot.as_deref().map(plot::plot_format).transpose()?;
    let list = outputs.load(|| {
        if args.scenes.is_empty() {
            scenes::default_set(&args.paper_scenes)
        } else {
            args.scenes
                .iter()
                .map(|s| scenes::resolve(s, &args.paper_scenes))
                .collect()
        }
    })?;
    let opts = sweep::SweepOptions {
        width: args.width,
        height: args.height,
        rounds: args.rounds,
        threads: crate::worker_threads(args.threads),
    };
    let start = std::time::Instant::now();
    let mut rows = Vec::new();
    for s in &list {
        let t = std::time::Instant::now();
        let r = sweep::sweep_scene(s, &opts)?;
        eprintln!(
            "{:<22} {} points in {:.1} s",
            s.name,
            r.len(),
            t.elapsed().as_secs_f64()
        );
        rows.extend(r);
    }
    let summary = summarise(&rows);
    println!(
        "Accuracy sweep at {}x{}, {} rounds, {} scenes ({:.1} s); geometric means over scenes:\n",
        args.width,
        args.height,
        args.rounds,
        list.len(),
        start.elapsed().as_secs_f64()
    );
    println!("{}", markdown(&summary));
    let text = csv(&rows);
    if args.csv.is_none() {
        println!("CSV:\n\n{text}");
    }
    let title = format!(
        "lumis accuracy knobs: {} scenes at {}x{}",
        list.len(),
        args.width,
        args.height
    );
    let plot = match args.plot.as_deref().zip(plot_format) {
        Some((path, format)) => Some((path, plot::encode_plot(&summary, &title, format)?)),
        None => None,
    };
    // Both files, or (if either fails) neither.
    let mut files: Vec<(&Path, &[u8])> = Vec::new();
    if let Some(path) = &args.csv {
        files.push((path, text.as_bytes()));
    }
    if let Some((path, bytes)) = &plot {
        files.push((path, bytes));
    }
    outputs.write(&files)
}

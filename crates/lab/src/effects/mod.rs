//! `lumis-lab effects`: what the effect decisions save, per scene: the default render against
//! `--effects all` in the same run.

pub mod measure;

#[cfg(test)]
mod tests;

use super::outputs::BenchOutputs;
use super::paper::table::table_i_files;
use crate::file_name;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;

/// Options of `lumis-lab effects`.
#[derive(Args, Debug)]
pub struct EffectsArgs {
    /// Scene files; with none, the built-in default scene and the paper's Table I scenes.
    scenes: Vec<PathBuf>,
    /// Folder of the paper's .scn files (used when no scene is given).
    #[arg(long, default_value = "../shared/paper-scenes/scenes")]
    paper_scenes: PathBuf,
    /// Image width for every scene.
    #[arg(long, default_value_t = 320)]
    width: u32,
    /// Image height for every scene.
    #[arg(long, default_value_t = 180)]
    height: u32,
    /// Timed rounds per mode (interleaved); the median is reported.
    #[arg(long, default_value_t = 3)]
    rounds: usize,
    /// Worker threads (default, and 0: one per core; more than 4 per core are capped).
    #[arg(long)]
    threads: Option<usize>,
    /// Measure a PNG-only render (no AOV rays) instead of an EXR one.
    #[arg(long)]
    png_only: bool,
    /// Write the CSV here as well as printing it.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// Default decisions against `--effects all` on every scene, same run, interleaved rounds.
pub fn run(args: &EffectsArgs) -> Result<()> {
    let outputs = BenchOutputs::prepare(&[("--csv", args.csv.as_deref())])?;
    let scenes = outputs.load(|| load_scenes(args))?;
    let threads = crate::worker_threads(args.threads);
    let mut rows = Vec::new();
    for (name, mut scene) in scenes {
        let st = scene.settings_mut();
        (st.width, st.height) = (args.width, args.height);
        let row = measure::measure_effects(&scene, &name, args.rounds, threads, !args.png_only)
            .with_context(|| name.clone())?;
        eprintln!(
            "{name:<24} default {:>8.3} s  all {:>8.3} s  ({:.2}x)",
            row.auto_seconds,
            row.all_seconds,
            row.all_seconds / row.auto_seconds.max(1e-9)
        );
        rows.push(row);
    }
    println!(
        "Effects at {}x{}, each scene's own samples, depth and cutoff, {} output, median of {} \
         interleaved rounds (render seconds); rays as default / all:\n",
        args.width,
        args.height,
        if args.png_only { "PNG-only" } else { "EXR" },
        args.rounds
    );
    println!("{}", measure::markdown(&rows));
    println!(
        "Rays the default did not trace, by reason:\n\n{}",
        measure::reasons_markdown(&rows)
    );
    let text = measure::csv(&rows);
    println!("CSV:\n\n{text}");
    if let Some(path) = &args.csv {
        outputs.write(&[(path, text.as_bytes())])?;
    }
    Ok(())
}

/// The scenes given, or the default scene and the paper's Table I scenes, with their names.
fn load_scenes(args: &EffectsArgs) -> Result<Vec<(String, lumis_core::scene::Scene)>> {
    let mut scenes = Vec::new();
    if args.scenes.is_empty() {
        scenes.push(("default".into(), lumis_io::formats::default_scene()?));
        for f in table_i_files(&args.paper_scenes) {
            scenes.push((file_name(&f), lumis_io::formats::load(&f)?));
        }
    } else {
        for f in &args.scenes {
            let scene =
                lumis_io::formats::load(f).with_context(|| format!("loading {}", f.display()))?;
            scenes.push((file_name(f), scene));
        }
    }
    Ok(scenes)
}

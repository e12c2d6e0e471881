//! `lumis-lab paper`: runs the paper's Table I and prints it as Markdown and CSV.

pub mod table;

use super::outputs::BenchOutputs;
use crate::file_name;
use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::PathBuf;
use table::{csv, markdown_table, measure, paper_configs, table_i_files, work_table};

/// Options of `lumis-lab paper`.
#[derive(Args, Debug)]
pub struct PaperArgs {
    /// Folder holding the paper's .scn files.
    #[arg(long, default_value = "../shared/paper-scenes/scenes")]
    scenes: PathBuf,
    /// Resolution scale: 1920x1080 times this.
    #[arg(long, default_value_t = 1.0)]
    scale: f32,
    /// Runs per cell; the median is reported.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
    /// Write the CSV here as well as printing it.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Only scenes whose file name contains this.
    #[arg(long)]
    only: Option<String>,
    /// Only these configurations (comma-separated labels, e.g. "bsp (baseline),bsp exhaustive").
    #[arg(long, value_delimiter = ',')]
    configs: Vec<String>,
}

/// Renders every Table I scene under every configuration and prints the tables.
pub fn run(args: &PaperArgs) -> Result<()> {
    if !(args.scale > 0.0 && args.scale <= 4.0) {
        bail!("--scale must be in (0, 4]");
    }
    let outputs = BenchOutputs::prepare(&[("--csv", args.csv.as_deref())])?;
    let files: Vec<PathBuf> = table_i_files(&args.scenes)
        .into_iter()
        .filter(|f| {
            args.only
                .as_ref()
                .is_none_or(|o| f.to_string_lossy().contains(o.as_str()))
        })
        .collect();
    if files.is_empty() {
        bail!(
            "{}: none of the paper's Table I scenes found there",
            args.scenes.display()
        );
    }
    let (w, h) = (
        ((1920.0 * args.scale).round() as u32).max(1),
        ((1080.0 * args.scale).round() as u32).max(1),
    );
    let configs: Vec<_> = paper_configs()
        .into_iter()
        .filter(|c| args.configs.is_empty() || args.configs.iter().any(|l| l == c.label))
        .collect();
    if configs.is_empty() {
        bail!(
            "--configs matches none of: {}",
            paper_configs()
                .iter()
                .map(|c| c.label)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    // Every scene is loaded before the first measurement, so that a --csv naming one of their
    // files is refused before the measuring, not after it.
    let scenes = outputs.load(|| {
        files
            .iter()
            .map(|f| Ok((file_name(f), lumis_io::formats::load(f)?)))
            .collect::<Result<Vec<_>>>()
    })?;
    let mut rows = Vec::new();
    for (name, mut scene) in scenes {
        // The paper's settings: 1 sample per pixel, 5 depth-of-field rays (the loader's defaults).
        let st = scene.settings_mut();
        (st.width, st.height, st.spp, st.lens_samples) = (w, h, 1, 5);
        for config in &configs {
            let m = measure(&scene, &name, config, args.repeat, None)
                .with_context(|| format!("{name}: {}", config.label))?;
            eprintln!(
                "{name:<24} {:<16} {:>9.3} s  {:>7.2} nodes/ray {:>7.2} prims/ray",
                m.config, m.seconds, m.nodes_per_ray, m.prims_per_ray
            );
            rows.push(m);
        }
    }
    println!(
        "Table I at {w}x{h}, 1 sample, 5 DOF rays, median of {} runs (build + render seconds):\n",
        args.repeat
    );
    println!("{}", markdown_table(&rows, &configs));
    println!("Work per ray:\n\n{}", work_table(&rows));
    let text = csv(&rows);
    println!("CSV:\n\n{text}");
    if let Some(path) = &args.csv {
        outputs.write(&[(path, text.as_bytes())])?;
    }
    Ok(())
}

//! `lumis-lab`: the research and benchmark commands, one module per subcommand: the paper's
//! Table I (with its measuring-only traversal, `Traversal::SegmentsOriginalRule`), load time
//! and memory, the accuracy sweep with its plot, and what the effect decisions save. A
//! separate binary so that the `lumis` command and the libraries carry none of it (plotters,
//! the wrong-answer traversal).

pub mod accuracy;
pub mod effects;
pub mod instances;
pub mod load;
mod outputs;
pub mod paper;

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

/// lumis-lab: benchmarks and accuracy studies of lumis.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Lab {
    #[command(subcommand)]
    command: BenchCommand,
}

/// The `lumis-lab` subcommands.
#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// The paper's Table I: every scene under bsp, bsmp and sah with and without scale lights.
    Paper(paper::PaperArgs),
    /// Load time and peak memory for a generated >= 1M-triangle OBJ and GLB.
    Load(load::LoadArgs),
    /// Error against a converged reference vs render time for every accuracy knob, one axis
    /// at a time from the defaults; CSV and a plot.
    Accuracy(accuracy::AccuracyArgs),
    /// What the effect decisions save: time and rays by kind of the default render against
    /// `--effects all`, per scene, in the same run.
    Effects(effects::EffectsArgs),
    /// Memory, load+build and render time of a model placed 1 to 100,000 times, flattened
    /// against instanced.
    Instances(instances::InstancesArgs),
    /// One scene of placements, for `instances`' child processes.
    #[command(hide = true)]
    InstancesOne(instances::InstancesOneArgs),
    /// One load, for `bench load`'s child processes: prints seconds and peak bytes.
    #[command(hide = true)]
    LoadOne {
        /// The file to load.
        file: PathBuf,
    },
}

fn main() {
    let lab = Lab::parse();
    if let Err(e) = run(&lab.command) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

/// The worker count for `--threads` (see `lumis_core::render::worker_threads`), its warning
/// printed on stderr.
fn worker_threads(requested: Option<usize>) -> Option<usize> {
    let (count, warning) = lumis_core::render::worker_threads(requested);
    if let Some(w) = warning {
        eprintln!("warning: {w}");
    }
    count
}

/// Runs one benchmark.
fn run(command: &BenchCommand) -> Result<()> {
    match command {
        BenchCommand::Paper(args) => paper::run(args),
        BenchCommand::Load(args) => load::run(args),
        BenchCommand::Accuracy(args) => accuracy::run(args),
        BenchCommand::Effects(args) => effects::run(args),
        BenchCommand::LoadOne { file } => load::run_one(file),
        BenchCommand::Instances(args) => instances::run(args),
        BenchCommand::InstancesOne(args) => instances::run_one(args),
    }
}

/// A scene's name in the tables: its file name.
fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

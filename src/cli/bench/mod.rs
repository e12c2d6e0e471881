//! `lumis bench ...`: the benchmarks, one module per subcommand.

pub mod accuracy;
pub mod effects;
pub mod load;
mod outputs;
pub mod paper;

use anyhow::Result;
use clap::Subcommand;
use std::path::{Path, PathBuf};

/// The `lumis bench` subcommands.
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
    /// One load, for `bench load`'s child processes: prints seconds and peak bytes.
    #[command(hide = true)]
    LoadOne {
        /// The file to load.
        file: PathBuf,
    },
}

/// Runs one benchmark.
pub fn run(command: &BenchCommand) -> Result<()> {
    match command {
        BenchCommand::Paper(args) => paper::run(args),
        BenchCommand::Load(args) => load::run(args),
        BenchCommand::Accuracy(args) => accuracy::run(args),
        BenchCommand::Effects(args) => effects::run(args),
        BenchCommand::LoadOne { file } => load::run_one(file),
    }
}

/// A scene's name in the tables: its file name.
fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

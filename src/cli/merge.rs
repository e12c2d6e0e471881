//! `lumis merge TILE.exr... -o FULL.exr`: the tiles of a farm render (`lumis render --tile`)
//! assembled into the image a single render writes (see `lumis::farm`).

use anyhow::{Result, bail};
use clap::Args;
use lumis::formats::{InputFile, file_id};
use lumis::output::{PlannedOutput, StagedOutputs, prepare_outputs};
use std::path::PathBuf;
use std::time::Instant;

/// Options of `lumis merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The tiles, written by `lumis render --tile I/N` (in any order): every tile 0..N-1 of
    /// one render, each once.
    #[arg(required = true, value_name = "TILE.exr")]
    tiles: Vec<PathBuf>,
    /// The merged EXR (written atomically: an existing file is replaced only by a complete one).
    #[arg(short, long, value_name = "FULL.exr")]
    output: PathBuf,
    /// No summary.
    #[arg(short, long)]
    quiet: bool,
}

/// Checks, merges and writes.
pub fn run(args: &MergeArgs) -> Result<()> {
    let t = Instant::now();
    let is_exr = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if !is_exr {
        bail!(
            "-o {}: the merged image is an EXR; give a file name ending in .exr",
            args.output.display()
        );
    }
    // Before any tile is decoded: a missing directory, or an output that is one of the tiles,
    // fails at once.
    let inputs: Vec<InputFile> = args.tiles.iter().map(|p| input_file(p.clone())).collect();
    let planned = [PlannedOutput {
        flag: "-o",
        path: &args.output,
    }];
    prepare_outputs(&planned, &inputs)?;
    let merged = lumis::farm::merge_tiles(&args.tiles)?;
    let mut staged = StagedOutputs::new();
    staged.stage_bytes(&args.output, &merged.bytes)?;
    staged.commit()?;
    if !args.quiet {
        let (w, h) = merged.size;
        let exposure = if merged.auto_exposure {
            format!("auto exposure {:+.2} EV", merged.exposure)
        } else {
            format!("exposure {:+.2} EV", merged.exposure)
        };
        eprintln!(
            "merged {} tiles into {} ({w}x{h}, {exposure}) in {:.3} s",
            merged.tiles,
            args.output.display(),
            t.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

/// A tile as an input of the run, so that `-o` cannot name one of them (also through a link).
fn input_file(path: PathBuf) -> InputFile {
    let id = std::fs::metadata(&path).ok().as_ref().and_then(file_id);
    let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
    InputFile {
        path,
        canonical,
        id,
    }
}

//! `lumis merge TILE.exr... -o FULL.exr`: the tiles of a farm render (`lumis render --tile`)
//! assembled into the film a single render makes and developed as `lumis render` develops it
//! (see `lumis_io::farm::merge`).

use super::values::{DisplayArg, TonemapArg};
use anyhow::{Result, bail};
use clap::Args;
use lumis_core::film::{DisplayTransform, Tonemap};
use lumis_io::files::{InputFile, file_id};
use lumis_io::output::{PlannedOutput, StagedOutputs, prepare_outputs};
use std::path::{Path, PathBuf};
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
    /// Also write a PNG preview, as `lumis render --png` would have (byte for byte, with the
    /// same --tonemap and --display).
    #[arg(long, value_name = "FILE.png")]
    png: Option<PathBuf>,
    /// The PNG's tone curve (as `lumis render --tonemap`).
    #[arg(long, value_enum, default_value_t = TonemapArg::None, requires = "png")]
    tonemap: TonemapArg,
    /// The PNG's display transform; default: the render's (its scene's `display`, recorded in
    /// the tiles).
    #[arg(long, value_enum, requires = "png")]
    display: Option<DisplayArg>,
    /// No summary.
    #[arg(short, long)]
    quiet: bool,
}

/// Checks, merges and writes.
pub fn run(args: &MergeArgs) -> Result<()> {
    let t = Instant::now();
    let has_extension = |p: &Path, ext: &str| {
        p.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    };
    if !has_extension(&args.output, "exr") {
        bail!(
            "-o {}: the merged image is an EXR; give a file name ending in .exr",
            args.output.display()
        );
    }
    if let Some(png) = args.png.as_deref().filter(|p| !has_extension(p, "png")) {
        bail!("--png {}: the file name must end in .png", png.display());
    }
    // Before any tile is decoded: a missing directory, or an output that is one of the tiles,
    // fails at once.
    let inputs: Vec<InputFile> = args.tiles.iter().map(|p| input_file(p.clone())).collect();
    let mut planned = vec![PlannedOutput {
        flag: "-o",
        path: &args.output,
    }];
    if let Some(png) = &args.png {
        planned.push(PlannedOutput {
            flag: "--png",
            path: png,
        });
    }
    prepare_outputs(&planned, &inputs)?;
    let mut merged = lumis_io::farm::merge_tiles(&args.tiles)?;
    // The same develop step as `lumis render`, on the film rebuilt from the tiles.
    let mut paths: Vec<&Path> = vec![&args.output];
    paths.extend(args.png.as_deref());
    let display = args.display.map(DisplayTransform::from);
    let developed = merged.develop(&paths, Tonemap::from(args.tonemap), display)?;
    let mut staged = StagedOutputs::new();
    for (path, bytes) in &developed.images {
        staged.stage_bytes(path, bytes)?;
    }
    staged.commit()?;
    if !args.quiet {
        let (w, h) = merged.film.full_size();
        let exposure = if developed.auto_exposure {
            format!("auto exposure {:+.2} EV", developed.exposure)
        } else {
            format!("exposure {:+.2} EV", developed.exposure)
        };
        eprintln!(
            "merged {} tiles into {} ({w}x{h}, {exposure}) in {:.3} s",
            merged.tiles,
            args.output.display(),
            t.elapsed().as_secs_f64()
        );
        if let Some(png) = &args.png {
            eprintln!("wrote {}", png.display());
        }
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

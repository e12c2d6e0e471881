//! `lumis hits SCENE --rays rays.npy --out hits.npy`: batch ray queries for cross-checks
//! (formats in `lumis::hits`).

use anyhow::{Context, Result};
use clap::Args;
use lumis::hits::{read_rays, trace_rays, triangle_rows, write_rows};
use std::path::PathBuf;

/// Arguments of `lumis hits`.
#[derive(Args, Debug)]
pub struct HitsArgs {
    /// Scene file (.toml, .scn, .obj, .gltf or .glb).
    scene: PathBuf,
    /// Input rays: float32 .npy of shape (N, 8): origin xyz, direction xyz, t_min, t_max.
    #[arg(long)]
    rays: PathBuf,
    /// Output hits: float32 .npy of shape (N, 9): t, primitive id, object id, u, v, normal
    /// xyz, primitive kind (0 sphere, 1 triangle); misses have t = inf and ids/kind -1.
    #[arg(long)]
    out: PathBuf,
    /// Occlusion queries: t of the first blocker found (not necessarily the nearest) or inf;
    /// ids and kind are -1.
    #[arg(long)]
    any_hit: bool,
    #[command(flatten)]
    accel: crate::cli_accel::AccelArgs,
    /// Worker threads (default: all cores); the output is the same for any count.
    #[arg(long)]
    threads: Option<usize>,
    /// Also write every triangle as float32 .npy of shape (M, 10): primitive id, then the
    /// three world-space vertices.
    #[arg(long)]
    triangles_out: Option<PathBuf>,
}

/// Loads the scene and rays, traces them, writes the hits (and triangles).
pub fn run_hits(args: &HitsArgs) -> Result<()> {
    let scene = lumis::scene::load(&args.scene)?;
    let rays = read_rays(&args.rays)?;
    let accel = args
        .accel
        .validated()?
        .build(&scene.geometry().prim_bounds());
    let run = || trace_rays(&scene, &accel, &rays, args.any_hit);
    let hits = match args.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .with_context(|| format!("could not start {n} worker threads"))?
            .install(run),
        None => run(),
    };
    write_rows(&args.out, &hits)?;
    if let Some(path) = &args.triangles_out {
        write_rows(path, &triangle_rows(&scene))?;
    }
    Ok(())
}

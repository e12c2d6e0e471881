//! `lumis hits SCENE --rays rays.npy --out hits.npy`: batch ray queries for cross-checks
//! (formats in `lumis::hits`).

use anyhow::{Context, Result, bail};
use clap::Args;
use lumis::accel::{Accel, AccelKind, BuildOptions};
use lumis::hits::{read_rays, trace_rays, triangle_rows, write_rows};
use std::path::PathBuf;

use crate::TraversalKind;

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
    /// Acceleration structure.
    #[arg(long, value_enum, default_value_t = AccelKind::Sah)]
    accel: AccelKind,
    /// How the hierarchy is walked.
    #[arg(long, value_enum, default_value_t = TraversalKind::Ordered)]
    traversal: TraversalKind,
    /// First segment length of the segments traversal (world units).
    #[arg(long, default_value_t = 2.0)]
    segment_init: f32,
    /// Segments double up to this length, then one unbounded pass follows.
    #[arg(long, default_value_t = lumis::bench::PAPER_SEGMENT_MAX)]
    segment_max: f32,
    /// Largest leaf of the hierarchies (default: 4 for sah, 20 for bsp and bsmp).
    #[arg(long)]
    leaf_size: Option<usize>,
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
    let build = BuildOptions {
        max_leaf_size: args.leaf_size.unwrap_or(args.accel.default_leaf_size()),
    };
    if build.max_leaf_size == 0 {
        bail!("--leaf-size must be at least 1");
    }
    let traversal = args
        .traversal
        .with_params(args.segment_init, args.segment_max)?;
    let accel =
        Accel::build(args.accel, &scene.geometry().prim_bounds(), &build).with_traversal(traversal);
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

//! `lumis hits SCENE --rays rays.npy --out hits.npy`: batch ray queries for cross-checks and
//! for timing against other tracers (formats in [`records`]).

pub mod all;
pub mod records;

use super::accel::AccelArgs;
use super::accuracy::AccuracyArgs;
use all::{HitRows, Query};
use anyhow::{Context, Result, bail};
use clap::Args;
use lumis_io::files::record_inputs;
use lumis_io::output::{PlannedOutput, StagedOutputs, prepare_outputs};
use records::{read_rays, spawn_rows, sphere_rows, stage_rows, triangle_rows};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `lumis hits`.
#[derive(Args, Debug)]
pub struct HitsArgs {
    /// Scene file (.toml, .scn, .obj, .gltf or .glb).
    scene: PathBuf,
    /// glTF files: draw every placement of a mesh as its own world-space copy (also each
    /// EXT_mesh_gpu_instancing instance) instead of making a mesh placed twice or more one
    /// prototype with an instance per placement. Objects keep their names either way.
    #[arg(long)]
    flatten_instances: bool,
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
    /// Every hit along each ray instead of the nearest, each surface crossing counted once and
    /// touches that do not cross flagged as grazes: --out is then float32 .npy (M, 11), one row
    /// per hit: ray index, the nine columns above, graze flag (1 graze, 0 crossing); rows by ray,
    /// then t. Uses the exact triangle tests (--precision fast counts as watertight).
    #[arg(long, conflicts_with = "any_hit")]
    all: bool,
    /// Nearest hits with each group of 8 consecutive rays traced as one packet where the group
    /// shares an origin and the signs of its directions (as the renderer traces a pixel's
    /// samples; order a camera's rays by 4x2 tiles for this), else one ray at a time. The same
    /// hits, bit for bit; for timing the packet walk.
    #[arg(long, conflicts_with_all = ["any_hit", "all"])]
    packets: bool,
    /// Append one column to every --out row, the instance hit (index in the scene's instance
    /// list, float32 like the other ids; -1 for a miss, an any-hit answer or a surface of no
    /// instance): (N, 10), or with --all (M, 12) after the graze flag. The primitive id of an
    /// instance's hit is its prototype's primitive. Without the flag the rows are as before.
    #[arg(long)]
    instance_ids: bool,
    #[command(flatten)]
    accel: AccelArgs,
    #[command(flatten)]
    accuracy: AccuracyArgs,
    /// Also write, per ray, where a secondary ray leaving its hit would start under the
    /// --offset rule: float32 .npy (N, 6), the origin on the side the ray came from (xyz) and
    /// on the far side (xyz); inf for misses.
    #[arg(long)]
    spawn_out: Option<PathBuf>,
    /// Worker threads (default, and 0: one per core; more than 4 per core are capped); the
    /// output is the same for any count.
    #[arg(long)]
    threads: Option<usize>,
    /// Also write every triangle as float32 .npy of shape (M, 10): primitive id, then the
    /// three world-space vertices.
    #[arg(long)]
    triangles_out: Option<PathBuf>,
    /// Also write every sphere as float32 .npy of shape (K, 5): primitive id, centre xyz,
    /// radius.
    #[arg(long)]
    spheres_out: Option<PathBuf>,
    /// Trace the whole ray set this many times (for timing; the hits of the last run are
    /// written, and every run gives the same hits).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
    repeat: u32,
    /// Build the accelerator this many times (for timing; the last build is traced). A fresh
    /// process's first build also pays for the system handing it new memory (on this project's
    /// virtual machines ~1.6 ms per MB, a third of a million-triangle build), which a build in a
    /// process that has built before, as Embree's in tools/bench_embree.py, does not.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    rebuild: u32,
    /// Write the phase times and sizes as JSON: {"rays", "load_s", "build_s" (the first build),
    /// "build_runs_s": [one per build], "trace_s": [one per run], "prims", "geometry_bytes",
    /// "accel_bytes", "accel_parts": {"nodes", "leaf_order", "packed"}, "sah_cost"}.
    #[arg(long)]
    timings: Option<PathBuf>,
}

/// Loads the scene and rays, traces them, writes the hits (and triangles, spheres, timings).
pub fn run(args: &HitsArgs) -> Result<()> {
    let accel_kind = args.accel.validated()?;
    let outputs = planned_outputs(args)?;
    let start = Instant::now();
    // Every file read (the scene, what it references, the rays): no output may be one of them.
    let (scene, mut inputs) = record_inputs(|| {
        lumis_io::formats::load_with(
            &args.scene,
            &lumis_io::formats::LoadOptions {
                flatten_instances: args.flatten_instances,
                ..Default::default()
            },
        )
    });
    let mut scene = scene?;
    args.accuracy.apply(scene.settings_mut())?;
    scene
        .settings()
        .validate()
        .context("the settings after the command-line overrides")?;
    let load_s = start.elapsed().as_secs_f64();
    let (rays, ray_inputs) = record_inputs(|| read_rays(&args.rays));
    let rays = rays?;
    inputs.extend(ray_inputs);
    prepare_outputs(&outputs, &inputs)?;
    let query = match (args.all, args.any_hit, args.packets) {
        (true, _, _) => Query::All,
        (_, true, _) => Query::AnyHit,
        (_, _, true) => Query::Packets,
        _ => Query::Nearest,
    };
    // The build runs on the same workers as the tracing, so `--threads 1` builds on one thread.
    let run = || {
        let mut build_s = Vec::with_capacity(args.rebuild as usize);
        for _ in 1..args.rebuild {
            let copy = scene.clone();
            let start = Instant::now();
            let world = accel_kind.build(copy);
            build_s.push(start.elapsed().as_secs_f64());
            drop(world);
        }
        let start = Instant::now();
        let world = accel_kind.build(scene);
        build_s.push(start.elapsed().as_secs_f64());
        let mut hits = HitRows::Nearest(Vec::new());
        let mut trace_s = Vec::with_capacity(args.repeat as usize);
        for _ in 0..args.repeat {
            let start = Instant::now();
            hits = hits.retrace(&world, &rays, query);
            trace_s.push(start.elapsed().as_secs_f64());
        }
        (world, build_s, hits, trace_s)
    };
    let (world, build_s, hits, trace_s) = match super::threads::resolve(args.threads, false) {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .with_context(|| format!("could not start {n} worker threads"))?
            .install(run),
        None => run(),
    };
    // Every result goes to a temporary file first; they replace existing files only once all
    // were written.
    let mut staged = StagedOutputs::new();
    hits.stage(&mut staged, &args.out, args.instance_ids)?;
    if let Some(path) = &args.spawn_out {
        stage_rows(&mut staged, path, &spawn_rows(&world, &rays[..]))?;
    }
    if let Some(path) = &args.triangles_out {
        let instances = world.scene().geometry().instances().len();
        if instances > 0 {
            // The rows are the scene's own world-space triangles; an instance is one primitive
            // whose triangles live in its prototype.
            eprintln!(
                "warning: --triangles-out: the triangles of {instances} instances are not \
                 written; add --flatten-instances to write every placement's"
            );
        }
        stage_rows(&mut staged, path, &triangle_rows(world.scene()))?;
    }
    if let Some(path) = &args.spheres_out {
        stage_rows(&mut staged, path, &sphere_rows(world.scene()))?;
    }
    if let Some(path) = &args.timings {
        let memory = world.accel().memory();
        let json = serde_json::json!({
            "rays": rays.len(),
            "load_s": load_s,
            "build_s": build_s[0],
            "build_runs_s": build_s,
            "trace_s": trace_s,
            "prims": world.scene().geometry().prims().len(),
            "geometry_bytes": world.scene().geometry().bytes(),
            "accel_bytes": world.accel().bytes(),
            "accel_parts": {
                "nodes": memory.nodes,
                "leaf_order": memory.leaf_order,
                "packed": memory.packed,
            },
            "sah_cost": world.accel().sah_cost(),
        });
        staged.stage_bytes(path, format!("{json}\n").as_bytes())?;
    }
    staged.commit()?;
    Ok(())
}

/// The result files with the flag naming each; the arrays must be named `.npy`, so that a
/// slip such as `--out hits.toml` cannot replace a file of another kind.
fn planned_outputs(args: &HitsArgs) -> Result<Vec<PlannedOutput<'_>>> {
    let arrays = [
        ("--out", Some(&args.out)),
        ("--spawn-out", args.spawn_out.as_ref()),
        ("--triangles-out", args.triangles_out.as_ref()),
        ("--spheres-out", args.spheres_out.as_ref()),
    ];
    let mut outputs = Vec::new();
    for (flag, path) in arrays {
        let Some(path) = path else { continue };
        if !is_npy(path) {
            bail!(
                "{flag} {}: the file name must end in .npy (the output is a NumPy array)",
                path.display()
            );
        }
        outputs.push(PlannedOutput { flag, path });
    }
    if let Some(path) = &args.timings {
        outputs.push(PlannedOutput {
            flag: "--timings",
            path,
        });
    }
    Ok(outputs)
}

fn is_npy(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("npy"))
}

//! `lumis render [SCENE]` (also `lumis [SCENE]`): one scene to EXR and/or PNG, with the
//! settings the flags override and a summary of the run.

mod identity;
mod record;
mod replay;

use super::accel::AccelArgs;
use super::accuracy::{AccuracyArgs, CutoffArgs};
use super::environment::EnvironmentArgs;
use super::frame::{FrameArgs, NumberedOutputs};
use super::interrupt::{Interrupted, on_ctrl_c};
use super::overrides::OverrideArgs;
use super::passes::PassArgs;
use super::stats::{PhaseTimes, summary, summary_json};
use super::values::{DisplayArg, UpArg};
use super::window::WindowArgs;
use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use lumis_core::film::DisplayTransform;
use lumis_core::render::{CancelFlag, RenderOptions, render};
use lumis_core::scene::UpAxis;
use lumis_io::display::{DisplayServer, LiveView};
use lumis_io::files::record_inputs;
use lumis_io::output::{
    Develop, ExrCamera, ExrMetadata, PlannedOutput, StagedOutputs, TileHeader, develop,
    prepare_outputs,
};
use lumis_io::request::{SceneOrigin, SettingsFlags, check_exposure, exposure_to_apply};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Options of `lumis render` (and of `lumis` with no subcommand).
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (.toml, .scn, .obj, .gltf or .glb); the built-in default scene when omitted.
    scene: Option<PathBuf>,
    /// Output image; the format follows the extension (.exr or .png). Default: out.exr and out.png.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write a PNG preview here.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Image width (overrides the scene).
    #[arg(long)]
    width: Option<u32>,
    /// Image height (overrides the scene).
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel along each axis (not in all): N gives NxN stratified samples, so
    /// --spp 4 traces 16 camera rays per pixel; --samples gives a total instead.
    #[arg(long)]
    spp: Option<u32>,
    /// Maximum reflection/refraction depth.
    #[arg(long)]
    max_depth: Option<u32>,
    /// Worker threads (default, and 0: one per core); more than 4 per core are capped, with a
    /// warning.
    #[arg(long)]
    threads: Option<usize>,
    /// Seed of the sample streams.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[command(flatten)]
    accel: AccelArgs,
    #[command(flatten)]
    accuracy: AccuracyArgs,
    #[command(flatten)]
    cutoff: CutoffArgs,
    /// glTF files: index of the scene to render (default: the file's default scene).
    #[arg(long, value_name = "N")]
    gltf_scene: Option<usize>,
    /// glTF files: look through the N-th camera met depth first in the scene (default: the
    /// first; the automatic framing camera when the file has none).
    #[arg(long, value_name = "N")]
    camera: Option<usize>,
    /// glTF and OBJ files: ignore the file's cameras and frame the model automatically.
    #[arg(long, conflicts_with = "camera")]
    auto_camera: bool,
    /// glTF and OBJ files: the model axis that points up; the model is turned so that it is
    /// up in lumis's Y-up world before the automatic camera and lights are placed (default: y,
    /// glTF's convention).
    #[arg(long, value_enum, value_name = "AXIS")]
    up: Option<UpArg>,
    /// glTF files: draw every placement of a mesh as its own world-space copy (also each
    /// EXT_mesh_gpu_instancing instance) instead of making a mesh placed twice or more one
    /// prototype with an instance per placement. Objects keep their names either way.
    #[arg(long)]
    flatten_instances: bool,
    /// Exposure in stops: linear colour x 2^EV before the EXR and the PNG are written
    /// (recorded in the EXR header as lumis/exposure). Default: the scene's `exposure`; for
    /// glTF and OBJ files automatic (a high percentile of the model's luminance to 0.8).
    #[arg(long, value_name = "EV", allow_negative_numbers = true)]
    exposure: Option<f32>,
    #[command(flatten)]
    window: WindowArgs,
    /// Record the render time in the EXR header (lumis/renderSeconds). Off by default, so the
    /// same input gives the same bytes; the summary prints the time anyway.
    #[arg(long)]
    timing_metadata: bool,
    /// Write 32-bit float RGBA to EXR instead of half.
    #[arg(long)]
    float: bool,
    #[command(flatten)]
    passes: PassArgs,
    /// PNG encoding: the sRGB curve, or clamp (value x 255, no curve, as the paper's program).
    /// Default: the scene's `display`, else srgb (clamp for .scn scenes). EXR stays linear.
    #[arg(long, value_enum)]
    display: Option<DisplayArg>,
    /// No progress bar and no summary.
    #[arg(short, long)]
    quiet: bool,
    /// Add traversal counters and every effect decision, with the rays it saved, to the
    /// summary.
    #[arg(long)]
    stats: bool,
    /// Also write the summary (times, rays traced by kind, rays not traced by reason, effect
    /// decisions) as JSON to this file.
    #[arg(long, value_name = "FILE")]
    stats_json: Option<PathBuf>,
    /// `auto`: trace only what can change the image; `all`: every effect, from every hit to
    /// every light, no cutoff (the reference `auto` is bit-identical to at cutoff 0).
    #[arg(long, value_name = "MODE", default_value = "auto")]
    effects: lumis_core::effects::EffectMode,
    #[command(flatten)]
    overrides: OverrideArgs,
    #[command(flatten)]
    environment: EnvironmentArgs,
    #[command(flatten)]
    frame: FrameArgs,
    /// Stream the image into a viewer that speaks tev's protocol as it renders ([HOST:]PORT;
    /// tev listens on 127.0.0.1:14158): tiles as they finish, then the image as the EXR holds
    /// it. A viewer that is absent, slow or goes away is a warning; the outputs are the same
    /// bytes either way.
    #[arg(long, value_name = "[HOST:]PORT", value_parser = display_server)]
    display_server: Option<DisplayServer>,
    /// Render again the image IMAGE.exr was rendered from, by its header: the same scene file,
    /// flags, seed, tile or frame (outputs, threads and reporting are this command's). Refused
    /// when an input file changed or is gone, or another lumis version made it. Writes the
    /// same bytes (unless it was made with --timing-metadata or cut short).
    #[arg(long, value_name = "IMAGE.exr", conflicts_with = "scene")]
    from: Option<PathBuf>,
}

fn display_server(s: &str) -> Result<DisplayServer, String> {
    DisplayServer::parse(s).map_err(|e| e.to_string())
}

impl RenderArgs {
    /// The `-D` overrides, then the `--env` flags as the `-D environment.*` they stand for.
    fn defines(&self) -> Result<Vec<lumis_io::formats::Override>> {
        let mut defines = self.overrides.defines().to_vec();
        defines.extend(self.environment.overrides()?);
        Ok(defines)
    }
}

/// Loads, overrides the settings from the flags, builds, renders, exposes and writes;
/// `matches` are the flags as given (recorded in the EXR header). With `--from`, replays the
/// image's own command instead.
pub fn run(args: &RenderArgs, matches: &clap::ArgMatches) -> Result<()> {
    if let Some(image) = &args.from {
        return replay::run(args, matches, image);
    }
    let mut times = PhaseTimes::default();
    let t = Instant::now();
    let defines = args.defines()?;
    let defines = defines.as_slice();
    // Every file the load reads, so that no output can overwrite one of them.
    let (scene, inputs) = record_inputs(|| match &args.scene {
        Some(path) => lumis_io::formats::load_with_overrides(
            path,
            &lumis_io::formats::LoadOptions {
                scene: args.gltf_scene,
                camera: args.camera,
                up: args.up.map(UpAxis::from).unwrap_or_default(),
                auto_camera: args.auto_camera,
                frame: args.frame.frame(),
                flatten_instances: args.flatten_instances,
            },
            defines,
        )
        .map_err(anyhow::Error::from),
        None if args.gltf_scene.is_some()
            || args.camera.is_some()
            || args.up.is_some()
            || args.auto_camera
            || args.flatten_instances =>
        {
            bail!(
                "--gltf-scene, --camera, --up, --auto-camera and --flatten-instances need a \
                 model file"
            )
        }
        None => lumis_io::formats::default_scene_at(defines, args.frame.frame())
            .context("loading the built-in default scene"),
    });
    let mut scene = scene?;
    if !args.quiet {
        for w in scene.warnings() {
            eprintln!("warning: {w}");
        }
    }
    let st = scene.settings_mut();
    SettingsFlags {
        width: args.width,
        height: args.height,
        spp: args.spp,
        max_depth: args.max_depth,
        // `--precision` is set with `--offset` and `--epsilon`, as `lumis hits` sets them.
        precision: None,
        display: args.display.map(DisplayTransform::from),
    }
    .apply(st);
    args.accuracy.apply(st)?;
    args.cutoff.apply(st)?;
    args.overrides.apply(st, args.quiet)?;
    // The same limits as every scene file's, checked before any work starts.
    st.validate()
        .context("the render settings after the command-line overrides")?;
    if let Some(ev) = args.exposure {
        check_exposure(ev).map_err(|m| anyhow!("--exposure {ev}: {m}"))?;
    }
    let choice = args.accel.validated()?;
    let window = args.window.window(st.width, st.height)?;
    // The exposure to apply, decided before the render; `None`: automatic, from the film.
    let origin = args
        .scene
        .as_deref()
        .map_or(SceneOrigin::BuiltIn, SceneOrigin::File);
    let fixed_exposure = exposure_to_apply(args.exposure, origin, st.exposure);
    let identity = args.identity(&inputs, st, matches)?;
    let tile_output = args
        .window
        .tile
        .map(|t| PathBuf::from(format!("tile_{}.exr", t.index)));
    let numbered =
        NumberedOutputs::new(&output_paths(args, tile_output.as_deref())?, scene.frame())?;
    let planned = numbered.planned();
    // Before the render: a missing directory or an output that is an input fails at once.
    prepare_outputs(&planned, &inputs)?;
    let outputs: Vec<PathBuf> = planned
        .iter()
        .filter(|o| o.flag != STATS_JSON)
        .map(|o| o.path.to_path_buf())
        .collect();
    times.load = t.elapsed();

    let t = Instant::now();
    let world = choice.build(scene);
    times.build = t.elapsed();

    let t = Instant::now();
    let show_progress = !args.quiet && std::io::stderr().is_terminal();
    let cancel = CancelFlag::default();
    // Without the handler Ctrl-C keeps its default (quit at once), which is still correct.
    let _ = on_ctrl_c(cancel.clone());
    let writes_exr = outputs.iter().any(|p| has_extension(p, "exr"));
    let live = args
        .display_server
        .as_ref()
        .map(|server| live_view(server, &outputs[0], scene_size(&world), window, args.quiet));
    let mut progress = super::progress::bar(show_progress);
    if let Some(live) = &live {
        progress = progress.and(live.clone());
    }
    let opts = RenderOptions {
        seed: args.seed,
        threads: super::threads::resolve(args.threads, args.quiet),
        progress,
        // Only EXR has depth, normal and id layers: a PNG-only render traces no rays for them.
        aov_layers: outputs.iter().any(|p| has_extension(p, "exr")),
        effects: args.effects,
        window,
        cancel,
        // Cryptomatte layers are EXR layers: a PNG-only render makes none.
        cryptomatte: args.passes.cryptomatte()?.filter(|_| writes_exr),
        transparent: args.passes.transparent(),
        // Pass layers are EXR layers too.
        passes: args.passes.pass_request(writes_exr),
    };
    let mut rendered = render(&world, &opts)?;
    let scene = world.scene();
    times.render = t.elapsed();

    let tile = args.window.tile.map(|spec| TileHeader {
        spec,
        exposure: fixed_exposure,
        display: scene.settings().display,
    });

    let t = Instant::now();
    let mut meta = ExrMetadata {
        float_rgba: args.float,
        spp_per_axis: scene.settings().spp,
        lens_samples: rendered.analysis.lens_rays,
        render_seconds: args.timing_metadata.then_some(times.render.as_secs_f32()),
        exposure: 0.0,
        z_miss: args.window.z_miss,
        partial: rendered.is_partial(),
        aov_layers: args.passes.aov_layers(scene.geometry().has_instances()),
        layout: args.passes.layout(),
        identity: Some(identity),
        tile,
        frame: scene.frame(),
    };
    let how = Develop {
        exposure: fixed_exposure,
        tonemap: args.overrides.tonemap(),
        display: scene.settings().display,
    };
    let paths: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    let (full_width, full_height) = rendered.film.full_size();
    let camera = ExrCamera::new(scene.camera(), full_width, full_height);
    let developed = develop(&mut rendered.film, &camera, &paths, &how, &mut meta)?;
    if developed.auto_exposure && !args.quiet {
        eprintln!("auto exposure: {:+.2} EV", developed.exposure);
    }
    // All outputs are written to temporary files first and renamed only when every one
    // succeeded, so a failing one leaves every existing file as it was.
    let mut staged = StagedOutputs::new();
    for (path, bytes) in &developed.images {
        staged.stage_bytes(path, bytes)?;
    }
    times.write = t.elapsed();

    if let Some(path) = &args.stats_json {
        let json = summary_json(&times, &rendered.counts, &rendered.analysis);
        staged.stage_bytes(path, json.as_bytes())?;
    }
    staged.commit()?;
    // The files first: a viewer only ever gets what is already on disk.
    if let Some(live) = &live {
        live.finish_with_exr(&rendered.film, &meta);
    }
    if !args.quiet {
        for path in &outputs {
            eprintln!("wrote {}", path.display());
        }
        eprint!(
            "{}",
            summary(&times, &rendered.counts, &rendered.analysis, args.stats)
        );
    }
    if rendered.is_partial() {
        return Err(Interrupted {
            done: rendered.tiles - rendered.unfinished_tiles,
            total: rendered.tiles,
        }
        .into());
    }
    Ok(())
}

/// The width and height of `world`'s image.
fn scene_size(world: &lumis_core::scene::World) -> (u32, u32) {
    let st = world.scene().settings();
    (st.width, st.height)
}

/// The live view of a render into `output` (the viewer's image is named after it) of the
/// `window` of a `full`-sized image; its warnings go to stderr unless `quiet`.
fn live_view(
    server: &DisplayServer,
    output: &Path,
    full: (u32, u32),
    window: Option<lumis_core::film::PixelWindow>,
    quiet: bool,
) -> Arc<LiveView> {
    let w = window.unwrap_or(lumis_core::film::PixelWindow::full(full.0, full.1));
    LiveView::open(
        server,
        &output.display().to_string(),
        full,
        (w.x0, w.y0, w.width(), w.height()),
        Arc::new(move |message| {
            if !quiet {
                eprintln!("warning: {message}");
            }
        }),
    )
}

/// The flag `output_paths` gives the `--stats-json` report.
const STATS_JSON: &str = "--stats-json";

/// The files to write, with the flag that named each: `-o` and `--png` when given, otherwise
/// `out.exr` and `out.png` (a tile: `tile_default`, the EXR alone); then the `--stats-json`
/// report.
fn output_paths<'a>(
    args: &'a RenderArgs,
    tile_default: Option<&'a Path>,
) -> Result<Vec<PlannedOutput<'a>>> {
    let mut paths: Vec<PlannedOutput<'a>> = Vec::new();
    if let Some(default) = tile_default {
        let path = args.output.as_deref().unwrap_or(default);
        if !has_extension(path, "exr") || args.png.is_some() {
            bail!(
                "--tile writes an EXR tile for `lumis merge`: give -o NAME.exr and no --png                  (the merge writes the finished image)"
            );
        }
        paths.push(PlannedOutput { flag: "-o", path });
        if let Some(json) = &args.stats_json {
            paths.push(PlannedOutput {
                flag: STATS_JSON,
                path: json,
            });
        }
        return Ok(paths);
    }
    let planned = |flag, path: &'static str| PlannedOutput {
        flag,
        path: Path::new(path),
    };
    match &args.output {
        Some(p) => paths.push(PlannedOutput {
            flag: "-o",
            path: p,
        }),
        None => paths.push(planned("the default output", "out.exr")),
    }
    match &args.png {
        Some(p) => paths.push(PlannedOutput {
            flag: "--png",
            path: p,
        }),
        None if args.output.is_none() => paths.push(planned("the default output", "out.png")),
        None => {}
    }
    if let Some(png) = &args.png
        && !has_extension(png, "png")
    {
        bail!("--png {}: the file name must end in .png", png.display());
    }
    // Checked before rendering so a typo does not cost a whole render.
    if let Some(bad) = paths
        .iter()
        .find(|p| !has_extension(p.path, "exr") && !has_extension(p.path, "png"))
    {
        bail!(
            "{}: unknown output format; expected a file name ending in .exr or .png",
            bad.path.display()
        );
    }
    if let Some(json) = &args.stats_json {
        if paths.iter().any(|p| p.path == json) {
            bail!(
                "--stats-json {}: that is also an image output; give the report its own file",
                json.display()
            );
        }
        paths.push(PlannedOutput {
            flag: STATS_JSON,
            path: json,
        });
    }
    Ok(paths)
}

fn has_extension(p: &Path, ext: &str) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

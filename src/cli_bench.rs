//! `lumis bench paper`: runs the paper's Table I and prints it as Markdown and CSV.

use anyhow::{Context, Result, bail};
use clap::Args;
use lumis::bench::{csv, markdown_table, measure, paper_configs, table_i_files, work_table};
use std::path::{Path, PathBuf};

/// Options of `lumis bench paper`.
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
pub fn run_paper(args: &PaperArgs) -> Result<()> {
    if !(args.scale > 0.0 && args.scale <= 4.0) {
        bail!("--scale must be in (0, 4]");
    }
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
    let mut rows = Vec::new();
    for file in &files {
        let mut scene = lumis::formats::load(file)?;
        // The paper's settings: 1 sample per pixel, 5 depth-of-field rays (the loader's defaults).
        let st = scene.settings_mut();
        (st.width, st.height, st.spp, st.lens_samples) = (w, h, 1, 5);
        let name = file_name(file);
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
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// Options of `lumis bench load`.
#[derive(Args, Debug)]
pub struct LoadArgs {
    /// Triangles in the generated meshes (rounded to a square grid).
    #[arg(long, default_value_t = 1_000_000)]
    triangles: u32,
    /// Loads per format; the median time and the largest peak memory are reported.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
}

/// Generates a large OBJ and GLB, then loads each in fresh child processes (`bench load-one`)
/// so that every peak-memory reading belongs to one load alone.
pub fn run_load(args: &LoadArgs) -> Result<()> {
    let n = ((args.triangles as f64 / 2.0).sqrt().ceil() as u32).max(1);
    let dir = tempfile::tempdir().context("creating a temporary folder")?;
    let exe = std::env::current_exe().context("finding the lumis executable")?;
    let tiny = dir.path().join("tiny.obj");
    lumis::bench_load::write_obj(&tiny, 1)?;
    let baseline = load_in_child(&exe, &tiny)?;
    println!(
        "{} triangles per mesh; baseline process (a 2-triangle OBJ): {:.1} MiB peak\n",
        2 * n * n,
        baseline.1 as f64 / (1 << 20) as f64
    );
    println!(
        "| format | file size | load time (median of {}) | triangles/s | peak memory | peak over baseline |",
        args.repeat
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for (ext, write) in [
        (
            "obj",
            lumis::bench_load::write_obj as fn(&Path, u32) -> std::io::Result<()>,
        ),
        ("glb", lumis::bench_load::write_glb),
    ] {
        let file = dir.path().join(format!("grid.{ext}"));
        write(&file, n).with_context(|| format!("writing {}", file.display()))?;
        let size = std::fs::metadata(&file)?.len();
        let mut runs = (0..args.repeat.max(1))
            .map(|_| load_in_child(&exe, &file))
            .collect::<Result<Vec<_>>>()?;
        runs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let median = runs[runs.len() / 2].0;
        let peak = runs.iter().map(|r| r.1).max().unwrap_or(0);
        let mib = |b: u64| b as f64 / (1 << 20) as f64;
        println!(
            "| {ext} | {:.1} MiB | {median:.3} s | {:.2} M | {:.1} MiB | {:.1} MiB |",
            mib(size),
            2.0 * (n as f64).powi(2) / median / 1e6,
            mib(peak),
            mib(peak.saturating_sub(baseline.1))
        );
    }
    Ok(())
}

/// Runs `lumis bench load-one FILE`; returns (seconds, peak bytes).
fn load_in_child(exe: &Path, file: &Path) -> Result<(f64, u64)> {
    let out = std::process::Command::new(exe)
        .args(["bench", "load-one"])
        .arg(file)
        .output()?;
    if !out.status.success() {
        bail!(
            "loading {} failed: {}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let mut words = text.split_whitespace();
    let seconds = words.next().and_then(|w| w.parse().ok());
    let peak = words.next().and_then(|w| w.parse().ok());
    match (seconds, peak) {
        (Some(s), Some(p)) => Ok((s, p)),
        _ => bail!("unexpected output from load-one: {text}"),
    }
}

/// `bench load-one FILE`: loads one file and prints "seconds peak_bytes".
pub fn run_load_one(file: &Path) -> Result<()> {
    let start = std::time::Instant::now();
    let scene = lumis::formats::load(file)?;
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(&scene);
    println!(
        "{seconds} {}",
        lumis::bench_load::peak_rss_bytes().unwrap_or(0)
    );
    Ok(())
}

/// Options of `lumis bench accuracy`.
#[derive(Args, Debug)]
pub struct AccuracyArgs {
    /// Scenes: files, paper scene names (looked up in --paper-scenes), or the built-ins
    /// `default`, `far-occluder`, `far-spheres`. Default: the default scene, allMaterials,
    /// texturesInYoFace, tumbledStones, assets/knot.obj, far-occluder and far-spheres.
    scenes: Vec<String>,
    /// Folder holding the paper's .scn files.
    #[arg(long, default_value = "../shared/paper-scenes/scenes")]
    paper_scenes: PathBuf,
    /// Image width of every render.
    #[arg(long, default_value_t = 160)]
    width: u32,
    /// Image height of every render.
    #[arg(long, default_value_t = 90)]
    height: u32,
    /// Timed rounds (the outer loop; each renders every point once); the median is kept.
    #[arg(long, default_value_t = 3)]
    rounds: usize,
    /// Render threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Write every scene's rows here as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the error-vs-time plot here (.png or .svg).
    #[arg(long)]
    plot: Option<PathBuf>,
}

/// Sweeps every accuracy knob on every scene, prints the summary table and writes CSV/plot.
pub fn run_accuracy(args: &AccuracyArgs) -> Result<()> {
    use lumis::bench_accuracy::{csv, markdown, plot, scenes, summarise, sweep};
    if args.width == 0 || args.height == 0 || args.rounds == 0 {
        bail!("--width, --height and --rounds must be at least 1");
    }
    let list = if args.scenes.is_empty() {
        scenes::default_set(&args.paper_scenes)?
    } else {
        args.scenes
            .iter()
            .map(|s| scenes::resolve(s, &args.paper_scenes))
            .collect::<Result<Vec<_>>>()?
    };
    let opts = sweep::SweepOptions {
        width: args.width,
        height: args.height,
        rounds: args.rounds,
        threads: args.threads,
    };
    let start = std::time::Instant::now();
    let mut rows = Vec::new();
    for s in &list {
        let t = std::time::Instant::now();
        let r = sweep::sweep_scene(s, &opts)?;
        eprintln!(
            "{:<22} {} points in {:.1} s",
            s.name,
            r.len(),
            t.elapsed().as_secs_f64()
        );
        rows.extend(r);
    }
    let summary = summarise(&rows);
    println!(
        "Accuracy sweep at {}x{}, {} rounds, {} scenes ({:.1} s); geometric means over scenes:\n",
        args.width,
        args.height,
        args.rounds,
        list.len(),
        start.elapsed().as_secs_f64()
    );
    println!("{}", markdown(&summary));
    let text = csv(&rows);
    if let Some(path) = &args.csv {
        std::fs::write(path, &text).with_context(|| format!("writing {}", path.display()))?;
    } else {
        println!("CSV:\n\n{text}");
    }
    if let Some(path) = &args.plot {
        let title = format!(
            "lumis accuracy knobs: {} scenes at {}x{}",
            list.len(),
            args.width,
            args.height
        );
        plot::write_plot(&summary, &title, path)?;
    }
    Ok(())
}

/// Options of `lumis bench effects`.
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
    /// Worker threads (default: all cores).
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
pub fn run_effects(args: &EffectsArgs) -> Result<()> {
    let mut scenes: Vec<(String, lumis::scene::Scene)> = Vec::new();
    if args.scenes.is_empty() {
        scenes.push(("default".into(), lumis::formats::default_scene()?));
        for f in table_i_files(&args.paper_scenes) {
            scenes.push((file_name(&f), lumis::formats::load(&f)?));
        }
    } else {
        for f in &args.scenes {
            let scene =
                lumis::formats::load(f).with_context(|| format!("loading {}", f.display()))?;
            scenes.push((file_name(f), scene));
        }
    }
    let mut rows = Vec::new();
    for (name, mut scene) in scenes {
        let st = scene.settings_mut();
        (st.width, st.height) = (args.width, args.height);
        let row = lumis::bench_effects::measure_effects(
            &scene,
            &name,
            args.rounds,
            args.threads,
            !args.png_only,
        )
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
    println!("{}", lumis::bench_effects::markdown(&rows));
    println!(
        "Rays the default did not trace, by reason:\n\n{}",
        lumis::bench_effects::reasons_markdown(&rows)
    );
    let text = lumis::bench_effects::csv(&rows);
    println!("CSV:\n\n{text}");
    if let Some(path) = &args.csv {
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

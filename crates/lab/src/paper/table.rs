//! The paper's Table I, measured: every scene is rendered under each configuration the paper
//! timed (plus SAH for reference); wall time is the median of K runs.

use lumis_core::accel::{AccelKind, BuildOptions, PAPER_SEGMENT_MAX, SegmentParams, Traversal};
use lumis_core::render::{RenderError, RenderOptions, render};
use lumis_core::scene::{Scene, World};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The figures of Table I in order, by file name.
pub const TABLE_I_SCENES: [&str; 11] = [
    "allMaterials.scn",
    "ballsInAPit.scn",
    "ballsOnAPlane.scn",
    "ballsOnAPlaneClose.scn",
    "line.scn",
    "lineFar.scn",
    "modelTest2.scn",
    "texturesInYoFace.scn",
    "triangleSpheres.scn",
    "triangleTest1.scn",
    "tumbledStones.scn",
];

/// One column group of Table I: an accelerator and how it is walked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Column label.
    pub label: &'static str,
    /// Accelerator.
    pub accel: AccelKind,
    /// Traversal.
    pub traversal: Traversal,
}

/// The configurations in Table I's order, baseline first, then SAH for reference, then the
/// paper's own exhaustive traversal over both of its trees (what its percentages compare against).
pub fn paper_configs() -> Vec<Config> {
    let seg = |init| {
        Traversal::Segments(SegmentParams {
            init,
            max: PAPER_SEGMENT_MAX,
        })
    };
    vec![
        Config {
            label: "bsp (baseline)",
            accel: AccelKind::Bsp,
            traversal: Traversal::Ordered,
        },
        Config {
            label: "bsp+seg2",
            accel: AccelKind::Bsp,
            traversal: seg(2.0),
        },
        Config {
            label: "bsp+seg4096",
            accel: AccelKind::Bsp,
            traversal: seg(4096.0),
        },
        Config {
            label: "bsmp",
            accel: AccelKind::Bsmp,
            traversal: Traversal::Ordered,
        },
        Config {
            label: "bsmp+seg2",
            accel: AccelKind::Bsmp,
            traversal: seg(2.0),
        },
        Config {
            label: "bsmp+seg4096",
            accel: AccelKind::Bsmp,
            traversal: seg(4096.0),
        },
        Config {
            label: "sah",
            accel: AccelKind::Sah,
            traversal: Traversal::Ordered,
        },
        Config {
            label: "bsp exhaustive",
            accel: AccelKind::Bsp,
            traversal: Traversal::Exhaustive,
        },
        Config {
            label: "bsmp exhaustive",
            accel: AccelKind::Bsmp,
            traversal: Traversal::Exhaustive,
        },
        // The original's acceptance rule, which can return a farther hit: wrong images, timed
        // only to show what the shortcut was worth.
        Config {
            label: "bsp+seg2 original rule",
            accel: AccelKind::Bsp,
            traversal: Traversal::SegmentsOriginalRule(SegmentParams {
                init: 2.0,
                max: PAPER_SEGMENT_MAX,
            }),
        },
        Config {
            label: "bsp+seg4096 original rule",
            accel: AccelKind::Bsp,
            traversal: Traversal::SegmentsOriginalRule(SegmentParams {
                init: 4096.0,
                max: PAPER_SEGMENT_MAX,
            }),
        },
    ]
}

/// One measured cell.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// Scene file name.
    pub scene: String,
    /// Configuration label.
    pub config: &'static str,
    /// Median wall time (build + render) over the repeats, seconds.
    pub seconds: f64,
    /// Hierarchy nodes visited per ray.
    pub nodes_per_ray: f64,
    /// Primitive tests per ray.
    pub prims_per_ray: f64,
    /// Rays traced in one run.
    pub rays: u64,
}

/// Renders `scene` under `config` `repeat` times; the scene's own settings are used as given.
pub fn measure(
    scene: &Scene,
    name: &str,
    config: &Config,
    repeat: usize,
    leaf_size: Option<usize>,
) -> Result<Measurement, RenderError> {
    let mut times = Vec::with_capacity(repeat);
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let scene = scene.clone();
        let start = Instant::now();
        let opts = BuildOptions {
            max_leaf_size: leaf_size.unwrap_or(config.accel.default_leaf_size()),
            ..Default::default()
        };
        let world = World::build(scene, config.accel, &opts).with_traversal(config.traversal);
        // Like the original's TGA, Table I's image has no depth/normal/id layers to trace.
        let opts = RenderOptions {
            aov_layers: false,
            ..RenderOptions::default()
        };
        let out = render(&world, &opts)?;
        times.push(start.elapsed().as_secs_f64());
        last = Some(out);
    }
    times.sort_by(f64::total_cmp);
    let counts = last.map(|r| r.counts).unwrap_or_default();
    let rays = counts.total().max(1);
    Ok(Measurement {
        scene: name.to_owned(),
        config: config.label,
        seconds: times[times.len() / 2],
        nodes_per_ray: counts.traversal.nodes_visited as f64 / rays as f64,
        prims_per_ray: counts.traversal.prim_tests as f64 / rays as f64,
        rays: counts.total(),
    })
}

/// The scene files of Table I found in `dir`, in figure order.
pub fn table_i_files(dir: &Path) -> Vec<PathBuf> {
    TABLE_I_SCENES
        .iter()
        .map(|n| dir.join(n))
        .filter(|p| p.is_file())
        .collect()
}

/// Table I layout: one row per scene, time and % vs the baseline per configuration, plus totals.
pub fn markdown_table(rows: &[Measurement], configs: &[Config]) -> String {
    let scenes: Vec<&str> = rows
        .iter()
        .map(|m| m.scene.as_str())
        .fold(Vec::new(), |mut v, s| {
            if !v.contains(&s) {
                v.push(s);
            }
            v
        });
    let cell =
        |scene: &str, label: &str| rows.iter().find(|m| m.scene == scene && m.config == label);
    let mut s = String::from("| scene |");
    for c in configs {
        let _ = write!(s, " {} s | % |", c.label);
    }
    s.push_str("\n|---|");
    s.push_str(&"---:|---:|".repeat(configs.len()));
    s.push('\n');
    let base = configs.first().map_or("", |c| c.label);
    let mut totals = vec![0.0f64; configs.len()];
    for scene in &scenes {
        let b = cell(scene, base).map_or(f64::NAN, |m| m.seconds);
        let _ = write!(s, "| {scene} |");
        for (i, c) in configs.iter().enumerate() {
            let t = cell(scene, c.label).map_or(f64::NAN, |m| m.seconds);
            totals[i] += t;
            let _ = write!(s, " {t:.3} | {:+.1} |", 100.0 * (t / b - 1.0));
        }
        s.push('\n');
    }
    let _ = write!(s, "| **total** |");
    for t in &totals {
        let _ = write!(s, " {t:.3} | {:+.1} |", 100.0 * (t / totals[0] - 1.0));
    }
    s.push('\n');
    s
}

/// Per-ray work: nodes visited and primitive tests per ray for every cell.
pub fn work_table(rows: &[Measurement]) -> String {
    let mut s = String::from(
        "| scene | config | rays | nodes/ray | prim tests/ray |\n|---|---|---:|---:|---:|\n",
    );
    for m in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.2} | {:.2} |",
            m.scene, m.config, m.rays, m.nodes_per_ray, m.prims_per_ray
        );
    }
    s
}

/// Every cell as CSV.
pub fn csv(rows: &[Measurement]) -> String {
    let mut s = String::from("scene,config,median_seconds,rays,nodes_per_ray,prim_tests_per_ray\n");
    for m in rows {
        let _ = writeln!(
            s,
            "{},{},{:.6},{},{:.4},{:.4}",
            m.scene, m.config, m.seconds, m.rays, m.nodes_per_ray, m.prims_per_ray
        );
    }
    s
}

//! The sweep: which settings are measured, and the interleaved timing loop.

use super::metrics::{Oracle, image_error};
use super::report::Row;
use super::scenes::BenchScene;
use anyhow::{Context, Result};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::geometry::{Offset, Precision};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Settings, World};
use std::collections::HashMap;
use std::time::Instant;

/// The accuracy knobs of one sweep point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knobs {
    /// Samples per pixel per axis.
    pub spp: u32,
    /// Recursion limit.
    pub max_depth: u32,
    /// Branch weight cutoff (0 = off).
    pub cutoff: f32,
    /// Ray/primitive precision.
    pub precision: Precision,
    /// Secondary-ray offset rule.
    pub offset: Offset,
    /// Adaptive supersampling threshold (`None`: off).
    pub adaptive: Option<f32>,
}

impl Default for Knobs {
    /// lumis's defaults (those of [`Settings::default`]).
    fn default() -> Self {
        let s = Settings::default();
        Knobs {
            spp: s.spp,
            max_depth: s.max_depth,
            cutoff: s.cutoff,
            precision: s.precision,
            offset: s.offset,
            adaptive: s.adaptive,
        }
    }
}

impl Knobs {
    /// The converged reference: 8x8 samples, float64, error-bound offsets, depth 16, no cutoff.
    pub const REFERENCE: Knobs = Knobs {
        spp: 8,
        max_depth: 16,
        cutoff: 0.0,
        precision: Precision::Double,
        offset: Offset::ErrorBound,
        adaptive: None,
    };

    /// Writes the knobs into `s`.
    pub fn apply(&self, s: &mut Settings) {
        (
            s.spp,
            s.max_depth,
            s.cutoff,
            s.precision,
            s.offset,
            s.adaptive,
        ) = (
            self.spp,
            self.max_depth,
            self.cutoff,
            self.precision,
            self.offset,
            self.adaptive,
        );
    }
}

/// One measured setting: which axis it varies (`knob`), its value there and all its knobs.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// `default`, `spp`, `max_depth`, `cutoff`, `precision`, `offset`, `adaptive`,
    /// `adaptive spp 4`, `corner` or `reference`.
    pub knob: &'static str,
    /// The varied value as text (the corner's name for corners).
    pub value: String,
    /// Every knob.
    pub knobs: Knobs,
}

/// The sweep: the defaults, each axis varied alone from them, the cheapest and the most
/// expensive corner, and the reference (timed like the rest, so its cost is on the plot too).
pub fn points() -> Vec<Point> {
    let d = Knobs::default();
    let mut v = vec![Point {
        knob: "default",
        value: "default".into(),
        knobs: d,
    }];
    let mut add = |knob, value: String, knobs| {
        v.push(Point { knob, value, knobs });
    };
    // Each axis skips the scene's own default value, which is the `default` point.
    for spp in [1, 2, 3, 4].into_iter().filter(|&x| x != d.spp) {
        add("spp", spp.to_string(), Knobs { spp, ..d });
    }
    for max_depth in [0, 1, 2, 3, 5, 8].into_iter().filter(|&x| x != d.max_depth) {
        add("max_depth", max_depth.to_string(), Knobs { max_depth, ..d });
    }
    for cutoff in [0.0, 1e-3, 1e-2, 5e-2, 0.2]
        .into_iter()
        .filter(|&x| x != d.cutoff)
    {
        add("cutoff", cutoff.to_string(), Knobs { cutoff, ..d });
    }
    for precision in Precision::ALL.into_iter().filter(|&x| x != d.precision) {
        add("precision", precision.to_string(), Knobs { precision, ..d });
    }
    let offsets = [
        Offset::ErrorBound,
        Offset::Ulp,
        Offset::Epsilon(1e-4),
        Offset::Epsilon(1e-2),
    ];
    for offset in offsets.into_iter().filter(|&x| x != d.offset) {
        add("offset", offset.to_string(), Knobs { offset, ..d });
    }
    // Adaptive supersampling at the default's samples per pixel, and at 4x4 (from the spp 4
    // point down): the thresholds from "refine nearly everything" to "refine only hard edges".
    let thresholds = [0.02, 0.05, 0.1, 0.2, 0.4];
    for t in thresholds.into_iter().filter(|&t| Some(t) != d.adaptive) {
        let knobs = Knobs {
            adaptive: Some(t),
            ..d
        };
        add("adaptive", t.to_string(), knobs);
    }
    for t in thresholds {
        let knobs = Knobs {
            spp: 4,
            adaptive: Some(t),
            ..d
        };
        add("adaptive spp 4", t.to_string(), knobs);
    }
    let cheapest = Knobs {
        spp: 1,
        max_depth: 0,
        cutoff: 0.2,
        precision: Precision::Fast,
        offset: Offset::Epsilon(1e-4),
        adaptive: None,
    };
    add("corner", "cheapest".into(), cheapest);
    let dearest = Knobs {
        spp: 4,
        max_depth: 8,
        cutoff: 0.0,
        precision: Precision::Double,
        offset: Offset::ErrorBound,
        adaptive: None,
    };
    add("corner", "most expensive".into(), dearest);
    add("reference", "reference".into(), Knobs::REFERENCE);
    v
}

/// How the sweep renders.
#[derive(Clone, Copy, Debug)]
pub struct SweepOptions {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed rounds; each round renders every point once, so drift in machine load spreads
    /// over all points instead of biasing the ones measured last.
    pub rounds: usize,
    /// Render threads (`None`: all cores).
    pub threads: Option<usize>,
}

/// Sweeps one scene: every point rendered `rounds` times (rounds outermost), then error
/// against the reference point's image and query disagreement against float64 brute force.
pub fn sweep_scene(bs: &BenchScene, opts: &SweepOptions) -> Result<Vec<Row>> {
    let mut scene = bs.scene.clone();
    (scene.settings_mut().width, scene.settings_mut().height) = (opts.width, opts.height);
    let mut world = World::build(scene, AccelKind::Sah, &BuildOptions::default());
    let points = points();
    let ropts = RenderOptions {
        threads: opts.threads,
        ..RenderOptions::default()
    };
    let mut times = vec![Vec::new(); points.len()];
    let mut films = vec![None; points.len()];
    // One untimed render first: the default is timed first in each round and would otherwise
    // pay for cold caches and thread-pool start-up, inflating every other point's speed-up.
    points[0].knobs.apply(world.settings_mut());
    render(&world, &ropts)?;
    for _ in 0..opts.rounds.max(1) {
        for (i, p) in points.iter().enumerate() {
            p.knobs.apply(world.settings_mut());
            let start = Instant::now();
            let r = render(&world, &ropts)
                .with_context(|| format!("{}: {} {}", bs.name, p.knob, p.value))?;
            times[i].push(start.elapsed().as_secs_f64());
            // Rendering is deterministic, so the first round's image stands for all.
            films[i].get_or_insert(r.film);
        }
    }
    let median = |t: &mut Vec<f64>| {
        t.sort_by(f64::total_cmp);
        t[t.len() / 2]
    };
    let seconds: Vec<f64> = times.iter_mut().map(median).collect();
    let reference = films[points.len() - 1].take().expect("rendered");
    let oracle = Oracle::new(world.scene());
    // Queries depend only on precision and offset: compare each pair once.
    let mut queries = HashMap::new();
    let mut rows = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let film = films[i].as_ref().unwrap_or(&reference);
        let key = (p.knobs.precision.name(), p.knobs.offset.to_string());
        let q = *queries.entry(key).or_insert_with(|| {
            p.knobs.apply(world.settings_mut());
            oracle.compare(&world)
        });
        rows.push(Row {
            scene: bs.name.clone(),
            point: p.clone(),
            seconds: seconds[i],
            time_ratio: seconds[i] / seconds[0],
            image: image_error(film, &reference),
            queries: q,
        });
    }
    Ok(rows)
}

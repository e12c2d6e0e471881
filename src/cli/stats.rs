//! The end-of-run summary: time per phase, rays by kind, throughput, and with `--stats` the
//! effect decisions; also as JSON (`--stats-json`).

use lumis_core::effects::Analysis;
use lumis_core::integrator::RayCounts;
use lumis_core::integrator::effects_text;
use serde::Serialize;
use std::fmt::Write as _;
use std::time::Duration;

/// Wall time of each phase of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct PhaseTimes {
    /// Reading and parsing the scene.
    pub load: Duration,
    /// Building the accelerator.
    pub build: Duration,
    /// Tracing.
    pub render: Duration,
    /// Encoding and writing images.
    pub write: Duration,
}

/// Formats the summary; `detailed` adds traversal counters and the effect decisions with the
/// rays each one saved.
pub fn summary(
    times: &PhaseTimes,
    counts: &RayCounts,
    analysis: &Analysis,
    detailed: bool,
) -> String {
    let secs = |d: Duration| d.as_secs_f64();
    let total = counts.total();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "time: load {:.3}s, build {:.3}s, render {:.3}s, write {:.3}s",
        secs(times.load),
        secs(times.build),
        secs(times.render),
        secs(times.write)
    );
    let _ = writeln!(
        s,
        "rays: {total} total = camera {} + aov {} + shadow {} + reflection {} + refraction {}",
        counts.camera, counts.aov, counts.shadow, counts.reflection, counts.refraction
    );
    if counts.cut() > 0 {
        let _ = writeln!(
            s,
            "cutoff: {} reflection/refraction branches below the cutoff not traced",
            counts.cut()
        );
    }
    if counts.not_traced.adaptive > 0 {
        let _ = writeln!(
            s,
            "adaptive: {} camera rays of converged pixels not traced",
            counts.not_traced.adaptive
        );
    }
    let mrays = total as f64 / secs(times.render).max(1e-9) / 1e6;
    let _ = writeln!(s, "speed: {mrays:.2} Mrays/s");
    if detailed {
        let per = |x: u64| x as f64 / total.max(1) as f64;
        let _ = writeln!(
            s,
            "traversal: {:.2} nodes visited/ray, {:.2} primitive tests/ray, {:.2} segments/ray",
            per(counts.traversal.nodes_visited),
            per(counts.traversal.prim_tests),
            per(counts.traversal.segments)
        );
        s += &effects_text(analysis, Some(counts));
    }
    s
}

/// The summary as one JSON document: `{"time": {...}, "rays": {...}, "effects": {...}}`.
pub fn summary_json(times: &PhaseTimes, counts: &RayCounts, analysis: &Analysis) -> String {
    #[derive(Serialize)]
    struct Time {
        load_s: f64,
        build_s: f64,
        render_s: f64,
        write_s: f64,
    }
    #[derive(Serialize)]
    struct Rays<'a> {
        total: u64,
        #[serde(flatten)]
        counts: &'a RayCounts,
    }
    #[derive(Serialize)]
    struct Report<'a> {
        time: Time,
        rays: Rays<'a>,
        effects: &'a Analysis,
    }
    let report = Report {
        time: Time {
            load_s: times.load.as_secs_f64(),
            build_s: times.build.as_secs_f64(),
            render_s: times.render.as_secs_f64(),
            write_s: times.write.as_secs_f64(),
        },
        rays: Rays {
            total: counts.total(),
            counts,
        },
        effects: analysis,
    };
    // Plain structs of numbers, strings and bools: serialising cannot fail.
    serde_json::to_string_pretty(&report).unwrap_or_default() + "\n"
}

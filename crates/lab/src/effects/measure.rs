//! One scene's measurement for `lumis-lab effects`: time and rays by kind of the default
//! render against `--effects all` (everything traced), in the same run in interleaved rounds,
//! and the tables that report them.

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::effects::EffectMode;
use lumis_core::integrator::RayCounts;
use lumis_core::render::{RenderError, RenderOptions, Rendered, render};
use lumis_core::scene::{Scene, World};
use std::fmt::Write as _;
use std::time::Instant;

/// One scene's measurement.
#[derive(Clone, Debug)]
pub struct EffectsRow {
    /// Scene name.
    pub scene: String,
    /// Median render seconds, default decisions.
    pub auto_seconds: f64,
    /// Median render seconds, `--effects all`.
    pub all_seconds: f64,
    /// Rays of one default render.
    pub auto: RayCounts,
    /// Rays of one `--effects all` render.
    pub all: RayCounts,
    /// The two images hold the same bits (expected whenever the scene's cutoff is 0).
    pub identical: bool,
    /// The scene's cutoff (a positive cutoff changes the image on purpose).
    pub cutoff: f32,
}

/// Renders `scene` (its own settings) `rounds` times in each mode, alternating which mode goes
/// first, after one untimed render of each; `aov_layers` as for an EXR (true) or PNG output.
pub fn measure_effects(
    scene: &Scene,
    name: &str,
    rounds: usize,
    threads: Option<usize>,
    aov_layers: bool,
) -> Result<EffectsRow, RenderError> {
    let world = World::build(scene.clone(), AccelKind::Sah, &BuildOptions::default());
    let run = |effects: EffectMode| -> Result<(f64, Rendered), RenderError> {
        let opts = RenderOptions {
            threads,
            aov_layers,
            effects,
            ..RenderOptions::default()
        };
        let start = Instant::now();
        let r = render(&world, &opts)?;
        Ok((start.elapsed().as_secs_f64(), r))
    };
    let (_, mut auto) = run(EffectMode::Auto)?;
    let (_, mut all) = run(EffectMode::All)?;
    let (mut t_auto, mut t_all) = (Vec::new(), Vec::new());
    for round in 0..rounds.max(1) {
        let order = if round % 2 == 0 {
            [EffectMode::Auto, EffectMode::All]
        } else {
            [EffectMode::All, EffectMode::Auto]
        };
        for mode in order {
            let (t, r) = run(mode)?;
            match mode {
                EffectMode::Auto => (t_auto.push(t), auto = r),
                EffectMode::All => (t_all.push(t), all = r),
            };
        }
    }
    let same = auto.film.rgba().len() == all.film.rgba().len()
        && auto
            .film
            .rgba()
            .iter()
            .zip(all.film.rgba())
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits));
    Ok(EffectsRow {
        scene: name.to_owned(),
        auto_seconds: median(&mut t_auto),
        all_seconds: median(&mut t_all),
        auto: auto.counts,
        all: all.counts,
        identical: same,
        cutoff: scene.settings().cutoff,
    })
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The rows as a Markdown table: times and their ratio, then rays by kind in both modes.
pub fn markdown(rows: &[EffectsRow]) -> String {
    let mut s = String::from(
        "| scene | default s | all s | all/default | rays default | rays all | shadow | \
         reflection | refraction | aov | same bits |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    let pair = |a: u64, b: u64| format!("{} / {}", si(a), si(b));
    for r in rows {
        let same = match (r.identical, r.cutoff > 0.0) {
            (true, _) => "yes".to_owned(),
            (false, true) => format!("no (cutoff {})", r.cutoff),
            (false, false) => "**NO**".to_owned(),
        };
        let _ = writeln!(
            s,
            "| {} | {:.3} | {:.3} | {:.2} | {} | {} | {} | {} | {} | {} | {same} |",
            r.scene,
            r.auto_seconds,
            r.all_seconds,
            r.all_seconds / r.auto_seconds.max(1e-9),
            si(r.auto.total()),
            si(r.all.total()),
            pair(r.auto.shadow, r.all.shadow),
            pair(r.auto.reflection, r.all.reflection),
            pair(r.auto.refraction, r.all.refraction),
            pair(r.auto.aov, r.all.aov),
        );
    }
    s
}

/// Why the default skipped rays, per scene: shadow rays by reason, branches by reason.
pub fn reasons_markdown(rows: &[EffectsRow]) -> String {
    let mut s = String::from(
        "| scene | shadow: back-facing | outside cone | dark light | unlit material | \
         reflection: material | zero weight | cutoff | refraction: material | TIR/zero | cutoff | \
         lens | aov |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let n = &r.auto.not_traced;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.scene,
            si(n.shadow.back_facing),
            si(n.shadow.outside_cone),
            si(n.shadow.dark_light),
            si(n.shadow.material_unlit),
            si(n.reflection.material),
            si(n.reflection.zero_weight),
            si(n.reflection.cutoff),
            si(n.refraction.material),
            si(n.refraction.zero_weight),
            si(n.refraction.cutoff),
            si(n.lens),
            si(n.aov),
        );
    }
    s
}

/// The rows as CSV, one line per scene.
pub fn csv(rows: &[EffectsRow]) -> String {
    let mut s = String::from(
        "scene,auto_s,all_s,auto_rays,all_rays,auto_shadow,all_shadow,auto_reflection,\
         all_reflection,auto_refraction,all_refraction,auto_aov,all_aov,identical\n",
    );
    for r in rows {
        let (a, b) = (&r.auto, &r.all);
        let _ = writeln!(
            s,
            "{},{:.4},{:.4},{},{},{},{},{},{},{},{},{},{},{}",
            r.scene,
            r.auto_seconds,
            r.all_seconds,
            a.total(),
            b.total(),
            a.shadow,
            b.shadow,
            a.reflection,
            b.reflection,
            a.refraction,
            b.refraction,
            a.aov,
            b.aov,
            r.identical
        );
    }
    s
}

/// A count with a k/M suffix, three significant figures.
fn si(n: u64) -> String {
    match n {
        0..1_000 => n.to_string(),
        1_000..1_000_000 => format!("{:.3}k", n as f64 / 1e3),
        _ => format!("{:.3}M", n as f64 / 1e6),
    }
}

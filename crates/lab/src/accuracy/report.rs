//! The sweep's results: one row per point and scene, as CSV, summarised over scenes, and the
//! summary as a Markdown table with the Pareto front marked.

use super::metrics::{ImageError, QueryError};
use super::sweep::Point;
use std::fmt::Write as _;

/// One sweep point on one scene.
#[derive(Clone, Debug)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// The settings measured.
    pub point: Point,
    /// Median render seconds over the rounds.
    pub seconds: f64,
    /// `seconds` over the default point's, same scene, same run.
    pub time_ratio: f64,
    /// Error against the reference image.
    pub image: ImageError,
    /// Disagreement with float64 brute force on pixel-centre and shadow rays.
    pub queries: QueryError,
}

/// The CSV header, matching [`csv`]'s columns.
pub const CSV_HEADER: &str = "scene,knob,value,spp,max_depth,cutoff,precision,offset,adaptive,seconds,time_ratio,rmse,rel_mse,p99,acne_px,lost_px,rays,ray_hit_miss,ray_prim,shadow_rays,shadow_disagree";

/// Every row as CSV, header first.
pub fn csv(rows: &[Row]) -> String {
    let mut s = format!("{CSV_HEADER}\n");
    for r in rows {
        let (k, e, q) = (&r.point.knobs, &r.image, &r.queries);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{:.6},{:.4},{:.6e},{:.6e},{:.6e},{},{},{},{},{},{},{}",
            r.scene,
            r.point.knob,
            r.point.value,
            k.spp,
            k.max_depth,
            k.cutoff,
            k.precision,
            k.offset,
            k.adaptive.map_or("off".to_string(), |t| t.to_string()),
            r.seconds,
            r.time_ratio,
            e.rmse,
            e.rel_mse,
            e.p99,
            e.acne,
            e.lost,
            q.rays,
            q.hit_miss,
            q.prim,
            q.shadow_rays,
            q.shadow
        );
    }
    s
}

/// One sweep point summarised over all scenes.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The settings.
    pub point: Point,
    /// Geometric mean over scenes of the time ratio.
    pub time_ratio: f64,
    /// Geometric mean over scenes of the relative MSE (floored at 1e-12 so exact zeros count).
    pub rel_mse: f64,
    /// Geometric mean over scenes of the RMSE (same floor).
    pub rmse: f64,
    /// Acne pixels, summed over scenes.
    pub acne: usize,
    /// Lost-shadow pixels, summed over scenes.
    pub lost: usize,
    /// Camera rays disagreeing (hit/miss or primitive), summed over scenes.
    pub ray_disagree: usize,
    /// Shadow rays disagreeing, summed over scenes.
    pub shadow_disagree: usize,
}

/// Per point (in sweep order), the geometric means over scenes: each scene weighs the same
/// whatever its absolute time or brightness, which ratios and relative errors need.
pub fn summarise(rows: &[Row]) -> Vec<Summary> {
    let mut out: Vec<(Summary, usize)> = Vec::new();
    for r in rows {
        let i = match out.iter().position(|(s, _)| s.point == r.point) {
            Some(i) => i,
            None => {
                out.push((
                    Summary {
                        point: r.point.clone(),
                        time_ratio: 0.0,
                        rel_mse: 0.0,
                        rmse: 0.0,
                        acne: 0,
                        lost: 0,
                        ray_disagree: 0,
                        shadow_disagree: 0,
                    },
                    0,
                ));
                out.len() - 1
            }
        };
        let (s, n) = &mut out[i];
        s.time_ratio += r.time_ratio.max(1e-12).ln();
        s.rel_mse += r.image.rel_mse.max(1e-12).ln();
        s.rmse += r.image.rmse.max(1e-12).ln();
        s.acne += r.image.acne;
        s.lost += r.image.lost;
        s.ray_disagree += r.queries.hit_miss + r.queries.prim;
        s.shadow_disagree += r.queries.shadow;
        *n += 1;
    }
    out.into_iter()
        .map(|(mut s, n)| {
            let n = n as f64;
            s.time_ratio = (s.time_ratio / n).exp();
            s.rel_mse = (s.rel_mse / n).exp();
            s.rmse = (s.rmse / n).exp();
            s
        })
        .collect()
}

/// Indices of the points on the Pareto front: no other point is both faster and more accurate.
pub fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (t, e) = points[i];
            !points
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

/// The summary as a Markdown table, Pareto-front points marked.
pub fn markdown(summary: &[Summary]) -> String {
    let xy: Vec<_> = summary.iter().map(|s| (s.time_ratio, s.rel_mse)).collect();
    let front = pareto(&xy);
    let mut t = String::from(
        "| knob | value | time ratio | relMSE | RMSE | acne px | lost px | camera-ray disagreements | shadow-ray disagreements | Pareto |\n|---|---|---:|---:|---:|---:|---:|---:|---:|:-:|\n",
    );
    for (i, s) in summary.iter().enumerate() {
        let _ = writeln!(
            t,
            "| {} | {} | {:.2} | {:.3e} | {:.3e} | {} | {} | {} | {} | {} |",
            s.point.knob,
            s.point.value,
            s.time_ratio,
            s.rel_mse,
            s.rmse,
            s.acne,
            s.lost,
            s.ray_disagree,
            s.shadow_disagree,
            if front.contains(&i) { "*" } else { "" }
        );
    }
    t
}

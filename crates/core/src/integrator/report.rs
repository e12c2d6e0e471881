//! The effect decisions and the rays they saved, in plain words (`--stats`, `lumis info`).

use super::{BranchSkips, RayCounts};
use crate::effects::Analysis;
use std::fmt::Write as _;

/// Every decision of `analysis` with its reason, one line each; with `counts` (after a
/// render) each ray kind adds a line of rays traced and not traced, by reason.
pub fn effects_text(analysis: &Analysis, counts: Option<&RayCounts>) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "effects ({}):", analysis.mode);
    for (name, d) in analysis.decisions() {
        let onoff = if d.on { "on" } else { "off" };
        let _ = writeln!(s, "  {name}: {onoff} — {}", d.reason);
        let Some(c) = counts else { continue };
        let nt = &c.not_traced;
        let line = match name {
            "shadows" => {
                let k = &nt.shadow;
                let asked = c.shadow + k.total();
                format!(
                    "{} traced, {} not traced ({:.0}% of {asked}): {} back-facing, {} outside a \
                     spot cone, {} to a zero-intensity light, {} from a material that ignores \
                     light, {} other zero contribution",
                    c.shadow,
                    k.total(),
                    percent(k.total(), asked),
                    k.back_facing,
                    k.outside_cone,
                    k.dark_light,
                    k.material_unlit,
                    k.zero_contribution
                )
            }
            "reflection" => branch_line(c.reflection, &nt.reflection, "reflect"),
            "refraction" => branch_line(c.refraction, &nt.refraction, "transmit"),
            "depth of field" => format!(
                "{} camera rays traced, {} identical lens rays not traced",
                c.camera, nt.lens
            ),
            "aov rays" => format!("{} traced, {} not traced", c.aov, nt.aov),
            _ => continue,
        };
        let _ = writeln!(s, "      {line}");
    }
    s
}

fn branch_line(traced: u64, k: &BranchSkips, verb: &str) -> String {
    format!(
        "{traced} traced, {} not traced: {} where the material does not {verb}, {} of weight \
         exactly 0 (Fresnel, total internal reflection), {} below the cutoff",
        k.total(),
        k.material,
        k.zero_weight,
        k.cutoff
    )
}

fn percent(part: u64, whole: u64) -> f64 {
    100.0 * part as f64 / whole.max(1) as f64
}

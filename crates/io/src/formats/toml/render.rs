//! `[render]` onto [`Settings`]: the one conversion of the table's keys, shared by the TOML
//! loader (over the defaults) and by `-D render.KEY=VALUE` overrides (over whatever a file of
//! any format set), so a key means and checks the same wherever it is written.

use super::schema::RenderDoc;
use lumis_core::geometry::{DEFAULT_EPSILON, Offset, check_cutoff, check_epsilon};
use lumis_core::math::Vec3;
use lumis_core::scene::{Settings, check_adaptive};

/// `base` with every key `r` gives replaced, each checked as the scene format documents it;
/// the message names the key. The caller runs [`Settings::validate`] on the result.
pub(super) fn merge(base: &Settings, r: &RenderDoc) -> Result<Settings, String> {
    Ok(Settings {
        width: r.width.unwrap_or(base.width),
        height: r.height.unwrap_or(base.height),
        spp: r.spp.unwrap_or(base.spp),
        max_depth: r.max_depth.unwrap_or(base.max_depth),
        ambient: r
            .ambient
            .map_or(Ok(base.ambient), |c| color("ambient", c))?,
        background: r
            .background
            .map_or(Ok(base.background), |c| color("background", c))?,
        exposure: r.exposure.unwrap_or(base.exposure),
        precision: match &r.precision {
            Some(p) => p.parse()?,
            None => base.precision,
        },
        offset: offset(base.offset, r)?,
        cutoff: r.cutoff.map_or(Ok(base.cutoff), check_cutoff)?,
        display: match &r.display {
            Some(name) => name.parse()?,
            None => base.display,
        },
        adaptive: match r.adaptive {
            Some(t) => Some(check_adaptive(t)?),
            None => base.adaptive,
        },
        ..base.clone()
    })
}

/// A colour: finite and non-negative.
pub(super) fn color(field: &str, c: [f32; 3]) -> Result<Vec3, String> {
    if !c.iter().all(|x| x.is_finite()) {
        return Err(format!("{field} {c:?} must be finite"));
    }
    if c.iter().any(|x| *x < 0.0) {
        return Err(format!("{field} {c:?} must be >= 0"));
    }
    Ok(Vec3::from(c))
}

/// `offset` and `epsilon`: an epsilon is only meaningful with `offset = "epsilon"`, given in
/// the same table or already in `base` (a `.scn` scene's, or an earlier override's).
fn offset(base: Offset, r: &RenderDoc) -> Result<Offset, String> {
    let base_epsilon = match base {
        Offset::Epsilon(e) => Some(e),
        _ => None,
    };
    let epsilon = r.epsilon.map(check_epsilon).transpose()?;
    let offset = match (&r.offset, epsilon) {
        (Some(name), e) => Offset::from_name(name, e.or(base_epsilon).unwrap_or(DEFAULT_EPSILON))?,
        (None, Some(e)) if base_epsilon.is_some() => Offset::Epsilon(e),
        (None, _) => base,
    };
    if r.epsilon.is_some() && !matches!(offset, Offset::Epsilon(_)) {
        return Err("epsilon is given but offset is not \"epsilon\"".into());
    }
    Ok(offset)
}

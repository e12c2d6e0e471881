//! Which parts of light transport a render simulates, and the proof that what it skips
//! changes nothing.
//!
//! Decisions are taken at four levels:
//! - **scene** ([`Analysis`]): shadows only with a light and a lit material, reflection and
//!   refraction only when some material reflects or transmits, depth-of-field lens rays only
//!   with an aperture, AOV rays only when the output has those layers;
//! - **material** ([`MaterialTraits`]): no Phong lobe without a specular term, no mirror ray
//!   from a non-reflective material, no shadow rays from a material that ignores light;
//! - **light**, per shading point: no shadow ray to a light whose unshadowed contribution is
//!   exactly zero (behind the surface, outside a spot cone, zero intensity);
//! - **hit**: no reflection or refraction branch of weight exactly zero (total internal
//!   reflection, Fresnel), and with a cutoff none below it.
//!
//! [`EffectMode::All`] turns every one of these tests off: every ray kind is traced from every
//! hit to every light. Each skip above is taken only where the traced ray's result is
//! multiplied by an exact zero, so the default image is bit-identical to the `All` one; the
//! tests in `tests/effects.rs` check this over every paper scene and asset.

mod analysis;

pub use analysis::{Analysis, Decision, MaterialTraits};

use std::fmt;
use std::str::FromStr;

/// How much of the light transport is traced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EffectMode {
    /// Only what can change the image (the default).
    #[default]
    Auto,
    /// Everything: every effect on, every per-material, per-light and per-hit test off, no
    /// cutoff. The reference the default is proven against, and the baseline of
    /// `lumis-lab effects`.
    All,
}

impl EffectMode {
    /// The name used on the command line and in the stats.
    pub fn name(self) -> &'static str {
        match self {
            EffectMode::Auto => "auto",
            EffectMode::All => "all",
        }
    }
}

impl fmt::Display for EffectMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for EffectMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(EffectMode::Auto),
            "all" => Ok(EffectMode::All),
            _ => Err(format!("unknown effect mode {s:?}; expected auto or all")),
        }
    }
}

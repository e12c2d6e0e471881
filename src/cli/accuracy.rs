//! The accuracy flags shared by `render` and `hits` (`--precision`, `--offset`, `--epsilon`),
//! plus `render`'s `--cutoff` and `--adaptive`; each overrides the scene file's `[render]` key
//! of the same name.

use super::values::{OffsetArg, PrecisionArg};
use anyhow::{Result, bail};
use clap::Args;
use lumis_core::geometry::{Offset, check_cutoff, check_epsilon};
use lumis_core::scene::{Settings, check_adaptive};

/// `--precision`, `--offset`, `--epsilon`.
#[derive(Args, Debug, Default)]
pub struct AccuracyArgs {
    /// Ray/primitive tests: f32 Moller-Trumbore and textbook quadratic (fast), watertight
    /// triangles and cancellation-free spheres (watertight, the default), or all in f64
    /// (double). Default: the scene's `precision`, else watertight.
    #[arg(long, value_enum)]
    precision: Option<PrecisionArg>,
    /// How secondary rays leave a surface: past the hit point's rounding-error bound (the
    /// default), that plus a fixed 256-ulp step, or a fixed --epsilon along the normal.
    #[arg(long, value_enum)]
    offset: Option<OffsetArg>,
    /// Distance (scene units) of `--offset epsilon` [default: 1e-4].
    #[arg(long, value_name = "E")]
    epsilon: Option<f32>,
}

/// `--cutoff` and `--adaptive`.
#[derive(Args, Debug, Default)]
pub struct CutoffArgs {
    /// Skip reflection/refraction branches whose weight in the pixel is below W (0 = off).
    /// Default: the scene's `cutoff`, else 0.01 (0 for .scn scenes, as the paper's program).
    #[arg(long, value_name = "W")]
    cutoff: Option<f32>,
    /// Adaptive supersampling: a base pass of 2 (spp 2) or 4 (spp >= 3) of each pixel's
    /// spp x spp samples, then all of them only where the relative contrast (linear, per
    /// channel and alpha) among those or against a neighbour's reaches T; 0 refines every
    /// pixel (the full image). Default: the scene's `adaptive`, else off.
    #[arg(long, value_name = "T")]
    adaptive: Option<f32>,
}

impl AccuracyArgs {
    /// Applies the flags over the scene's settings, or names the bad flag.
    pub fn apply(&self, st: &mut Settings) -> Result<()> {
        if let Some(p) = self.precision {
            st.precision = p.into();
        }
        let epsilon = match self.epsilon {
            Some(e) => Some(check_epsilon(e).map_err(|m| anyhow::anyhow!("--epsilon: {m}"))?),
            None => None,
        };
        let scene_epsilon = match st.offset {
            Offset::Epsilon(e) => e,
            _ => lumis_core::geometry::DEFAULT_EPSILON,
        };
        st.offset = match (self.offset, epsilon) {
            (Some(OffsetArg::ErrorBound), None) => Offset::ErrorBound,
            (Some(OffsetArg::Ulp), None) => Offset::Ulp,
            (Some(OffsetArg::Epsilon), e) => Offset::Epsilon(e.unwrap_or(scene_epsilon)),
            (None, Some(e)) if matches!(st.offset, Offset::Epsilon(_)) => Offset::Epsilon(e),
            (_, Some(_)) => bail!("--epsilon needs --offset epsilon"),
            (None, None) => st.offset,
        };
        Ok(())
    }
}

impl CutoffArgs {
    /// Applies `--cutoff` and `--adaptive` over the scene's settings.
    pub fn apply(&self, st: &mut Settings) -> Result<()> {
        if let Some(w) = self.cutoff {
            st.cutoff = check_cutoff(w).map_err(|m| anyhow::anyhow!("--cutoff: {m}"))?;
        }
        if let Some(t) = self.adaptive {
            st.adaptive = Some(check_adaptive(t).map_err(|m| anyhow::anyhow!("--adaptive: {m}"))?);
        }
        Ok(())
    }
}

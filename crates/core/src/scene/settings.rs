//! Render settings: what a scene file's `[render]` table (or a format's own keywords) sets and
//! the command line overrides.

use super::limits::{MAX_EXPOSURE, MAX_RADIANCE};
use crate::film::DisplayTransform;
use crate::geometry::{Offset, Precision};
use crate::math::Vec3;

/// The default contribution cutoff: branches below 1% of the pixel are not traced. Measured
/// in docs/accuracy.md (`lumis-lab accuracy`): 0.79x the time of no cutoff for +0.3% relMSE,
/// far below the sampling error of the default 2x2 samples. The `.scn` loader sets 0, so the
/// paper's scenes trace every branch to `maxReflections` (the paper's program itself stops
/// reflections below a refraction after one bounce; BENCHMARKS.md, Phase 7).
pub const DEFAULT_CUTOFF: f32 = 0.01;

/// Render settings a scene file may give; CLI flags override them.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel along each axis: `spp x spp` stratified samples.
    pub spp: u32,
    /// Longest chain of reflection/refraction bounces after the camera ray.
    pub max_depth: u32,
    /// Ambient radiance added as `ambient * kd` at every hit.
    pub ambient: Vec3,
    /// Radiance of rays that escape (counted as emitted: alpha 1 when non-black).
    pub background: Vec3,
    /// Exposure in stops applied to the PNG preview.
    pub exposure: f32,
    /// Lens samples per pixel sample (the `.scn` "depthComplexity"); used only with depth of field.
    pub lens_samples: u32,
    /// Index of refraction of the space outside every object (the `.scn` "startingMaterial").
    pub medium_ior: f32,
    /// How rays meet primitives (`precision`, `--precision`).
    pub precision: Precision,
    /// How secondary rays leave surfaces (`offset` and `epsilon`, `--offset`, `--epsilon`).
    pub offset: Offset,
    /// Reflection and refraction branches whose weight in the pixel falls below this are not
    /// traced (`cutoff`, `--cutoff`); 0 traces every branch up to `max_depth`. The default
    /// [`DEFAULT_CUTOFF`] sits at the knee of the measured curve (docs/accuracy.md).
    pub cutoff: f32,
    /// How the PNG preview encodes linear values (`display`, `--display`): the sRGB curve by
    /// default; `.scn` scenes clamp without a curve, as the paper's program writes its images.
    pub display: DisplayTransform,
    /// Adaptive supersampling (`adaptive`, `--adaptive T`): a base pass of a few of the
    /// `spp x spp` samples, the rest only where the relative contrast among a pixel's base
    /// samples or against a neighbour's exceeds `T` ([`crate::render`]); `None` takes every
    /// sample everywhere, and `Some(0.0)` refines every pixel (the same image).
    pub adaptive: Option<f32>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 360,
            spp: 2,
            max_depth: 5,
            ambient: Vec3::splat(0.05),
            background: Vec3::ZERO,
            exposure: 0.0,
            lens_samples: 1,
            medium_ior: 1.0,
            precision: Precision::default(),
            offset: Offset::default(),
            cutoff: DEFAULT_CUTOFF,
            display: DisplayTransform::Srgb,
            adaptive: None,
        }
    }
}

/// `t` if it is a usable adaptive threshold ([`Settings::adaptive`]): finite and >= 0.
pub fn check_adaptive(t: f32) -> Result<f32, String> {
    if t.is_finite() && t >= 0.0 {
        Ok(t)
    } else {
        Err(format!(
            "adaptive threshold {t} must be finite and >= 0 (0 refines every pixel)"
        ))
    }
}

/// Largest image rendered: 2^27 pixels (~11600 x 11600) keeps the film under ~6 GB.
pub const MAX_PIXELS: u64 = 1 << 27;
/// Longest image side.
pub const MAX_SIDE: u32 = 1 << 16;
/// Largest samples per pixel along each axis.
pub const MAX_SPP: u32 = 64;
/// Largest number of lens samples per pixel sample.
pub const MAX_LENS_SAMPLES: u32 = 64;
/// Deepest reflection/refraction recursion (each bounce is a stack frame of the integrator).
pub const MAX_DEPTH: u32 = 64;

/// A setting outside what the renderer accepts.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SettingsError {
    /// Sides within [`MAX_SIDE`] but more than [`MAX_PIXELS`] pixels in all.
    #[error("image size {0}x{1} is more than {MAX_PIXELS} pixels")]
    ImageSize(u32, u32),
    /// A count outside its range.
    #[error("{name} {value} must be in {min}..={max}")]
    Count {
        /// The setting, as scene files and flags name it.
        name: &'static str,
        /// Its value.
        value: u32,
        /// Smallest allowed.
        min: u32,
        /// Largest allowed.
        max: u32,
    },
    /// A number that is not finite or outside its range.
    #[error("{name} {value} must be {expected}")]
    Number {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f32,
        /// What it must be.
        expected: &'static str,
    },
}

impl Settings {
    /// Checks every limit; the one place they are written. Every loader calls this on what a
    /// file set, the command line after its overrides, and [`crate::render::render`] before
    /// it starts, so a value is refused with the same message wherever it came from.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let (w, h) = (self.width, self.height);
        for (name, value, min, max) in [
            ("width", w, 1, MAX_SIDE),
            ("height", h, 1, MAX_SIDE),
            ("spp", self.spp, 1, MAX_SPP),
            ("max_depth", self.max_depth, 0, MAX_DEPTH),
            ("lens samples", self.lens_samples, 1, MAX_LENS_SAMPLES),
        ] {
            if !(min..=max).contains(&value) {
                return Err(SettingsError::Count {
                    name,
                    value,
                    min,
                    max,
                });
            }
        }
        if w as u64 * h as u64 > MAX_PIXELS {
            return Err(SettingsError::ImageSize(w, h));
        }
        let number = |name, value: f32, ok: bool, expected| {
            if ok {
                Ok(())
            } else {
                Err(SettingsError::Number {
                    name,
                    value,
                    expected,
                })
            }
        };
        number(
            "exposure",
            self.exposure,
            self.exposure.abs() <= MAX_EXPOSURE,
            "finite, within +-64 stops",
        )?;
        number(
            "cutoff",
            self.cutoff,
            (0.0..=1.0).contains(&self.cutoff),
            "in [0, 1]",
        )?;
        number(
            "medium index of refraction",
            self.medium_ior,
            self.medium_ior.is_finite() && self.medium_ior > 0.0,
            "positive and finite",
        )?;
        for (name, c) in [("ambient", self.ambient), ("background", self.background)] {
            for v in c.to_array() {
                number(
                    name,
                    v,
                    v.is_finite() && (0.0..=MAX_RADIANCE).contains(&v),
                    "finite, in [0, 1e6]",
                )?;
            }
        }
        if let Some(t) = self.adaptive {
            number(
                "adaptive threshold",
                t,
                t.is_finite() && t >= 0.0,
                "finite and >= 0",
            )?;
        }
        if let Offset::Epsilon(e) = self.offset {
            number(
                "epsilon",
                e,
                e.is_finite() && e > 0.0,
                "positive and finite",
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_each_limit_is_refused_by_name() {
        assert_eq!(Settings::default().validate(), Ok(()));
        let refused = |edit: &dyn Fn(&mut Settings)| {
            let mut s = Settings::default();
            edit(&mut s);
            s.validate().unwrap_err().to_string()
        };
        assert_eq!(refused(&|s| s.width = 0), "width 0 must be in 1..=65536");
        assert_eq!(
            refused(&|s| s.height = MAX_SIDE + 1),
            "height 65537 must be in 1..=65536"
        );
        // Within each side's limit, but too many pixels in all.
        assert_eq!(
            refused(&|s| (s.width, s.height) = (MAX_SIDE, MAX_SIDE)),
            "image size 65536x65536 is more than 134217728 pixels"
        );
        assert_eq!(refused(&|s| s.spp = 0), "spp 0 must be in 1..=64");
        assert_eq!(refused(&|s| s.spp = 65), "spp 65 must be in 1..=64");
        assert_eq!(
            refused(&|s| s.max_depth = 65),
            "max_depth 65 must be in 0..=64"
        );
        assert_eq!(
            refused(&|s| s.lens_samples = 0),
            "lens samples 0 must be in 1..=64"
        );
        assert_eq!(
            refused(&|s| s.exposure = f32::NAN),
            "exposure NaN must be finite, within +-64 stops"
        );
        assert_eq!(
            refused(&|s| s.exposure = 65.0),
            "exposure 65 must be finite, within +-64 stops"
        );
        assert!(refused(&|s| s.background.x = 2e6).starts_with("background 2000000 must be"));
        assert_eq!(refused(&|s| s.cutoff = 1.5), "cutoff 1.5 must be in [0, 1]");
        assert!(refused(&|s| s.medium_ior = 0.0).starts_with("medium index of refraction 0"));
        assert!(refused(&|s| s.ambient.y = -1.0).starts_with("ambient -1"));
        assert!(refused(&|s| s.background.x = f32::INFINITY).starts_with("background inf"));
        assert!(refused(&|s| s.offset = Offset::Epsilon(0.0)).starts_with("epsilon 0"));
        assert_eq!(
            refused(&|s| s.adaptive = Some(-0.1)),
            "adaptive threshold -0.1 must be finite and >= 0"
        );
        assert_eq!(
            refused(&|s| s.adaptive = Some(f32::NAN)),
            "adaptive threshold NaN must be finite and >= 0"
        );
        // The edges of each range are accepted.
        let mut s = Settings {
            spp: MAX_SPP,
            max_depth: 0,
            lens_samples: MAX_LENS_SAMPLES,
            cutoff: 1.0,
            adaptive: Some(0.0),
            ..Settings::default()
        };
        (s.width, s.height) = (MAX_SIDE, (MAX_PIXELS / MAX_SIDE as u64) as u32);
        assert_eq!(s.validate(), Ok(()));
    }
}

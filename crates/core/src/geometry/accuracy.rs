//! The accuracy choices of ray queries and secondary rays: how primitives are intersected
//! ([`Precision`]) and how rays leave a surface ([`Offset`]). Both are scene settings
//! (`[render] precision`, `offset`, `epsilon`) and flags (`--precision`, `--offset`,
//! `--epsilon`), honoured by every accelerator, the renderer and `lumis hits`.
//!
//! ```toml
//! [render]
//! precision = "watertight"   # fast | watertight | double
//! offset = "error-bound"     # error-bound | ulp | epsilon
//! epsilon = 1e-4             # scene units, for offset = "epsilon"
//! ```
//!
//! `docs/accuracy.md` measures what each choice costs in time and buys in error.

use std::fmt;
use std::str::FromStr;

/// How ray/primitive intersections are computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Precision {
    /// `f32` Moller-Trumbore triangles without watertightness and the textbook `f32` sphere
    /// quadratic: what many renderers ship. Rays slip through shared edges, more so far from
    /// the origin; huge spheres lose their digits.
    Fast,
    /// The watertight triangle test (Woop et al. 2013) with an `f64` plane distance, and the
    /// cancellation-free sphere test: no leaks at shared edges and vertices, `t` to a few ulps.
    #[default]
    Watertight,
    /// Everything in `f64` (the watertight algorithm evaluated in `f64`, spheres with
    /// error-free arithmetic throughout): the reference of the accuracy curves.
    Double,
}

/// How a secondary ray's origin leaves the surface it starts on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Offset {
    /// Past the hit point's own rounding-error bound along the geometric normal, then one ulp
    /// (pbrt-v4's `OffsetRayOrigin`): no acne, and the smallest push that guarantees it, so
    /// contact shadows survive far from the origin.
    #[default]
    ErrorBound,
    /// The error-bound push plus a fixed 256-ulp step of the coordinates (Ray Tracing Gems
    /// ch. 6), lumis's rule before the accuracy options: the step grows with the distance from
    /// the origin (0.5 units at 1e5) and lifts shadow rays over nearby occluders.
    Ulp,
    /// A fixed distance along the geometric normal, in scene units: the classic epsilon.
    /// Too small far from the origin (acne), too large near small geometry (lost shadows).
    Epsilon(f32),
}

/// The default of `--epsilon`, in scene units.
pub const DEFAULT_EPSILON: f32 = 1e-4;

impl Precision {
    /// Every choice, for sweeps and tests.
    pub const ALL: [Precision; 3] = [Precision::Fast, Precision::Watertight, Precision::Double];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Precision::Fast => "fast",
            Precision::Watertight => "watertight",
            Precision::Double => "double",
        }
    }
}

impl Offset {
    /// The name used in scene files and on the command line (without the epsilon value).
    pub fn name(self) -> &'static str {
        match self {
            Offset::ErrorBound => "error-bound",
            Offset::Ulp => "ulp",
            Offset::Epsilon(_) => "epsilon",
        }
    }

    /// The offset called `name`, with `epsilon` for the fixed-distance rule.
    pub fn from_name(name: &str, epsilon: f32) -> Result<Self, String> {
        match name {
            "error-bound" => Ok(Offset::ErrorBound),
            "ulp" => Ok(Offset::Ulp),
            "epsilon" => Ok(Offset::Epsilon(epsilon)),
            _ => Err(format!(
                "unknown offset {name:?}; expected error-bound, ulp or epsilon"
            )),
        }
    }
}

impl FromStr for Precision {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Precision::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| format!("unknown precision {s:?}; expected fast, watertight or double"))
    }
}

impl fmt::Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for Offset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Offset::Epsilon(e) => write!(f, "epsilon {e:e}"),
            other => f.write_str(other.name()),
        }
    }
}

/// Checks an epsilon given for the fixed-distance offset.
pub fn check_epsilon(e: f32) -> Result<f32, String> {
    if e > 0.0 && e.is_finite() {
        Ok(e)
    } else {
        Err(format!("epsilon {e} must be positive and finite"))
    }
}

/// Checks a contribution cutoff: a weight in `[0, 1]` (0 turns the cutoff off).
pub fn check_cutoff(w: f32) -> Result<f32, String> {
    if (0.0..=1.0).contains(&w) {
        Ok(w)
    } else {
        Err(format!("cutoff {w} must lie in [0, 1] (0 = off)"))
    }
}

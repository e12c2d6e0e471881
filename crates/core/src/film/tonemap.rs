//! Tone mapping of the PNG preview: how exposed linear values above 1 are brought into the
//! display range before the display transform encodes them. The EXR is never tone mapped.

use std::fmt;
use std::str::FromStr;

/// The curve applied per channel to the exposed linear value of the PNG (`--tonemap`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Tonemap {
    /// No curve: values above 1 clip in the display transform.
    #[default]
    None,
    /// Krzysztof Narkowicz's fit of the ACES reference rendering and output transforms
    /// ("ACES Filmic Tone Mapping Curve", 2016, knarkowicz.wordpress.com):
    /// `f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to [0, 1]. A toe that
    /// deepens shadows, mid-grey 0.18 to about 0.267, and a shoulder that reaches 1 at
    /// x = 7.24 instead of clipping at 1. Its output is display-linear, so the sRGB curve follows.
    Filmic,
}

impl Tonemap {
    /// Both curves, in documentation order.
    pub const ALL: [Tonemap; 2] = [Tonemap::None, Tonemap::Filmic];

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Tonemap::None => "none",
            Tonemap::Filmic => "filmic",
        }
    }

    /// The tone-mapped value of an exposed linear value. `None` passes the value through
    /// (the display transform clamps it); `Filmic` maps [0, inf) into [0, 1], NaN and negative
    /// values to 0.
    pub fn apply(self, linear: f32) -> f32 {
        match self {
            Tonemap::None => linear,
            Tonemap::Filmic => aces_narkowicz(linear),
        }
    }
}

/// Narkowicz's rational ACES fit (coefficients from the publication), clamped to [0, 1].
fn aces_narkowicz(x: f32) -> f32 {
    const A: f32 = 2.51;
    const B: f32 = 0.03;
    const C: f32 = 2.43;
    const D: f32 = 0.59;
    const E: f32 = 0.14;
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    if x.is_infinite() {
        return 1.0;
    }
    (x * (A * x + B) / (x * (C * x + D) + E)).min(1.0)
}

impl FromStr for Tonemap {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Tonemap::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| format!("unknown tonemap {s:?}; expected none or filmic"))
    }
}

impl fmt::Display for Tonemap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filmic_known_values() {
        let f = |x| Tonemap::Filmic.apply(x);
        assert_eq!([f(0.0), f(-1.0), f(f32::NAN)], [0.0, 0.0, 0.0]);
        // By hand from the formula: 0.18 * 0.4818 / (0.18 * 1.0274 + 0.14) = 0.266899.
        assert!((f(0.18) - 0.266_899).abs() < 1e-5, "{}", f(0.18));
        // 2.54 / 3.16 = 0.803797.
        assert!((f(1.0) - 0.803_797).abs() < 1e-5, "{}", f(1.0));
        // 2 * 5.05 / (2 * 5.45 + 0.14) = 10.1 / 11.04 = 0.914855.
        assert!((f(2.0) - 0.914_855).abs() < 1e-5, "{}", f(2.0));
        // The shoulder crosses 1 where 0.08 x^2 - 0.56 x - 0.14 = 0, x = 7.24, then stays clamped.
        assert!(f(7.2) < 1.0 && f(7.3) == 1.0);
        assert_eq!([f(1e6), f(f32::INFINITY)], [1.0, 1.0]);
        // Monotonic over the range a render produces.
        let samples: Vec<f32> = (0..=1000).map(|i| f(i as f32 * 0.012)).collect();
        assert!(samples.windows(2).all(|w| w[0] <= w[1]));
    }

    #[test]
    fn none_passes_values_through_and_names_round_trip() {
        assert_eq!(Tonemap::None.apply(3.5), 3.5);
        for t in Tonemap::ALL {
            assert_eq!(t.name().parse::<Tonemap>(), Ok(t));
            assert_eq!(t.to_string(), t.name());
        }
        assert!(
            "aces"
                .parse::<Tonemap>()
                .unwrap_err()
                .contains("none or filmic")
        );
    }
}

//! The display transform of the PNG preview: how a linear value becomes an 8-bit code value.
//! The EXR is always linear; only the PNG is display-referred.

use std::fmt;
use std::str::FromStr;

/// How the PNG encodes linear values after exposure (`display` in a scene's `[render]`,
/// `--display` on the command line).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DisplayTransform {
    /// The sRGB transfer curve (IEC 61966-2-1): the PNG shows the linear image as a monitor
    /// should. The default for every format but `.scn`.
    #[default]
    Srgb,
    /// No transfer curve: `clamp(value, 0, 1) * 255`, rounded. The paper's program writes its
    /// images this way (its colours are display values already), so `.scn` scenes default to it
    /// and their PNGs compare directly with the original's TGAs.
    Clamp,
}

impl DisplayTransform {
    /// Both transforms, in documentation order.
    pub const ALL: [DisplayTransform; 2] = [DisplayTransform::Srgb, DisplayTransform::Clamp];

    /// The name used by scene files and the command line.
    pub fn name(self) -> &'static str {
        match self {
            DisplayTransform::Srgb => "srgb",
            DisplayTransform::Clamp => "clamp",
        }
    }

    /// The 8-bit code value of a linear value (exposure already applied). NaN and values
    /// below 0 give 0, values above 1 give 255.
    pub fn encode8(self, linear: f32) -> u8 {
        match self {
            DisplayTransform::Srgb => linear_to_srgb8(linear),
            DisplayTransform::Clamp => (unit(linear) * 255.0 + 0.5) as u8,
        }
    }
}

/// `linear` clamped to `[0, 1]`, NaN to 0 (tested explicitly: `clamp` would pass NaN through
/// to the cast).
fn unit(linear: f32) -> f32 {
    if linear.is_nan() || linear <= 0.0 {
        0.0
    } else {
        linear.min(1.0)
    }
}

/// Linear value to an 8-bit sRGB code value (IEC 61966-2-1), clamped, rounded to nearest.
pub fn linear_to_srgb8(linear: f32) -> u8 {
    let c = unit(linear);
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0 + 0.5) as u8
}

impl FromStr for DisplayTransform {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        DisplayTransform::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| format!("unknown display {s:?}; expected srgb or clamp"))
    }
}

impl fmt::Display for DisplayTransform {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_known_values() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(0.5), 188);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(7.0), 255);
        assert_eq!(linear_to_srgb8(f32::INFINITY), 255);
        // Linear segment: 0.001 * 12.92 * 255 = 3.29.
        assert_eq!(linear_to_srgb8(0.001), 3);
    }

    #[test]
    fn clamp_known_values() {
        let c = |v| DisplayTransform::Clamp.encode8(v);
        assert_eq!([c(0.0), c(-1.0), c(f32::NAN)], [0, 0, 0]);
        // 0.5 * 255 = 127.5 rounds up; 0.2 * 255 = 51 exactly; 0.001 * 255 = 0.255 rounds down.
        assert_eq!([c(0.5), c(0.2), c(0.001)], [128, 51, 0]);
        assert_eq!([c(1.0), c(7.0), c(f32::INFINITY)], [255, 255, 255]);
        // Rounding, not truncation: 100.6 / 255 gives 101.
        assert_eq!(c(100.6 / 255.0), 101);
        assert_eq!(DisplayTransform::Srgb.encode8(0.5), 188);
    }

    #[test]
    fn names_round_trip() {
        for d in DisplayTransform::ALL {
            assert_eq!(d.name().parse::<DisplayTransform>(), Ok(d));
            assert_eq!(d.to_string(), d.name());
        }
        assert_eq!(DisplayTransform::default(), DisplayTransform::Srgb);
        assert!(
            "sRGB"
                .parse::<DisplayTransform>()
                .unwrap_err()
                .contains("srgb or clamp")
        );
    }
}

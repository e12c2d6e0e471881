//! The value sets of the flags that name a library choice (`--accel`, `--traversal`,
//! `--precision`, `--offset`, `--up`, `--display`, `--tonemap`), as clap enums mapped onto the library's own.
//!
//! The library stays free of clap; the variants' doc comments here are the `--help` text of
//! each value, and the spellings clap derives from the variant names are the accepted values.

use clap::ValueEnum;
use lumis_core::accel::AccelKind;
use lumis_core::film::{DisplayTransform, Tonemap};
use lumis_core::geometry::Precision;
use lumis_core::scene::UpAxis;

/// `--accel`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AccelArg {
    /// Test every primitive: the reference all others are checked against.
    Brute,
    /// The paper's baseline: split at the spatial centre, axes cycling x, y, z.
    Bsp,
    /// The paper's BSMP: split at the median primitive centroid, axes cycling.
    Bsmp,
    /// Binned surface-area-heuristic BVH, collapsed to 8-wide SIMD nodes with packed leaves.
    Sah,
}

impl From<AccelArg> for AccelKind {
    fn from(a: AccelArg) -> Self {
        match a {
            AccelArg::Brute => AccelKind::Brute,
            AccelArg::Bsp => AccelKind::Bsp,
            AccelArg::Bsmp => AccelKind::Bsmp,
            AccelArg::Sah => AccelKind::Sah,
        }
    }
}

/// `--traversal`; segment lengths come from their own flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TraversalArg {
    Ordered,
    Segments,
    /// The paper's own walk: every crossed node, no order, no culling (for comparisons).
    Exhaustive,
}

/// `--precision`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    Fast,
    Watertight,
    Double,
}

impl From<PrecisionArg> for Precision {
    fn from(p: PrecisionArg) -> Self {
        match p {
            PrecisionArg::Fast => Precision::Fast,
            PrecisionArg::Watertight => Precision::Watertight,
            PrecisionArg::Double => Precision::Double,
        }
    }
}

/// `--offset`; the epsilon's distance comes from `--epsilon` or the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OffsetArg {
    ErrorBound,
    Ulp,
    Epsilon,
}

/// `--up`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum UpArg {
    /// +Y is up (glTF's convention, and the default).
    Y,
    /// +Z is up: the model is turned -90 degrees about X, so +Z goes to +Y and -Y (the usual
    /// front of a Z-up model) to +Z.
    Z,
}

impl From<UpArg> for UpAxis {
    fn from(u: UpArg) -> Self {
        match u {
            UpArg::Y => UpAxis::Y,
            UpArg::Z => UpAxis::Z,
        }
    }
}

/// `--display`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DisplayArg {
    /// The sRGB transfer curve (IEC 61966-2-1): the PNG shows the linear image as a monitor
    /// should. The default for every format but `.scn`.
    Srgb,
    /// No transfer curve: `clamp(value, 0, 1) * 255`, rounded. The paper's program writes its
    /// images this way (its colours are display values already), so `.scn` scenes default to it
    /// and their PNGs compare directly with the original's TGAs.
    Clamp,
}

impl From<DisplayArg> for DisplayTransform {
    fn from(d: DisplayArg) -> Self {
        match d {
            DisplayArg::Srgb => DisplayTransform::Srgb,
            DisplayArg::Clamp => DisplayTransform::Clamp,
        }
    }
}

/// `--tonemap`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum TonemapArg {
    /// No curve: values above 1 clip.
    #[default]
    None,
    /// Narkowicz's fit of the ACES filmic curve: a soft shoulder up to 1 at 7.24 x white.
    Filmic,
}

impl From<TonemapArg> for Tonemap {
    fn from(t: TonemapArg) -> Self {
        match t {
            TonemapArg::None => Tonemap::None,
            TonemapArg::Filmic => Tonemap::Filmic,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flag's spelling of each value.
    fn names<T: ValueEnum>() -> Vec<String> {
        T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_owned())
            .collect()
    }

    /// The value of `--accel` naming `kind`: a match, so a kind added to the library does not
    /// compile here until it has a flag value.
    fn accel_arg(kind: AccelKind) -> AccelArg {
        match kind {
            AccelKind::Brute => AccelArg::Brute,
            AccelKind::Bsp => AccelArg::Bsp,
            AccelKind::Bsmp => AccelArg::Bsmp,
            AccelKind::Sah => AccelArg::Sah,
        }
    }

    #[test]
    fn every_accel_kind_has_one_flag_value_and_all_lists_them() {
        assert_eq!(names::<AccelArg>(), ["brute", "bsp", "bsmp", "sah"]);
        // `AccelKind::ALL` is what the integration tests run over: it must hold every kind.
        let kinds: Vec<AccelKind> = AccelArg::value_variants()
            .iter()
            .map(|&a| a.into())
            .collect();
        assert_eq!(kinds, AccelKind::ALL);
        for kind in AccelKind::ALL {
            assert_eq!(AccelKind::from(accel_arg(kind)), kind);
            assert_eq!(
                accel_arg(kind).to_possible_value().unwrap().get_name(),
                kind.name()
            );
        }
    }

    #[test]
    fn the_values_keep_the_library_names() {
        assert_eq!(
            names::<TraversalArg>(),
            ["ordered", "segments", "exhaustive"]
        );
        let precisions: Vec<String> = PrecisionArg::value_variants()
            .iter()
            .map(|&p| Precision::from(p).name().to_owned())
            .collect();
        assert_eq!(names::<PrecisionArg>(), precisions);
        assert_eq!(names::<OffsetArg>(), ["error-bound", "ulp", "epsilon"]);
        let up: Vec<UpAxis> = UpArg::value_variants().iter().map(|&u| u.into()).collect();
        assert_eq!(up, UpAxis::ALL);
        let up_names: Vec<&str> = up.iter().map(|u| u.name()).collect();
        assert_eq!(names::<UpArg>(), up_names);
        let displays: Vec<String> = DisplayArg::value_variants()
            .iter()
            .map(|&d| DisplayTransform::from(d).name().to_owned())
            .collect();
        assert_eq!(names::<DisplayArg>(), displays);
        assert_eq!(
            DisplayArg::value_variants()
                .iter()
                .map(|&d| DisplayTransform::from(d))
                .collect::<Vec<_>>(),
            DisplayTransform::ALL
        );
        let tonemaps: Vec<Tonemap> = TonemapArg::value_variants()
            .iter()
            .map(|&t| t.into())
            .collect();
        assert_eq!(tonemaps, Tonemap::ALL);
        let names_of: Vec<&str> = Tonemap::ALL.iter().map(|t| t.name()).collect();
        assert_eq!(names::<TonemapArg>(), names_of);
    }
}

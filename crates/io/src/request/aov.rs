//! The extra layers a render can be asked for by name (`--aov`, `aovs=`): the EXR's AOV
//! layers and its light-path passes.

use std::fmt;
use std::str::FromStr;

use lumis_core::render::PassRequest;

use crate::output::AovLayers;

/// One extra layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// `albedo.R/G/B`: the material's diffuse colour at the hit.
    Albedo,
    /// `P.X/Y/Z`: the world-space hit point.
    Position,
    /// `uv.U/V`: texture coordinates at the hit.
    Uv,
    /// The light-path passes (`diffuse`, `specular`, `reflection`, `refraction`, `emission`,
    /// `ambient`, `background`), which add up to the beauty.
    LightPaths,
    /// One pass per light, `light.<name>`.
    Lights,
    /// `samples`: the pixel samples each pixel took (fewer than `spp x spp` where adaptive
    /// supersampling found the base pass enough).
    Samples,
}

impl Aov {
    /// Every layer, in documentation order.
    pub const ALL: [Aov; 6] = [
        Aov::Albedo,
        Aov::Position,
        Aov::Uv,
        Aov::LightPaths,
        Aov::Lights,
        Aov::Samples,
    ];

    /// The name used on the command line (`--aov`) and in Python (`aovs=`).
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Position => "position",
            Aov::Uv => "uv",
            Aov::LightPaths => "lightpaths",
            Aov::Lights => "lights",
            Aov::Samples => "samples",
        }
    }
}

impl FromStr for Aov {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Aov::ALL.into_iter().find(|a| a.name() == s).ok_or_else(|| {
            format!(
                "unknown AOV {s:?}; expected albedo, position, uv, lightpaths, lights or samples"
            )
        })
    }
}

impl fmt::Display for Aov {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The AOV layers `aovs` asks for, with `id.instance` whenever the scene has `instances`
/// (never asked for by name).
pub fn aov_layers(aovs: &[Aov], instances: bool) -> AovLayers {
    AovLayers {
        albedo: aovs.contains(&Aov::Albedo),
        position: aovs.contains(&Aov::Position),
        uv: aovs.contains(&Aov::Uv),
        samples: aovs.contains(&Aov::Samples),
        instance: instances,
    }
}

/// The RGB passes `aovs` asks for; none unless an EXR is written (only EXR has pass layers).
pub fn pass_request(aovs: &[Aov], writes_exr: bool) -> PassRequest {
    PassRequest {
        light_paths: writes_exr && aovs.contains(&Aov::LightPaths),
        lights: writes_exr && aovs.contains(&Aov::Lights),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_nothing_else_does() {
        for aov in Aov::ALL {
            assert_eq!(aov.name().parse::<Aov>(), Ok(aov));
            assert_eq!(aov.to_string(), aov.name());
        }
        for bad in ["", "Albedo", "light_paths", "lightpaths "] {
            assert!(bad.parse::<Aov>().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn each_name_turns_on_its_own_layer() {
        let none = aov_layers(&[], false);
        assert_eq!(none, AovLayers::default());
        assert!(aov_layers(&[], true).instance);
        let uv = aov_layers(&[Aov::Uv], false);
        assert!(uv.uv && !uv.albedo && !uv.position && !uv.instance);
        let all = aov_layers(&Aov::ALL, false);
        assert!(all.albedo && all.position && all.uv);
        let passes = pass_request(&[Aov::Lights], true);
        assert!(passes.lights && !passes.light_paths);
        let passes = pass_request(&Aov::ALL, false);
        assert!(!passes.lights && !passes.light_paths);
    }
}

//! The flags of `lumis render` that choose what the EXR holds beyond the beauty, depth,
//! normal and id layers: extra AOVs, Cryptomatte, the channel naming, transparent misses.

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use lumis_core::cryptomatte::{DEFAULT_LEVELS, MAX_LEVELS};
use lumis_core::render::PassRequest;
use lumis_io::output::{AovLayers, ChannelLayout};
use lumis_io::request::{Aov, aov_layers, pass_request};

/// One value of `--aov`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AovArg {
    /// albedo.R/G/B: the material's diffuse colour kd at the hit, textures evaluated, not lit.
    Albedo,
    /// P.X/Y/Z: the world-space hit point (projects through worldToNDC onto the pixel centre).
    Position,
    /// uv.U/V: texture coordinates at the hit (a mesh's uvs, else its barycentrics; on
    /// spheres u = (atan2(z, x) + pi) / 2pi, v = acos(y / r) / pi, v = 0 at the top).
    Uv,
    /// The light-path passes, each RGB over every sample like the beauty, which they add up
    /// to: diffuse and specular (direct light at the first hit), reflection and refraction
    /// (everything seen through the first hit's mirror or refracted ray), emission, ambient
    /// (the environment's diffuse light, if any), background (escaping camera rays).
    Lightpaths,
    /// One RGB pass per light, light.<name>: its direct diffuse + specular at the first hit
    /// (they add up to diffuse + specular).
    Lights,
    /// samples: the pixel samples each pixel took (spp x spp, fewer where --adaptive kept a
    /// pixel's base pass).
    Samples,
}

/// `--layout`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LayoutArg {
    /// R, G, B, A, Z, N.X, id.object, albedo.R, P.X, uv.U, CryptoObject00.R, ...
    Lumis,
    /// Blender's multilayer names: ViewLayer.Combined.R, ViewLayer.Depth.Z,
    /// ViewLayer.Normal.X, ViewLayer.IndexOB.X, ViewLayer.IndexPrim.X, ViewLayer.DiffCol.R,
    /// ViewLayer.Position.X, ViewLayer.UV.U/V/A (A: 1 on hits), ViewLayer.CryptoObject00.R;
    /// the light paths as ViewLayer.DiffDir, GlossDir, GlossInd, TransInd, Emit, Env (and
    /// lumis's Ambient), each light as ViewLayer.Combined_<name>, the shadow catcher's pass
    /// as ViewLayer.Shadow Catcher.
    Blender,
}

impl From<AovArg> for Aov {
    fn from(a: AovArg) -> Self {
        match a {
            AovArg::Albedo => Aov::Albedo,
            AovArg::Position => Aov::Position,
            AovArg::Uv => Aov::Uv,
            AovArg::Lightpaths => Aov::LightPaths,
            AovArg::Lights => Aov::Lights,
            AovArg::Samples => Aov::Samples,
        }
    }
}

impl From<LayoutArg> for ChannelLayout {
    fn from(l: LayoutArg) -> Self {
        match l {
            LayoutArg::Lumis => ChannelLayout::Lumis,
            LayoutArg::Blender => ChannelLayout::Blender,
        }
    }
}

/// EXR passes and alpha.
#[derive(Args, Debug)]
pub struct PassArgs {
    /// EXR only: extra AOV layers, a comma list or repeated, from the pinhole ray through
    /// each pixel centre like Z and N (0 where it misses). Ignored for a PNG-only output.
    #[arg(long, value_enum, value_delimiter = ',', value_name = "LIST")]
    aov: Vec<AovArg>,
    /// EXR only: CryptoObject and CryptoMaterial layers (Cryptomatte 1.1.0): anti-aliased
    /// mattes by object and material name from every camera sample, with their manifest.
    #[arg(long)]
    cryptomatte: bool,
    /// Cryptomatte ranks (ids) kept per pixel, 1 to 128; two per RGBA layer
    /// (CryptoObject00, CryptoObject01, ...). Needs --cryptomatte.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_LEVELS, requires = "cryptomatte")]
    cryptomatte_levels: u32,
    /// EXR channel names: lumis's own or Blender's multilayer convention (same values; the
    /// Blender UV pass adds its A channel).
    #[arg(long, value_enum, default_value = "lumis")]
    layout: LayoutArg,
    /// Camera rays that hit nothing are transparent: A = 0 and no background colour there
    /// (reflections and refractions still see the background), so edges carry fractional,
    /// premultiplied alpha for compositing over a plate. Without it a miss is the background
    /// colour with A = 1 (A = 0 only when the background is black).
    #[arg(long)]
    transparent: bool,
}

impl PassArgs {
    /// The optional AOV layers asked for, with `id.instance` when the scene has instances.
    pub fn aov_layers(&self, instances: bool) -> AovLayers {
        aov_layers(&self.aovs(), instances)
    }

    /// The RGB passes to fill (none unless an EXR is written).
    pub fn pass_request(&self, writes_exr: bool) -> PassRequest {
        pass_request(&self.aovs(), writes_exr)
    }

    fn aovs(&self) -> Vec<Aov> {
        self.aov.iter().map(|&a| a.into()).collect()
    }

    /// The Cryptomatte ranks per pixel, or `None` without `--cryptomatte`.
    pub fn cryptomatte(&self) -> Result<Option<u32>> {
        if !self.cryptomatte {
            return Ok(None);
        }
        if !(1..=MAX_LEVELS).contains(&self.cryptomatte_levels) {
            bail!(
                "--cryptomatte-levels {}: expected 1 to {MAX_LEVELS}",
                self.cryptomatte_levels
            );
        }
        Ok(Some(self.cryptomatte_levels))
    }

    /// The channel naming.
    pub fn layout(&self) -> ChannelLayout {
        self.layout.into()
    }

    /// Whether misses are transparent.
    pub fn transparent(&self) -> bool {
        self.transparent
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

    #[test]
    fn the_values_are_the_library_names() {
        let aovs: Vec<&str> = AovArg::value_variants()
            .iter()
            .map(|&a| Aov::from(a).name())
            .collect();
        assert_eq!(names::<AovArg>(), aovs);
        assert_eq!(
            AovArg::value_variants()
                .iter()
                .map(|&a| Aov::from(a))
                .collect::<Vec<_>>(),
            Aov::ALL
        );
        let layouts: Vec<ChannelLayout> = LayoutArg::value_variants()
            .iter()
            .map(|&l| l.into())
            .collect();
        assert_eq!(layouts, ChannelLayout::ALL);
        let names_of_layouts: Vec<&str> = layouts.iter().map(|l| l.name()).collect();
        assert_eq!(names::<LayoutArg>(), names_of_layouts);
    }
}

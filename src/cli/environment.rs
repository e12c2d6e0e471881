//! `--env FILE` and its companions: the HDR environment around the scene, for every scene
//! format. Each flag stands for a `-D environment.KEY=VALUE` applied after the `-D`s (explicit
//! flags win), so it meets the `[environment]` table's schema and checks
//! (`lumis_io::formats::toml`, `environment.rs`).

use anyhow::{Context, Result};
use clap::Args;
use lumis_io::formats::Override;

/// `--env`, `--env-rotation`, `--env-intensity`, `--env-sun`.
#[derive(Args, Debug, Default)]
pub struct EnvironmentArgs {
    /// HDR environment: a latitude-longitude Radiance .hdr or OpenEXR image around the
    /// scene, oriented as Mitsuba 3's envmap (Y up; the image centre looks along +Z). Escaping
    /// rays see it and it lights every surface as ambient light (its diffuse irradiance,
    /// unshadowed); it replaces the scene's background and ambient colours.
    #[arg(long, value_name = "FILE")]
    env: Option<std::path::PathBuf>,
    /// Turns the environment about the up axis (+Y) by DEG degrees, as Mitsuba's
    /// <rotate y="1" angle="DEG"/> on the envmap's to_world does.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    env_rotation: Option<f64>,
    /// Scales the environment's radiance.
    #[arg(long, value_name = "X")]
    env_intensity: Option<f64>,
    /// Takes the environment's sun (its brightest compact region) out of the map as a
    /// directional light named "sun", with hard shadows; refused, with the numbers, for a map
    /// without one.
    #[arg(long)]
    env_sun: bool,
}

impl EnvironmentArgs {
    /// The flags as `-D environment.*` overrides, to apply after the command line's `-D`s.
    pub fn overrides(&self) -> Result<Vec<Override>> {
        let mut out = Vec::new();
        if let Some(file) = &self.env {
            // Absolute, since a scene resolves relative paths against its own folder and a
            // flag's path is the shell's.
            let file =
                std::path::absolute(file).with_context(|| format!("--env {}", file.display()))?;
            let text = file
                .to_str()
                .with_context(|| format!("--env {}: not a UTF-8 path", file.display()))?;
            out.push(Override::string("environment.file", text).map_err(anyhow::Error::msg)?);
        }
        if let Some(r) = self.env_rotation {
            out.push(Override::number("environment.rotation", r).map_err(anyhow::Error::msg)?);
        }
        if let Some(i) = self.env_intensity {
            out.push(Override::number("environment.intensity", i).map_err(anyhow::Error::msg)?);
        }
        if self.env_sun {
            out.push(Override::boolean("environment.sun", true).map_err(anyhow::Error::msg)?);
        }
        Ok(out)
    }
}

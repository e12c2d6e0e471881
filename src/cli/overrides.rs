//! The render flags pbrt-v4 and Mitsuba 3 users reach for first, as one group of
//! `lumis render`: `-D KEY=VALUE` scene parameters, `--samples` (a total count), `--background`,
//! `--tonemap` and `--quick`.
//!
//! Precedence, lowest first: the scene file, then `-D` (in order, the last wins), then the
//! explicit flags (`--width`, `--spp`, `--samples`, `--background`, ...), then `--quick`,
//! which cuts down whatever render the rest describes.

use super::values::TonemapArg;
use anyhow::{Result, bail};
use clap::Args;
use lumis_core::film::Tonemap;
use lumis_core::math::Vec3;
use lumis_core::scene::{MAX_SPP, Settings};
use lumis_io::formats::Override;

/// What `--quick` divides each image side by (pbrt-v4's `--quick` does the same).
pub const QUICK_DIVISOR: u32 = 4;
/// The deepest reflection/refraction chain of a `--quick` render: enough to see through a
/// glass sphere (in and out) and one mirror.
pub const QUICK_MAX_DEPTH: u32 = 3;

/// `-D`, `--samples`, `--background`, `--tonemap`, `--quick`.
#[derive(Args, Debug, Default)]
pub struct OverrideArgs {
    /// Set a scene parameter as the scene file would, checked the same way. KEY is a dotted
    /// TOML key: render.spp, camera.fov, materials.NAME.ior, sphere.0.radius (by index) or
    /// sphere.NAME.radius (by name); VALUE a TOML value (4, 30.5, "srgb", [1,2,3], true; a
    /// bare word is a string). Repeatable: a later -D wins over an earlier one, -D wins over
    /// the file, and explicit flags (--spp, --width, ...) win over -D. Files other than TOML
    /// take only render.* keys (render.spp is per axis, as in the file).
    #[arg(short = 'D', value_name = "KEY=VALUE", value_parser = parse_override)]
    define: Vec<Override>,
    /// Samples per pixel in all (not per axis, unlike --spp), rounded to the nearest square
    /// for the stratified grid: --samples 10 renders 9 (3x3) and says so.
    #[arg(long, value_name = "N", conflicts_with = "spp",
          value_parser = clap::value_parser!(u32).range(1..))]
    samples: Option<u32>,
    /// Linear radiance of rays that miss everything, overriding the scene's background in
    /// every format (e.g. 0.2,0.3,0.5).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb)]
    background: Option<Vec3>,
    /// PNG tone curve between the exposure and the display transform; the EXR stays linear.
    #[arg(long, value_enum, default_value_t = TonemapArg::None)]
    tonemap: TonemapArg,
    /// Fast preview: each image side / 4 (at least 1 pixel), 1 sample per pixel, 1 lens
    /// sample (depth of field stays, sampled once), max depth at most 3. Applied last, to the
    /// render the scene, -D and the other flags describe.
    #[arg(long)]
    quick: bool,
}

impl OverrideArgs {
    /// The `-D` overrides, in command-line order.
    pub fn defines(&self) -> &[Override] {
        &self.define
    }

    /// Applies `--samples`, `--background` and then `--quick` over `st` (after the scene,
    /// `-D` and the other flags); says on stderr, unless `quiet`, what was rounded or cut.
    pub fn apply(&self, st: &mut Settings, quiet: bool) -> Result<()> {
        if let Some(n) = self.samples {
            let side = nearest_square_side(n);
            if side > MAX_SPP {
                bail!(
                    "--samples {n}: at most {} ({MAX_SPP}x{MAX_SPP}) samples per pixel",
                    MAX_SPP * MAX_SPP
                );
            }
            if side * side != n && !quiet {
                eprintln!("--samples {n}: using {} ({side}x{side})", side * side);
            }
            st.spp = side;
        }
        if let Some(bg) = self.background {
            st.background = bg;
        }
        if self.quick {
            st.width = (st.width / QUICK_DIVISOR).max(1);
            st.height = (st.height / QUICK_DIVISOR).max(1);
            st.spp = 1;
            st.lens_samples = 1;
            st.max_depth = st.max_depth.min(QUICK_MAX_DEPTH);
            if !quiet {
                eprintln!(
                    "--quick: {}x{}, 1 sample per pixel, max depth {}",
                    st.width, st.height, st.max_depth
                );
            }
        }
        Ok(())
    }

    /// The PNG tone curve of `--tonemap`.
    pub fn tonemap(&self) -> Tonemap {
        Tonemap::from(self.tonemap)
    }
}

/// The side of the square sample grid nearest `n` samples: `k` with `k^2` closest to `n`
/// (no integer lies halfway between two squares, so there are no ties).
pub fn nearest_square_side(n: u32) -> u32 {
    // In u64: (k + 1)^2 overflows u32 for n near u32::MAX.
    let (n, k) = (u64::from(n), u64::from(n.isqrt()));
    let side = if n - k * k > (k + 1) * (k + 1) - n {
        k + 1
    } else {
        k.max(1)
    };
    side as u32
}

fn parse_override(s: &str) -> Result<Override, String> {
    s.parse()
}

/// `R,G,B`: three finite, non-negative linear values.
fn parse_rgb(s: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [r, g, b] = parts[..] else {
        return Err(format!("{s:?}: expected R,G,B, e.g. 0.2,0.3,0.5"));
    };
    let mut c = [0.0f32; 3];
    for (v, text) in c.iter_mut().zip([r, g, b]) {
        *v = text
            .parse()
            .map_err(|_| format!("{text:?} is not a number (expected R,G,B)"))?;
        if !(v.is_finite() && *v >= 0.0) {
            return Err(format!("{text}: each component must be finite and >= 0"));
        }
    }
    Ok(Vec3::from(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_round_to_the_nearest_square() {
        let sides: Vec<u32> = [1, 2, 3, 4, 5, 6, 7, 9, 10, 12, 13, 16, 4096, 4160, 4161]
            .iter()
            .map(|&n| nearest_square_side(n))
            .collect();
        // 2 is nearer 1 than 4; 3 nearer 4; 12 nearer 9 (by 3) than 16 (by 4); 13 nearer 16.
        assert_eq!(sides, [1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 64, 64, 65]);
        assert_eq!(nearest_square_side(u32::MAX), 65536);
    }

    #[test]
    fn quick_cuts_the_render_down_and_samples_override_spp() {
        let mut st = Settings {
            width: 641,
            height: 3,
            spp: 4,
            max_depth: 10,
            lens_samples: 8,
            ..Settings::default()
        };
        let args = OverrideArgs {
            quick: true,
            ..OverrideArgs::default()
        };
        args.apply(&mut st, true).unwrap();
        assert_eq!(
            (st.width, st.height, st.spp, st.lens_samples, st.max_depth),
            (160, 1, 1, 1, 3)
        );
        let args = OverrideArgs {
            samples: Some(10),
            background: Some(Vec3::new(0.25, 0.5, 1.0)),
            ..OverrideArgs::default()
        };
        args.apply(&mut st, true).unwrap();
        assert_eq!((st.spp, st.background), (3, Vec3::new(0.25, 0.5, 1.0)));
        let too_many = OverrideArgs {
            samples: Some(5000),
            ..OverrideArgs::default()
        };
        let e = too_many.apply(&mut st, true).unwrap_err().to_string();
        assert_eq!(e, "--samples 5000: at most 4096 (64x64) samples per pixel");
    }

    #[test]
    fn background_parses_three_linear_values() {
        assert_eq!(parse_rgb("0.25, 0.5,1"), Ok(Vec3::new(0.25, 0.5, 1.0)));
        assert!(parse_rgb("1,2").unwrap_err().contains("R,G,B"));
        assert!(parse_rgb("1,x,2").unwrap_err().contains("\"x\""));
        assert!(parse_rgb("1,-1,2").unwrap_err().contains(">= 0"));
        assert!(parse_rgb("1,inf,2").is_err());
    }
}

//! Flags that choose which pixels a render computes and how the EXR stores misses:
//! `--crop` (pbrt's `--cropwindow`, NDC), `--pixel-bounds` (pbrt's `--pixelbounds`, pixels),
//! `--tile` (a farm job's strip) and `--z-miss`.

use anyhow::{Result, bail};
use clap::Args;
use lumis_core::film::PixelWindow;
use lumis_core::film::TileSpec;

/// The window and depth flags of `lumis render`.
#[derive(Args, Debug)]
pub struct WindowArgs {
    /// Render only this part of the image, in normalized coordinates x0,x1,y0,y1 in [0,1]
    /// (y down, as pbrt's --cropwindow; pixel bounds are ceil(resolution x value)). The EXR
    /// stores it as its data window inside the full display window; the PNG holds just it.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = parse_crop, allow_negative_numbers = true)]
    crop: Option<[f32; 4]>,
    /// Render only pixels x0..x1, y0..y1 (end exclusive, as pbrt's --pixelbounds); stored like
    /// --crop.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = parse_pixel_bounds, conflicts_with = "crop")]
    pixel_bounds: Option<PixelWindow>,
    /// Render tile I of N (0-based, 0 <= I < N) for a render farm: a fixed split of the image
    /// into N horizontal strips (edges on multiples of 16 rows while there are enough), written
    /// as an EXR tile (default tile_I.exr) for `lumis merge` to assemble into the image a
    /// single render gives, bit for bit. See docs/farm.md.
    #[arg(long, value_name = "I/N", conflicts_with_all = ["crop", "pixel_bounds"])]
    pub tile: Option<TileSpec>,
    /// The EXR depth (Z) of pixels whose centre ray escaped: `inf` (default) or a large
    /// finite number such as 1e10, for compositors whose depth merges break on infinities.
    #[arg(
        long,
        value_name = "inf|DEPTH",
        value_parser = parse_z_miss,
        default_value = "inf",
        allow_negative_numbers = true
    )]
    pub z_miss: f32,
}

impl WindowArgs {
    /// The pixels to render of a `width x height` image (`None`: all), checked against it.
    pub fn window(&self, width: u32, height: u32) -> Result<Option<PixelWindow>> {
        if let Some(tile) = self.tile {
            return match tile.window(width, height) {
                Ok(w) => Ok(Some(w)),
                Err(e) => bail!("--tile: {e}"),
            };
        }
        let (flag, window) = match (self.crop, self.pixel_bounds) {
            (Some(c), _) => ("--crop", PixelWindow::from_crop(c, width, height)),
            (None, Some(w)) => ("--pixel-bounds", w),
            (None, None) => return Ok(None),
        };
        if let Err(e) = window.check(width, height) {
            bail!("{flag}: {e}");
        }
        Ok(Some(window))
    }
}

/// Four comma-separated numbers.
fn four<T: std::str::FromStr>(s: &str) -> Result<[T; 4], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let values: Vec<T> = parts
        .iter()
        .map(|p| p.parse::<T>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected four comma-separated numbers x0,x1,y0,y1, got {s:?}"))?;
    values
        .try_into()
        .map_err(|_| format!("expected four comma-separated numbers x0,x1,y0,y1, got {s:?}"))
}

fn parse_crop(s: &str) -> Result<[f32; 4], String> {
    let c: [f32; 4] = four(s)?;
    if !c.iter().all(|v| (0.0..=1.0).contains(v)) {
        return Err(format!("every value must be in [0, 1], got {s:?}"));
    }
    if c[0] >= c[1] || c[2] >= c[3] {
        return Err(format!("expected x0 < x1 and y0 < y1, got {s:?}"));
    }
    Ok(c)
}

fn parse_pixel_bounds(s: &str) -> Result<PixelWindow, String> {
    let [x0, x1, y0, y1]: [u32; 4] = four(s)?;
    if x0 >= x1 || y0 >= y1 {
        return Err(format!("expected x0 < x1 and y0 < y1, got {s:?}"));
    }
    Ok(PixelWindow { x0, x1, y0, y1 })
}

fn parse_z_miss(s: &str) -> Result<f32, String> {
    if s.eq_ignore_ascii_case("inf") {
        return Ok(f32::INFINITY);
    }
    match s.parse::<f32>() {
        Ok(z) if z.is_finite() && z > 0.0 => Ok(z),
        _ => Err(format!(
            "expected inf or a positive finite depth, got {s:?}"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_parse_and_bad_ones_are_named() {
        assert_eq!(parse_crop("0,0.5,0.25,1").unwrap(), [0.0, 0.5, 0.25, 1.0]);
        assert!(parse_crop("0,1.5,0,1").unwrap_err().contains("[0, 1]"));
        assert!(parse_crop("0.5,0.5,0,1").unwrap_err().contains("x0 < x1"));
        assert!(parse_crop("0,1,0").unwrap_err().contains("four"));
        let w = parse_pixel_bounds("2,10,3,7").unwrap();
        assert_eq!((w.width(), w.height()), (8, 4));
        assert!(parse_pixel_bounds("2,-1,3,7").is_err());
        assert_eq!(parse_z_miss("inf").unwrap(), f32::INFINITY);
        assert_eq!(parse_z_miss("1e10").unwrap(), 1e10);
        assert!(parse_z_miss("nan").is_err() && parse_z_miss("-3").is_err());
    }
}

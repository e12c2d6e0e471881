//! The accuracy plot: relative MSE (log) against time ratio (log), one series per knob through
//! the defaults, the corners as markers, and the Pareto front over every point.

use super::report::{Summary, pareto};
use anyhow::{Result, anyhow, bail};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Where a TTF for the PNG's text is looked for (after `$LUMIS_PLOT_FONT`). plotters' bitmap
/// backend rasterises text itself, and lumis ships no font, so one is read from the system.
pub const FONT_PATHS: [&str; 5] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
];

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("plotting: {e}")
}

/// Registers the first font found as plotters' "sans-serif"; false when there is none.
fn register_font() -> Result<bool> {
    let env = std::env::var("LUMIS_PLOT_FONT").ok();
    for path in env.iter().map(String::as_str).chain(FONT_PATHS) {
        if let Ok(bytes) = lumis_io::files::read_regular(Path::new(path)) {
            // plotters keeps fonts for the life of the process.
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
                .map_err(|_| anyhow!("{path}: not a font plotters can read"))?;
            return Ok(true);
        }
    }
    Ok(false)
}

/// The two kinds of plot file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotFormat {
    Svg,
    Png,
}

/// The format `path` asks for (by extension), with plotters' font registered: checked before
/// the sweep, so a wrong name or a PNG with no font to draw its text fails at once.
pub fn plot_format(path: &Path) -> Result<PlotFormat> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match ext.as_deref() {
        Some("svg") => PlotFormat::Svg,
        Some("png") => PlotFormat::Png,
        _ => bail!("--plot {}: the plot must be .png or .svg", path.display()),
    };
    // The SVG names its font and draws without one.
    if !register_font()? && format == PlotFormat::Png {
        bail!(
            "no TTF font found for the PNG plot (tried $LUMIS_PLOT_FONT and {}); set LUMIS_PLOT_FONT or write an .svg",
            FONT_PATHS.join(", ")
        );
    }
    Ok(format)
}

/// The plot's file content in `format` (from [`plot_format`], which registers the font).
pub fn encode_plot(summary: &[Summary], title: &str, format: PlotFormat) -> Result<Vec<u8>> {
    let size = (960u32, 640u32);
    match format {
        PlotFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                draw(&root, summary, title)?;
                root.present().map_err(err)?;
            }
            Ok(svg.into_bytes())
        }
        PlotFormat::Png => {
            let mut buf = vec![0u8; (size.0 * size.1 * 3) as usize];
            {
                let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
                draw(&root, summary, title)?;
                root.present().map_err(err)?;
            }
            // The encoder image::save_buffer uses for a .png, so the bytes are as they were.
            let mut png = std::io::Cursor::new(Vec::new());
            image::write_buffer_with_format(
                &mut png,
                &buf,
                size.0,
                size.1,
                image::ExtendedColorType::Rgb8,
                image::ImageFormat::Png,
            )
            .map_err(|e| anyhow!("encoding the PNG plot: {e}"))?;
            Ok(png.into_inner())
        }
    }
}

/// Each knob's series, drawn from the point it varies (knob and value: the defaults, or the
/// spp 4 point for adaptive sampling at 4x4).
const SERIES: [(&str, RGBColor, (&str, &str)); 7] = [
    ("spp", RGBColor(31, 119, 180), DEFAULT),
    ("max_depth", RGBColor(255, 127, 14), DEFAULT),
    ("cutoff", RGBColor(44, 160, 44), DEFAULT),
    ("precision", RGBColor(214, 39, 40), DEFAULT),
    ("offset", RGBColor(148, 103, 189), DEFAULT),
    ("adaptive", RGBColor(23, 190, 207), DEFAULT),
    ("adaptive spp 4", RGBColor(227, 119, 194), ("spp", "4")),
];

const DEFAULT: (&str, &str) = ("default", "default");

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    summary: &[Summary],
    title: &str,
) -> Result<()> {
    root.fill(&WHITE).map_err(err)?;
    // The reference is error 0 by definition: off a log axis.
    let shown: Vec<&Summary> = summary
        .iter()
        .filter(|s| s.point.knob != "reference")
        .collect();
    if shown.is_empty() {
        bail!("nothing to plot");
    }
    let xy: Vec<(f64, f64)> = shown.iter().map(|s| (s.time_ratio, s.rel_mse)).collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in &xy {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(
            (x0 / 1.3..x1 * 1.3).log_scale(),
            (y0 / 2.0..y1 * 2.0).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("render time / default's (geometric mean over scenes)")
        .y_desc("relative MSE vs reference (geometric mean)")
        .x_label_formatter(&|v| format!("{v:.2}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(err)?;
    for (knob, color, (from_knob, from_value)) in SERIES {
        let from = shown
            .iter()
            .find(|s| s.point.knob == from_knob && s.point.value == from_value);
        let mut pts: Vec<(f64, f64)> = shown
            .iter()
            .filter(|s| s.point.knob == knob)
            .chain(from)
            .map(|s| (s.time_ratio, s.rel_mse))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
            .map_err(err)?
            .label(knob)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        chart
            .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, color.filled())))
            .map_err(err)?;
    }
    let corners: Vec<(f64, f64)> = shown
        .iter()
        .filter(|s| s.point.knob == "corner")
        .map(|s| (s.time_ratio, s.rel_mse))
        .collect();
    chart
        .draw_series(
            corners
                .into_iter()
                .map(|p| TriangleMarker::new(p, 7, BLACK.filled())),
        )
        .map_err(err)?
        .label("corners (all cheapest / all dearest)")
        .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLACK.filled()));
    let mut front: Vec<(f64, f64)> = pareto(&xy).into_iter().map(|i| xy[i]).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front.clone(), BLACK.stroke_width(1)))
        .map_err(err)?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    chart
        .draw_series(
            front
                .into_iter()
                .map(|p| Circle::new(p, 8, BLACK.stroke_width(1))),
        )
        .map_err(err)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

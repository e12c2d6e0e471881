//! Automatic exposure for model files, whose lights (photometric glTF units, or the default
//! rig) give no hint of a sensible brightness: the exposure that puts a high percentile of the
//! covered pixels' luminance at a fixed level, so highlights are bright without most of the
//! model clipping. A function of the film alone, so as deterministic as the render.

use crate::film::Film;
use crate::math::Vec4;

/// The luminance percentile of the covered pixels that [`auto_exposure`] places.
pub const AUTO_EXPOSURE_PERCENTILE: f32 = 0.9;
/// Where that percentile lands, in linear units (0.8 encodes to about 231 in sRGB).
pub const AUTO_EXPOSURE_TARGET: f32 = 0.8;

/// The exposure in stops, rounded to 1/100 stop (what is printed is what is applied), that
/// takes the [`AUTO_EXPOSURE_PERCENTILE`] luminance (Rec. 709 weights) of the pixels with
/// coverage (alpha > 0) to [`AUTO_EXPOSURE_TARGET`]; clamped to +-24 stops. 0 for a film with
/// no covered, lit pixel.
pub fn auto_exposure(film: &Film) -> f32 {
    auto_exposure_of(film.rgba())
}

/// [`auto_exposure`] of linear premultiplied RGBA pixels (a merged image's, in `lumis merge`).
pub fn auto_exposure_of(rgba: &[Vec4]) -> f32 {
    let mut lum: Vec<f32> = rgba
        .iter()
        .filter(|p| p.w > 0.0)
        .map(|p| 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z)
        .filter(|y| y.is_finite())
        .collect();
    if lum.is_empty() {
        return 0.0;
    }
    lum.sort_by(f32::total_cmp);
    let at = ((lum.len() - 1) as f32 * AUTO_EXPOSURE_PERCENTILE).round() as usize;
    let level = lum[at];
    if level <= 0.0 {
        return 0.0;
    }
    let stops = (AUTO_EXPOSURE_TARGET / level).log2().clamp(-24.0, 24.0);
    (stops * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::PixelAov;

    #[test]
    fn places_the_percentile_at_the_target_and_ignores_the_background() {
        let mut film = Film::new(10, 2);
        for x in 0..10 {
            // A bright row of 8 lux-scale pixels and an uncovered row.
            film.set(x, 0, Vec4::new(3.2, 3.2, 3.2, 1.0), PixelAov::MISS);
        }
        assert_eq!(auto_exposure(&film), -2.0);
        film.expose(auto_exposure(&film));
        assert_eq!(film.pixel(3, 0), Vec4::new(0.8, 0.8, 0.8, 1.0));
        assert_eq!(auto_exposure(&Film::new(4, 4)), 0.0);
    }
}

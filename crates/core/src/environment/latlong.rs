//! A latitude-longitude image and the one mapping between directions and its texels.
//!
//! The convention is Mitsuba 3's `envmap` emitter (and so the one most HDRIs are shot for):
//! Y is up; a unit direction `d = (x, y, z)` in the map's own frame shows the image at
//!
//! ```text
//! u = atan2(x, -z) / 2pi   wrapped to [0, 1)   (u = 0 and 1: the -Z direction)
//! v = acos(y) / pi                             (v = 0: straight up, the top row)
//! ```
//!
//! so the centre of the image (u = 0.5) looks along +Z, and u grows towards +X from -Z.
//! Texel `(i, j)` covers `u in [i/W, (i+1)/W)`, `v in [j/H, (j+1)/H)`; lookups interpolate
//! bilinearly between texel centres, wrapping in u and clamping in v.

use crate::math::Vec3;
use std::f32::consts::{PI, TAU};

/// Linear RGB texels of a latitude-longitude map, row 0 at the top (+Y).
#[derive(Clone, Debug, PartialEq)]
pub struct LatLong {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl LatLong {
    /// The map of `width x height` texels, row-major from the top-left; `None` when the
    /// texel count does not match or a side is 0.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Option<Self> {
        (width > 0 && height > 0 && texels.len() == width as usize * height as usize).then_some(
            Self {
                width,
                height,
                texels,
            },
        )
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texels, row-major from the top-left.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Mutable texels (the sun extraction paints its region out).
    pub(super) fn texels_mut(&mut self) -> &mut [Vec3] {
        &mut self.texels
    }

    /// Texel `(i, j)`.
    pub fn texel(&self, i: u32, j: u32) -> Vec3 {
        self.texels[(j * self.width + i) as usize]
    }

    /// The value at map coordinates `(u, v)` (any u: it wraps; v clamped to [0, 1]),
    /// interpolated bilinearly between texel centres.
    pub fn lookup(&self, u: f32, v: f32) -> Vec3 {
        let (w, h) = (self.width as f32, self.height as f32);
        let x = u * w - 0.5;
        let y = (v * h - 0.5).clamp(0.0, h - 1.0);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // rem_euclid on the float keeps any u (even far outside [0, 1)) inside the row.
        let i0 = (x0.rem_euclid(w) as u32).min(self.width - 1);
        let i1 = if i0 + 1 == self.width { 0 } else { i0 + 1 };
        let j0 = y0 as u32;
        let j1 = (j0 + 1).min(self.height - 1);
        let row = |j| self.texel(i0, j) * (1.0 - fx) + self.texel(i1, j) * fx;
        row(j0) * (1.0 - fy) + row(j1) * fy
    }

    /// The unit direction at the centre of texel `(i, j)`.
    pub fn texel_direction(&self, i: u32, j: u32) -> Vec3 {
        direction(
            (i as f32 + 0.5) / self.width as f32,
            (j as f32 + 0.5) / self.height as f32,
        )
    }

    /// The solid angle texel row `j` covers, per texel: `(2pi / W) (cos theta0 - cos theta1)`.
    /// Exact for the map's cells, so the rows of a map add up to 4pi.
    pub fn texel_solid_angle(&self, j: u32) -> f32 {
        let h = f64::from(self.height);
        let theta0 = f64::from(j) / h * std::f64::consts::PI;
        let theta1 = f64::from(j + 1) / h * std::f64::consts::PI;
        (std::f64::consts::TAU / f64::from(self.width) * (theta0.cos() - theta1.cos())) as f32
    }
}

/// The map coordinates `(u, v)` of unit direction `d` (module docs).
#[inline]
pub fn uv_of(d: Vec3) -> (f32, f32) {
    let u = d.x.atan2(-d.z) * (1.0 / TAU);
    let u = if u < 0.0 { u + 1.0 } else { u };
    (u, d.y.clamp(-1.0, 1.0).acos() * (1.0 / PI))
}

/// The unit direction at map coordinates `(u, v)`: [`uv_of`] inverted.
pub fn direction(u: f32, v: f32) -> Vec3 {
    let (sin_t, cos_t) = (v * PI).sin_cos();
    let (sin_p, cos_p) = (u * TAU).sin_cos();
    Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_map_as_mitsuba_does() {
        // Hand-derived from u = atan2(x, -z) / 2pi, v = acos(y) / pi.
        for (d, u, v) in [
            (Vec3::new(0.0, 0.0, -1.0), 0.0, 0.5),
            (Vec3::new(1.0, 0.0, 0.0), 0.25, 0.5),
            (Vec3::new(0.0, 0.0, 1.0), 0.5, 0.5),
            (Vec3::new(-1.0, 0.0, 0.0), 0.75, 0.5),
            // At the pole u is arbitrary: atan2(0, -0) = pi.
            (Vec3::new(0.0, 1.0, 0.0), 0.5, 0.0),
        ] {
            let (gu, gv) = uv_of(d);
            assert!(
                (gu - u).abs() < 1e-6 && (gv - v).abs() < 1e-6,
                "{d} -> {gu} {gv}"
            );
            if v != 0.0 {
                assert!(direction(u, v).distance(d) < 1e-6);
            }
        }
        assert!((uv_of(Vec3::NEG_Y).1 - 1.0).abs() < 1e-6);
    }

    #[test]
    fn lookup_hits_texel_centres_wraps_in_u_and_clamps_in_v() {
        let texels = (0..8).map(|k| Vec3::splat(k as f32)).collect();
        let m = LatLong::new(4, 2, texels).unwrap();
        assert_eq!(m.lookup(0.125, 0.25), Vec3::splat(0.0));
        assert_eq!(m.lookup(0.375, 0.75), Vec3::splat(5.0));
        // Halfway between the last and the first column of row 0: wraps.
        assert_eq!(m.lookup(0.0, 0.25), Vec3::splat(1.5));
        assert_eq!(m.lookup(1.0, 0.25), Vec3::splat(1.5));
        // Above the first row's centre: clamped to it.
        assert_eq!(m.lookup(0.125, 0.0), Vec3::splat(0.0));
        assert_eq!(m.lookup(0.125, 1.0), Vec3::splat(4.0));
        assert!(m.lookup(-7.3, 0.5).is_finite() && m.lookup(1e9, 0.5).is_finite());
    }

    #[test]
    fn texel_solid_angles_add_up_to_the_sphere() {
        let m = LatLong::new(16, 8, vec![Vec3::ZERO; 128]).unwrap();
        let total: f32 = (0..8).map(|j| m.texel_solid_angle(j) * 16.0).sum();
        assert!((total - 4.0 * PI).abs() < 1e-5, "{total}");
    }
}

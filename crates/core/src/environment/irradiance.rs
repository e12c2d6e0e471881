//! The environment's diffuse irradiance for every normal, computed once at load: the cosine
//! convolution of the map, tabulated on a small latitude-longitude grid.
//!
//! A pre-convolved map rather than 9 spherical-harmonic coefficients: SH of order 2 ring
//! (negative lobes, a dark halo opposite) around a bright sun, where the tabulated sum is the
//! integral itself up to the grid's resolution. The source is first resampled to
//! a grid of the map's width clamped to [`MIN_SOURCE_WIDTH`]..=[`SOURCE_WIDTH`] cells across
//! (box filter weighted by each texel's exact
//! solid angle, or interpolation where the map is coarser), then
//!
//! ```text
//! E(n) = sum over cells k of  L_k * Omega_k * max(0, n . w_k)
//! ```
//!
//! for `n` at each of the [`WIDTH`] x [`WIDTH`]/2 texel centres of the table ([`Cells`]). The
//! table is smooth (a cosine lobe is ~90 degrees wide), so bilinear lookups between its
//! centres lose nothing visible; tests compare it with closed forms.

use super::latlong::LatLong;
use crate::math::Vec3;
use rayon::prelude::*;

/// Width of the irradiance table (height: half of it).
pub const WIDTH: u32 = 64;
/// Widest grid the source is filtered to before the convolution.
pub const SOURCE_WIDTH: u32 = 128;
/// Narrowest: a coarser map is interpolated onto this many cells across, enough for the
/// cosine's quadrature (a uniform sky within 0.5%) at a sixteenth of the widest grid's cost.
pub const MIN_SOURCE_WIDTH: u32 = 32;

/// `E(n)` for every normal of the table's grid.
pub(super) fn irradiance_table(map: &LatLong) -> LatLong {
    let cells = Cells::of(&filtered(map));
    let table = LatLong::new(
        WIDTH,
        WIDTH / 2,
        vec![Vec3::ZERO; (WIDTH * WIDTH / 2) as usize],
    )
    .expect("a non-empty table");
    let texels: Vec<Vec3> = (0..WIDTH / 2)
        .into_par_iter()
        .flat_map_iter(|j| {
            let table = &table;
            let cells = &cells;
            (0..WIDTH).map(move |i| cells.irradiance(table.texel_direction(i, j)))
        })
        .collect();
    LatLong::new(WIDTH, WIDTH / 2, texels).expect("one texel per cell")
}

/// The filtered cells as columns of f32 (directions and `L * Omega` per channel), four cells
/// to a [`glam::Vec4`], so that the sum over them runs four cells at a time in SSE (a sum in
/// one scalar accumulator cannot be vectorised: float addition is not associative). Each of
/// the four lanes adds at most 2048 positive terms in f32 (relative error < 1e-4, far below
/// the table's own discretisation); the lanes are added in f64. Padding cells are zero.
struct Cells {
    dir: [Vec<glam::Vec4>; 3],
    value: [Vec<glam::Vec4>; 3],
}

impl Cells {
    fn of(cells: &[(glam::DVec3, glam::DVec3)]) -> Self {
        let column = |f: &dyn Fn(&(glam::DVec3, glam::DVec3)) -> f64| {
            cells
                .chunks(4)
                .map(|c| {
                    let at = |k: usize| c.get(k).map_or(0.0, |c| f(c) as f32);
                    glam::Vec4::new(at(0), at(1), at(2), at(3))
                })
                .collect::<Vec<_>>()
        };
        Self {
            dir: [column(&|c| c.0.x), column(&|c| c.0.y), column(&|c| c.0.z)],
            value: [column(&|c| c.1.x), column(&|c| c.1.y), column(&|c| c.1.z)],
        }
    }

    /// `sum L_k Omega_k max(0, n . w_k)`.
    fn irradiance(&self, n: Vec3) -> Vec3 {
        let (nx, ny, nz) = (
            glam::Vec4::splat(n.x),
            glam::Vec4::splat(n.y),
            glam::Vec4::splat(n.z),
        );
        let [dx, dy, dz] = &self.dir;
        let [r, g, b] = &self.value;
        let mut acc = [glam::Vec4::ZERO; 3];
        for k in 0..dx.len() {
            let cos = (nx * dx[k] + ny * dy[k] + nz * dz[k]).max(glam::Vec4::ZERO);
            acc[0] += r[k] * cos;
            acc[1] += g[k] * cos;
            acc[2] += b[k] * cos;
        }
        let total = |a: glam::Vec4| a.to_array().iter().map(|&v| f64::from(v)).sum::<f64>() as f32;
        Vec3::new(total(acc[0]), total(acc[1]), total(acc[2]))
    }
}

/// The map on a grid of its own width clamped to [`MIN_SOURCE_WIDTH`]..=[`SOURCE_WIDTH`]
/// (height half of it): each cell's centre direction
/// and `L * Omega`, with `L` the solid-angle-weighted mean of the source texels whose centres
/// fall in the cell, or (a map coarser than the grid) the map interpolated at its centre, so
/// that the cosine is integrated on a fine grid whatever the map's size.
fn filtered(map: &LatLong) -> Vec<(glam::DVec3, glam::DVec3)> {
    let w = map.width().clamp(MIN_SOURCE_WIDTH, SOURCE_WIDTH) & !1;
    let h = w / 2;
    let grid = LatLong::new(w, h, vec![Vec3::ZERO; (w * h) as usize]).expect("non-empty");
    let mut sums = vec![(glam::DVec3::ZERO, 0.0f64); (w * h) as usize];
    for j in 0..map.height() {
        let omega = f64::from(map.texel_solid_angle(j));
        let cj = (u64::from(j) * u64::from(h) / u64::from(map.height())) as u32;
        for i in 0..map.width() {
            let ci = (u64::from(i) * u64::from(w) / u64::from(map.width())) as u32;
            let cell = &mut sums[(cj * w + ci) as usize];
            cell.0 += map.texel(i, j).as_dvec3() * omega;
            cell.1 += omega;
        }
    }
    (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| {
            let (sum, weight) = sums[(j * w + i) as usize];
            let radiance = if weight > 0.0 {
                sum / weight
            } else {
                let (u, v) = ((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                map.lookup(u, v).as_dvec3()
            };
            let omega = f64::from(grid.texel_solid_angle(j));
            (grid.texel_direction(i, j).as_dvec3(), radiance * omega)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    fn map(w: u32, h: u32, f: impl Fn(Vec3) -> Vec3) -> LatLong {
        let probe = LatLong::new(w, h, vec![Vec3::ZERO; (w * h) as usize]).unwrap();
        let texels = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| f(probe.texel_direction(i, j)))
            .collect();
        LatLong::new(w, h, texels).unwrap()
    }

    fn at(table: &LatLong, n: Vec3) -> Vec3 {
        let (u, v) = super::super::latlong::uv_of(n);
        table.lookup(u, v)
    }

    #[test]
    fn a_uniform_sky_gives_pi_l_everywhere() {
        let t = irradiance_table(&map(256, 128, |_| Vec3::new(1.0, 2.0, 0.5)));
        for n in [
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::X,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
        ] {
            let e = at(&t, n) / PI;
            assert!(e.distance(Vec3::new(1.0, 2.0, 0.5)) < 5e-3, "{n}: {e}");
        }
    }

    #[test]
    fn an_upper_hemisphere_gives_the_closed_form() {
        // L = 1 above the horizon: E(n) = pi (1 + n.y) / 2 (the cosine lobe's share of it).
        let t = irradiance_table(&map(512, 256, |d| Vec3::splat(f32::from(d.y > 0.0))));
        for n in [Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::new(0.6, 0.8, 0.0)] {
            let want = PI * (1.0 + n.y) / 2.0;
            let e = at(&t, n).x;
            assert!((e - want).abs() < 0.02, "{n}: {e} vs {want}");
        }
    }

    #[test]
    fn a_small_bright_patch_lights_like_a_directional_light() {
        // A patch of solid angle Omega around +X of radiance L: E(n) ~ L Omega max(0, n.x).
        let probe = map(512, 256, |_| Vec3::ZERO);
        let mut omega = 0.0;
        let t = irradiance_table(&map(512, 256, |d| {
            let on = d.x > 0.999;
            Vec3::splat(if on { 1000.0 } else { 0.0 })
        }));
        for j in 0..256 {
            for i in 0..512 {
                if probe.texel_direction(i, j).x > 0.999 {
                    omega += probe.texel_solid_angle(j);
                }
            }
        }
        let e_axis = at(&t, Vec3::X).x;
        assert!((e_axis / (1000.0 * omega) - 1.0).abs() < 0.02, "{e_axis}");
        assert!(at(&t, Vec3::NEG_X).x.abs() < 1e-3);
        let e45 = at(&t, Vec3::new(1.0, 1.0, 0.0).normalize()).x;
        assert!(
            (e45 / e_axis - std::f32::consts::FRAC_1_SQRT_2).abs() < 0.03,
            "{e45}"
        );
    }
}

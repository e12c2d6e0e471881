//! `--env-sun`: the brightest compact region of the map becomes a directional light, so an
//! HDRI's sun casts the hard shadows a Whitted renderer can cast, and is painted out of the
//! map so that its light is not counted twice (once by the light, once by the ambient term).
//!
//! The region is the 8-connected set of texels (wrapping in u) around the brightest texel
//! whose luminance is at least [`THRESHOLD`] of the peak. It must be compact (at most
//! [`MAX_SOLID_ANGLE`] sr: the real sun is 6.8e-5 sr, HDRIs blur and clip it to a few 1e-3)
//! and stand out (a peak at least [`MIN_CONTRAST`] times the map's mean luminance); otherwise
//! the map has no sun and the request is refused with the numbers. The region's texels take
//! the mean of the texels bordering it; the light gets what was removed:
//!
//! ```text
//! irradiance = sum over the region of (L_i - fill) * Omega_i      (RGB, at normal incidence)
//! direction  = the luminance-weighted mean of the region's texel directions
//! ```

use super::latlong::LatLong;
use crate::math::Vec3;

/// Share of the peak luminance a texel needs to belong to the sun.
pub const THRESHOLD: f32 = 0.05;
/// Largest solid angle (sr) a sun may cover: a disk of ~5.6 degrees radius.
pub const MAX_SOLID_ANGLE: f32 = 0.03;
/// How many times brighter than the map's mean the peak must be.
pub const MIN_CONTRAST: f32 = 20.0;

/// The sun taken out of a map (in the map's own frame, before rotation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Unit direction from the scene towards the sun.
    pub direction: Vec3,
    /// Irradiance on a surface facing the sun (RGB).
    pub irradiance: Vec3,
    /// Solid angle of the region painted out, in sr.
    pub solid_angle: f32,
    /// Texels painted out.
    pub texels: usize,
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Finds the sun of `map`, paints it out and returns it; `Err` says why the map has none.
pub(super) fn extract_sun(map: &mut LatLong) -> Result<Sun, String> {
    let (w, h) = (map.width(), map.height());
    let (mut peak, mut at, mut sum, mut omega_all) = (0.0f32, 0usize, 0.0f64, 0.0f64);
    for (k, c) in map.texels().iter().enumerate() {
        let y = luminance(*c);
        let omega = f64::from(map.texel_solid_angle(k as u32 / w));
        sum += f64::from(y) * omega;
        omega_all += omega;
        if y > peak {
            (peak, at) = (y, k);
        }
    }
    let mean = (sum / omega_all) as f32;
    if peak <= 0.0 {
        return Err("the map is black: there is no sun to take out".into());
    }
    if peak < MIN_CONTRAST * mean {
        return Err(format!(
            "no region stands out: the brightest texel ({peak:.4}) is {:.1} times the mean \
             luminance ({mean:.4}); a sun needs {MIN_CONTRAST}",
            peak / mean
        ));
    }
    let threshold = peak * THRESHOLD;
    let mut inside = vec![false; map.texels().len()];
    let mut region = Vec::new();
    let mut stack = vec![at];
    inside[at] = true;
    let mut solid_angle = 0.0f32;
    while let Some(k) = stack.pop() {
        region.push(k);
        let (i, j) = ((k as u32 % w) as i64, (k as u32 / w) as i64);
        solid_angle += map.texel_solid_angle(j as u32);
        if solid_angle > MAX_SOLID_ANGLE {
            return Err(format!(
                "no compact bright region: the area around the brightest texel (above {} of \
                 its luminance) covers more than {MAX_SOLID_ANGLE} sr",
                THRESHOLD
            ));
        }
        for n in neighbours(i, j, w, h) {
            if !inside[n] && luminance(map.texels()[n]) >= threshold {
                inside[n] = true;
                stack.push(n);
            }
        }
    }
    // The fill: the mean of the texels bordering the region.
    let (mut fill, mut ring) = (Vec3::ZERO, 0u32);
    let mut seen = vec![false; inside.len()];
    for &k in &region {
        let (i, j) = ((k as u32 % w) as i64, (k as u32 / w) as i64);
        for n in neighbours(i, j, w, h) {
            if !inside[n] && !seen[n] {
                seen[n] = true;
                fill += map.texels()[n];
                ring += 1;
            }
        }
    }
    let fill = if ring > 0 {
        fill / ring as f32
    } else {
        Vec3::ZERO
    };
    let (mut irradiance, mut towards) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    region.sort_unstable(); // the sums in one order, whatever the fill visited first
    for &k in &region {
        let (i, j) = (k as u32 % w, k as u32 / w);
        let omega = f64::from(map.texel_solid_angle(j));
        let c = map.texels()[k];
        irradiance += (c - fill).max(Vec3::ZERO).as_dvec3() * omega;
        towards += map.texel_direction(i, j).as_dvec3() * f64::from(luminance(c)) * omega;
        map.texels_mut()[k] = fill;
    }
    Ok(Sun {
        direction: towards.normalize().as_vec3(),
        irradiance: irradiance.as_vec3(),
        solid_angle,
        texels: region.len(),
    })
}

/// The 8 neighbours of texel `(i, j)`, wrapping in u and stopping at the poles' rows.
fn neighbours(i: i64, j: i64, w: u32, h: u32) -> impl Iterator<Item = usize> {
    let (w, h) = (i64::from(w), i64::from(h));
    (-1..=1i64)
        .flat_map(|dj| (-1..=1i64).map(move |di| (di, dj)))
        .filter(|&d| d != (0, 0))
        .filter_map(move |(di, dj)| {
            let nj = j + dj;
            (0..h)
                .contains(&nj)
                .then(|| (nj * w + (i + di).rem_euclid(w)) as usize)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(w: u32, h: u32, sun: Vec3, radius: f32, radiance: f32) -> LatLong {
        let probe = LatLong::new(w, h, vec![Vec3::ZERO; (w * h) as usize]).unwrap();
        let texels = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| {
                let d = probe.texel_direction(i, j);
                let base = Vec3::new(0.2, 0.3, 0.5);
                if d.dot(sun) > radius.cos() {
                    base + Vec3::splat(radiance)
                } else {
                    base
                }
            })
            .collect();
        LatLong::new(w, h, texels).unwrap()
    }

    #[test]
    fn the_sun_becomes_a_light_with_the_energy_it_had() {
        let towards = Vec3::new(0.3, 0.8, -0.5).normalize();
        let mut m = sky(1024, 512, towards, 0.04, 5000.0);
        let before: Vec3 = m.texels().iter().copied().sum();
        let sun = extract_sun(&mut m).unwrap();
        assert!(sun.direction.dot(towards) > 0.9999, "{}", sun.direction);
        // A disk of radius 0.04 rad: Omega = 2pi (1 - cos 0.04).
        let omega = std::f32::consts::TAU * (1.0 - 0.04f32.cos());
        let want = 5000.0 * omega;
        assert!(
            (sun.irradiance.x / want - 1.0).abs() < 0.05,
            "{} vs {want}",
            sun.irradiance
        );
        // Painted out with the sky around it.
        assert!(
            m.texels()
                .iter()
                .all(|c| c.distance(Vec3::new(0.2, 0.3, 0.5)) < 1e-5)
        );
        assert!(before.x > m.texels().iter().copied().sum::<Vec3>().x);
    }

    #[test]
    fn a_map_without_a_sun_is_refused_with_a_reason() {
        let mut flat = sky(64, 32, Vec3::Y, 0.0, 0.0);
        assert!(extract_sun(&mut flat).unwrap_err().contains("stands out"));
        let mut black = LatLong::new(4, 2, vec![Vec3::ZERO; 8]).unwrap();
        assert!(extract_sun(&mut black).unwrap_err().contains("black"));
        // A bright half-sky is not compact.
        let mut big = sky(256, 128, Vec3::Y, 0.3, 5000.0);
        assert!(extract_sun(&mut big).unwrap_err().contains("compact"));
    }

    #[test]
    fn a_sun_across_the_seam_is_found_whole() {
        let towards = Vec3::new(0.0, 0.3, -1.0).normalize(); // u = 0: the seam
        let mut m = sky(512, 256, towards, 0.05, 3000.0);
        let sun = extract_sun(&mut m).unwrap();
        assert!(sun.direction.dot(towards) > 0.9999, "{}", sun.direction);
    }
}

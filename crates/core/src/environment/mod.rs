//! Light from the world: an HDR latitude-longitude image around the scene (`--env`,
//! `[environment]`). It is what rays see when they escape, and the source of the ambient
//! term: the map's diffuse irradiance for the shading normal, computed once at load
//! ([`irradiance`]), unshadowed as Whitted's constant ambient is. Optionally its sun becomes a
//! directional light with hard shadows ([`sun`]).
//!
//! Orientation: Mitsuba 3's `envmap` ([`latlong`]); `rotation` turns the map about +Y by that
//! many degrees, as Mitsuba's `<rotate y="1" angle="..."/>` on the emitter's `to_world` does
//! (a feature of the map seen along -Z at rotation 0 is seen along -X at rotation 90).

pub mod irradiance;
pub mod latlong;
pub mod sun;

pub use latlong::LatLong;
pub use sun::Sun;

use crate::light::Light;
use crate::math::Vec3;

/// How a map is placed and scaled in the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Degrees about +Y (Mitsuba's `to_world` rotation of the emitter).
    pub rotation_degrees: f32,
    /// Scale of every texel (Mitsuba's `scale`).
    pub intensity: f32,
}

impl Default for Placement {
    fn default() -> Self {
        Self {
            rotation_degrees: 0.0,
            intensity: 1.0,
        }
    }
}

/// An environment ready to render: the map, its irradiance table, its placement and the sun
/// taken out of it, if asked for.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    map: LatLong,
    irradiance: LatLong,
    placement: Placement,
    /// cos and sin of the rotation: world to map is a turn by -rotation about +Y.
    cos: f32,
    sin: f32,
    sun: Option<Sun>,
    /// Where the map came from, for reports and headers.
    source: String,
}

impl Environment {
    /// The environment of `map` placed by `placement`; with `sun`, its sun is taken out as a
    /// directional light (`Err`: why the map has none, or a placement out of range).
    pub fn new(
        mut map: LatLong,
        placement: Placement,
        sun: bool,
        source: impl Into<String>,
    ) -> Result<Self, String> {
        let Placement {
            rotation_degrees,
            intensity,
        } = placement;
        if !rotation_degrees.is_finite() || rotation_degrees.abs() > 36000.0 {
            return Err(format!(
                "rotation {rotation_degrees} must be a finite angle in degrees (|r| <= 36000)"
            ));
        }
        if !(intensity.is_finite() && (0.0..=1e6).contains(&intensity)) {
            return Err(format!("intensity {intensity} must be in 0..=1e6"));
        }
        let sun = if sun {
            Some(sun::extract_sun(&mut map).map_err(|e| format!("--env-sun: {e}"))?)
        } else {
            None
        };
        let irradiance = irradiance::irradiance_table(&map);
        let (sin, cos) = rotation_degrees.to_radians().sin_cos();
        Ok(Self {
            map,
            irradiance,
            placement,
            cos,
            sin,
            sun,
            source: source.into(),
        })
    }

    /// The map's direction of world direction `d`: the rotation undone.
    #[inline]
    fn to_map(&self, d: Vec3) -> Vec3 {
        Vec3::new(
            self.cos * d.x - self.sin * d.z,
            d.y,
            self.sin * d.x + self.cos * d.z,
        )
    }

    /// World direction of the map's direction `d`.
    fn to_world(&self, d: Vec3) -> Vec3 {
        Vec3::new(
            self.cos * d.x + self.sin * d.z,
            d.y,
            -self.sin * d.x + self.cos * d.z,
        )
    }

    /// Radiance arriving from the world along unit direction `-d` (what a ray leaving in
    /// direction `d` sees). `d` need not be normalised; a zero `d` sees the top row.
    #[inline]
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (u, v) = latlong::uv_of(self.to_map(d.normalize_or(Vec3::Y)));
        self.map.lookup(u, v) * self.placement.intensity
    }

    /// Irradiance on a surface with unit normal `n` from the whole map, unshadowed.
    #[inline]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        let (u, v) = latlong::uv_of(self.to_map(n.normalize_or(Vec3::Y)));
        self.irradiance.lookup(u, v).max(Vec3::ZERO) * self.placement.intensity
    }

    /// The sun as a light in world space, if one was taken out.
    pub fn sun_light(&self) -> Option<Light> {
        self.sun.map(|s| Light::Directional {
            direction: -self.to_world(s.direction),
            irradiance: s.irradiance * self.placement.intensity,
        })
    }

    /// The sun taken out (in the map's frame), if any.
    pub fn sun(&self) -> Option<&Sun> {
        self.sun.as_ref()
    }

    /// The map (after the sun was painted out).
    pub fn map(&self) -> &LatLong {
        &self.map
    }

    /// Placement.
    pub fn placement(&self) -> Placement {
        self.placement
    }

    /// Where the map came from (a path, for reports).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Whether every texel is black (escaping rays then see nothing, as without a map).
    pub fn is_black(&self) -> bool {
        self.placement.intensity == 0.0 || self.map.texels().iter().all(|c| *c == Vec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map with one bright texel column-block at u in [0, 1/8) (around -Z at the horizon).
    fn marked() -> LatLong {
        let (w, h) = (64u32, 32u32);
        let texels = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| {
                if i < 8 && (12..20).contains(&j) {
                    Vec3::new(1.0, 0.0, 0.0)
                } else {
                    Vec3::splat(0.01)
                }
            })
            .collect();
        LatLong::new(w, h, texels).unwrap()
    }

    #[test]
    fn rotation_turns_the_map_like_mitsubas_to_world() {
        // The mark is centred at u = 1/16: direction atan2(x, -z) = 2pi/16 from -Z towards +X.
        let phi = std::f32::consts::TAU / 16.0;
        let mark = Vec3::new(phi.sin(), 0.0, -phi.cos());
        let at = |deg: f32, d: Vec3| {
            let p = Placement {
                rotation_degrees: deg,
                intensity: 2.0,
            };
            Environment::new(marked(), p, false, "test")
                .unwrap()
                .radiance(d)
        };
        assert_eq!(at(0.0, mark).x, 2.0);
        // Mitsuba's rotate(y, 90) maps -Z to -X: the mark turns with it.
        let turned = Vec3::new(-phi.cos(), 0.0, -phi.sin());
        assert_eq!(at(90.0, turned).x, 2.0);
        assert!(at(90.0, mark).x < 0.1);
    }

    #[test]
    fn irradiance_is_scaled_and_finite_for_any_normal() {
        let p = Placement {
            rotation_degrees: 30.0,
            intensity: 3.0,
        };
        let uniform = LatLong::new(16, 8, vec![Vec3::ONE; 128]).unwrap();
        let e = Environment::new(uniform, p, false, "u").unwrap();
        for n in [Vec3::Y, Vec3::ZERO, Vec3::new(1e-30, 0.0, 0.0), Vec3::NEG_Z] {
            let v = e.irradiance(n);
            assert!(
                (v.x / (3.0 * std::f32::consts::PI) - 1.0).abs() < 0.01,
                "{n}: {v}"
            );
        }
    }

    #[test]
    fn bad_placements_are_refused() {
        let m = || LatLong::new(2, 1, vec![Vec3::ONE; 2]).unwrap();
        for (r, i) in [
            (f32::NAN, 1.0),
            (0.0, -1.0),
            (0.0, f32::INFINITY),
            (1e9, 1.0),
        ] {
            let p = Placement {
                rotation_degrees: r,
                intensity: i,
            };
            assert!(Environment::new(m(), p, false, "x").is_err());
        }
    }

    #[test]
    fn the_sun_light_points_away_from_the_sun_after_rotation() {
        let (w, h) = (256u32, 128u32);
        let probe = LatLong::new(w, h, vec![Vec3::ZERO; (w * h) as usize]).unwrap();
        let towards = Vec3::new(0.0, 0.6, -0.8);
        let texels = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| {
                let d = probe.texel_direction(i, j);
                Vec3::splat(if d.dot(towards) > 0.999 { 1e4 } else { 0.1 })
            })
            .collect();
        let map = LatLong::new(w, h, texels).unwrap();
        let p = Placement {
            rotation_degrees: 90.0,
            intensity: 1.0,
        };
        let e = Environment::new(map, p, true, "s").unwrap();
        let Some(Light::Directional { direction, .. }) = e.sun_light() else {
            panic!("no sun")
        };
        // -Z turns to -X: the sun is at (-0.8, 0.6, 0), its light travels the other way.
        assert!(
            direction.dot(Vec3::new(0.8, -0.6, 0.0)) > 0.999,
            "{direction}"
        );
    }
}

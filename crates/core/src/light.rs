//! Point, spot and directional lights.
//!
//! ```toml
//! [[light]]
//! type = "point"
//! position = [4.0, 6.0, 3.0]
//! color = [1.0, 0.9, 0.8]
//! intensity = 60.0      # radiant intensity, W/sr: irradiance = intensity / d^2
//!
//! [[light]]
//! type = "directional"
//! direction = [-1.0, -2.0, -1.0]   # the way the light travels
//! color = [1.0, 1.0, 1.0]
//! intensity = 1.5                  # irradiance on a surface facing the light
//! ```

use crate::math::Vec3;

/// Ceiling of a light's irradiance at a shaded point (reached only within ~1e-3 of a light of
/// the largest power, `scene::limits::MAX_LIGHT_POWER`).
pub const MAX_IRRADIANCE: f32 = 1e26;

/// Lumens per watt: the luminous efficacy of 555 nm light, which defines the candela. glTF
/// light intensities are photometric (candela, lux); lumis's are radiometric (W/sr, W/m^2).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// A light that casts hard shadows.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Isotropic point source; `intensity` is colour times radiant intensity.
    Point { position: Vec3, intensity: Vec3 },
    /// A point source whose irradiance does not fall off with distance: the `.scn` lights.
    Unattenuated { position: Vec3, irradiance: Vec3 },
    /// Infinitely distant source; `direction` is the unit direction light travels,
    /// `irradiance` is colour times irradiance at normal incidence.
    Directional { direction: Vec3, irradiance: Vec3 },
    /// A point source emitting into a cone around the unit `direction` (world space, the way
    /// the light travels): full `intensity` inside the inner cone (`cos >= cos_inner`), none
    /// outside the outer one (`cos <= cos_outer`), and between them the squared linear ramp in
    /// the cosine that the glTF `KHR_lights_punctual` specification recommends.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_inner: f32,
        cos_outer: f32,
    },
}

/// What a light delivers to a point: unit direction towards it, distance, irradiance at normal incidence.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit vector from the shaded point towards the light.
    pub wi: Vec3,
    /// Distance to the light (infinite for directional lights).
    pub distance: f32,
    /// Irradiance on a surface facing the light.
    pub irradiance: Vec3,
}

impl Light {
    /// True when the light emits nothing (zero colour or intensity): it can light no point.
    pub fn is_dark(&self) -> bool {
        let power = match self {
            Light::Point { intensity, .. } | Light::Spot { intensity, .. } => intensity,
            Light::Unattenuated { irradiance, .. } | Light::Directional { irradiance, .. } => {
                irradiance
            }
        };
        *power == Vec3::ZERO
    }

    /// True for a spot light (whose cone can exclude a point).
    pub fn is_spot(&self) -> bool {
        matches!(self, Light::Spot { .. })
    }

    /// The light as seen from `p`.
    pub fn sample(&self, p: Vec3) -> LightSample {
        match self {
            Light::Point {
                position,
                intensity,
            } => {
                let d = *position - p;
                let dist2 = d.length_squared().max(f32::MIN_POSITIVE);
                let distance = dist2.sqrt();
                LightSample {
                    wi: d / distance,
                    distance,
                    // I / d^2 has no bound as d -> 0 (a surface through the light): capped, so
                    // sums of lights stay finite.
                    irradiance: (*intensity / dist2).min(Vec3::splat(MAX_IRRADIANCE)),
                }
            }
            Light::Unattenuated {
                position,
                irradiance,
            } => {
                let d = *position - p;
                let distance = d.length().max(f32::MIN_POSITIVE);
                LightSample {
                    wi: d / distance,
                    distance,
                    irradiance: *irradiance,
                }
            }
            Light::Directional {
                direction,
                irradiance,
            } => LightSample {
                wi: -*direction,
                distance: f32::INFINITY,
                irradiance: *irradiance,
            },
            Light::Spot {
                position,
                direction,
                intensity,
                cos_inner,
                cos_outer,
            } => {
                let d = *position - p;
                let dist2 = d.length_squared().max(f32::MIN_POSITIVE);
                let distance = dist2.sqrt();
                let wi = d / distance;
                let falloff = spot_falloff(-wi.dot(*direction), *cos_inner, *cos_outer);
                LightSample {
                    wi,
                    distance,
                    irradiance: (*intensity * (falloff / dist2)).min(Vec3::splat(MAX_IRRADIANCE)),
                }
            }
        }
    }
}

/// Angular falloff of a spot light at cosine `cos` from its axis: 1 inside the inner cone, 0
/// outside the outer one, `t^2` for the linear ramp `t` in between (glTF's recommended curve:
/// smooth at the outer edge, cheap to evaluate).
pub fn spot_falloff(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    if cos >= cos_inner {
        return 1.0;
    }
    if cos <= cos_outer {
        return 0.0;
    }
    // Here cos_outer < cos < cos_inner, so the width is positive.
    let t = (cos - cos_outer) / (cos_inner - cos_outer);
    t * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spot_is_full_inside_dark_outside_and_ramps_between() {
        let spot = Light::Spot {
            position: Vec3::new(0.0, 2.0, 0.0),
            direction: -Vec3::Y,
            intensity: Vec3::splat(4.0),
            cos_inner: 0.9,
            cos_outer: 0.7,
        };
        // Straight below at distance 2: I / d^2.
        assert!((spot.sample(Vec3::ZERO).irradiance.x - 1.0).abs() < 1e-6);
        // 45 degrees off axis: cos 0.707 is outside the inner cone, just inside the outer one.
        let e = spot.sample(Vec3::new(2.0, 0.0, 0.0)).irradiance.x;
        let t = (std::f32::consts::FRAC_1_SQRT_2 - 0.7) / 0.2;
        assert!((e - 4.0 * t * t / 8.0).abs() < 1e-5, "{e}");
        // Beside the light: dark.
        assert_eq!(spot.sample(Vec3::new(5.0, 2.0, 0.0)).irradiance, Vec3::ZERO);
        // Equal cones: a hard edge, no division by zero.
        assert_eq!(spot_falloff(0.5, 0.5, 0.5), 1.0);
        assert_eq!(spot_falloff(0.49, 0.5, 0.5), 0.0);
    }
}

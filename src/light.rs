//! Point and directional lights.
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
                    irradiance: *intensity / dist2,
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
        }
    }
}

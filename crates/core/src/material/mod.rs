//! Whitted materials: Lambert diffuse, Phong specular, mirror reflection, Fresnel refraction,
//! emission.
//!
//! Outgoing radiance at a hit (documented in docs/shading.md):
//! `Le + ambient*kd + sum over unshadowed lights of (kd/pi * cos + ks*(n+2)/(2pi)*cos_r^n) * E
//!  + reflectivity * L(mirror) + transmission * (F * L(mirror) + (1 - F) * L(refracted))`.
//!
//! ```toml
//! [materials.glass]
//! diffuse = [0.0, 0.0, 0.0]
//! transmission = 1.0
//! ior = 1.5
//! ```

mod textured;

use std::sync::Arc;

use crate::math::Vec3;
pub use crate::texture::{NormalMap, Texture};
pub use textured::{
    AtHit, DIELECTRIC_F0, MAX_SHININESS, MetalRough, TexturedParams, dielectric_f0, metal_rough,
    textured_bounds,
};

/// A material. Colours are linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Diffuse albedo `kd` in [0,1].
    pub diffuse: Texture,
    /// Phong specular colour `ks`.
    pub specular: Vec3,
    /// Phong exponent `n` (0 disables the highlight).
    pub shininess: f32,
    /// Mirror reflection weight in [0,1].
    pub reflectivity: f32,
    /// Transmission weight in [0,1]; the transmitted part is split by Fresnel.
    pub transmission: f32,
    /// Index of refraction of the inside (outside is 1).
    pub ior: f32,
    /// Emitted radiance.
    pub emission: Vec3,
    /// Optional noise perturbation of the shading normal (the `.scn` `NormalMap`).
    pub normal_map: Option<NormalMap>,
    /// Parameters that vary over the surface (glTF textures and vertex colours): where given,
    /// shading evaluates them at each hit ([`Material::at_hit`]) and the fields above are only
    /// upper bounds, for the effect decisions.
    pub textured: Option<Arc<TexturedParams>>,
    /// A shadow catcher (Cycles' flag): camera rays that meet it show what is behind it (the
    /// background, or nothing under `--transparent`) darkened by the shadow it receives, so a
    /// model can be composited onto a photographed plate; other rays pass through it.
    pub shadow_catcher: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            diffuse: Texture::Solid(Vec3::splat(0.8)),
            specular: Vec3::ZERO,
            shininess: 0.0,
            reflectivity: 0.0,
            transmission: 0.0,
            ior: 1.5,
            emission: Vec3::ZERO,
            normal_map: None,
            textured: None,
            shadow_catcher: false,
        }
    }
}

impl Material {
    /// True when shading reads the hit's texture coordinates.
    pub fn reads_uv(&self) -> bool {
        self.diffuse.reads_uv() || self.textured.is_some()
    }

    /// True when the material spawns mirror rays (its own or the reflected part of transmission).
    pub fn reflects(&self) -> bool {
        self.reflectivity > 0.0 || self.transmission > 0.0
    }

    /// True when it spawns refraction rays.
    pub fn transmits(&self) -> bool {
        self.transmission > 0.0
    }

    /// The shading normal to use at world point `p`: `ns` bent by the normal map if there is
    /// one, else `ns`. `ns` and `ng` are unit and on the same side; a bend that would cross to
    /// the other side of `ng` is dropped, since shading from behind the surface makes black
    /// speckles and rays refracted the wrong way.
    pub fn shading_normal(&self, ns: Vec3, ng: Vec3, p: Vec3) -> Vec3 {
        match &self.normal_map {
            Some(map) => Some(map.perturb(ns, p))
                .filter(|n| n.dot(ng) > 0.0)
                .unwrap_or(ns),
            None => ns,
        }
    }

    /// True when direct lighting (and so shadow rays) can contribute.
    pub fn is_lit(&self) -> bool {
        !self.diffuse.is_black() || self.has_phong()
    }

    /// True when the material has a Phong highlight: a non-zero specular colour and a positive
    /// exponent (an exponent of 0 or less means "no highlight", as in the `.scn` format).
    pub fn has_phong(&self) -> bool {
        self.specular != Vec3::ZERO && self.shininess > 0.0
    }

    /// The Phong lobe's BRDF for light arriving along `wi` seen from `wo` about the unit
    /// shading normal `ns`: `ks (n+2)/(2 pi) cos_r^n`. Evaluated in full for every material (the
    /// `--effects all` reference calls it even where [`Material::has_phong`] is false): without
    /// a highlight the colour factor is zero and the exponent clamped to 0, so the product is an
    /// exact zero, never `0 * inf`.
    pub fn phong(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        let ks = if self.shininess > 0.0 {
            self.specular
        } else {
            Vec3::ZERO
        };
        let n = self.shininess.max(0.0);
        let cos_r = reflect(-wi, ns).dot(wo).max(0.0);
        ks * ((n + 2.0) * 0.5 * std::f32::consts::FRAC_1_PI) * cos_r.powf(n)
    }
}

/// Unpolarised Fresnel reflectance for a dielectric; `cos_i` is the cosine on the incident side
/// and `eta` = n_incident / n_transmitted. Returns 1 on total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Mirror direction of `d` about unit normal `n`.
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - n * (2.0 * d.dot(n))
}

/// Refracted unit direction of unit `d` through a surface with unit normal `n` facing the
/// incident side, `eta` = n_incident / n_transmitted; `None` on total internal reflection.
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    Some((d * eta + n * (eta * cos_i - (1.0 - sin2_t).sqrt())).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_normal_incidence_glass() {
        // ((n-1)/(n+1))^2 = 0.04 for n = 1.5, from either side.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel_dielectric(0.1, 1.5), 1.0);
    }

    #[test]
    fn shading_normal_applies_the_map_and_keeps_the_side() {
        let p = Vec3::new(0.3, 1.7, -2.4);
        assert_eq!(
            Material::default().shading_normal(Vec3::Z, Vec3::Z, p),
            Vec3::Z
        );
        let bumpy = Material {
            normal_map: Some(NormalMap {
                scale: 0.5,
                amount: 0.3,
            }),
            ..Material::default()
        };
        let n = bumpy.shading_normal(Vec3::Z, Vec3::Z, p);
        assert!(n != Vec3::Z && n.z > 0.0 && (n.length() - 1.0).abs() < 1e-5);
        // A huge amount tips some normals below the surface; those fall back to `ns`.
        let wild = Material {
            normal_map: Some(NormalMap {
                scale: 0.5,
                amount: 50.0,
            }),
            ..Material::default()
        };
        let mut fell_back = false;
        for i in 0..200 {
            let q = Vec3::new(i as f32 * 0.137, i as f32 * 0.071, 0.33);
            let n = wild.shading_normal(Vec3::Z, Vec3::Z, q);
            assert!(n.z > 0.0);
            fell_back |= n == Vec3::Z;
        }
        assert!(fell_back);
    }

    #[test]
    fn snell_holds() {
        let d = Vec3::new(0.6, -0.8, 0.0);
        let t = refract(d, Vec3::Y, 1.0 / 1.33).unwrap();
        assert!((t.x - 0.6 / 1.33).abs() < 1e-6);
        assert!(refract(Vec3::new(0.9, -0.43589, 0.0).normalize(), Vec3::Y, 1.5).is_none());
    }
}

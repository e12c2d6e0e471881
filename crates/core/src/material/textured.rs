//! glTF metallic-roughness parameters that vary over a surface (textures, vertex colours),
//! mapped onto the Whitted material at each hit by the same rule as constant factors
//! ([`metal_rough`], documented in `docs/gltf.md`):
//!
//! - base colour `c = factor * texture (sRGB) * COLOR_0`, alpha likewise;
//! - metallic `m = factor * texture.B`, roughness `r = factor * texture.G` (linear);
//! - emission `= factor * strength * emissive texture (sRGB)`;
//! - the normal texture (linear, `(2 rgb - 1) * (scale, scale, 1)`) bends the shading normal
//!   in the tangent frame of the hit;
//! - occlusion `1 + strength * (texture.R - 1)` scales the ambient term only (it stands for
//!   the ambient light a crevice cannot see; direct light has shadow rays for that).

use std::sync::Arc;

use super::{Material, Texture};
use crate::geometry::HitAttributes;
use crate::math::{Vec3, Vec4};
use crate::texture::TextureRef;

/// Largest Phong exponent a perfectly smooth surface gets.
pub const MAX_SHININESS: f32 = 10_000.0;

/// Reflectance at normal incidence of glTF's default dielectric (ior 1.5): its F0 without
/// `KHR_materials_ior`, and the fixed F0 of a `KHR_materials_clearcoat` layer.
pub const DIELECTRIC_F0: f32 = 0.04;

/// Reflectance at normal incidence of a dielectric of index `ior` in air,
/// `((ior - 1) / (ior + 1))^2` (the F0 `KHR_materials_ior` defines). Worked in `f64` so that
/// ior 1.5 gives exactly [`DIELECTRIC_F0`] (in `f32` the square rounds one step above it).
pub fn dielectric_f0(ior: f32) -> f32 {
    let r = (f64::from(ior) - 1.0) / (f64::from(ior) + 1.0);
    (r * r) as f32
}

/// The Whitted parameters of one metallic-roughness point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    /// Diffuse albedo.
    pub kd: Vec3,
    /// Phong colour.
    pub ks: Vec3,
    /// Phong exponent.
    pub shininess: f32,
    /// Mirror weight.
    pub reflectivity: f32,
}

/// The mapping rule, with base colour `c`, metallic `m`, roughness `r`, transmission `t` (all
/// in [0, 1]) and smoothness `s = (1 - r)^2`: mirror `m s` (Whitted has no glossy lobe: only
/// smooth metal mirrors), diffuse `c (1 - m s)(1 - t)` (a rough metal's broad lobe lit by
/// point lights looks diffuse), Phong `ks = lerp(f0, c, m)` (`f0` is glTF's 0.04 unless
/// `KHR_materials_ior` or `KHR_materials_specular` change it) with the Blinn-Phong exponent of the GGX lobe's width
/// `2 / alpha^2 - 2`, `alpha = r^2`, at most [`MAX_SHININESS`].
pub fn metal_rough(c: Vec3, m: f32, r: f32, t: f32, f0: Vec3) -> MetalRough {
    let smooth = (1.0 - r) * (1.0 - r);
    let alpha2 = (r * r).powi(2).max(2.0 / (MAX_SHININESS + 2.0));
    MetalRough {
        kd: c * (1.0 - m * smooth) * (1.0 - t),
        ks: f0.lerp(c, m),
        shininess: (2.0 / alpha2 - 2.0).clamp(0.0, MAX_SHININESS),
        reflectivity: m * smooth,
    }
}

/// The factors and textures of one glTF material, for evaluation at each hit.
#[derive(Clone, Debug, PartialEq)]
pub struct TexturedParams {
    /// `baseColorFactor` (linear RGBA).
    pub base_color: Vec4,
    /// `baseColorTexture` (sRGB).
    pub base_texture: Option<TextureRef>,
    /// `metallicFactor`.
    pub metallic: f32,
    /// `roughnessFactor`.
    pub roughness: f32,
    /// `metallicRoughnessTexture` (linear; B metal, G roughness).
    pub metal_rough_texture: Option<TextureRef>,
    /// Dielectric reflectance at normal incidence (0.04, or from `KHR_materials_ior` and
    /// `KHR_materials_specular`).
    pub f0: Vec3,
    /// Mirror weight added by `KHR_materials_clearcoat`.
    pub clearcoat: f32,
    /// Transmission weight (`KHR_materials_transmission`).
    pub transmission: f32,
    /// `alphaMode` `BLEND` without transmission: transmission is `1 - alpha` at each hit.
    pub blend: bool,
    /// `emissiveFactor * emissive_strength`.
    pub emission: Vec3,
    /// `emissiveTexture` (sRGB).
    pub emissive_texture: Option<TextureRef>,
    /// `normalTexture` (linear) and its `scale`.
    pub normal_texture: Option<(TextureRef, f32)>,
    /// `occlusionTexture` (linear, R) and its `strength`.
    pub occlusion_texture: Option<(TextureRef, f32)>,
}

/// A material evaluated at one hit.
#[derive(Clone, Debug)]
pub struct AtHit {
    /// The constant material that holds there.
    pub material: Material,
    /// Factor on the ambient term (1: no occlusion).
    pub occlusion: f32,
    /// The shading normal, bent by the normal texture (unit, on `ng`'s side).
    pub ns: Vec3,
}

impl TexturedParams {
    /// A white, fully rough dielectric without textures (glTF's factor defaults but metallic
    /// 0): the parameters a mesh without a material evaluates its vertex colours with.
    pub fn white_dielectric() -> Self {
        Self {
            base_color: Vec4::ONE,
            base_texture: None,
            metallic: 0.0,
            roughness: 1.0,
            metal_rough_texture: None,
            f0: Vec3::splat(DIELECTRIC_F0),
            clearcoat: 0.0,
            transmission: 0.0,
            blend: false,
            emission: Vec3::ZERO,
            emissive_texture: None,
            normal_texture: None,
            occlusion_texture: None,
        }
    }

    /// Base colour (RGB) and alpha at a hit with attributes `at`.
    fn base(&self, at: &HitAttributes) -> Vec4 {
        let tex = self
            .base_texture
            .as_ref()
            .map_or(Vec4::ONE, |t| t.sample(&at.uvs));
        self.base_color * tex * at.color.clamp(Vec4::ZERO, Vec4::ONE)
    }

    /// The shading normal `ns` (unit, on the side of `ng`) bent by the normal texture in the
    /// hit's tangent frame; `ns` itself without a map or a tangent, or where the bent normal
    /// would cross to the other side of `ng` (shading from behind makes black speckles).
    fn bent_normal(&self, at: &HitAttributes, ns: Vec3, ng: Vec3) -> Vec3 {
        let (Some((tex, scale)), Some(tangent)) = (&self.normal_texture, at.tangent) else {
            return ns;
        };
        // Gram-Schmidt: the interpolated tangent is not quite perpendicular to `ns`.
        let Some(t) = (tangent.truncate() - ns * ns.dot(tangent.truncate())).try_normalize() else {
            return ns;
        };
        let b = ns.cross(t) * if tangent.w < 0.0 { -1.0 } else { 1.0 };
        let texel = tex.sample(&at.uvs).truncate() * 2.0 - Vec3::ONE;
        let local = texel * Vec3::new(*scale, *scale, 1.0);
        (t * local.x + b * local.y + ns * local.z)
            .try_normalize()
            .filter(|n| n.dot(ng) > 0.0)
            .unwrap_or(ns)
    }
}

/// `base` (for its `ior` and noise normal map) with parameters `p` to evaluate at each hit,
/// and fields that bound every hit's: the largest diffuse, Phong colour, exponent, mirror and
/// transmission weights and emission any texel can give (textures and colours are at most 1),
/// so the effect decisions made from them never skip what a hit needs.
pub fn textured_bounds(base: &Material, p: Arc<TexturedParams>) -> Material {
    let c = p.base_color.truncate();
    let t = if p.blend { 0.0 } else { p.transmission };
    let textured = p.metal_rough_texture.is_some();
    let constant = metal_rough(c, p.metallic, p.roughness, t, p.f0);
    Material {
        diffuse: Texture::Solid(c * (1.0 - t)),
        specular: p.f0.max(c),
        shininess: if textured {
            MAX_SHININESS
        } else {
            constant.shininess
        },
        reflectivity: (if textured {
            p.metallic
        } else {
            constant.reflectivity
        } + p.clearcoat)
            .min(1.0),
        transmission: if p.blend { 1.0 } else { p.transmission },
        ior: base.ior,
        emission: p.emission,
        normal_map: base.normal_map,
        textured: Some(p),
        shadow_catcher: base.shadow_catcher,
    }
}

impl Material {
    /// This material at a hit with attributes `at`, shading normal `ns` and geometric normal
    /// `ng` (unit, same side); `None` when nothing varies (no [`Material::textured`]).
    pub fn at_hit(&self, at: &HitAttributes, ns: Vec3, ng: Vec3) -> Option<AtHit> {
        let p = self.textured.as_deref()?;
        let base = p.base(at);
        let (mut metallic, mut roughness) = (p.metallic, p.roughness);
        if let Some(t) = &p.metal_rough_texture {
            let texel = t.sample(&at.uvs);
            metallic *= texel.z;
            roughness *= texel.y;
        }
        let transmission = if p.blend {
            1.0 - base.w
        } else {
            p.transmission
        };
        let mr = metal_rough(base.truncate(), metallic, roughness, transmission, p.f0);
        let emission = match &p.emissive_texture {
            Some(t) => p.emission * t.sample(&at.uvs).truncate(),
            None => p.emission,
        };
        let occlusion = p.occlusion_texture.as_ref().map_or(1.0, |(t, strength)| {
            1.0 + strength * (t.sample(&at.uvs).x - 1.0)
        });
        Some(AtHit {
            material: Material {
                diffuse: Texture::Solid(mr.kd),
                specular: mr.ks,
                shininess: mr.shininess,
                reflectivity: (mr.reflectivity + p.clearcoat).min(1.0),
                transmission,
                ior: self.ior,
                emission,
                normal_map: self.normal_map,
                textured: None,
                shadow_catcher: self.shadow_catcher,
            },
            occlusion,
            ns: p.bent_normal(at, ns, ng),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;
    use crate::texture::{Encoding, Sampler, Texels};

    fn solid(rgba: [u8; 4], encoding: Encoding) -> TextureRef {
        TextureRef {
            image: Arc::new(Texels::new(1, 1, vec![rgba]).unwrap()),
            sampler: Sampler::default(),
            transform: None,
            tex_coord: 0,
            encoding,
        }
    }

    fn at_hit(p: TexturedParams, at: &HitAttributes) -> AtHit {
        let m = Material {
            textured: Some(Arc::new(p)),
            ..Material::default()
        };
        m.at_hit(at, Vec3::Z, Vec3::Z).unwrap()
    }

    const AT: HitAttributes = HitAttributes {
        uvs: [Vec2::ZERO; 2],
        color: Vec4::ONE,
        tangent: Some(Vec4::new(1.0, 0.0, 0.0, 1.0)),
    };

    #[test]
    fn dielectric_f0_is_gltfs_constant_at_ior_1_5() {
        assert_eq!(dielectric_f0(1.5), DIELECTRIC_F0);
        assert_eq!(dielectric_f0(1.0), 0.0);
        assert!((dielectric_f0(2.0) - 1.0 / 9.0).abs() < 1e-7);
    }

    #[test]
    fn metal_roughness_texture_and_emission_multiply_their_factors() {
        let p = TexturedParams {
            metallic: 1.0,
            roughness: 1.0,
            // G = 0 roughness, B = 255 metal: a mirror.
            metal_rough_texture: Some(solid([0, 0, 255, 255], Encoding::Linear)),
            emission: Vec3::new(2.0, 1.0, 0.0),
            emissive_texture: Some(solid([255, 128, 255, 255], Encoding::Srgb)),
            ..TexturedParams::white_dielectric()
        };
        let h = at_hit(p, &AT);
        assert_eq!(h.material.reflectivity, 1.0);
        let e = h.material.emission;
        assert!(
            (e.x - 2.0).abs() < 1e-6 && (e.y - 0.2158605).abs() < 1e-4,
            "{e}"
        );
    }

    #[test]
    fn occlusion_and_vertex_colour_and_normal_map() {
        let p = TexturedParams {
            occlusion_texture: Some((solid([0, 0, 0, 255], Encoding::Linear), 0.5)),
            // (255, 128, 255): a normal tipped towards +x in tangent space.
            normal_texture: Some((solid([255, 128, 255, 255], Encoding::Linear), 1.0)),
            ..TexturedParams::white_dielectric()
        };
        let at = HitAttributes {
            color: Vec4::new(0.5, 1.0, 1.0, 1.0),
            ..AT
        };
        let h = at_hit(p, &at);
        assert_eq!(h.occlusion, 0.5);
        let Texture::Solid(kd) = h.material.diffuse else {
            panic!()
        };
        assert_eq!(kd, Vec3::new(0.5, 1.0, 1.0));
        assert!(h.ns.x > 0.6 && h.ns.z > 0.6, "{}", h.ns);
    }
}

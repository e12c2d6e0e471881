//! glTF metallic-roughness materials to lumis's Whitted materials. Constant factors map by
//! [`metal_rough`] (documented with its reasons in `docs/gltf.md`); a material with textures
//! (or used by a mesh with vertex colours) keeps its factors and texture references in
//! [`TexturedParams`], evaluated by the same rule at every hit, and its [`Material`] fields
//! hold bounds over all hits, which the effect decisions read. Further rules:
//!
//! - `emission = emissiveFactor * emissive_strength` (times the emissive texture);
//! - `transmission = t`, `ior` from `KHR_materials_ior` (default 1.5);
//! - `alphaMode` BLEND without transmission: `transmission = 1 - alpha`, `ior = 1` (a straight
//!   see-through, with a warning); MASK: an alpha test during intersection (see
//!   [`lumis_core::geometry::AlphaTest`]), the surface opaque where it passes;
//! - the dielectric F0 is `((ior - 1) / (ior + 1))^2` (0.04 at the default 1.5), and
//!   `KHR_materials_specular` makes it `min(F0 * specularColorFactor, 1) * specularFactor`
//!   (the extension's rule); `KHR_materials_clearcoat` adds a mirror of weight
//!   `clearcoatFactor * 0.04 * (1 - clearcoatRoughness)^2`;
//! - everything else (sheen, volume, unlit, their textures, unknown extensions) is ignored with
//!   a warning naming it and the material.

use std::sync::Arc;

use serde_json::Value;

use super::textures::{Images, Slot, reference};
use lumis_core::geometry::AlphaTest;
use lumis_core::material::{
    DIELECTRIC_F0, Material, Texture, TexturedParams, dielectric_f0, metal_rough, textured_bounds,
};
use lumis_core::math::{Vec3, Vec4};
use lumis_core::scene::limits::{MAX_RADIANCE, clamp_range};
use lumis_core::texture::Encoding;

/// A converted material.
pub(super) struct Converted {
    /// The lumis material.
    pub material: Material,
    /// Its parameters for per-hit evaluation (also when `material` has none: a mesh with
    /// vertex colours gets a variant that has them).
    pub params: TexturedParams,
    /// `alphaMode` MASK: the test its meshes' triangles get.
    pub alpha: Option<Arc<AlphaTest>>,
    /// It has a normal texture, so its meshes need tangents.
    pub needs_tangents: bool,
    /// The material as errors and warnings name it, e.g. `materials[2] "brass"`.
    pub element: String,
}

impl Converted {
    /// The material for a mesh with vertex colours, which always varies over the surface.
    pub fn with_vertex_colors(&self) -> Material {
        textured_bounds(&self.material, Arc::new(self.params.clone()))
    }

    /// What meshes without a material get: lumis's grey rather than glTF's default
    /// (metallic 1, roughness 1), which a Whitted renderer without environment light would
    /// show almost black; with vertex colours, white dielectric times the colours.
    pub fn default_material() -> Self {
        Self {
            material: Material::default(),
            params: TexturedParams::white_dielectric(),
            alpha: None,
            needs_tangents: false,
            element: "default material".into(),
        }
    }
}

/// Converts material `m`; warnings name `origin` and the material.
pub(super) fn convert(
    m: &gltf::Material,
    images: &mut Images,
    warnings: &mut Vec<String>,
) -> Converted {
    let element = match (m.index(), m.name()) {
        (Some(i), Some(n)) => format!("materials[{i}] \"{n}\""),
        (Some(i), None) => format!("materials[{i}]"),
        (None, _) => "default material".into(),
    };
    let origin = images.origin.display().to_string();
    let mut warn = |msg: String| warnings.push(format!("{origin}: {element}: {msg}"));
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, alpha] = pbr.base_color_factor().map(unit);
    let base_color = Vec4::new(r, g, b, alpha);

    let transmission = m
        .transmission()
        .map_or(0.0, |t| unit(t.transmission_factor()));
    if let Some(t) = m.transmission().and_then(|t| t.transmission_texture()) {
        let i = t.texture().index();
        warn(format!(
            "KHR_materials_transmission transmissionTexture (textures[{i}]) is not used; \
             the factor applies everywhere"
        ));
    }
    let mut ior = match m.ior() {
        Some(ior) if ior >= 1.0 && ior.is_finite() => ior,
        Some(ior) => {
            warn(format!("ior {ior} is below 1; using 1.5"));
            1.5
        }
        None => 1.5,
    };
    // The file's index sets F0 even where BLEND below replaces it for refraction.
    let f0 = dielectric_f0(ior);
    let mut blend = false;
    let mut alpha_test = None;
    match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => {}
        gltf::material::AlphaMode::Mask => alpha_test = Some(m.alpha_cutoff().unwrap_or(0.5)),
        gltf::material::AlphaMode::Blend if transmission == 0.0 => {
            blend = true;
            // Index 1: the blended surface lets light straight through without bending it.
            ior = 1.0;
            warn(
                "alphaMode BLEND is approximated as transmission 1 - alpha with ior 1 (no \
                 sorting or compositing in a ray tracer)"
                    .into(),
            );
        }
        gltf::material::AlphaMode::Blend => warn(
            "alphaMode BLEND is ignored: KHR_materials_transmission gives the see-through".into(),
        ),
    }

    let strength = m.emissive_strength().filter(|s| *s >= 0.0).unwrap_or(1.0);
    let mut emission = Vec3::from(m.emissive_factor()).max(Vec3::ZERO) * strength;
    if !emission.is_finite() {
        warn("emission is not finite; set to 0".into());
        emission = Vec3::ZERO;
    }
    // As every bad material value in glTF, too bright an emission is a warning (the limit is
    // the scene's, `scene::limits`).
    let (clamped, changed) = clamp_range(emission, MAX_RADIANCE);
    if changed {
        warn(format!(
            "emission {emission} is above {MAX_RADIANCE:e}; clamped to it"
        ));
        emission = clamped;
    }

    let transform = |ext: Option<&Value>| ext.cloned();
    let mut slot = |name, tex: gltf::Texture, tex_coord, ext: Option<Value>, encoding| {
        reference(
            images,
            Slot {
                name,
                texture: tex,
                tex_coord,
                transform: ext.as_ref(),
                encoding,
            },
            &mut warn,
        )
    };
    let base_texture = pbr.base_color_texture().and_then(|i| {
        let ext = transform(i.extension_value("KHR_texture_transform"));
        slot(
            "baseColorTexture",
            i.texture(),
            i.tex_coord(),
            ext,
            Encoding::Srgb,
        )
    });
    let metal_rough_texture = pbr.metallic_roughness_texture().and_then(|i| {
        let ext = transform(i.extension_value("KHR_texture_transform"));
        slot(
            "metallicRoughnessTexture",
            i.texture(),
            i.tex_coord(),
            ext,
            Encoding::Linear,
        )
    });
    let emissive_texture = m.emissive_texture().and_then(|i| {
        let ext = transform(i.extension_value("KHR_texture_transform"));
        slot(
            "emissiveTexture",
            i.texture(),
            i.tex_coord(),
            ext,
            Encoding::Srgb,
        )
    });
    let normal_texture = m.normal_texture().and_then(|i| {
        let ext = transform(i.extension_value("KHR_texture_transform"));
        let scale = if i.scale().is_finite() {
            i.scale()
        } else {
            1.0
        };
        slot(
            "normalTexture",
            i.texture(),
            i.tex_coord(),
            ext,
            Encoding::Linear,
        )
        .map(|t| (t, scale))
    });
    let occlusion_texture = m.occlusion_texture().and_then(|i| {
        let ext = transform(i.extension_value("KHR_texture_transform"));
        let strength = unit(i.strength());
        slot(
            "occlusionTexture",
            i.texture(),
            i.tex_coord(),
            ext,
            Encoding::Linear,
        )
        .map(|t| (t, strength))
    });

    let (f0, clearcoat) = extensions(m, f0, &mut warn);
    let params = TexturedParams {
        base_color,
        base_texture,
        metallic: unit(pbr.metallic_factor()),
        roughness: unit(pbr.roughness_factor()),
        metal_rough_texture,
        f0,
        clearcoat,
        transmission,
        blend,
        emission,
        emissive_texture,
        normal_texture,
        occlusion_texture,
    };
    let alpha = alpha_test.map(|cutoff| {
        Arc::new(AlphaTest {
            factor: alpha,
            texture: params.base_texture.clone(),
            cutoff,
        })
    });
    let constant = params.base_texture.is_none()
        && params.metal_rough_texture.is_none()
        && params.emissive_texture.is_none()
        && params.normal_texture.is_none()
        && params.occlusion_texture.is_none();
    let mut material = Material {
        ior,
        ..Material::default()
    };
    let material = if constant {
        let t = if blend {
            1.0 - base_color.w
        } else {
            transmission
        };
        let mr = metal_rough(
            base_color.truncate(),
            params.metallic,
            params.roughness,
            t,
            f0,
        );
        material.diffuse = Texture::Solid(mr.kd);
        material.specular = mr.ks;
        material.shininess = mr.shininess;
        material.reflectivity = (mr.reflectivity + clearcoat).min(1.0);
        material.transmission = t;
        material.emission = emission;
        material
    } else {
        material.emission = emission;
        textured_bounds(&material, Arc::new(params.clone()))
    };
    Converted {
        material,
        needs_tangents: params.normal_texture.is_some(),
        params,
        alpha,
        element,
    }
}

/// Extensions lumis reads somewhere (the rest of `extensionsUsed` is warned of; material
/// extensions also get a warning on each material that has them).
const KNOWN: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_clearcoat",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    "EXT_mesh_gpu_instancing",
];

/// Warnings naming every entry of `extensionsUsed` lumis does not read, but material ones,
/// which [`convert`] names on each material.
pub(super) fn unused_extensions(doc: &gltf::Document, origin: &std::path::Path) -> Vec<String> {
    doc.extensions_used()
        .filter(|e| !KNOWN.contains(e) && !e.starts_with("KHR_materials_"))
        .map(|e| {
            format!(
                "{}: extensionsUsed: extension {e} is not supported by lumis; ignored",
                origin.display()
            )
        })
        .collect()
}

/// Reads the extensions that map (`KHR_materials_specular`'s factors into the dielectric F0,
/// which is `ior_f0` without them; `KHR_materials_clearcoat` into a mirror weight) and warns
/// of every other one and of their textures. Returns `(f0, clearcoat mirror weight)`.
fn extensions(m: &gltf::Material, ior_f0: f32, warn: &mut dyn FnMut(String)) -> (Vec3, f32) {
    let mut f0 = Vec3::splat(ior_f0);
    let mut clearcoat = 0.0;
    let Some(exts) = m.extensions() else {
        return (f0, clearcoat);
    };
    let number = |v: &Value, key: &str, default: f32| {
        v.get(key)
            .and_then(Value::as_f64)
            .map_or(default, |x| unit(x as f32))
    };
    let textures = |v: &Value, ext: &str, warn: &mut dyn FnMut(String)| {
        if let Some(obj) = v.as_object() {
            for key in obj.keys().filter(|k| k.ends_with("Texture")) {
                warn(format!(
                    "{ext} {key} is not used; its factor applies everywhere"
                ));
            }
        }
    };
    for (name, v) in exts {
        match name.as_str() {
            "KHR_materials_specular" => {
                let colour = v
                    .get("specularColorFactor")
                    .and_then(Value::as_array)
                    .and_then(|a| match a.as_slice() {
                        [r, g, b] => Some(Vec3::new(
                            r.as_f64()? as f32,
                            g.as_f64()? as f32,
                            b.as_f64()? as f32,
                        )),
                        _ => None,
                    })
                    .filter(|c| c.is_finite())
                    .unwrap_or(Vec3::ONE)
                    .max(Vec3::ZERO);
                // The colour may exceed 1 and is clamped before the factor weights it.
                f0 = (f0 * colour).min(Vec3::ONE) * number(v, "specularFactor", 1.0);
                textures(v, name, warn);
            }
            "KHR_materials_clearcoat" => {
                let smooth = (1.0 - number(v, "clearcoatRoughness", 0.0)).powi(2);
                // The coat is its own layer of fixed index 1.5, whatever the base's ior.
                clearcoat = number(v, "clearcoatFactor", 0.0) * DIELECTRIC_F0 * smooth;
                textures(v, name, warn);
            }
            other => {
                warn(format!(
                    "extension {other} is not supported by lumis; ignored"
                ));
            }
        }
    }
    (f0, clearcoat)
}

/// `x` clamped to `[0, 1]` (glTF factors are specified there; JSON cannot carry NaN).
fn unit(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

//! glTF metallic-roughness materials to lumis's Whitted materials. The rules (documented with
//! their reasons in `docs/gltf.md`), with base colour `c`, metallic `m`, roughness `r`,
//! transmission `t` and smoothness `s = (1 - r)^2`:
//!
//! - mirror `reflectivity = m * s` (Whitted has no glossy lobe: only smooth metal mirrors);
//! - diffuse `kd = c * (1 - m * s) * (1 - t)` (a rough metal's broad lobe, lit by point lights,
//!   looks diffuse, so it keeps its colour instead of going black);
//! - Phong `ks = lerp(0.04, c, m)`, exponent `n = 2 / alpha^2 - 2` with `alpha = r^2`, at most
//!   10 000 (the Blinn-Phong exponent with the GGX lobe's width; 0 for `r = 1`: no highlight);
//! - `emission = emissiveFactor * emissive_strength`;
//! - `transmission = t`, `ior` from `KHR_materials_ior` (default 1.5);
//! - `alphaMode` BLEND without transmission: `transmission = 1 - alpha`, `ior = 1` (a straight
//!   see-through); MASK: opaque when `alpha >= alphaCutoff`, else fully see-through.

use std::path::Path;

use super::Resolver;
use super::buffers::{UriError, read_uri, resolve_uri};
use crate::material::{Material, Texture};
use crate::math::Vec3;
use crate::texture::ImageTexture;

/// Largest Phong exponent a perfectly smooth surface gets.
const MAX_SHININESS: f32 = 10_000.0;

/// Reflectance of a dielectric at normal incidence (ior 1.5), glTF's fixed F0.
const DIELECTRIC_F0: f32 = 0.04;

/// A converted material and what it could not apply yet.
pub(super) struct Converted {
    /// The lumis material.
    pub material: Material,
    /// Index of the base colour texture's image; the loader decodes it and multiplies it
    /// into `diffuse` (which holds the factor meanwhile).
    pub base_color_image: Option<usize>,
    /// The material as errors and warnings name it, e.g. `materials[2] "brass"`.
    pub element: String,
}

/// Converts material `m` of the glTF file `origin`; warnings name the file and the material.
pub(super) fn convert(m: &gltf::Material, origin: &Path, warnings: &mut Vec<String>) -> Converted {
    let element = match (m.index(), m.name()) {
        (Some(i), Some(n)) => format!("materials[{i}] \"{n}\""),
        (Some(i), None) => format!("materials[{i}]"),
        (None, _) => "default material".into(),
    };
    let mut warn = |msg: String| warnings.push(format!("{}: {element}: {msg}", origin.display()));
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, alpha] = pbr.base_color_factor().map(unit);
    let base = Vec3::new(r, g, b);
    let metallic = unit(pbr.metallic_factor());
    let roughness = unit(pbr.roughness_factor());
    let smooth = (1.0 - roughness) * (1.0 - roughness);

    let mut transmission = m
        .transmission()
        .map_or(0.0, |t| unit(t.transmission_factor()));
    let mut ior = match m.ior() {
        Some(ior) if ior >= 1.0 && ior.is_finite() => ior,
        Some(ior) => {
            warn(format!("ior {ior} is below 1; using 1.5"));
            1.5
        }
        None => 1.5,
    };
    let alpha_factor = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => 1.0,
        gltf::material::AlphaMode::Mask => {
            if alpha >= m.alpha_cutoff().unwrap_or(0.5) {
                1.0
            } else {
                0.0
            }
        }
        gltf::material::AlphaMode::Blend => alpha,
    };
    if alpha_factor < 1.0 && transmission == 0.0 {
        transmission = 1.0 - alpha_factor;
        // Index 1: the blended surface lets light straight through without bending it.
        ior = 1.0;
    }

    let alpha2 = (roughness * roughness)
        .powi(2)
        .max(2.0 / (MAX_SHININESS + 2.0));
    let shininess = (2.0 / alpha2 - 2.0).clamp(0.0, MAX_SHININESS);
    let strength = m.emissive_strength().filter(|s| *s >= 0.0).unwrap_or(1.0);
    let emission = Vec3::from(m.emissive_factor()).max(Vec3::ZERO) * strength;

    let base_color_image = pbr.base_color_texture().map(|info| {
        if info.tex_coord() != 0 {
            warn(format!(
                "base colour texture uses TEXCOORD_{}; lumis reads TEXCOORD_0 only",
                info.tex_coord()
            ));
        }
        info.texture().source().index()
    });
    if !emission.is_finite() {
        warn("emission is not finite; set to 0".into());
    }
    Converted {
        material: Material {
            diffuse: Texture::Solid(base * (1.0 - metallic * smooth) * (1.0 - transmission)),
            specular: Vec3::splat(DIELECTRIC_F0).lerp(base, metallic),
            shininess,
            reflectivity: metallic * smooth,
            transmission,
            ior,
            emission: if emission.is_finite() {
                emission
            } else {
                Vec3::ZERO
            },
            normal_map: None,
        },
        base_color_image,
        element,
    }
}

/// `x` clamped to `[0, 1]` (glTF factors are specified there; JSON cannot carry NaN).
fn unit(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

/// Where an image's bytes are: the resolved file, an embedded data URI, or a buffer view.
/// Decodes `image` (an external file, a data URI or a buffer view of `buffers`) into a linear
/// texture; the error says which image failed and why.
pub(super) fn decode_image(
    image: &gltf::Image,
    buffers: &[Vec<u8>],
    origin: &Path,
    resolver: Resolver<'_>,
) -> Result<ImageTexture, String> {
    let at = format!("images[{}]", image.index());
    let (bytes, name) = match image.source() {
        gltf::image::Source::Uri { uri, .. } => {
            let name = if uri.starts_with("data:") {
                origin.to_path_buf()
            } else {
                resolve_uri(origin, uri)
            };
            let bytes = read_uri(uri, origin, resolver).map_err(|e| match e {
                UriError::Data(m) => format!("{at}: {m}"),
                UriError::File(f, e) => format!("{at}: cannot read {}: {e}", f.display()),
            })?;
            (bytes, name)
        }
        gltf::image::Source::View { view, .. } => {
            let buffer = buffers
                .get(view.buffer().index())
                .ok_or(format!("{at}: its buffer is missing"))?;
            let bytes = buffer
                .get(view.offset()..view.offset().saturating_add(view.length()))
                .ok_or(format!(
                    "{at}: bufferViews[{}] lies outside its buffer",
                    view.index()
                ))?;
            (bytes.to_vec(), origin.to_path_buf())
        }
    };
    ImageTexture::decode(&bytes, &name).map_err(|e| format!("{at}: {e}"))
}

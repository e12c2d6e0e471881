//! MTL materials to lumis materials; the mapping, `illum` table included, is documented in
//! `docs/obj-mtl.md`. Nothing here fails: a bad value or a missing texture becomes a warning
//! naming the file and material, and a default takes its place.
//!
//! ```text
//! newmtl glass
//! Kd 0 0 0
//! Ks 1 1 1
//! Ns 200
//! Ni 1.5
//! d 0.1          # transmission 0.9
//! illum 7        # refraction with Fresnel
//! ```

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::Resolver;
use lumis_core::material::{MAX_SHININESS, Material, Texture};
use lumis_core::math::Vec3;
use lumis_core::scene::limits::{MAX_RADIANCE, clamp_range};
use lumis_core::texture::ImageTexture;

/// Turns MTL materials into lumis materials, loading each texture file once.
pub(super) struct MtlConverter<'a> {
    resolver: Resolver<'a>,
    /// Texture path to the decoded image, `None` once it has failed (warned about once).
    textures: HashMap<PathBuf, Option<Arc<ImageTexture>>>,
    /// Problems survived, each naming its file.
    pub warnings: Vec<String>,
}

impl<'a> MtlConverter<'a> {
    /// A converter reading texture files through `resolver`.
    pub fn new(resolver: Resolver<'a>) -> Self {
        Self {
            resolver,
            textures: HashMap::new(),
            warnings: Vec::new(),
        }
    }

    /// The lumis material for `m`, read from the MTL file `mtl` (texture paths start in its
    /// folder).
    pub fn convert(&mut self, m: &tobj::Material, mtl: &Path) -> Material {
        let d = Material::default();
        let at = format!("{}: material \"{}\"", mtl.display(), m.name);
        // Reflectances above 1 (exporters write `Ks 1.5`) and absurd emission are clamped with
        // a warning, as every bad MTL value is: the scene's limits are `scene::limits`.
        let kd = self.colour(&at, "Kd", m.diffuse, Vec3::splat(0.8), 1.0);
        let ks = self.colour(&at, "Ks", m.specular, Vec3::ZERO, 1.0);
        let emission = self.colour(&at, "Ke", m.emissive, Vec3::ZERO, MAX_RADIANCE);
        let shininess = match m.shininess {
            Some(n) if n.is_finite() && n > MAX_SHININESS => {
                self.warnings.push(format!(
                    "{at}: Ns {n} is above {MAX_SHININESS}; clamped to it"
                ));
                MAX_SHININESS
            }
            Some(n) if n.is_finite() && n >= 0.0 => n,
            Some(n) => self.warn_default(&at, "Ns", n, 0.0),
            None => 0.0,
        };
        let ior = match m.optical_density {
            Some(n) if n.is_finite() && n > 0.0 => n,
            Some(n) => self.warn_default(&at, "Ni", n, d.ior),
            None => d.ior,
        };
        // Opacity: `d`, or `Tr` = 1 - d when only that is given.
        let tr = m
            .unknown_param
            .get("Tr")
            .and_then(|t| t.trim().parse::<f32>().ok());
        let opacity = match m.dissolve.or(tr.map(|t| 1.0 - t)) {
            Some(o) if (0.0..=1.0).contains(&o) => o,
            Some(o) => self.warn_default(&at, "d/Tr", o, 1.0),
            None => 1.0,
        };
        let illum = m.illumination_model.unwrap_or(2);
        let mirror = (ks.x + ks.y + ks.z) / 3.0;
        let (specular, reflectivity, transmission) = match illum {
            // Colour only / Lambert: no highlight.
            0 | 1 => (Vec3::ZERO, 0.0, 1.0 - opacity),
            2 => (ks, 0.0, 1.0 - opacity),
            // Mirror (3, 8 without ray tracing, 5 whose Fresnel lumis approximates by Ks).
            3 | 5 | 8 => (ks, mirror.clamp(0.0, 1.0), 1.0 - opacity),
            // Glass: exporters write `d 1` by default, so an opaque d means fully clear.
            4 | 6 | 7 | 9 => (ks, 0.0, if opacity < 1.0 { 1.0 - opacity } else { 1.0 }),
            other => {
                self.warnings.push(format!(
                    "{at}: illum {other} is not supported; shaded as illum 2 (Phong)"
                ));
                (ks, 0.0, 1.0 - opacity)
            }
        };
        let diffuse = match &m.diffuse_texture {
            Some(name) => self.texture(&at, mtl, name, m.diffuse.map_or(Vec3::ONE, |_| kd)),
            None => None,
        };
        Material {
            diffuse: diffuse.unwrap_or(Texture::Solid(kd)),
            specular,
            shininess,
            reflectivity,
            transmission,
            ior,
            emission,
            normal_map: None,
            textured: None,
            shadow_catcher: false,
        }
    }

    /// A finite, non-negative colour clamped to `max` (with a warning), or `default` with a
    /// warning.
    fn colour(
        &mut self,
        at: &str,
        key: &str,
        c: Option<[f32; 3]>,
        default: Vec3,
        max: f32,
    ) -> Vec3 {
        match c.map(Vec3::from) {
            Some(c) if c.is_finite() && c.min_element() >= 0.0 => {
                let (clamped, changed) = clamp_range(c, max);
                if changed {
                    self.warnings.push(format!(
                        "{at}: {key} {c} is above {max}; clamped to {clamped}"
                    ));
                }
                clamped
            }
            Some(c) => {
                self.warnings.push(format!(
                    "{at}: {key} {c} must be finite and >= 0; using {default}"
                ));
                default
            }
            None => default,
        }
    }

    fn warn_default(&mut self, at: &str, key: &str, got: f32, default: f32) -> f32 {
        self.warnings.push(format!(
            "{at}: {key} {got} is out of range; using {default}"
        ));
        default
    }

    /// `map_Kd name` as an image texture tinted by `tint`; `None` (with a warning) when the file
    /// cannot be read or decoded.
    fn texture(&mut self, at: &str, mtl: &Path, name: &str, tint: Vec3) -> Option<Texture> {
        let mut name = name.trim();
        if name.starts_with('-') {
            // Options such as `-s 1 1 1` or `-bm 0.5` precede the file name.
            self.warnings
                .push(format!("{at}: map_Kd options in \"{name}\" are ignored"));
            name = name.split_whitespace().last().unwrap_or(name);
        }
        // Exporters on Windows write backslashes.
        let file = name.replace('\\', "/");
        let path = mtl.parent().unwrap_or(Path::new("")).join(file);
        let image = match self.textures.get(&path) {
            Some(cached) => cached.clone(),
            None => {
                let loaded = (self.resolver)(&path)
                    .map_err(|e| e.to_string())
                    .and_then(|bytes| {
                        crate::formats::images::image_texture(&bytes, &path)
                            .map_err(|e| e.to_string())
                    });
                let image = match loaded {
                    Ok(img) => Some(Arc::new(img)),
                    Err(e) => {
                        self.warnings.push(format!(
                            "{at}: cannot load texture {}: {e}; using the plain Kd colour",
                            path.display()
                        ));
                        None
                    }
                };
                self.textures.insert(path, image.clone());
                image
            }
        };
        image.map(|image| Texture::Image { image, tint })
    }
}

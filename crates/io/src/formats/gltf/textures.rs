//! Texture references of glTF materials: the image (decoded once however many references
//! share it), the sampler's wrap modes and filter, the coordinate set, and
//! `KHR_texture_transform`. A reference that cannot be honoured is left out with a warning
//! naming the material and the texture.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use gltf::texture::{MagFilter, WrappingMode};
use serde_json::Value;

use super::Resolver;
use super::buffers::{UriError, read_uri, resolve_uri};
use lumis_core::math::Vec2;
use lumis_core::texture::{Encoding, Sampler, Texels, TextureRef, UvTransform, Wrap};

/// The images of one file, decoded on first use.
pub(super) struct Images<'a> {
    pub buffers: &'a [Vec<u8>],
    pub origin: &'a Path,
    pub resolver: Resolver<'a>,
    cache: HashMap<usize, Result<Arc<Texels>, String>>,
    /// Textures some reference applied, for the warning about the others.
    used: Vec<bool>,
}

impl<'a> Images<'a> {
    pub fn new(buffers: &'a [Vec<u8>], origin: &'a Path, resolver: Resolver<'a>) -> Self {
        Self {
            buffers,
            origin,
            resolver,
            cache: HashMap::new(),
            used: Vec::new(),
        }
    }

    /// Warnings naming every texture of `doc` that no applied reference uses.
    pub fn unused(&self, doc: &gltf::Document) -> Vec<String> {
        doc.textures()
            .filter(|t| !self.used.get(t.index()).copied().unwrap_or(false))
            .map(|t| {
                let name = t.name().map_or(String::new(), |n| format!(" \"{n}\""));
                let image = t
                    .source()
                    .map_or("no image".into(), |i| format!("images[{}]", i.index()));
                format!(
                    "{}: textures[{}]{name} ({image}) is not used by lumis",
                    self.origin.display(),
                    t.index(),
                )
            })
            .collect()
    }

    /// The texels of `image`, or why they cannot be had.
    fn get(&mut self, image: &gltf::Image) -> Result<Arc<Texels>, String> {
        let (buffers, origin, resolver) = (self.buffers, self.origin, self.resolver);
        self.cache
            .entry(image.index())
            .or_insert_with(|| decode_image(image, buffers, origin, resolver).map(Arc::new))
            .clone()
    }
}

/// One texture slot of a material, as the file gives it.
pub(super) struct Slot<'a> {
    /// How warnings name it, e.g. `emissiveTexture`.
    pub name: &'static str,
    pub texture: gltf::Texture<'a>,
    pub tex_coord: u32,
    /// The texture info's `KHR_texture_transform` object, if any.
    pub transform: Option<&'a Value>,
    pub encoding: Encoding,
}

/// The reference `slot` makes, or `None` (with a warning through `warn`) when it cannot be
/// applied: an unreadable image, or a coordinate set past `TEXCOORD_1`.
pub(super) fn reference(
    images: &mut Images,
    slot: Slot,
    warn: &mut dyn FnMut(String),
) -> Option<TextureRef> {
    let name = slot.name;
    let (transform, tex_coord) = match slot.transform {
        Some(t) => {
            let (transform, set) = parse_transform(t);
            (Some(transform), set.unwrap_or(slot.tex_coord))
        }
        None => (None, slot.tex_coord),
    };
    if tex_coord > 1 {
        warn(format!(
            "{name} uses TEXCOORD_{tex_coord}; lumis reads TEXCOORD_0 and TEXCOORD_1 only; \
             texture not applied"
        ));
        return None;
    }
    // `source` is optional: an extension (KHR_texture_basisu, EXT_texture_webp) may be the
    // only one naming the image.
    let Some(source) = slot.texture.source() else {
        warn(format!(
            "{name} not applied: textures[{}] has no source image lumis can read (only an \
             extension's)",
            slot.texture.index()
        ));
        return None;
    };
    let image = match images.get(&source) {
        Ok(image) => image,
        Err(e) => {
            warn(format!("{name} not applied: {e}"));
            return None;
        }
    };
    let index = slot.texture.index();
    if images.used.len() <= index {
        images.used.resize(index + 1, false);
    }
    images.used[index] = true;
    let s = slot.texture.sampler();
    let wrap = |m: WrappingMode| match m {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
    };
    Some(TextureRef {
        image,
        sampler: Sampler {
            wrap_u: wrap(s.wrap_s()),
            wrap_v: wrap(s.wrap_t()),
            nearest: s.mag_filter() == Some(MagFilter::Nearest),
        },
        transform,
        tex_coord,
        encoding: slot.encoding,
    })
}

/// A `KHR_texture_transform` object: the transform (defaults for missing or malformed members)
/// and its `texCoord` override.
fn parse_transform(v: &Value) -> (UvTransform, Option<u32>) {
    let pair = |key: &str, default: Vec2| {
        v.get(key)
            .and_then(Value::as_array)
            .and_then(|a| match a.as_slice() {
                [x, y] => Some(Vec2::new(x.as_f64()? as f32, y.as_f64()? as f32)),
                _ => None,
            })
            .filter(|p| p.is_finite())
            .unwrap_or(default)
    };
    let rotation = v
        .get("rotation")
        .and_then(Value::as_f64)
        .map(|r| r as f32)
        .filter(|r| r.is_finite())
        .unwrap_or(0.0);
    let tex_coord = v
        .get("texCoord")
        .and_then(Value::as_u64)
        .map(|t| t.min(u64::from(u32::MAX)) as u32);
    (
        UvTransform {
            offset: pair("offset", Vec2::ZERO),
            rotation,
            scale: pair("scale", Vec2::ONE),
        },
        tex_coord,
    )
}

/// Decodes `image` (an external file, a data URI or a buffer view of `buffers`); the error
/// says which image failed and why.
fn decode_image(
    image: &gltf::Image,
    buffers: &[Vec<u8>],
    origin: &Path,
    resolver: Resolver<'_>,
) -> Result<Texels, String> {
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
    crate::formats::images::texels(&bytes, &name).map_err(|e| format!("{at}: {e}"))
}

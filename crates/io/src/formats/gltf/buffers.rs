//! The container and the bytes behind it: GLB header checks, JSON parsing and schema
//! validation, buffer loading (GLB binary chunk, base64 data URIs, external files) and a
//! bounds check of every accessor before anything reads through it.
//!
//! The `gltf` crate's reader slices buffers without checking lengths (and underflows on an
//! accessor of count 0), so every accessor is checked here first; after this, reading an
//! accessor through the crate cannot go out of bounds.

use std::path::{Path, PathBuf};

use gltf::Document;

use super::super::{Resolver, SceneError};
use super::{checks, lenient};

/// Extensions lumis understands; a file that requires any other one is refused.
pub(super) const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_mesh_quantization",
    "KHR_texture_transform",
    "EXT_mesh_gpu_instancing",
];

/// Parses a .gltf (JSON) or .glb file, refuses unsupported required extensions, and validates
/// the document's references (leniently where the specification is: see [`lenient`]). Returns
/// the document and the GLB binary chunk, if any.
pub(super) fn parse(
    bytes: &[u8],
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<(Document, Option<Vec<u8>>), SceneError> {
    let fail = |message: String| SceneError::Gltf {
        path: path.to_path_buf(),
        message,
    };
    if bytes.starts_with(b"glTF") {
        // The crate subtracts the header size from the declared length without checking it.
        let declared = bytes
            .get(8..12)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
        match declared {
            Some(n) if n >= 20 && n <= bytes.len() => {}
            Some(n) => {
                return Err(fail(format!(
                    "GLB header: truncated file: the header gives {n} bytes, the file has {}",
                    bytes.len()
                )));
            }
            None => {
                return Err(fail(format!(
                    "GLB header: truncated file: {} bytes, shorter than the 12-byte header",
                    bytes.len()
                )));
            }
        }
    }
    let (json, blob) = if bytes.starts_with(b"glTF") {
        let glb = gltf::binary::Glb::from_slice(bytes).map_err(|e| fail(describe(&e)))?;
        (glb.json, glb.bin.map(std::borrow::Cow::into_owned))
    } else {
        (std::borrow::Cow::Borrowed(bytes), None)
    };
    let document = Document::from_json_without_validation(lenient::root(&json, path, warnings)?);
    // Checked before validation, which would only say "unsupported extension" without its name.
    for (i, ext) in document.extensions_required().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            return Err(SceneError::invalid(
                path,
                format!("extensionsRequired[{i}]"),
                format!(
                    "the file requires extension {ext}, which lumis does not support \
                     (supported: {})",
                    SUPPORTED_EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    let mut json = document.into_json();
    // Extensions lumis reads itself, which the crate's validation would refuse as unknown
    // when required (they were checked above).
    json.extensions_required.retain(|e| {
        !matches!(
            e.as_str(),
            "KHR_mesh_quantization" | "KHR_texture_transform" | "EXT_mesh_gpu_instancing"
        )
    });
    // gltf-json's validation indexes the POSITION accessor before checking that it exists.
    let accessors = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            if let Some(bad) = prim.attributes.values().find(|i| i.value() >= accessors) {
                return Err(SceneError::invalid(
                    path,
                    format!("meshes[{m}].primitives[{p}].attributes"),
                    format!(
                        "accessor {} does not exist (the file has {accessors})",
                        bad.value()
                    ),
                ));
            }
        }
    }
    checks::check_elements(&json, path)?;
    let document = lenient::validate(json, path, warnings)?;
    Ok((document, blob))
}

/// The crate's error without its own "invalid glTF" prefix (the variant adds one).
fn describe(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Validation(errors) => errors
            .iter()
            .map(|(at, what)| format!("{at}: {what}"))
            .collect::<Vec<_>>()
            .join("; "),
        gltf::Error::Binary(b) => format!("GLB container: {b}"),
        gltf::Error::Deserialize(j) => format!("JSON: {j}"),
        other => other.to_string(),
    }
}

/// The bytes of every buffer, in buffer order. `origin` is the glTF file (relative URIs start
/// in its folder); `resolver` reads external files.
pub(super) fn load_buffers(
    doc: &Document,
    mut blob: Option<Vec<u8>>,
    origin: &Path,
    resolver: Resolver<'_>,
) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let element = format!("buffers[{}]", buffer.index());
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                SceneError::invalid(
                    origin,
                    &element,
                    "refers to the GLB binary chunk, but the file has none",
                )
            })?,
            gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, origin, resolver).map_err(|e| e.at(origin, &element))?
            }
        };
        if data.len() < buffer.length() {
            return Err(SceneError::invalid(
                origin,
                &element,
                format!(
                    "has {} bytes, but its byteLength is {}",
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        // Views are checked against the declared length, not against padding or extra bytes.
        data.truncate(buffer.length());
        out.push(data);
    }
    Ok(out)
}

/// Why a URI could not be read, before the element is known.
pub(super) enum UriError {
    /// A malformed data URI.
    Data(String),
    /// An external file that could not be read.
    File(PathBuf, std::io::Error),
}

impl UriError {
    /// The error as a scene error of `element` in `origin`.
    pub(super) fn at(self, origin: &Path, element: &str) -> SceneError {
        match self {
            UriError::Data(message) => SceneError::invalid(origin, element, message),
            UriError::File(file, source) => SceneError::Asset {
                path: origin.to_path_buf(),
                element: element.to_string(),
                file: file.clone(),
                source: Box::new(SceneError::Read { path: file, source }),
            },
        }
    }
}

/// The bytes a buffer or image URI names: a base64 data URI, or a file relative to `origin`.
pub(super) fn read_uri(
    uri: &str,
    origin: &Path,
    resolver: Resolver<'_>,
) -> Result<Vec<u8>, UriError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or_else(|| UriError::Data("only base64 data URIs are supported".into()))?;
        return base64_decode(payload)
            .ok_or_else(|| UriError::Data("the data URI is not valid base64".into()));
    }
    let file = resolve_uri(origin, uri);
    resolver(&file).map_err(|e| UriError::File(file, e))
}

/// A relative URI reference (percent-encoded, `/`-separated) as a path beside `origin`.
pub(super) fn resolve_uri(origin: &Path, uri: &str) -> PathBuf {
    origin
        .parent()
        .unwrap_or(Path::new(""))
        .join(percent_decode(uri))
}

/// Undoes `%XX` escapes; malformed escapes stay as they are.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        match (
            b[i],
            b.get(i + 1).and_then(|&c| hex(c)),
            b.get(i + 2).and_then(|&c| hex(c)),
        ) {
            (b'%', Some(hi), Some(lo)) => {
                out.push((hi * 16 + lo) as u8);
                i += 3;
            }
            (c, ..) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Standard base64 (with or without `=` padding); `None` on any other character.
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let s = s.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    for chunk in s.chunks(4) {
        if chunk.len() == 1 {
            return None;
        }
        let mut acc = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            acc |= value(c)? << (18 - 6 * k);
        }
        out.extend_from_slice(&acc.to_be_bytes()[1..chunk.len()]);
    }
    Some(out)
}

/// Checks that every accessor (and every buffer view it uses) lies inside its buffer and that
/// sparse indices are strictly increasing and in range, so the crate's reader never slices
/// out of bounds.
pub(super) fn check_accessors(
    doc: &Document,
    buffers: &[Vec<u8>],
    origin: &Path,
) -> Result<(), SceneError> {
    for view in doc.views() {
        let len = buffers.get(view.buffer().index()).map_or(0, Vec::len);
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|end| end > len) {
            return Err(SceneError::invalid(
                origin,
                format!("bufferViews[{}]", view.index()),
                format!(
                    "bytes {}..{} lie outside buffers[{}] ({len} bytes)",
                    view.offset(),
                    view.offset().saturating_add(view.length()),
                    view.buffer().index()
                ),
            ));
        }
    }
    for accessor in doc.accessors() {
        let element = format!("accessors[{}]", accessor.index());
        let err = |message: String| SceneError::invalid(origin, &element, message);
        let count = accessor.count();
        if count == 0 {
            return Err(err("count is 0".into()));
        }
        if let Some(view) = accessor.view() {
            fits(&view, accessor.offset(), count, accessor.size()).map_err(err)?;
        }
        if let Some(sparse) = accessor.sparse() {
            let n = sparse.count();
            if n == 0 || n > count {
                return Err(err(format!("sparse count {n} must be in 1..={count}")));
            }
            let indices = sparse.indices();
            let size = indices.index_type().size();
            fits(&indices.view(), indices.offset(), n, size)
                .map_err(|m| err(format!("sparse indices: {m}")))?;
            let values = sparse.values();
            fits(&values.view(), values.offset(), n, accessor.size())
                .map_err(|m| err(format!("sparse values: {m}")))?;
            // The crate's sparse iterator silently drops indices that are out of order.
            let view = indices.view();
            let stride = view.stride().unwrap_or(size);
            let data = &buffers[view.buffer().index()][view.offset()..][indices.offset()..];
            let mut previous: Option<usize> = None;
            for k in 0..n {
                let b = &data[k * stride..k * stride + size];
                let i = match size {
                    1 => b[0] as usize,
                    2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                    _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
                };
                if i >= count || previous.is_some_and(|p| i <= p) {
                    return Err(err(format!(
                        "sparse index {k} is {i}: sparse indices must increase and stay below {count}"
                    )));
                }
                previous = Some(i);
            }
        }
    }
    Ok(())
}

/// Checks that `count` elements of `size` bytes from `offset` in `view` (at its stride) fit.
fn fits(view: &gltf::buffer::View, offset: usize, count: usize, size: usize) -> Result<(), String> {
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "byteStride {stride} of bufferViews[{}] is smaller than an element ({size} bytes)",
            view.index()
        ));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(size));
    match end {
        Some(end) if end <= view.length() => Ok(()),
        _ => Err(format!(
            "{count} elements of {size} bytes from byte {offset} do not fit bufferViews[{}] \
             ({} bytes)",
            view.index(),
            view.length()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_strings() {
        assert_eq!(base64_decode("TWFu").as_deref(), Some(&b"Man"[..]));
        assert_eq!(base64_decode("TWE=").as_deref(), Some(&b"Ma"[..]));
        assert_eq!(base64_decode("TQ==").as_deref(), Some(&b"M"[..]));
        assert_eq!(base64_decode("").as_deref(), Some(&b""[..]));
        assert_eq!(base64_decode("TQ!="), None);
        assert_eq!(base64_decode("TWFuT"), None);
    }

    #[test]
    fn uris_are_percent_decoded_beside_the_file() {
        let p = resolve_uri(Path::new("/a/b/model.gltf"), "my%20mesh.bin");
        assert_eq!(p, Path::new("/a/b/my mesh.bin"));
        assert_eq!(percent_decode("100%"), "100%");
    }
}

//! Checks of JSON elements that the `gltf` crate's own validation lets through but its
//! accessors then `unwrap` (a panic) or that would size an allocation from a number alone.
//! They run on the document before anything reads through it, and each error names the
//! element.

use std::path::Path;

use gltf::json::Root;

use super::super::SceneError;

/// Most elements of an accessor that has no buffer view (all zeros, plus its sparse values):
/// no bytes in the file back such a count, so this stated limit bounds what it allocates
/// (2^20 elements: at most 16 MiB for a VEC4 of floats).
pub(super) const MAX_IMPLIED: usize = 1 << 20;

/// Refuses images whose source the crate would `unwrap` (neither `uri` nor `bufferView`, both,
/// or a `bufferView` without `mimeType`), buffers of `byteLength` 0 (the specification's
/// minimum is 1), and accessors without a buffer view whose `count` exceeds [`MAX_IMPLIED`].
pub(super) fn check_elements(json: &Root, path: &Path) -> Result<(), SceneError> {
    for (i, image) in json.images.iter().enumerate() {
        let problem = match (&image.uri, &image.buffer_view, &image.mime_type) {
            (None, None, _) => Some("has neither `uri` nor `bufferView`"),
            (Some(_), Some(_), _) => Some("has both `uri` and `bufferView`"),
            (None, Some(_), None) => Some("has a `bufferView` but no `mimeType`"),
            _ => None,
        };
        if let Some(problem) = problem {
            return Err(SceneError::invalid(path, format!("images[{i}]"), problem));
        }
    }
    for (i, buffer) in json.buffers.iter().enumerate() {
        if buffer.byte_length.0 == 0 {
            return Err(SceneError::invalid(
                path,
                format!("buffers[{i}]"),
                "byteLength is 0 (a buffer has at least 1 byte)",
            ));
        }
    }
    for (i, accessor) in json.accessors.iter().enumerate() {
        let count = accessor.count.0;
        if accessor.buffer_view.is_none() && count > MAX_IMPLIED as u64 {
            return Err(SceneError::invalid(
                path,
                format!("accessors[{i}]"),
                format!(
                    "has no bufferView and count {count}: no bytes back its elements, and at \
                     most {MAX_IMPLIED} are accepted"
                ),
            ));
        }
    }
    Ok(())
}

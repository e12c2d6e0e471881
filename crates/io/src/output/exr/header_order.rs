//! Puts the attributes of an encoded single-part OpenEXR header into a fixed order.
//!
//! The exr crate keeps custom attributes in a `HashMap` and writes them in its iteration
//! order, which changes from run to run, so two renders of the same scene gave files that
//! differ in the header. The attributes are sorted here by name, after encoding. The header
//! keeps its length, so the chunk offset table after it stays valid.
//!
//! Layout (OpenEXR file layout spec): magic `76 2f 31 01`, 4 version bytes, then attributes
//! `name\0 type\0 size:i32le value[size]`, then one `\0`; then the offset table and the chunks.

/// The file with its header attributes sorted by name; `None` when `bytes` is not a
/// single-part OpenEXR file whose header parses (the caller then keeps the bytes as they are).
pub fn sorted_header(bytes: &[u8]) -> Option<Vec<u8>> {
    const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
    const MULTIPART: u8 = 0x10; // bit 12 of the version field, in its second byte
    if bytes.len() < 8 || bytes[..4] != MAGIC || bytes[5] & MULTIPART != 0 {
        return None;
    }
    let mut attributes: Vec<&[u8]> = Vec::new();
    let mut at = 8;
    loop {
        if *bytes.get(at)? == 0 {
            break;
        }
        let start = at;
        at = nul_end(bytes, at)?; // name
        at = nul_end(bytes, at)?; // type
        let size = i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?);
        let size = usize::try_from(size).ok()?;
        at = at.checked_add(4 + size)?;
        if at > bytes.len() {
            return None;
        }
        attributes.push(&bytes[start..at]);
    }
    // Names are unique in a header, so comparing whole records orders them by name.
    attributes.sort_unstable();
    let mut out = Vec::with_capacity(bytes.len());
    out.extend_from_slice(&bytes[..8]);
    for a in attributes {
        out.extend_from_slice(a);
    }
    out.extend_from_slice(&bytes[at..]);
    debug_assert_eq!(out.len(), bytes.len());
    Some(out)
}

/// The index just past the `\0` that ends the string starting at `at`.
fn nul_end(bytes: &[u8], at: usize) -> Option<usize> {
    let len = bytes.get(at..)?.iter().position(|&b| b == 0)?;
    Some(at + len + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attribute(name: &str, value: &[u8]) -> Vec<u8> {
        let mut a = format!("{name}\0float\0").into_bytes();
        a.extend_from_slice(&(value.len() as i32).to_le_bytes());
        a.extend_from_slice(value);
        a
    }

    #[test]
    fn attributes_come_out_sorted_and_the_rest_unchanged() {
        let head = [0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
        let (b, a) = (attribute("b", &[1, 2, 3, 4]), attribute("a", &[0, 0, 0, 0]));
        let file = |first: &[u8], second: &[u8]| {
            [&head[..], first, second, &[0], b"offsets and chunks"].concat()
        };
        let sorted = sorted_header(&file(&b, &a)).unwrap();
        assert_eq!(sorted, file(&a, &b));
        assert_eq!(sorted_header(&sorted).unwrap(), sorted);
    }

    #[test]
    fn anything_else_is_left_alone() {
        assert_eq!(sorted_header(b"not an exr"), None);
        let truncated = [0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0, b'a', 0, b'f'];
        assert_eq!(sorted_header(&truncated), None);
        let multipart = [0x76, 0x2f, 0x31, 0x01, 2, 0x10, 0, 0, 0];
        assert_eq!(sorted_header(&multipart), None);
    }
}

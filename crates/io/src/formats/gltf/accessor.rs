//! Reading vertex attribute accessors of any component type as floats, with the
//! specification's conversions: `normalized` integers map to [0, 1] (unsigned) or [-1, 1]
//! (signed, `max(c / (2^(n-1) - 1), -1)`), other integers keep their value
//! (`KHR_mesh_quantization` positions and texture coordinates). Sparse accessors are applied.
//!
//! [`super::buffers::check_accessors`] has checked every byte range before this runs; the
//! reads here still go through `get`, so a missed case is an error, never a panic.

use gltf::accessor::{DataType, Dimensions};

use super::checks::MAX_IMPLIED;

/// Which component types an attribute may use, after the core specification and
/// `KHR_mesh_quantization`'s table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Allowed {
    /// POSITION: float, or (un)normalized (unsigned) byte / short.
    Position,
    /// NORMAL, TANGENT: float, or normalized signed byte / short.
    Direction,
    /// TEXCOORD_n: float, or (un)normalized (unsigned) byte / short.
    TexCoord,
    /// COLOR_n: float, or normalized unsigned byte / short.
    Color,
    /// `EXT_mesh_gpu_instancing` TRANSLATION and SCALE: float only (lumis does not read the
    /// quantised forms `KHR_mesh_quantization` would allow there).
    Float,
    /// `EXT_mesh_gpu_instancing` ROTATION: float, or normalized signed byte / short.
    Rotation,
}

impl Allowed {
    fn accepts(self, t: DataType, normalized: bool) -> bool {
        use DataType::*;
        match (self, t) {
            (_, F32) => true,
            (Allowed::Position | Allowed::TexCoord, I8 | U8 | I16 | U16) => true,
            (Allowed::Direction | Allowed::Rotation, I8 | I16) => normalized,
            (Allowed::Color, U8 | U16) => normalized,
            _ => false,
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Allowed::Position | Allowed::TexCoord => {
                "FLOAT, or BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT (KHR_mesh_quantization)"
            }
            Allowed::Direction => "FLOAT, or normalized BYTE or SHORT (KHR_mesh_quantization)",
            Allowed::Color => "FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT",
            Allowed::Float => "FLOAT",
            Allowed::Rotation => "FLOAT, or normalized BYTE or SHORT (KHR_mesh_quantization)",
        }
    }
}

/// The elements of `acc` as `N` floats each; the error says what is wrong with the accessor
/// (its caller adds the element's name). `dims` are the accepted dimensions.
pub(super) fn read<const N: usize>(
    acc: &gltf::Accessor,
    dims: &[Dimensions],
    allowed: Allowed,
    buffers: &[Vec<u8>],
) -> Result<Vec<[f32; N]>, String> {
    let width = acc.dimensions().multiplicity();
    if !dims.contains(&acc.dimensions()) || width > N {
        return Err(format!(
            "is {:?}; expected {}",
            acc.dimensions(),
            dims.iter()
                .map(|d| format!("{d:?}").to_uppercase())
                .collect::<Vec<_>>()
                .join(" or ")
        ));
    }
    let (t, normalized) = (acc.data_type(), acc.normalized());
    if !allowed.accepts(t, normalized) {
        return Err(format!(
            "has component type {t:?}{}; expected {}",
            if normalized { " (normalized)" } else { "" },
            allowed.describe()
        ));
    }
    let size = t.size();
    let decode = |b: &[u8]| -> f32 {
        let v = match t {
            DataType::I8 => b[0] as i8 as f32,
            DataType::U8 => b[0] as f32,
            DataType::I16 => i16::from_le_bytes([b[0], b[1]]) as f32,
            DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as f32,
            DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        };
        if !normalized {
            return v;
        }
        match t {
            DataType::I8 => (v / 127.0).max(-1.0),
            DataType::U8 => v / 255.0,
            DataType::I16 => (v / 32767.0).max(-1.0),
            DataType::U16 => v / 65535.0,
            _ => v,
        }
    };
    let element = |bytes: &[u8]| -> [f32; N] {
        let mut out = [0.0; N];
        for (k, o) in out.iter_mut().enumerate().take(width) {
            *o = decode(&bytes[k * size..(k + 1) * size]);
        }
        out
    };
    let count = acc.count();
    if acc.view().is_none() && count > MAX_IMPLIED {
        // No bytes back such an accessor: its count alone would size the allocation.
        return Err(format!(
            "has no buffer view and {count} elements (at most {MAX_IMPLIED} are accepted)"
        ));
    }
    let elem_size = acc.size();
    let mut out = vec![[0.0; N]; count];
    if let Some(view) = acc.view() {
        let data = slice(buffers, &view, acc.offset())?;
        let stride = view.stride().unwrap_or(elem_size);
        for (i, o) in out.iter_mut().enumerate() {
            let at = i * stride;
            *o = element(
                data.get(at..at + elem_size)
                    .ok_or("lies outside its buffer view")?,
            );
        }
    }
    if let Some(sparse) = acc.sparse() {
        let indices = sparse.indices();
        let isize = indices.index_type().size();
        let idata = slice(buffers, &indices.view(), indices.offset())?;
        let values = sparse.values();
        let vdata = slice(buffers, &values.view(), values.offset())?;
        for k in 0..sparse.count() {
            let b = idata
                .get(k * isize..(k + 1) * isize)
                .ok_or("sparse indices lie outside their view")?;
            let i = match isize {
                1 => b[0] as usize,
                2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
            };
            let v = vdata
                .get(k * elem_size..(k + 1) * elem_size)
                .ok_or("sparse values lie outside their view")?;
            *out.get_mut(i).ok_or("a sparse index is out of range")? = element(v);
        }
    }
    Ok(out)
}

/// The bytes of `view` from `offset` on.
fn slice<'a>(
    buffers: &'a [Vec<u8>],
    view: &gltf::buffer::View,
    offset: usize,
) -> Result<&'a [u8], String> {
    buffers
        .get(view.buffer().index())
        .and_then(|b| b.get(view.offset()..view.offset().checked_add(view.length())?))
        .and_then(|b| b.get(offset..))
        .ok_or_else(|| format!("bufferViews[{}] lies outside its buffer", view.index()))
}

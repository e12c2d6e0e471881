//! One glTF mesh primitive to one lumis [`Mesh`] in the mesh's own (object) space: triangle
//! lists, strips and fans; u8/u16/u32 or implied indices; sparse accessors (through the crate's
//! reader, after [`super::buffers::check_accessors`] has checked every byte range);
//! `NORMAL` when given (otherwise the mesh is flat-shaded, as the specification asks) and
//! `TEXCOORD_0`.

use std::path::Path;

use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::super::SceneError;
use crate::geometry::{Mesh, MeshError};
use crate::math::{Vec2, Vec3};

/// Reads primitive `prim` of mesh `mesh_index`. `Ok(None)` for a primitive lumis does not
/// draw (points, lines, no whole triangle); `warnings` gets the reason.
pub(super) fn primitive_mesh(
    prim: &gltf::Primitive,
    mesh_index: usize,
    buffers: &[Vec<u8>],
    origin: &Path,
    warnings: &mut Vec<String>,
) -> Result<Option<Mesh>, SceneError> {
    let element = format!("meshes[{mesh_index}].primitives[{}]", prim.index());
    let err = |message: String| SceneError::invalid(origin, &element, message);
    let mode = prim.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        warnings.push(format!(
            "{}: {element}: mode {mode:?} is not drawn (lumis renders triangles only)",
            origin.display()
        ));
        return Ok(None);
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));

    let pos_acc = prim
        .get(&Semantic::Positions)
        .ok_or_else(|| err("has no POSITION attribute".into()))?;
    let pos_name = format!("POSITION accessors[{}]", pos_acc.index());
    if !is(&pos_acc, Dimensions::Vec3, &[DataType::F32]) {
        return Err(err(format!("{pos_name} must be VEC3 of FLOAT")));
    }
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(|| err(format!("{pos_name} has no data")))?
        .map(Vec3::from)
        .collect();

    let normals = match prim.get(&Semantic::Normals) {
        Some(acc) if is(&acc, Dimensions::Vec3, &[DataType::F32]) => {
            reader.read_normals().map(|n| n.map(Vec3::from).collect())
        }
        Some(acc) => {
            return Err(err(format!(
                "NORMAL accessors[{}] must be VEC3 of FLOAT",
                acc.index()
            )));
        }
        None => None,
    };

    let uv_types = [DataType::F32, DataType::U8, DataType::U16];
    let uvs: Option<Vec<Vec2>> = match prim.get(&Semantic::TexCoords(0)) {
        Some(acc) if is(&acc, Dimensions::Vec2, &uv_types) => reader
            .read_tex_coords(0)
            .map(|t| t.into_f32().map(Vec2::from).collect()),
        Some(acc) => {
            warnings.push(format!(
                "{}: {element}: TEXCOORD_0 accessors[{}] is not VEC2 of FLOAT, UNSIGNED_BYTE \
                 or UNSIGNED_SHORT; texture coordinates ignored",
                origin.display(),
                acc.index()
            ));
            None
        }
        None => None,
    };

    let (index_name, indices): (String, Vec<u32>) = match prim.indices() {
        Some(acc) => {
            let name = format!("indices accessors[{}]", acc.index());
            let int_types = [DataType::U8, DataType::U16, DataType::U32];
            if !is(&acc, Dimensions::Scalar, &int_types) {
                return Err(err(format!(
                    "{name} must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT"
                )));
            }
            let idx = reader
                .read_indices()
                .ok_or_else(|| err(format!("{name} has no data")))?;
            (name, idx.into_u32().collect())
        }
        None => (
            "implied indices".into(),
            (0..positions.len() as u32).collect(),
        ),
    };

    let (triangles, leftover) = triangulate(mode, &indices);
    if leftover > 0 {
        warnings.push(format!(
            "{}: {element}: {leftover} trailing indices do not make a whole triangle; ignored",
            origin.display()
        ));
    }
    if triangles.is_empty() {
        warnings.push(format!(
            "{}: {element}: no triangles; skipped",
            origin.display()
        ));
        return Ok(None);
    }
    let mesh = Mesh::new(positions, normals, uvs, triangles).map_err(|e| match e {
        MeshError::NonFinitePosition(_) => err(format!("{pos_name}: {e}")),
        MeshError::IndexOutOfRange { .. } => err(format!("{index_name}: {e}")),
        MeshError::AttributeCount { .. } => err(e.to_string()),
    })?;
    Ok(Some(mesh))
}

/// True when `acc` has dimensions `dims` and one of the component types `types`.
fn is(acc: &gltf::Accessor, dims: Dimensions, types: &[DataType]) -> bool {
    acc.dimensions() == dims && types.contains(&acc.data_type())
}

/// Triangles of a list, strip or fan (the specification's vertex order, so front faces stay
/// counter-clockwise), and the number of list indices left over. Strips and fans drop their
/// degenerate triangles (repeated vertices, used to stitch strips together).
pub(super) fn triangulate(mode: Mode, idx: &[u32]) -> (Vec<[u32; 3]>, usize) {
    match mode {
        Mode::Triangles => {
            let tris = idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            (tris, idx.len() % 3)
        }
        Mode::TriangleStrip => {
            // Odd triangles swap their last two vertices to keep the winding.
            let tris = (0..idx.len().saturating_sub(2))
                .map(|i| {
                    let (b, c) = if i % 2 == 0 {
                        (i + 1, i + 2)
                    } else {
                        (i + 2, i + 1)
                    };
                    [idx[i], idx[b], idx[c]]
                })
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            (tris, 0)
        }
        Mode::TriangleFan => {
            let tris = (1..idx.len().saturating_sub(1))
                .map(|i| [idx[i], idx[i + 1], idx[0]])
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            (tris, 0)
        }
        _ => (Vec::new(), 0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_alternate_winding_and_fans_pivot_on_the_first_vertex() {
        let (strip, _) = triangulate(Mode::TriangleStrip, &[0, 1, 2, 3, 4]);
        assert_eq!(strip, [[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        let (fan, _) = triangulate(Mode::TriangleFan, &[0, 1, 2, 3]);
        assert_eq!(fan, [[1, 2, 0], [2, 3, 0]]);
        let (list, left) = triangulate(Mode::Triangles, &[0, 1, 2, 3]);
        assert_eq!((list, left), (vec![[0, 1, 2]], 1));
        let (stitched, _) = triangulate(Mode::TriangleStrip, &[0, 1, 2, 2, 3]);
        assert_eq!(stitched, [[0, 1, 2]]);
    }
}

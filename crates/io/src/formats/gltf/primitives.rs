//! One glTF mesh primitive to one lumis [`Mesh`] in the mesh's own (object) space: triangle
//! lists, strips and fans; u8/u16/u32 or implied indices; sparse accessors (through the crate's
//! reader, after [`super::buffers::check_accessors`] has checked every byte range);
//! `NORMAL` when given (otherwise the mesh is flat-shaded, as the specification asks),
//! `TEXCOORD_0`/`_1`, `COLOR_0` and `TANGENT` (generated MikkTSpace tangents when a normal
//! texture needs them and the file has none), in any component type the specification and
//! `KHR_mesh_quantization` allow ([`super::accessor`]). Attributes lumis does not use are
//! warned of.

use std::path::Path;

use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::super::SceneError;
use super::accessor::{self, Allowed};
use super::materials::Converted;
use super::tangents;
use lumis_core::geometry::{Mesh, MeshAttributes, MeshError};
use lumis_core::math::{Vec2, Vec3, Vec4};

/// Shorthand: the dimensions of positions, normals and RGB colours.
const VEC3: Dimensions = Dimensions::Vec3;

/// Reads primitive `prim` of mesh `mesh_index`. `Ok(None)` for a primitive lumis does not
/// draw (points, lines, no whole triangle); `warnings` gets the reason.
pub(super) fn primitive_mesh(
    prim: &gltf::Primitive,
    mesh_index: usize,
    buffers: &[Vec<u8>],
    origin: &Path,
    material: &Converted,
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
    let mut warn = |msg: String| warnings.push(format!("{}: {element}: {msg}", origin.display()));

    let pos_acc = prim
        .get(&Semantic::Positions)
        .ok_or_else(|| err("has no POSITION attribute".into()))?;
    let pos_name = format!("POSITION accessors[{}]", pos_acc.index());
    let positions: Vec<Vec3> = accessor::read::<3>(&pos_acc, &[VEC3], Allowed::Position, buffers)
        .map_err(|e| err(format!("{pos_name} {e}")))?
        .into_iter()
        .map(Vec3::from)
        .collect();

    let normals = match prim.get(&Semantic::Normals) {
        Some(acc) => Some(
            accessor::read::<3>(&acc, &[VEC3], Allowed::Direction, buffers)
                .map_err(|e| err(format!("NORMAL accessors[{}] {e}", acc.index())))?
                .into_iter()
                // Quantized normals are only nearly unit.
                .map(|n| Vec3::from(n).normalize_or_zero())
                .collect::<Vec<_>>(),
        ),
        None => None,
    };

    let mut uv_set = |set: u32| -> Option<Vec<Vec2>> {
        let acc = prim.get(&Semantic::TexCoords(set))?;
        match accessor::read::<2>(&acc, &[Dimensions::Vec2], Allowed::TexCoord, buffers) {
            Ok(t) => Some(t.into_iter().map(Vec2::from).collect()),
            Err(e) => {
                warn(format!(
                    "TEXCOORD_{set} accessors[{}] {e}; texture coordinates ignored",
                    acc.index()
                ));
                None
            }
        }
    };
    let uvs = uv_set(0);
    let uv1 = uv_set(1);
    let colors = prim.get(&Semantic::Colors(0)).and_then(|acc| {
        let dims = [VEC3, Dimensions::Vec4];
        match accessor::read::<4>(&acc, &dims, Allowed::Color, buffers) {
            Ok(c) => {
                let rgb = acc.dimensions() == VEC3;
                Some(
                    c.into_iter()
                        .map(|c| Vec4::new(c[0], c[1], c[2], if rgb { 1.0 } else { c[3] }))
                        .collect::<Vec<_>>(),
                )
            }
            Err(e) => {
                warn(format!(
                    "COLOR_0 accessors[{}] {e}; colours ignored",
                    acc.index()
                ));
                None
            }
        }
    });
    let file_tangents = prim.get(&Semantic::Tangents).and_then(|acc| {
        if !material.needs_tangents {
            warn("TANGENT is not used (the material has no normalTexture)".into());
            return None;
        }
        match accessor::read::<4>(&acc, &[Dimensions::Vec4], Allowed::Direction, buffers) {
            Ok(t) => Some(t.into_iter().map(Vec4::from).collect::<Vec<_>>()),
            Err(e) => {
                warn(format!(
                    "TANGENT accessors[{}] {e}; tangents generated instead",
                    acc.index()
                ));
                None
            }
        }
    });
    unused_attributes(prim, &mut warn);
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
        warn(format!(
            "{leftover} trailing indices do not make a whole triangle; ignored"
        ));
    }
    if triangles.is_empty() {
        warn("no triangles; skipped".into());
        return Ok(None);
    }
    let counts = |e: MeshError| match e {
        MeshError::NonFinitePosition(_) => err(format!("{pos_name}: {e}")),
        MeshError::IndexOutOfRange { .. } => err(format!("{index_name}: {e}")),
        MeshError::AttributeCount { .. } | MeshError::BadAttribute { .. } => err(e.to_string()),
    };
    // Checked before the tangents, which index the vertex arrays by these triangles (found by
    // fuzzing: a TANGENT accessor with an out-of-range index used to panic here).
    for (tri, t) in triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= positions.len()) {
            return Err(counts(MeshError::IndexOutOfRange {
                tri,
                index,
                count: positions.len(),
            }));
        }
    }
    let tangents = if material.needs_tangents {
        let set = material
            .params
            .normal_texture
            .as_ref()
            .map_or(0, |(t, _)| t.tex_coord);
        let set_uvs = if set == 1 {
            uv1.as_deref()
        } else {
            uvs.as_deref()
        };
        match (file_tangents, normals.as_deref(), set_uvs) {
            (Some(t), ..) if t.len() == positions.len() => Some(
                triangles
                    .iter()
                    .map(|idx| idx.map(|i| t[i as usize]))
                    .collect(),
            ),
            (_, Some(n), Some(uv)) if n.len() == positions.len() && uv.len() == n.len() => {
                tangents::generate(&positions, n, uv, &triangles)
            }
            _ => {
                warn(format!(
                    "normalTexture of {} not applied: tangents need TANGENT, or NORMAL and \
                     TEXCOORD_{set} to generate them",
                    material.element
                ));
                None
            }
        }
    } else {
        None
    };
    let mut mesh = Mesh::new(positions, normals, uvs, triangles)
        .and_then(|m| {
            m.with_attributes(MeshAttributes {
                uv1,
                colors,
                tangents,
            })
        })
        .map_err(counts)?;
    mesh.set_alpha_test(material.alpha.clone());
    Ok(Some(mesh))
}

/// Warns of every attribute lumis does not read (skinning, further UV and colour sets,
/// application-specific ones) and of morph targets.
fn unused_attributes(prim: &gltf::Primitive, warn: &mut dyn FnMut(String)) {
    for (semantic, acc) in prim.attributes() {
        let unused = match &semantic {
            Semantic::TexCoords(n) => *n > 1,
            Semantic::Colors(n) => *n > 0,
            Semantic::Joints(_) | Semantic::Weights(_) => true,
            Semantic::Positions | Semantic::Normals | Semantic::Tangents => false,
            #[allow(unreachable_patterns)]
            _ => true,
        };
        if unused {
            warn(format!(
                "attribute {} (accessors[{}]) is not used",
                semantic.to_string(),
                acc.index()
            ));
        }
    }
    if prim.morph_targets().len() > 0 {
        warn(format!(
            "{} morph targets are not used (the base shape is drawn)",
            prim.morph_targets().len()
        ));
    }
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

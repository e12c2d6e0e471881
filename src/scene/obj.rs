//! Wavefront OBJ meshes through `tobj`: polygons are triangulated, positions/normals/UVs share
//! one index. Materials (`mtllib`/`usemtl`) are ignored for now: the scene file's `material`
//! applies, and a missing MTL file is not an error.
//!
//! ```toml
//! [[mesh]]
//! name = "knot"
//! file = "../assets/knot.obj"   # relative to the scene file's folder
//! material = "gold"
//! ```

use std::io::BufRead;
use std::path::Path;

use super::SceneError;
use crate::geometry::Mesh;
use crate::math::{Vec2, Vec3};

/// Reads every object of the OBJ text in `reader` as `(name, mesh)` in object-space
/// coordinates. `path` names the file in errors. Objects whose normals (or UVs) do not cover
/// every vertex lose them, so they are flat-shaded (or use barycentric UVs).
pub fn load_obj_meshes(
    reader: &mut impl BufRead,
    path: &Path,
) -> Result<Vec<(String, Mesh)>, SceneError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let obj_err = |message: String| SceneError::Obj {
        path: path.to_path_buf(),
        message,
    };
    // tobj indexes its own buffers; a panic there on hostile input must not take the caller down.
    let loaded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        tobj::load_obj_buf(reader, &options, |_| Ok(Default::default()))
    }))
    .map_err(|_| obj_err("the OBJ parser failed on this file".into()))?;
    let (models, _materials) = loaded.map_err(|e| obj_err(e.to_string()))?;
    let mut meshes = Vec::with_capacity(models.len());
    for model in models {
        let m = model.mesh;
        let positions = vec3s(&m.positions);
        let n = positions.len();
        let normals = Some(vec3s(&m.normals)).filter(|v| v.len() == n && n > 0);
        let uvs: Vec<Vec2> = m
            .texcoords
            .chunks_exact(2)
            .map(|c| Vec2::new(c[0], c[1]))
            .collect();
        let uvs = Some(uvs).filter(|v| v.len() == n && n > 0);
        let indices: Vec<[u32; 3]> = m
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        if indices.is_empty() {
            continue;
        }
        let mesh = Mesh::new(positions, normals, uvs, indices)
            .map_err(|e| obj_err(format!("object \"{}\": {e}", model.name)))?;
        meshes.push((model.name, mesh));
    }
    if meshes.is_empty() {
        return Err(obj_err("the file contains no faces".into()));
    }
    Ok(meshes)
}

/// All objects of an OBJ text merged into one mesh (one scene object with one material).
/// Normals and UVs survive only when every object has them.
pub fn load_obj_merged(reader: &mut impl BufRead, path: &Path) -> Result<Mesh, SceneError> {
    let mut meshes = load_obj_meshes(reader, path)?;
    if meshes.len() == 1
        && let Some((_, mesh)) = meshes.pop()
    {
        return Ok(mesh);
    }
    let mut positions = Vec::new();
    let mut normals = Some(Vec::new());
    let mut uvs = Some(Vec::new());
    let mut indices = Vec::new();
    for (_, m) in &meshes {
        let base = positions.len() as u32;
        indices.extend(m.indices().iter().map(|t| t.map(|i| i + base)));
        positions.extend_from_slice(m.positions());
        normals = normals.and_then(|mut v: Vec<Vec3>| {
            v.extend_from_slice(m.normals()?);
            Some(v)
        });
        uvs = uvs.and_then(|mut v: Vec<Vec2>| {
            v.extend_from_slice(m.uvs()?);
            Some(v)
        });
    }
    Mesh::new(positions, normals, uvs, indices).map_err(|e| SceneError::Obj {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Flat `[x, y, z, x, y, z, ...]` to vectors.
fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

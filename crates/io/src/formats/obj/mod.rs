//! Wavefront OBJ models with their MTL materials (documented in `docs/obj-mtl.md`).
//!
//! `tobj` parses; lumis checks indices first (errors name the file and line, see
//! [`scan`]), triangulates polygons itself by ear clipping (so concave faces come out
//! right), flips `v` to the top-left texture convention and converts materials
//! ([`mtl`]). Each OBJ object or group (`o`/`g`), split further where `usemtl` changes
//! inside it, becomes one [`ObjObject`]. Normals: an object whose every vertex has a normal is
//! smooth-shaded with them; otherwise the whole object is flat-shaded (geometric normals).
//! Texture coordinates likewise survive only when every vertex has one.
//!
//! ```toml
//! [[mesh]]
//! name = "knot"
//! file = "../assets/knot.obj"   # relative to the scene file's folder
//! material = "gold"             # optional: without it, the MTL materials apply
//! ```

mod mtl;
mod mtl_parse;
mod scan;

use std::cell::RefCell;
use std::collections::HashSet;
use std::io::BufRead;
use std::path::{Path, PathBuf};

use super::{LoadOptions, Resolver, SceneError, read_file, read_file_bytes};
use crate::files::guard::guarded;
use lumis_core::geometry::{Mesh, Triangulation, triangulate_polygon};
use lumis_core::material::Material;
use lumis_core::math::{Vec2, Vec3};
use lumis_core::scene::{Scene, SceneBuilder, UpAxis, default_rig, framing_camera};
use mtl::MtlConverter;
use mtl_parse::parse_mtl;
use scan::scan;

/// One object (or group, or run of faces with one `usemtl`) of an OBJ file.
#[derive(Clone, Debug)]
pub struct ObjObject {
    /// The `o`/`g` name (`unnamed_object` before any).
    pub name: String,
    /// Its triangles, in the file's coordinates.
    pub mesh: Mesh,
    /// Index into [`ObjModel::materials`]; `None` without `usemtl` or for an unknown name.
    pub material: Option<usize>,
}

/// An OBJ file loaded with its materials.
#[derive(Clone, Debug)]
pub struct ObjModel {
    /// The objects that have at least one non-degenerate face, in file order.
    pub objects: Vec<ObjObject>,
    /// The materials of every MTL file the OBJ names, in order.
    pub materials: Vec<Material>,
    /// The `newmtl` name of each of [`Self::materials`]: what their Cryptomatte
    /// (`CryptoMaterial`) mattes are called, so a compositor sees the artist's names.
    pub material_names: Vec<String>,
    /// Problems survived (missing MTL or texture, ignored points/lines, degenerate faces), each
    /// naming its file.
    pub warnings: Vec<String>,
}

/// Loads the OBJ text `bytes` read from `path`. With `resolver`, `mtllib` files (relative to
/// the OBJ's folder) and their textures are read through it; without, materials are skipped.
/// Errors name `path` and, where the scan finds it, the line.
pub fn load_obj(
    bytes: &[u8],
    path: &Path,
    resolver: Option<Resolver<'_>>,
) -> Result<ObjModel, SceneError> {
    let obj_err = |message: String| SceneError::Obj {
        path: path.to_path_buf(),
        message,
    };
    let text = String::from_utf8_lossy(bytes);
    let scanned = scan(&text, path)?;
    let mut warnings = scanned.warnings;
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let folder = path.parent().unwrap_or(Path::new("")).to_path_buf();
    // The MTL file each loaded material came from, in tobj's order, and what went wrong.
    let mtl_sources: RefCell<Vec<PathBuf>> = RefCell::default();
    let mtl_warnings: RefCell<Vec<String>> = RefCell::default();
    let load_mtl = |name: &Path| {
        let Some(resolver) = resolver else {
            return Err(tobj::LoadError::OpenFileFailed);
        };
        let mtl = folder.join(name);
        match resolver(&mtl) {
            Ok(bytes) => {
                let (materials, warnings) = parse_mtl(&bytes, &mtl);
                mtl_warnings.borrow_mut().extend(warnings);
                mtl_sources
                    .borrow_mut()
                    .extend(std::iter::repeat_n(mtl.clone(), materials.len()));
                // Later definitions of a name win, as in tobj's own MTL reader.
                let map = materials
                    .iter()
                    .enumerate()
                    .map(|(i, m)| (m.name.clone(), i))
                    .collect();
                Ok((materials, map))
            }
            Err(e) => {
                mtl_warnings.borrow_mut().push(format!(
                    "{}: cannot load material library {}: {e}; its materials are replaced by \
                     the default material",
                    path.display(),
                    mtl.display()
                ));
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    // The scan has checked every index tobj will use; should a hostile file still find a
    // panic in tobj, it becomes this file's error, printed without the panic text.
    let loaded = guarded(|| tobj::load_obj_buf(&mut scanned.text.as_bytes(), &options, load_mtl))
        .map_err(obj_err)?;
    let (models, tobj_materials) = loaded.map_err(|e| obj_err(e.to_string()))?;
    warnings.extend(mtl_warnings.into_inner());
    let tobj_materials = tobj_materials.unwrap_or_default();
    let mut materials = Vec::with_capacity(tobj_materials.len());
    let mut material_names = Vec::with_capacity(tobj_materials.len());
    if let Some(resolver) = resolver {
        let mut converter = MtlConverter::new(resolver);
        for (m, source) in tobj_materials.iter().zip(mtl_sources.into_inner()) {
            materials.push(converter.convert(m, &source));
            material_names.push(m.name.clone());
        }
        warnings.extend(converter.warnings);
        let known: HashSet<&str> = tobj_materials.iter().map(|m| m.name.as_str()).collect();
        for (name, line) in &scanned.usemtl {
            if !known.contains(name.as_str()) {
                warnings.push(format!(
                    "{}: line {line}: usemtl \"{name}\": no such material in the loaded MTL \
                     files; the default material is used",
                    path.display()
                ));
            }
        }
    }
    // tobj keeps faces in file order, so the scan's face lines label them when counts agree.
    let total_faces: usize = models.iter().map(|m| face_count(&m.mesh)).sum();
    let face_lines = (total_faces == scanned.face_lines.len()).then_some(&scanned.face_lines);
    let mut first_face = 0;
    let mut objects = Vec::with_capacity(models.len());
    for model in models {
        let faces = face_count(&model.mesh);
        let lines = face_lines.map(|l| &l[first_face..first_face + faces]);
        first_face += faces;
        let (indices, notes) = triangulate(&model.mesh, lines);
        for note in notes {
            warnings.push(format!(
                "{}: {note} (object \"{}\")",
                path.display(),
                model.name
            ));
        }
        if indices.is_empty() {
            continue;
        }
        let mesh = to_mesh(&model.mesh, indices)
            .map_err(|e| obj_err(format!("object \"{}\": {e}", model.name)))?;
        let material = model.mesh.material_id.filter(|&i| i < materials.len());
        objects.push(ObjObject {
            name: model.name,
            mesh,
            material,
        });
    }
    if objects.is_empty() {
        return Err(obj_err("the file contains no faces".into()));
    }
    Ok(ObjModel {
        objects,
        materials,
        material_names,
        warnings,
    })
}

/// Number of polygons in a tobj mesh (an empty `face_arities` means all triangles).
fn face_count(m: &tobj::Mesh) -> usize {
    if m.face_arities.is_empty() {
        m.indices.len() / 3
    } else {
        m.face_arities.len()
    }
}

/// Triangles of every polygon of `m` (indices into its vertex arrays), and notes about faces
/// that were skipped or fanned, naming their lines when `lines` has them.
fn triangulate(m: &tobj::Mesh, lines: Option<&[usize]>) -> (Vec<[u32; 3]>, Vec<String>) {
    let mut tris = Vec::with_capacity(m.indices.len() / 3);
    let mut notes = Vec::new();
    let mut start = 0;
    for face in 0..face_count(m) {
        let arity = m.face_arities.get(face).map_or(3, |&a| a as usize);
        let Some(corners) = m.indices.get(start..start + arity) else {
            break;
        };
        start += arity;
        let at = match lines {
            Some(l) => format!("line {}", l[face]),
            None => format!("face {face}"),
        };
        let points: Vec<Vec3> = corners
            .iter()
            .map(|&i| {
                let k = 3 * i as usize;
                m.positions
                    .get(k..k + 3)
                    .map_or(Vec3::NAN, |p| Vec3::new(p[0], p[1], p[2]))
            })
            .collect();
        let local = match triangulate_polygon(&points) {
            Triangulation::Ears(t) => t,
            Triangulation::Fan(t) => {
                notes.push(format!(
                    "{at}: polygon is not simple (it crosses itself) or too large to ear-clip; \
                     triangulated as a fan"
                ));
                t
            }
            Triangulation::Degenerate => {
                notes.push(format!(
                    "{at}: polygon has exactly zero area (collinear or repeated points); skipped"
                ));
                continue;
            }
        };
        tris.extend(local.into_iter().map(|t| t.map(|k| corners[k])));
    }
    (tris, notes)
}

/// A lumis mesh from tobj's single-index arrays: normals and UVs only when every vertex has
/// one; `v` flipped so `uv = (0, 0)` is the image's top-left.
fn to_mesh(
    m: &tobj::Mesh,
    indices: Vec<[u32; 3]>,
) -> Result<Mesh, lumis_core::geometry::MeshError> {
    let positions = vec3s(&m.positions);
    let n = positions.len();
    let normals = Some(vec3s(&m.normals)).filter(|v| v.len() == n);
    let uvs: Vec<Vec2> = m
        .texcoords
        .chunks_exact(2)
        .map(|c| Vec2::new(c[0], 1.0 - c[1]))
        .collect();
    let uvs = Some(uvs).filter(|v| v.len() == n);
    Mesh::new(positions, normals, uvs, indices)
}

/// Every object of the OBJ text in `reader` as `(name, mesh)`, without materials (MTL files
/// are not read). `path` names the file in errors.
pub fn load_obj_meshes(
    reader: &mut impl BufRead,
    path: &Path,
) -> Result<Vec<(String, Mesh)>, SceneError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|source| SceneError::Read {
            path: path.to_path_buf(),
            source,
        })?;
    let model = load_obj(&bytes, path, None)?;
    Ok(model
        .objects
        .into_iter()
        .map(|o| (o.name, o.mesh))
        .collect())
}

/// All objects of an OBJ text merged into one mesh (one scene object with one material).
pub fn load_obj_merged(reader: &mut impl BufRead, path: &Path) -> Result<Mesh, SceneError> {
    let meshes: Vec<Mesh> = load_obj_meshes(reader, path)?
        .into_iter()
        .map(|(_, m)| m)
        .collect();
    merge_meshes(meshes).map_err(|e| SceneError::Obj {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Meshes concatenated into one; normals and UVs survive only when every mesh has them.
pub(super) fn merge_meshes(mut meshes: Vec<Mesh>) -> Result<Mesh, lumis_core::geometry::MeshError> {
    if meshes.len() == 1
        && let Some(mesh) = meshes.pop()
    {
        return Ok(mesh);
    }
    let mut positions = Vec::new();
    let mut normals = Some(Vec::new());
    let mut uvs = Some(Vec::new());
    let mut indices = Vec::new();
    for m in &meshes {
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
    Mesh::new(positions, normals, uvs, indices)
}

/// Flat `[x, y, z, x, y, z, ...]` to vectors.
fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

/// A bare OBJ file as a scene: one scene object per OBJ object, materials from its MTL files,
/// turned so that `options.up` is up (the other options are glTF's).
pub fn load_obj_scene(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let bytes = read_file(path)?;
    let model = load_obj(&bytes, path, Some(&read_file_bytes))?;
    let mut b = SceneBuilder::new();
    for w in model.warnings {
        b.warn(w);
    }
    let ids: Vec<u32> = model
        .materials
        .into_iter()
        .zip(model.material_names)
        .map(|(m, name)| b.add_named_material(name, m))
        .collect();
    let default = b.add_named_material("default", Material::default());
    let turn = options.up.to_y_up();
    for o in model.objects {
        let material = o.material.map_or(default, |k| ids[k]);
        let mesh = match options.up {
            UpAxis::Y => o.mesh,
            UpAxis::Z => o.mesh.transformed(&turn),
        };
        b.add_mesh(o.name, mesh, material);
    }
    let bounds = b.bounds();
    let (w, h) = (b.settings_mut().width, b.settings_mut().height);
    let camera = framing_camera(bounds, w, h);
    for light in default_rig(bounds, &camera) {
        b.add_rig_light(light);
    }
    b.build(camera)
        .map_err(|e| SceneError::invalid(path, e.element, e.message))
}

//! `[[mesh]]` elements: inline meshes and model files (OBJ, glTF/GLB, `.m`), their transform
//! and shading normals.
//!
//! An OBJ `file` with a `material` key becomes one scene object (all OBJ objects merged) with
//! that material; without `material`, every OBJ object becomes its own scene object named
//! `NAME/OBJECT` (just `NAME` when the file has one object) with its MTL material, and the
//! default grey material where the OBJ names none. A glTF file works the same way with its
//! node-placed meshes (`NAME/OBJECT`, each under its node transform, then the element's) and
//! its materials; its cameras and lights are not used. A `.m` file is one object with the
//! element's material.

use std::path::{Path, PathBuf};

use super::super::LoadOptions;
use super::super::gltf::load_gltf_bytes;
use super::super::obj::{self, ObjModel};
use super::super::scn::parse_m;
use super::schema::{MeshDoc, Scale};
use super::{Loader, SceneError};
use lumis_core::geometry::{Mesh, Primitive};
use lumis_core::math::{Mat4, Vec3};

/// One object of a mesh element: its mesh (transformed) and material.
pub(super) struct MeshPart {
    /// The model's object name (`NAME/OBJECT`); `None` when the element makes one object.
    pub object: Option<String>,
    pub mesh: Mesh,
    pub material: u32,
}

impl Loader<'_> {
    /// Adds the scene objects of mesh element `e` (see the module docs for how many).
    pub(super) fn add_mesh(
        &mut self,
        e: &str,
        name: String,
        m: &MeshDoc,
    ) -> Result<(), SceneError> {
        for part in self.mesh_parts(e, m)? {
            let object = match part.object {
                None => name.clone(),
                Some(o) => format!("{name}/{o}"),
            };
            self.builder.add_mesh(object, part.mesh, part.material);
        }
        Ok(())
    }

    /// The objects mesh element `e` makes, each under the element's transform, with their
    /// materials added to the builder (in the order the objects are added, so ids do not
    /// depend on whether the element is drawn or instanced).
    pub(super) fn mesh_parts(&mut self, e: &str, m: &MeshDoc) -> Result<Vec<MeshPart>, SceneError> {
        let xf = self.transform(e, m)?;
        let one = |mesh, material| {
            vec![MeshPart {
                object: None,
                mesh,
                material,
            }]
        };
        let Some(file) = m.file.as_deref() else {
            let mesh = self.inline_mesh(e, m)?;
            let material = self.material_ref(e, m.material.as_deref())?;
            return Ok(one(self.finish(e, m, mesh, &xf)?, material));
        };
        if m.positions.is_some() {
            return Err(self.err(e, "give either file or positions + indices"));
        }
        if m.indices.is_some() || m.normals.is_some() {
            return Err(self.err(e, "indices/normals go with inline positions, not file"));
        }
        match extension(file).as_deref() {
            Some("gltf" | "glb") => return self.gltf_parts(e, m, file, &xf),
            Some("m") => {
                let path = resolve(self.origin, file);
                let bytes = self.read_asset(e, &path)?;
                let text = String::from_utf8_lossy(&bytes);
                let mesh = parse_m(&text, &path).map_err(|err| self.asset_error(e, &path, err))?;
                let material = self.material_ref(e, m.material.as_deref())?;
                return Ok(one(self.finish(e, m, mesh, &xf)?, material));
            }
            Some("obj") => {}
            _ => {
                return Err(self.err(
                    e,
                    format!("file {file:?}: expected a .obj, .gltf, .glb or .m model"),
                ));
            }
        }
        // An explicit material overrides the MTL ones, which are then not even read.
        let with_mtl = m.material.is_none();
        let model = self.obj_file(e, file, with_mtl)?;
        for w in model.warnings {
            self.builder.warn(w);
        }
        if !with_mtl {
            let meshes = model.objects.into_iter().map(|o| o.mesh).collect();
            let mesh = obj::merge_meshes(meshes).map_err(|err| self.err(e, err.to_string()))?;
            let material = self.material_ref(e, m.material.as_deref())?;
            return Ok(one(self.finish(e, m, mesh, &xf)?, material));
        }
        let ids: Vec<u32> = model
            .materials
            .into_iter()
            .zip(model.material_names)
            .map(|(mat, name)| self.builder.add_named_material(name, mat))
            .collect();
        let single = model.objects.len() == 1;
        let mut parts = Vec::with_capacity(model.objects.len());
        for o in model.objects {
            let material = match o.material {
                Some(k) => ids[k],
                None => self.material_ref(e, None)?,
            };
            parts.push(MeshPart {
                object: (!single).then_some(o.name),
                mesh: self.finish(e, m, o.mesh, &xf)?,
                material,
            });
        }
        Ok(parts)
    }

    /// The mesh of inline `positions` + `indices` (+ `normals`).
    fn inline_mesh(&self, e: &str, m: &MeshDoc) -> Result<Mesh, SceneError> {
        let positions = m
            .positions
            .as_ref()
            .ok_or_else(|| self.err(e, "give either file or positions + indices"))?;
        let indices = m
            .indices
            .clone()
            .ok_or_else(|| self.err(e, "inline positions need indices"))?;
        let v3 = |v: &Vec<[f32; 3]>| v.iter().map(|p| Vec3::from(*p)).collect();
        for p in positions.iter().chain(m.normals.iter().flatten()) {
            self.finite(e, "vertex", p)?;
        }
        Mesh::new(v3(positions), m.normals.as_ref().map(v3), None, indices)
            .map_err(|err| self.err(e, err.to_string()))
    }

    /// `smooth` applied, then the transform `xf`.
    fn finish(&self, e: &str, m: &MeshDoc, mesh: Mesh, xf: &Mat4) -> Result<Mesh, SceneError> {
        let mesh = match m.smooth {
            Some(true) if mesh.normals().is_none() => with_normals(mesh, true),
            Some(false) => with_normals(mesh, false),
            _ => Ok(mesh),
        }
        .map_err(|err| self.err(e, err.to_string()))?;
        let mesh = mesh.transformed(xf);
        // The builder checks this too, but only here are the element and its file both known.
        lumis_core::scene::limits::check_bounds(&mesh.bounds()).map_err(|msg| match &m.file {
            Some(file) => self.err(e, format!("{file}: {msg}")),
            None => self.err(e, msg),
        })?;
        Ok(mesh)
    }

    /// Object to world: scale, then rotate about X, Y, Z (degrees), then translate.
    fn transform(&self, e: &str, m: &MeshDoc) -> Result<Mat4, SceneError> {
        let t = m.translate.unwrap_or([0.0; 3]);
        let r = m.rotate.unwrap_or([0.0; 3]);
        let s = match m.scale {
            None => [1.0; 3],
            Some(Scale::Uniform(s)) => [s; 3],
            Some(Scale::PerAxis(s)) => s,
        };
        self.finite(e, "translate", &t)?;
        self.finite(e, "rotate", &r)?;
        self.finite(e, "scale", &s)?;
        if s.contains(&0.0) {
            return Err(self.err(e, format!("scale {s:?} must be non-zero")));
        }
        let [rx, ry, rz] = r.map(f32::to_radians);
        Ok(Mat4::from_translation(Vec3::from(t))
            * Mat4::from_rotation_z(rz)
            * Mat4::from_rotation_y(ry)
            * Mat4::from_rotation_x(rx)
            * Mat4::from_scale(Vec3::from(s)))
    }

    /// The OBJ model `file` (relative to the scene's folder), with its MTL materials when
    /// `with_mtl`; every file goes through the resolver.
    fn obj_file(&self, e: &str, file: &str, with_mtl: bool) -> Result<ObjModel, SceneError> {
        let path = resolve(self.origin, file);
        let bytes = self.read_asset(e, &path)?;
        obj::load_obj(&bytes, &path, with_mtl.then_some(self.resolver))
            .map_err(|err| self.asset_error(e, &path, err))
    }

    /// The meshes and materials of glTF `file`, each mesh under its node transform and then `xf`.
    fn gltf_parts(
        &mut self,
        e: &str,
        m: &MeshDoc,
        file: &str,
        xf: &Mat4,
    ) -> Result<Vec<MeshPart>, SceneError> {
        let path = resolve(self.origin, file);
        let bytes = self.read_asset(e, &path)?;
        // Flattened: the objects are copied below as world-space meshes, one each (a TOML
        // scene places no instances), so a mesh shared by nodes must come as copies too.
        let options = LoadOptions {
            flatten_instances: true,
            ..LoadOptions::default()
        };
        let model = load_gltf_bytes(&bytes, &path, self.resolver, &options)
            .map_err(|err| self.asset_error(e, &path, err))?;
        for w in model.warnings() {
            self.builder.warn(w.clone());
        }
        let override_material = m
            .material
            .as_deref()
            .map(|r| self.material_ref(e, Some(r)))
            .transpose()?;
        let mut materials = std::collections::HashMap::new();
        let single = model.objects().len() == 1;
        let mut parts = Vec::new();
        for (object, o) in model.objects().iter().enumerate() {
            // A glTF scene holds only meshes, one per object: find this object's.
            let mesh =
                model
                    .geometry()
                    .prims()
                    .iter()
                    .enumerate()
                    .find_map(|(p, prim)| match prim {
                        Primitive::Triangle { mesh, .. }
                            if model.object_of(p as u32) == object as u32 =>
                        {
                            Some(*mesh)
                        }
                        _ => None,
                    });
            let Some(mesh) = mesh else { continue };
            let material = match override_material {
                Some(id) => id,
                // Under the file's own name (glTF's, or `material<i>`), for CryptoMaterial.
                None => *materials.entry(o.material).or_insert_with(|| {
                    let k = o.material as usize;
                    self.builder.add_named_material(
                        model.material_names()[k].clone(),
                        model.materials()[k].clone(),
                    )
                }),
            };
            let mesh = self.finish(e, m, model.geometry().meshes()[mesh as usize].clone(), xf)?;
            parts.push(MeshPart {
                object: (!single).then(|| o.name.clone()),
                mesh,
                material,
            });
        }
        Ok(parts)
    }

    /// The bytes of a model file, through the resolver; errors name the element and the file.
    fn read_asset(&self, e: &str, path: &Path) -> Result<Vec<u8>, SceneError> {
        (self.resolver)(path).map_err(|source| {
            self.asset_error(
                e,
                path,
                SceneError::Read {
                    path: path.to_path_buf(),
                    source,
                },
            )
        })
    }

    /// `source` as the failure of element `e` to load `path`.
    fn asset_error(&self, e: &str, path: &Path, source: SceneError) -> SceneError {
        SceneError::Asset {
            path: self.origin.to_path_buf(),
            element: e.to_string(),
            file: path.to_path_buf(),
            source: Box::new(source),
        }
    }
}

/// The lower-case extension of a file name.
fn extension(file: &str) -> Option<String> {
    Path::new(file)
        .extension()
        .and_then(|x| x.to_str())
        .map(str::to_ascii_lowercase)
}

/// `file` relative to the folder of `origin` (absolute paths stay as they are).
fn resolve(origin: &Path, file: &str) -> PathBuf {
    origin
        .parent()
        .unwrap_or(Path::new(""))
        .join(Path::new(file))
}

/// The mesh with area-weighted vertex normals (`smooth`) or with none (flat shading).
fn with_normals(m: Mesh, smooth: bool) -> Result<Mesh, lumis_core::geometry::MeshError> {
    let normals = smooth.then(|| {
        let mut n = vec![Vec3::ZERO; m.positions().len()];
        for tri in 0..m.triangle_count() as u32 {
            let [a, b, c] = m.corners(tri);
            // The cross product's length is twice the area: large faces weigh more.
            let face = (b - a).cross(c - a);
            for i in m.indices()[tri as usize] {
                n[i as usize] += face;
            }
        }
        n.into_iter().map(Vec3::normalize_or_zero).collect()
    });
    let uvs = m.uvs().map(<[_]>::to_vec);
    Mesh::new(m.positions().to_vec(), normals, uvs, m.indices().to_vec())
}

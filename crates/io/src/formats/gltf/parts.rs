//! A glTF mesh as lumis draws it: its drawable primitives in object space, each with the lumis
//! material it gets. Read once per mesh however many nodes (or instances) place it, so a
//! flattened copy and a prototype's part are the same triangles with the same material.

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use super::super::SceneError;
use super::materials::Converted;
use super::primitives;
use lumis_core::geometry::Mesh;
use lumis_core::scene::SceneBuilder;

/// One drawable primitive of a mesh.
pub(super) struct DrawPart {
    /// The primitive's index in its mesh (the `/<index>` of object names).
    pub prim: usize,
    /// Object-space triangles.
    pub mesh: Mesh,
    /// The lumis material.
    pub material: u32,
}

/// A mesh's drawable parts, and how many primitives it has (drawable or not), which decides
/// whether object names carry the primitive index.
pub(super) struct MeshParts {
    pub parts: Vec<DrawPart>,
    pub primitive_count: usize,
}

impl MeshParts {
    /// The object name of `part` placed as `placement` (a node's name, or `node/i` for an
    /// `EXT_mesh_gpu_instancing` instance): the primitive index is added when the mesh has
    /// several primitives, drawable or not, so names do not depend on what is drawn.
    pub fn object_name(&self, placement: &str, part: &DrawPart) -> String {
        if self.primitive_count > 1 {
            format!("{placement}/{}", part.prim)
        } else {
            placement.to_string()
        }
    }
}

/// The materials of parts: one per glTF material (converted in file order by the caller), plus
/// the vertex-colour variants and the default material, added to the scene when first used.
pub(super) struct Parts<'a> {
    pub converted: &'a [Converted],
    pub material_ids: &'a [u32],
    pub material_names: &'a [String],
    pub fallback: Converted,
    /// Materials of meshes with vertex colours, by glTF material (`None`: the default).
    colour_variants: HashMap<Option<usize>, u32>,
    default_material: Option<u32>,
    cache: HashMap<usize, Rc<MeshParts>>,
}

impl<'a> Parts<'a> {
    pub fn new(
        converted: &'a [Converted],
        material_ids: &'a [u32],
        material_names: &'a [String],
    ) -> Self {
        Self {
            converted,
            material_ids,
            material_names,
            fallback: Converted::default_material(),
            colour_variants: HashMap::new(),
            default_material: None,
            cache: HashMap::new(),
        }
    }

    /// The parts of `mesh`, read on first use. Errors name the mesh or primitive; primitives
    /// that are not drawn get a warning (once per mesh).
    pub fn of(
        &mut self,
        mesh: &gltf::Mesh,
        b: &mut SceneBuilder,
        data: &[Vec<u8>],
        origin: &Path,
        warnings: &mut Vec<String>,
    ) -> Result<Rc<MeshParts>, SceneError> {
        if let Some(p) = self.cache.get(&mesh.index()) {
            return Ok(p.clone());
        }
        if mesh.primitives().len() == 0 {
            return Err(SceneError::invalid(
                origin,
                format!("meshes[{}]", mesh.index()),
                "has no primitives",
            ));
        }
        let mut parts = Vec::new();
        for prim in mesh.primitives() {
            if prim.get(&gltf::Semantic::Positions).is_none() {
                // Allowed by the specification, which asks that such primitives be skipped.
                warnings.push(format!(
                    "{}: meshes[{}].primitives[{}]: no POSITION attribute; not drawn",
                    origin.display(),
                    mesh.index(),
                    prim.index()
                ));
                continue;
            }
            let index = prim.material().index();
            let conv = index
                .and_then(|i| self.converted.get(i))
                .unwrap_or(&self.fallback);
            let Some(object_mesh) =
                primitives::primitive_mesh(&prim, mesh.index(), data, origin, conv, warnings)?
            else {
                continue;
            };
            let coloured = object_mesh.attributes().is_some_and(|a| a.colors.is_some());
            let material = self.material(index, coloured, b);
            parts.push(DrawPart {
                prim: prim.index(),
                mesh: object_mesh,
                material,
            });
        }
        let parts = Rc::new(MeshParts {
            parts,
            primitive_count: mesh.primitives().len(),
        });
        self.cache.insert(mesh.index(), parts.clone());
        Ok(parts)
    }

    /// The lumis material of a primitive with glTF material `index`, with or without vertex
    /// colours.
    fn material(&mut self, index: Option<usize>, coloured: bool, b: &mut SceneBuilder) -> u32 {
        let name = |i: Option<usize>| match i {
            Some(i) => self.material_names[i].clone(),
            // The glTF specification's "default material" of primitives without one.
            None => "default".to_string(),
        };
        let conv = index
            .and_then(|i| self.converted.get(i))
            .unwrap_or(&self.fallback);
        match index {
            // Vertex colours vary the base colour over the surface.
            _ if coloured => *self.colour_variants.entry(index).or_insert_with(|| {
                // The same material of the file: the same matte.
                b.add_named_material(name(index), conv.with_vertex_colors())
            }),
            Some(i) => self.material_ids[i],
            None => *self.default_material.get_or_insert_with(|| {
                b.add_named_material(name(None), self.fallback.material.clone())
            }),
        }
    }
}

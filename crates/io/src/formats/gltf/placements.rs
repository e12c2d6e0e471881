//! Where each mesh is drawn, decided before anything is added to the scene: every placement
//! of a mesh (a node, or each `EXT_mesh_gpu_instancing` instance of one) is counted first, and
//! a mesh placed twice or more becomes one prototype with an instance per placement; a mesh
//! placed once is flattened into world-space triangles, as it always was. With
//! `flatten_instances` every placement is flattened (to compare the two, or for renderers
//! downstream that want plain meshes).

use std::collections::HashMap;
use std::path::Path;

use glam::DAffine3;

use super::super::SceneError;
use super::gpu_instancing;
use super::nodes::Placed;
use lumis_core::geometry::{Mesh, leaves_no_area};
use lumis_core::math::Mat4;
use lumis_core::scene::{Part, SceneBuilder, Shape};

use super::parts::MeshParts;

/// Most triangles `flatten_instances` may copy out of `EXT_mesh_gpu_instancing` instances:
/// their count comes from the file, and each copies the whole mesh (2^26 triangles are some
/// 6 GiB of meshes), so the product is bounded before anything is copied.
const MAX_FLATTENED_TRIANGLES: usize = 1 << 26;

/// The placements of the chosen scene's meshes.
pub(super) struct Plan {
    /// Node-space instance transforms of `EXT_mesh_gpu_instancing` nodes, by node index.
    gpu: HashMap<usize, Vec<DAffine3>>,
    /// Meshes (by index) that become prototypes.
    shared: Vec<bool>,
    /// Prototypes made so far, by mesh index.
    prototypes: HashMap<usize, u32>,
}

impl Plan {
    /// Counts the placements of every mesh of `placed` (reading the instancing extension's
    /// accessors, whose errors surface here, before anything is built).
    pub fn new(
        placed: &[Placed],
        doc: &gltf::Document,
        data: &[Vec<u8>],
        origin: &Path,
        flatten: bool,
        warnings: &mut Vec<String>,
    ) -> Result<Self, SceneError> {
        let mut gpu = HashMap::new();
        let mut uses = vec![0usize; doc.meshes().len()];
        for Placed { node, .. } in placed {
            let local = gpu_instancing::local_transforms(node, doc, data, origin)?;
            match (node.mesh(), local) {
                (Some(mesh), Some(local)) => {
                    uses[mesh.index()] = uses[mesh.index()].saturating_add(local.len());
                    gpu.insert(node.index(), local);
                }
                (Some(mesh), None) => uses[mesh.index()] += 1,
                (None, Some(_)) => warnings.push(format!(
                    "{}: nodes[{}].extensions.{}: the node has no mesh to instance; ignored",
                    origin.display(),
                    node.index(),
                    gpu_instancing::NAME
                )),
                (None, None) => {}
            }
        }
        Ok(Self {
            gpu,
            shared: uses.iter().map(|&n| n >= 2 && !flatten).collect(),
            prototypes: HashMap::new(),
        })
    }

    /// Draws `parts` (of `mesh`) wherever `placed` puts it: as instances of the mesh's
    /// prototype (made on first use) or as world-space copies. Objects are named after the
    /// node (`node<index>` without a name), `/<i>` added for the i-th instance of the
    /// extension, `/<primitive>` for meshes with several primitives, in both modes alike.
    pub fn draw(
        &mut self,
        placed: &Placed,
        node_name: &str,
        mesh: usize,
        parts: &MeshParts,
        b: &mut SceneBuilder,
        origin: &Path,
    ) -> Result<(), SceneError> {
        if parts.parts.is_empty() {
            return Ok(());
        }
        let world = placed.world;
        let gpu = self.gpu.get(&placed.node.index());
        if !self.shared[mesh] {
            match gpu {
                None => flatten(parts, node_name, &world, b),
                Some(local) => {
                    let triangles: usize =
                        parts.parts.iter().map(|p| p.mesh.triangle_count()).sum();
                    if triangles.saturating_mul(local.len()) > MAX_FLATTENED_TRIANGLES {
                        return Err(SceneError::invalid(
                            origin,
                            format!(
                                "nodes[{}].extensions.{}",
                                placed.node.index(),
                                gpu_instancing::NAME
                            ),
                            format!(
                                "{} instances of meshes[{mesh}] ({triangles} triangles each) \
                                 would flatten to more than {MAX_FLATTENED_TRIANGLES} \
                                 triangles; load without flattening instances",
                                local.len()
                            ),
                        ));
                    }
                    let world = DAffine3::from_mat4(world.as_dmat4());
                    for (i, l) in local.iter().enumerate() {
                        let m = glam::DMat4::from(world * *l).as_mat4();
                        flatten(parts, &format!("{node_name}/{i}"), &m, b);
                    }
                }
            }
            return Ok(());
        }
        let prototype = *self.prototypes.entry(mesh).or_insert_with(|| {
            b.add_prototype(
                parts
                    .parts
                    .iter()
                    .map(|p| Part {
                        name: p.prim.to_string(),
                        shape: Shape::Mesh(p.mesh.clone()),
                        material: p.material,
                    })
                    .collect(),
            )
        });
        // The builder names a one-part instance's object after the instance alone: give it
        // the name its flattened copy would have (`node/1` when primitive 0 is not drawn).
        let instance_name = |placement: &str| match parts.parts.as_slice() {
            [only] => parts.object_name(placement, only),
            _ => placement.to_string(),
        };
        // f32 -> f64 is exact: an instance of a plain node sits exactly where its flattened
        // copy would.
        let world = DAffine3::from_mat4(world.as_dmat4());
        match gpu {
            None => {
                b.add_instance(prototype, instance_name(node_name), world);
            }
            Some(local) => {
                for (i, l) in local.iter().enumerate() {
                    b.add_instance(
                        prototype,
                        instance_name(&format!("{node_name}/{i}")),
                        world * *l,
                    );
                }
            }
        }
        Ok(())
    }
}

/// World-space copies of `parts` placed by `world`, one object each. A placement that leaves
/// no area (zero scale on two or three axes: how glTF hides a mesh) keeps its objects, empty,
/// as an instance placed so does (`SceneBuilder::add_instance`).
fn flatten(parts: &MeshParts, placement: &str, world: &Mat4, b: &mut SceneBuilder) {
    let hidden = leaves_no_area(&DAffine3::from_mat4(world.as_dmat4()));
    for p in &parts.parts {
        let mesh = match hidden {
            false => p.mesh.clone().transformed(world),
            true => Mesh::new(vec![], None, None, vec![]).expect("an empty mesh is valid"),
        };
        b.add_mesh(parts.object_name(placement, p), mesh, p.material);
    }
}

//! Placements with no inverse. A transform with a zero scale (glTF allows one on a node or an
//! `EXT_mesh_gpu_instancing` entry, and files use it to hide a mesh) cannot move rays into its
//! prototype's space. Such a placement is drawn the way `--flatten-instances` draws every
//! placement: world-space copies of the prototype's meshes, one object per part, so object
//! names, materials and pixels are the flattened scene's. It is no instance: its hits carry no
//! instance id, and instance indices count the placements that are instances.
//!
//! - Zero scale on two or three axes (rank 1 or 0) maps every triangle onto a line or a
//!   point, which no ray hits: the objects are kept, empty, and nothing is copied (the glTF
//!   specification lets renderers skip such meshes). A file of 100,000 hidden placements
//!   therefore costs 100,000 names, not 100,000 copies.
//! - Zero scale on one axis (rank 2) flattens the mesh into a plane, which rays do hit: it is
//!   copied, within [`MAX_SINGULAR_TRIANGLES`] for the scene, so that no file can make the
//!   loader copy a mesh without bound. A sphere flattened into a plane is an elliptic disc,
//!   for which lumis has no primitive: refused, naming the placement.

use glam::{DAffine3, DMat4};

use super::SceneBuilder;
use crate::geometry::leaves_no_area;

/// Most triangles singular placements may copy into one scene (about 1.6 GB of meshes).
pub(super) const MAX_SINGULAR_TRIANGLES: usize = 1 << 24;

/// What a prototype's part is, to flatten it.
#[derive(Clone, Copy, Debug)]
pub(super) enum PartShape {
    /// `meshes()[index]` of the prototype's geometry.
    Mesh(u32),
    /// A sphere.
    Sphere,
}

impl SceneBuilder {
    /// Draws prototype `prototype` placed by singular `to_world` as placement `name` (see the
    /// module docs); returns its first object's id.
    pub(super) fn add_singular_placement(
        &mut self,
        prototype: u32,
        name: &str,
        to_world: DAffine3,
    ) -> u32 {
        let onto_a_plane = !leaves_no_area(&to_world);
        // The flattened copies' transform, rounded to f32 as glTF's is.
        let copy_to_world = DMat4::from(to_world).as_mat4();
        let shapes = self.geometry.prototypes()[prototype as usize].clone();
        let first = self.objects.len() as u32;
        for (object, material, shape) in self.part_objects(prototype, name) {
            match shape {
                PartShape::Mesh(mesh) if onto_a_plane => {
                    let mesh = &shapes.geometry().meshes()[mesh as usize];
                    if let Some(left) = self.singular_budget.checked_sub(mesh.triangle_count()) {
                        self.singular_budget = left;
                        let copy = mesh.clone().transformed(&copy_to_world);
                        self.add_mesh(object, copy, material);
                        continue;
                    }
                    self.check(
                        || format!("instance \"{name}\""),
                        Err(format!(
                            "its transform is singular (a zero scale), so its mesh is copied \
                             flattened instead of instanced, and such copies would exceed \
                             {MAX_SINGULAR_TRIANGLES} triangles"
                        )),
                    );
                }
                PartShape::Sphere if onto_a_plane => self.check(
                    || format!("instance \"{name}\""),
                    Err(
                        "its transform is singular (a zero scale on one axis): it flattens \
                         the sphere into an elliptic disc, which lumis cannot trace"
                            .to_string(),
                    ),
                ),
                // A line or a point: nothing a ray can hit.
                _ => {}
            }
            self.push_object(object, material, 0);
        }
        first
    }
}

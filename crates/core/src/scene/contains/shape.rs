//! What containment keeps of one mesh: whether it is closed, a hierarchy over its triangles
//! with area (for the exact on-surface test) and, for a mesh that is not closed, the far-field
//! data of its winding number.

use super::box_tree::BoxTree;
use super::closed::is_closed;
use super::winding::Dipoles;
use crate::geometry::{Mesh, on_triangle, triangle_area_is_zero};
use crate::math::{Aabb, Vec3};

/// One mesh, prepared for point queries.
#[derive(Clone, Debug)]
pub(super) struct MeshShape {
    /// Closed (see [`super::closed`]) and without an alpha test: the even-odd rule answers.
    pub closed: bool,
    /// The bounds of its triangles with area: no point outside is inside or on the surface.
    pub bounds: Aabb,
    /// Over its triangles with area (those without are no part of the surface).
    tree: BoxTree,
    /// For a mesh that is not closed: the winding number's far field.
    dipoles: Option<Dipoles>,
}

impl MeshShape {
    /// Prepares `mesh`. An alpha-tested mesh is never closed: the ray tests skip what its
    /// alpha cuts away, so its crossings have no parity to rely on.
    pub fn build(mesh: &Mesh) -> Self {
        let n = mesh.triangle_count() as u32;
        let flat: Vec<bool> = (0..n)
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                triangle_area_is_zero(a, b, c)
            })
            .collect();
        let closed = mesh.alpha_test().is_none() && is_closed(mesh, &flat);
        let boxes: Vec<Aabb> = (0..n).map(|t| mesh.triangle_bounds(t)).collect();
        let tree = BoxTree::build(&boxes, (0..n).filter(|&t| !flat[t as usize]));
        let bounds = tree.nodes.first().map_or(Aabb::EMPTY, |root| root.bounds);
        let dipoles = (!closed).then(|| Dipoles::build(&tree, mesh));
        Self {
            closed,
            bounds,
            tree,
            dipoles,
        }
    }

    /// True when `p` lies on a triangle of `mesh` (this shape's mesh), exactly.
    pub fn on_surface(&self, mesh: &Mesh, p: Vec3) -> bool {
        self.tree
            .any_near(p, |tri| on_triangle(p, mesh.corners(tri)))
    }

    /// The winding number of `mesh` (this shape's mesh) at `p` through the hierarchy, `None`
    /// for a closed mesh (which keeps no far field).
    pub fn winding(&self, mesh: &Mesh, p: Vec3) -> Option<f64> {
        let dipoles = self.dipoles.as_ref()?;
        Some(dipoles.winding(&self.tree, mesh, p.as_dvec3()))
    }

    /// [`MeshShape::build`] keeping the far field whether or not the mesh is closed, for
    /// tests.
    #[cfg(test)]
    pub fn build_open(mesh: &Mesh) -> Self {
        let mut shape = Self::build(mesh);
        shape.dipoles = Some(Dipoles::build(&shape.tree, mesh));
        shape
    }

    /// The winding number at `q` without the far field, for tests.
    #[cfg(test)]
    pub fn winding_exact_sum(&self, mesh: &Mesh, q: glam::DVec3) -> f64 {
        super::winding::winding_exact_sum(mesh, self.tree.items.iter().copied(), q)
    }
}

/// Whether the winding number `w` counts as inside: its magnitude at least 1/2, so a surface
/// wound inwards (`w` near -1 inside) holds its inside too.
pub(super) fn winding_inside(w: f64) -> bool {
    w.abs() >= 0.5
}

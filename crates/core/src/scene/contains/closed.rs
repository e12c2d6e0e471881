//! Which meshes are closed: those whose inside the even-odd rule answers exactly.
//!
//! A mesh is closed when every edge is shared by an even number of its faces, an edge being
//! the pair of its end points' exact `f32` positions (`-0` as `+0`, in either order): vertices
//! at one position count as one, so a mesh whose vertices were never welded (STL) is closed
//! when the welded one is. Then the faces bound a solid (mod 2), and every ray's crossings,
//! counted by the all-hits rule, have the parity of "inside".
//!
//! Faces without area (collinear or coincident corners, exactly) are never hit, so they are
//! no part of the surface; their edges still tell something. A mesh is closed when either
//! count is even everywhere: that of the faces with area alone, or that of all faces (an edge
//! of zero length left out). The second admits a mesh whose crack at a T-junction is filled by
//! a zero-area face, as tessellators write them; both imply that the faces with area bound a
//! solid, since a zero-area face's own boundary cancels as a set of segments.

use crate::geometry::Mesh;

/// The position of a vertex as the bits of its coordinates, `-0` taken as `+0`.
fn position_key(p: crate::math::Vec3) -> [u32; 3] {
    (p + crate::math::Vec3::ZERO).to_array().map(f32::to_bits)
}

/// True when `mesh` is closed (see the module docs); `flat[tri]` says whether a face has no
/// area. A mesh without faces is closed (it holds nothing).
pub(super) fn is_closed(mesh: &Mesh, flat: &[bool]) -> bool {
    // One id per distinct position: sort the vertices by position, number the runs.
    let positions = mesh.positions();
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_unstable_by_key(|&i| (position_key(positions[i as usize]), i));
    let mut weld = vec![0u32; positions.len()];
    let mut id = 0u32;
    for (k, w) in order.windows(2).enumerate() {
        if position_key(positions[w[0] as usize]) != position_key(positions[w[1] as usize]) {
            id += 1;
        }
        weld[order[k + 1] as usize] = id;
    }
    // Every edge as (smaller id, larger id) with a flag for faces without area.
    let mut edges: Vec<(u64, bool)> = Vec::with_capacity(3 * mesh.triangle_count());
    for (tri, idx) in mesh.indices().iter().enumerate() {
        let [a, b, c] = idx.map(|i| weld[i as usize]);
        for (u, w) in [(a, b), (b, c), (c, a)] {
            if u != w {
                let key = (u64::from(u.min(w)) << 32) | u64::from(u.max(w));
                edges.push((key, flat[tri]));
            }
        }
    }
    edges.sort_unstable();
    let (mut all_even, mut area_even) = (true, true);
    for run in edges.chunk_by(|a, b| a.0 == b.0) {
        let with_area = run.iter().filter(|e| !e.1).count();
        all_even &= run.len() % 2 == 0;
        area_even &= with_area % 2 == 0;
    }
    all_even || area_even
}

//! Tangent frames for normal textures when the file gives no `TANGENT`: MikkTSpace (the
//! specification's choice, through the `mikktspace` crate), one tangent per triangle corner.
//!
//! MikkTSpace works in OpenGL's texture orientation, `v` upwards; glTF's `v` points down the
//! image, so `v` is flipped on the way in. The bitangent `w * cross(n, t)` then points up the
//! image, where a normal texture's green channel points.

use lumis_core::math::{Vec2, Vec3, Vec4};

struct Input<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    out: Vec<[Vec4; 3]>,
}

impl Input<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.triangles[face][vert] as usize
    }
}

impl mikktspace::Geometry for Input<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs[self.vertex(face, vert)];
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        if let Some(corner) = self.out.get_mut(face).and_then(|f| f.get_mut(vert)) {
            *corner = Vec4::from(tangent);
        }
    }
}

/// Per-corner tangents (xyz unit, w handedness) of `triangles`; `None` when MikkTSpace gives
/// up, or would be given a mesh it cannot take (see [`hashable`]).
pub(super) fn generate(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
) -> Option<Vec<[Vec4; 3]>> {
    let n = positions.len();
    if triangles.iter().flatten().any(|&i| i as usize >= n) || !hashable(positions, triangles) {
        return None;
    }
    let mut input = Input {
        positions,
        normals,
        uvs,
        triangles,
        out: vec![[Vec4::new(1.0, 0.0, 0.0, 1.0); 3]; triangles.len()],
    };
    mikktspace::generate_tangents(&mut input).then_some(input.out)
}

/// Whether MikkTSpace can sort the corners of `triangles` into its grid of cells. It spreads
/// them over the widest axis of their bounding box by `(x - min) / (max - min)` and indexes past
/// its table when no corner lands in the last cell (mikktspace 0.3 panics, found by fuzzing):
/// that happens when every corner is the same point (0 / 0), when a coordinate is not finite,
/// or when the extent overflows `f32` (x / inf). Such meshes have no area to shade or are
/// refused by the mesh check (coordinates beyond its limit), so nothing is lost by not asking.
fn hashable(positions: &[Vec3], triangles: &[[u32; 3]]) -> bool {
    let mut corners = triangles.iter().flatten().map(|&i| positions[i as usize]);
    let Some(first) = corners.next() else {
        return false;
    };
    let mut bounds = Some((first, first)).filter(|_| first.is_finite());
    for p in corners {
        bounds = bounds
            .filter(|_| p.is_finite())
            .map(|(lo, hi)| (lo.min(p), hi.max(p)));
    }
    let spread = bounds.is_some_and(|(min, max)| {
        let extent = max - min;
        extent.is_finite() && extent.max_element() > 0.0
    });
    // It also follows dangling pointers when every triangle has two equal corners (its
    // test for degenerate triangles).
    spread
        && triangles.iter().any(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            a != b && a != c && b != c
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small meshes drawn from a few coordinate values, so that repeated corners, point-like
    /// and flat triangles, zero normals, repeated uvs and extreme extents all come up; MikkTSpace
    /// must give tangents or `None`, never panic.
    #[test]
    fn odd_meshes_never_panic() {
        let values = [
            0.0,
            1.0,
            -1.0,
            1e-30,
            3e38,
            -3e38,
            1e-45,
            f32::NAN,
            f32::INFINITY,
        ];
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 33) as usize % n
        };
        for case in 0..4000 {
            let vertices = 1 + next(5);
            // Finite coordinates most of the time; every value sometimes.
            let pool = if case % 4 == 0 { values.len() } else { 5 };
            let mut v3 = || Vec3::new(values[next(pool)], values[next(pool)], values[next(pool)]);
            let positions: Vec<Vec3> = (0..vertices).map(|_| v3()).collect();
            let normals: Vec<Vec3> = (0..vertices).map(|_| v3()).collect();
            let uvs: Vec<Vec2> = (0..vertices)
                .map(|_| Vec2::new(values[next(3)], values[next(3)]))
                .collect();
            let triangles: Vec<[u32; 3]> = (0..1 + next(4))
                .map(|_| [0; 3].map(|_| next(vertices) as u32))
                .collect();
            let out = std::panic::catch_unwind(|| generate(&positions, &normals, &uvs, &triangles));
            assert!(
                out.is_ok(),
                "case {case}: {positions:?} {normals:?} {uvs:?} {triangles:?}"
            );
        }
    }

    #[test]
    fn a_mesh_of_one_point_or_overflowing_extent_is_not_hashed() {
        let tri = [[0, 1, 2]];
        let at = |p: [f32; 3]| Vec3::from(p);
        assert!(!hashable(&[at([1.0; 3]); 3], &tri));
        assert!(!hashable(
            &[at([-3e38, 0.0, 0.0]), at([3e38, 0.0, 0.0]), at([0.0; 3])],
            &tri
        ));
        assert!(!hashable(
            &[at([f32::NAN, 0.0, 0.0]), at([1.0; 3]), at([0.0; 3])],
            &tri
        ));
        assert!(hashable(
            &[at([0.0; 3]), at([1.0, 0.0, 0.0]), at([0.0, 1.0, 0.0])],
            &tri
        ));
    }
}

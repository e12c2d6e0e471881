//! Tangent frames for normal textures when the file gives no `TANGENT`: MikkTSpace (the
//! specification's choice, through the `mikktspace` crate), one tangent per triangle corner.
//!
//! MikkTSpace works in OpenGL's texture orientation, `v` upwards; glTF's `v` points down the
//! image, so `v` is flipped on the way in. The bitangent `w * cross(n, t)` then points up the
//! image, where a normal texture's green channel points.

use crate::math::{Vec2, Vec3, Vec4};

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
/// up. Every index must be in range for the three arrays (the mesh checks them first).
pub(super) fn generate(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
) -> Option<Vec<[Vec4; 3]>> {
    let n = positions.len();
    if triangles.iter().flatten().any(|&i| i as usize >= n) {
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

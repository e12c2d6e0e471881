//! Indexed triangle meshes: a shared vertex buffer with optional per-vertex normals and UVs,
//! and the glTF extras of [`MeshAttributes`] (second UV set, colours, tangents, alpha test).

use super::mesh_attributes::{HitAttributes, MeshAttributes, SharedAlphaTest};
use crate::math::{Aabb, Mat4, Vec2, Vec3};

/// Why a mesh could not be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// A triangle names a vertex past the end of the buffer.
    #[error("triangle {tri} uses vertex {index}, but the mesh has only {count} vertices")]
    IndexOutOfRange {
        tri: usize,
        index: u32,
        count: usize,
    },
    /// A position is NaN or infinite.
    #[error("vertex {0} has a non-finite position")]
    NonFinitePosition(usize),
    /// A normal or texture coordinate is NaN, infinite or beyond [`MAX_ATTRIBUTE`]
    /// (interpolating it would overflow).
    #[error("vertex {index} has a non-finite or huge {what} (|x| <= 1e18)")]
    BadAttribute { what: &'static str, index: usize },
    /// Normals or UVs are given but not one per vertex.
    #[error("{what} count {got} does not match the vertex count {expected}")]
    AttributeCount {
        what: &'static str,
        got: usize,
        expected: usize,
    },
}

/// Largest |component| of a vertex normal or texture coordinate.
pub const MAX_ATTRIBUTE: f32 = 1e18;

/// A triangle mesh in world space. Fields are private: the constructor checks every index.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    indices: Vec<[u32; 3]>,
    /// Boxed: most meshes have none, and a `Mesh` is copied into every scene's list.
    extra: Option<Box<MeshAttributes>>,
    alpha: Option<SharedAlphaTest>,
}

impl Mesh {
    /// Bytes of its arrays (positions, indices and the optional normals and uvs).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.positions.as_slice())
            + std::mem::size_of_val(self.indices.as_slice())
            + self
                .normals
                .as_ref()
                .map_or(0, |n| std::mem::size_of_val(n.as_slice()))
            + self
                .uvs
                .as_ref()
                .map_or(0, |u| std::mem::size_of_val(u.as_slice()))
            + self.extra.as_ref().map_or(0, |e| e.bytes())
    }

    /// Builds a mesh, checking that every index is in range, every position is finite and
    /// every attribute array has one entry per vertex.
    pub fn new(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        indices: Vec<[u32; 3]>,
    ) -> Result<Self, MeshError> {
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition(i));
        }
        for (tri, idx) in indices.iter().enumerate() {
            if let Some(&index) = idx.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(MeshError::IndexOutOfRange {
                    tri,
                    index,
                    count: positions.len(),
                });
            }
        }
        let check = |what, got: Option<usize>| match got {
            Some(got) if got != positions.len() => Err(MeshError::AttributeCount {
                what,
                got,
                expected: positions.len(),
            }),
            _ => Ok(()),
        };
        check("normal", normals.as_ref().map(Vec::len))?;
        check("uv", uvs.as_ref().map(Vec::len))?;
        // Barycentric interpolation sums three weighted values: within the limit they stay
        // finite (a NaN or infinite uv would put NaN in the texture lookup and the AOVs).
        let ok = |x: f32| x.abs() <= MAX_ATTRIBUTE;
        let bad_normal = normals
            .iter()
            .flatten()
            .position(|n| !n.to_array().into_iter().all(ok));
        if let Some(index) = bad_normal {
            return Err(MeshError::BadAttribute {
                what: "normal",
                index,
            });
        }
        let bad_uv = uvs
            .iter()
            .flatten()
            .position(|t| !t.to_array().into_iter().all(ok));
        if let Some(index) = bad_uv {
            return Err(MeshError::BadAttribute { what: "uv", index });
        }
        Ok(Self {
            positions,
            normals,
            uvs,
            indices,
            extra: None,
            alpha: None,
        })
    }

    /// This mesh with the extra attributes `extra`, checking that every per-vertex array has
    /// one entry per vertex and the tangents one per triangle.
    pub fn with_attributes(mut self, extra: MeshAttributes) -> Result<Self, MeshError> {
        let n = self.positions.len();
        let check = |what, got: Option<usize>, expected: usize| match got {
            Some(got) if got != expected => Err(MeshError::AttributeCount {
                what,
                got,
                expected,
            }),
            _ => Ok(()),
        };
        check("TEXCOORD_1", extra.uv1.as_ref().map(Vec::len), n)?;
        check("colour", extra.colors.as_ref().map(Vec::len), n)?;
        check(
            "tangent (per triangle)",
            extra.tangents.as_ref().map(Vec::len),
            self.indices.len(),
        )?;
        self.extra = (extra != MeshAttributes::default()).then(|| Box::new(extra));
        Ok(self)
    }

    /// The extra attributes, if any.
    pub fn attributes(&self) -> Option<&MeshAttributes> {
        self.extra.as_deref()
    }

    /// Sets the alpha test intersection applies to this mesh's triangles.
    pub fn set_alpha_test(&mut self, alpha: Option<SharedAlphaTest>) {
        self.alpha = alpha;
    }

    /// The alpha test, if the mesh has one.
    pub fn alpha_test(&self) -> Option<&SharedAlphaTest> {
        self.alpha.as_ref()
    }

    /// Every attribute at barycentrics `(u, v)` of triangle `tri`.
    pub fn hit_attributes(&self, tri: u32, u: f32, v: f32) -> HitAttributes {
        let uv0 = self.uv(tri, u, v);
        match &self.extra {
            Some(e) => e.at(tri, self.indices[tri as usize], u, v, uv0),
            None => HitAttributes {
                uvs: [uv0; 2],
                color: crate::math::Vec4::ONE,
                tangent: None,
            },
        }
    }

    /// False when the mesh's alpha test cuts the point `(u, v)` of triangle `tri` away.
    #[inline]
    pub fn alpha_passes(&self, tri: u32, u: f32, v: f32) -> bool {
        match &self.alpha {
            None => true,
            Some(a) => a.passes(&self.hit_attributes(tri, u, v)),
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Per-vertex shading normals, if the mesh is smooth-shaded.
    pub fn normals(&self) -> Option<&[Vec3]> {
        self.normals.as_deref()
    }

    /// Per-vertex texture coordinates, if any.
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }

    /// Triangle vertex indices.
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.indices
    }

    /// The three corners of triangle `tri`.
    #[inline(always)]
    pub fn corners(&self, tri: u32) -> [Vec3; 3] {
        let [a, b, c] = self.indices[tri as usize];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Bounding box of triangle `tri`.
    pub fn triangle_bounds(&self, tri: u32) -> Aabb {
        Aabb::from_points(self.corners(tri))
    }

    /// Bounding box of the whole mesh.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }

    /// Shading normal at barycentrics `(u, v)` (weights of vertices 1 and 2), if the mesh has normals.
    pub fn shading_normal(&self, tri: u32, u: f32, v: f32) -> Option<Vec3> {
        let n = self.normals.as_ref()?;
        let [a, b, c] = self.indices[tri as usize];
        let s = n[a as usize] * (1.0 - u - v) + n[b as usize] * u + n[c as usize] * v;
        Some(s.normalize_or_zero()).filter(|s| *s != Vec3::ZERO)
    }

    /// Texture coordinate at barycentrics `(u, v)`, or the barycentrics themselves without UVs.
    pub fn uv(&self, tri: u32, u: f32, v: f32) -> Vec2 {
        match &self.uvs {
            Some(uv) => {
                let [a, b, c] = self.indices[tri as usize];
                uv[a as usize] * (1.0 - u - v) + uv[b as usize] * u + uv[c as usize] * v
            }
            None => Vec2::new(u, v),
        }
    }

    /// This mesh moved to world space by `m` (normals by its inverse transpose). A transform with a
    /// negative determinant flips the winding so faces keep pointing the same way.
    pub fn transformed(mut self, m: &Mat4) -> Self {
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        let normal_m = m.inverse().transpose();
        if let Some(ns) = &mut self.normals {
            for n in ns {
                *n = normal_m.transform_vector3(*n).normalize_or_zero();
            }
        }
        let swap = m.determinant() < 0.0;
        if let Some(e) = &mut self.extra {
            e.transform(m, swap);
        }
        if swap {
            for idx in &mut self.indices {
                idx.swap(1, 2);
            }
            // Swapping corners 1 and 2 swaps the barycentric roles; UV/normal lookups use the
            // same indices, so they stay consistent.
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_out_of_range_index_and_nan() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let err = Mesh::new(p.clone(), None, None, vec![[0, 1, 3]]).unwrap_err();
        assert_eq!(
            err,
            MeshError::IndexOutOfRange {
                tri: 0,
                index: 3,
                count: 3
            }
        );
        let mut bad = p;
        bad[1].x = f32::NAN;
        assert_eq!(
            Mesh::new(bad, None, None, vec![[0, 1, 2]]).unwrap_err(),
            MeshError::NonFinitePosition(1)
        );
    }
}

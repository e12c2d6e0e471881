//! What a mesh may carry beyond positions, normals and one UV set, for glTF materials: a
//! second UV set, vertex colours, tangent frames for normal maps, and the alpha test of a
//! `MASK` material, which intersection itself applies (so a cut-out hole lets camera and
//! shadow rays through alike, in every accelerator).

use std::sync::Arc;

use crate::math::{Mat4, Vec2, Vec4};
use crate::texture::TextureRef;

/// Per-vertex extras of a [`super::Mesh`]; each array has one entry per vertex, but
/// `tangents`, which has one per triangle corner (generated tangents may differ between the
/// triangles that share a vertex).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttributes {
    /// `TEXCOORD_1`.
    pub uv1: Option<Vec<Vec2>>,
    /// `COLOR_0` as linear RGBA (alpha 1 where the file gives RGB).
    pub colors: Option<Vec<Vec4>>,
    /// Per triangle, per corner: unit tangent (xyz) and handedness (w = ±1), the bitangent
    /// being `w * cross(normal, tangent)`.
    pub tangents: Option<Vec<[Vec4; 3]>>,
}

/// A material's alpha test (`alphaMode` `MASK`): a hit counts only where
/// `factor * texture alpha * vertex alpha >= cutoff`.
#[derive(Clone, Debug, PartialEq)]
pub struct AlphaTest {
    /// The base colour factor's alpha.
    pub factor: f32,
    /// The base colour texture, whose alpha multiplies in.
    pub texture: Option<TextureRef>,
    /// `alphaCutoff`.
    pub cutoff: f32,
}

/// Attributes interpolated at one hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitAttributes {
    /// `TEXCOORD_0` and `TEXCOORD_1` (the first where the second is missing).
    pub uvs: [Vec2; 2],
    /// Vertex colour, 1 without one.
    pub color: Vec4,
    /// Interpolated tangent (not normalised) and handedness, if the mesh has tangents.
    pub tangent: Option<Vec4>,
}

impl MeshAttributes {
    /// Bytes of the arrays.
    pub fn bytes(&self) -> usize {
        self.uv1
            .as_ref()
            .map_or(0, |a| std::mem::size_of_val(a.as_slice()))
            + self
                .colors
                .as_ref()
                .map_or(0, |a| std::mem::size_of_val(a.as_slice()))
            + self
                .tangents
                .as_ref()
                .map_or(0, |a| std::mem::size_of_val(a.as_slice()))
    }

    /// The attributes of triangle `tri` (vertices `idx`) at barycentrics `(u, v)`, with `uv0`
    /// the first UV set's value there.
    pub fn at(&self, tri: u32, idx: [u32; 3], u: f32, v: f32, uv0: Vec2) -> HitAttributes {
        let w = [1.0 - u - v, u, v];
        let [a, b, c] = idx.map(|i| i as usize);
        HitAttributes {
            uvs: [
                uv0,
                self.uv1
                    .as_ref()
                    .map_or(uv0, |t| t[a] * w[0] + t[b] * w[1] + t[c] * w[2]),
            ],
            color: self
                .colors
                .as_ref()
                .map_or(Vec4::ONE, |t| t[a] * w[0] + t[b] * w[1] + t[c] * w[2]),
            tangent: self.tangents.as_ref().map(|t| {
                let [ta, tb, tc] = t[tri as usize];
                let xyz = ta.truncate() * w[0] + tb.truncate() * w[1] + tc.truncate() * w[2];
                // Handedness does not interpolate: a triangle has one.
                xyz.extend(ta.w)
            }),
        }
    }

    /// Moves the tangents by `m` (they are surface directions, like edges); a mirroring `m`
    /// flips handedness, since it flips the normal's cross product, and `swap` (the mesh's
    /// winding flip) swaps corners 1 and 2 as the indices were.
    pub(super) fn transform(&mut self, m: &Mat4, swap: bool) {
        let flip = if m.determinant() < 0.0 { -1.0 } else { 1.0 };
        if let Some(ts) = &mut self.tangents {
            for corners in ts.iter_mut() {
                for t in corners.iter_mut() {
                    let d = m.transform_vector3(t.truncate()).normalize_or_zero();
                    *t = d.extend(t.w * flip);
                }
                if swap {
                    corners.swap(1, 2);
                }
            }
        }
    }
}

impl AlphaTest {
    /// True when a hit with these attributes is kept.
    pub fn passes(&self, at: &HitAttributes) -> bool {
        let tex = self.texture.as_ref().map_or(1.0, |t| t.sample(&at.uvs).w);
        self.factor * tex * at.color.w >= self.cutoff
    }
}

/// An alpha test shared by the meshes of one material.
pub type SharedAlphaTest = Arc<AlphaTest>;

//! The AOV layers written only on request (`--aov albedo,position,uv`), all FLOAT, from the
//! centre ray of each pixel like the depth, normal and id layers:
//!
//! | channel             | content                                                        |
//! |---------------------|----------------------------------------------------------------|
//! | `albedo.R/G/B`      | diffuse albedo `kd` at the hit (textures evaluated); 0 at misses |
//! | `P.X/Y/Z`           | world-space hit point; 0 at misses                             |
//! | `uv.U/V`            | texture coordinates at the hit; 0 at misses                    |
//! | `uv.A` (Blender layout only) | 1 where the centre ray hit a surface, 0 at misses     |

use super::layout::ChannelLayout;
use lumis_core::film::{Film, PixelAov};

/// Which of the optional AOV layers to write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AovLayers {
    /// `albedo.R/G/B`.
    pub albedo: bool,
    /// `P.X/Y/Z` (world position).
    pub position: bool,
    /// `uv.U/V`.
    pub uv: bool,
}

/// The requested layers' channels of `film`, as (lumis name, values row-major), with the
/// extra channels `layout` has.
pub(super) fn channels(
    film: &Film,
    layers: AovLayers,
    layout: ChannelLayout,
) -> Vec<(&'static str, Vec<f32>)> {
    let aov = film.aov();
    let take = |f: fn(&PixelAov) -> f32| aov.iter().map(f).collect::<Vec<f32>>();
    let mut out = Vec::new();
    if layers.albedo {
        out.push(("albedo.R", take(|a| a.albedo.x)));
        out.push(("albedo.G", take(|a| a.albedo.y)));
        out.push(("albedo.B", take(|a| a.albedo.z)));
    }
    if layers.position {
        out.push(("P.X", take(|a| a.position.x)));
        out.push(("P.Y", take(|a| a.position.y)));
        out.push(("P.Z", take(|a| a.position.z)));
    }
    if layers.uv {
        out.push(("uv.U", take(|a| a.uv.x)));
        out.push(("uv.V", take(|a| a.uv.y)));
        if layout.uv_has_alpha() {
            let hit = |a: &PixelAov| if a.object_id >= 0 { 1.0 } else { 0.0 };
            out.push(("uv.A", take(hit)));
        }
    }
    out
}

//! What a render traced, by ray kind, and what it decided not to trace, by reason.

use crate::accel::TraversalStats;
use serde::Serialize;

/// Rays traced, by kind, rays not traced, by reason, and the traversal counters; one per
/// worker, summed at the end.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    /// Primary rays from the camera (every sample, through the lens).
    pub camera: u64,
    /// Pinhole rays through pixel centres that fill the depth, normal and id layers.
    pub aov: u64,
    /// Shadow rays towards lights.
    pub shadow: u64,
    /// Mirror rays (reflectivity and the Fresnel-reflected part of glass).
    pub reflection: u64,
    /// Refracted rays.
    pub refraction: u64,
    /// Rays the decisions of [`crate::effects`] left out.
    pub not_traced: NotTraced,
    /// Accelerator work for all of the above.
    pub traversal: TraversalStats,
}

/// Rays not traced, by kind and reason. A skipped reflection or refraction branch counts once:
/// the rays its subtree would have spawned are not counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct NotTraced {
    /// Shadow rays, by reason.
    pub shadow: ShadowSkips,
    /// Mirror rays, by reason.
    pub reflection: BranchSkips,
    /// Refraction rays, by reason.
    pub refraction: BranchSkips,
    /// Lens rays per sample beyond the first on a pinhole camera (all the same ray).
    pub lens: u64,
    /// Centre rays for AOV layers when no output has them (one per pixel).
    pub aov: u64,
    /// Camera rays of the pixel samples adaptive supersampling found unneeded (lens rays
    /// included; `--adaptive`).
    pub adaptive: u64,
}

/// Why shadow rays were not cast, one count per (shading point, light) pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ShadowSkips {
    /// The material ignores light (black diffuse, no highlight; pure emitters).
    pub material_unlit: u64,
    /// The light has zero intensity.
    pub dark_light: u64,
    /// The light is behind the surface as shaded (cos <= 0 to the shading or geometric normal).
    pub back_facing: u64,
    /// The point lies outside the spot light's cone.
    pub outside_cone: u64,
    /// Any other exactly-zero unshadowed contribution (e.g. underflow).
    pub zero_contribution: u64,
}

/// Why a reflection or refraction branch was not traced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct BranchSkips {
    /// The material never spawns this kind of ray.
    pub material: u64,
    /// Its weight is exactly zero at this hit (Fresnel, total internal reflection).
    pub zero_weight: u64,
    /// Its weight in the pixel fell below the cutoff (not zero: this one changes the image).
    pub cutoff: u64,
}

impl ShadowSkips {
    /// Shadow rays not cast, all reasons.
    pub fn total(&self) -> u64 {
        self.material_unlit
            + self.dark_light
            + self.back_facing
            + self.outside_cone
            + self.zero_contribution
    }
}

impl BranchSkips {
    /// Branches not traced, all reasons.
    pub fn total(&self) -> u64 {
        self.material + self.zero_weight + self.cutoff
    }
}

impl RayCounts {
    /// Every ray traced.
    pub fn total(&self) -> u64 {
        self.camera + self.aov + self.shadow + self.reflection + self.refraction
    }

    /// Reflection and refraction branches cut by the contribution cutoff.
    pub fn cut(&self) -> u64 {
        self.not_traced.reflection.cutoff + self.not_traced.refraction.cutoff
    }
}

/// Field-by-field sums, so the per-tile counts add up to the render's.
macro_rules! add_fields {
    ($ty:ty { $($f:ident),* }) => {
        impl std::ops::AddAssign for $ty {
            fn add_assign(&mut self, o: Self) {
                $(self.$f += o.$f;)*
            }
        }
    };
}

add_fields!(RayCounts {
    camera,
    aov,
    shadow,
    reflection,
    refraction,
    not_traced,
    traversal
});
add_fields!(NotTraced {
    shadow,
    reflection,
    refraction,
    lens,
    aov,
    adaptive
});
add_fields!(ShadowSkips {
    material_unlit,
    dark_light,
    back_facing,
    outside_cone,
    zero_contribution
});
add_fields!(BranchSkips {
    material,
    zero_weight,
    cutoff
});

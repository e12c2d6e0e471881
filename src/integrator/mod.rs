//! Integrators turn a camera ray into radiance. They read the scene and never touch the film.

mod whitted;

pub use whitted::Whitted;

use crate::accel::TraversalStats;

/// Rays traced, by kind, plus the traversal counters; one per worker, summed at the end.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
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
    /// Reflection and refraction branches not traced because their weight fell below the
    /// cutoff (not rays: counted apart from the total).
    pub cut: u64,
    /// Accelerator work for all of the above.
    pub traversal: TraversalStats,
}

impl RayCounts {
    /// Every ray traced.
    pub fn total(&self) -> u64 {
        self.camera + self.aov + self.shadow + self.reflection + self.refraction
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        self.camera += o.camera;
        self.aov += o.aov;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.cut += o.cut;
        self.traversal += o.traversal;
    }
}

//! Integrators turn a camera ray into radiance. They read the scene and never touch the film.

mod counts;
mod whitted;

pub use counts::{BranchSkips, NotTraced, RayCounts, ShadowSkips};
pub use whitted::{CameraSample, Whitted};

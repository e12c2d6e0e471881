//! Integrators turn a camera ray into radiance. They read the scene and never touch the film.

mod counts;
mod report;
mod whitted;

pub use counts::{BranchSkips, NotTraced, RayCounts, ShadowSkips};
pub use report::effects_text;
pub use whitted::{CameraSample, Whitted};

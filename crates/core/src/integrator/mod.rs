//! Integrators turn a camera ray into radiance. They read the scene and never touch the film.

mod camera;
mod catcher;
mod counts;
pub mod paths;
mod report;
mod whitted;

pub use camera::CameraSample;
pub use counts::{BranchSkips, NotTraced, RayCounts, ShadowSkips};
pub use paths::{LightPaths, Split};
pub use report::effects_text;
pub use whitted::Whitted;

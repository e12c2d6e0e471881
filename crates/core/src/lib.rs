//! lumis-core: an offline Whitted-style ray tracer's core, with no file formats and no
//! command line.
//!
//! The data flows one way: a scene is assembled through [`scene::SceneBuilder`] (the file
//! formats of `lumis-io` fill it) into a [`scene::Scene`], an [`accel::Accel`] is built over its
//! primitives' bounding boxes, [`render::render`] traces camera rays through an
//! [`integrator`] into a [`film::Film`], and the film's develop operations (exposure, tonemap,
//! display transform, finite check) prepare it for whoever writes it.

pub mod accel;
pub mod batch;
pub mod camera;
pub mod cryptomatte;
pub mod effects;
pub mod environment;
pub mod film;
pub mod geometry;
mod huge_pages;
pub mod instancing;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod render;
pub mod rng;
pub mod scene;
pub mod texture;

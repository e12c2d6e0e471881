//! lumis: an offline Whitted-style ray tracer.
//!
//! The data flows one way: a scene file is loaded by [`formats::load`] into a [`scene::Scene`], an
//! [`accel::Accel`] is built over its primitives' bounding boxes, [`render::render`] traces
//! camera rays through an integrator into a [`film::Film`], and [`output`] writes it.

pub mod accel;
pub mod camera;
pub mod cryptomatte;
pub mod effects;
pub mod farm;
pub mod film;
pub mod formats;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod output;
pub mod rays;
pub mod render;
pub mod rng;
pub mod scene;
pub mod texture;

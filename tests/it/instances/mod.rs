//! Instancing (issue 28): prototypes placed by affine transforms, traced through two levels.
//!
//! - [`agreement`]: every accelerator and traversal over instances answers as brute force over
//!   instances (brute force inside them too), bit for bit, for nearest, any and all hits.
//! - [`flattened`]: the same placements flattened into world-space copies agree within the
//!   documented bound (the object-space ray rounds once).
//! - [`hard`]: instanced closed meshes far from the origin, mirrored, scaled 1e-6..1e6: no
//!   leaks, hits within the bound of an independent `f64` oracle.
//! - [`in_flight`]: the batch walk, which enters instances in place, answers as the one-ray
//!   walk and brute force over instances, records bit for bit.

mod agreement;
mod fixtures;
mod flattened;
mod hard;
mod in_flight;
mod one_instance;

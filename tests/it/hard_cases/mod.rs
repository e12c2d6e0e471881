//! The hard-case suite: numerically difficult inputs, each checked against an oracle written
//! independently of the code under test (exact rational arithmetic in [`exact`], or float64 with
//! a stated bound) and run through every accelerator x traversal ([`harness`]).
//!
//! One module per family; `docs/hard-cases.md` lists every case in one line with what it
//! guards against.

use crate::common;

pub mod exact;
mod harness;

mod camera;
mod directions;
mod far_origins;
mod glass;
mod offsets;
mod polygons;
mod shading;
mod spheres;
mod triangles;

//! The floor every reader stands on: reading an input whole and only if it is a regular file,
//! noting which files a run read (so no output can overwrite one), and the guard around calls
//! into parser crates. Formats, rays, outputs and the farm all read through here.

pub mod guard;
mod inputs;
mod regular;

pub use inputs::{InputFile, file_id, record_inputs};
pub(crate) use regular::file_kind;
pub use regular::read_regular;

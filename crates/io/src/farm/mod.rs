//! Rendering one image on many machines: `lumis render --tile I/N` renders a fixed strip of
//! the image ([`lumis_core::film::TileSpec`]) into an EXR tile, and `lumis merge` ([`merge`]) assembles the tiles
//! into the file a single `lumis render` would have written, byte for byte.
//!
//! Why the bytes can match: every pixel's samples depend only on the seed and the pixel, never
//! on the tile or thread that rendered it; a tile keeps the film's floats before exposure
//! (see `output::exr`'s provenance attributes); the merge reads each tile back through
//! `output::exr` into a film of its strip, pastes the strips into the film of the whole image,
//! and develops that film with `output::develop`, the step `lumis render` develops its film
//! with (automatic exposure over the whole image, the half conversion, the same writer and
//! header order), from the metadata and camera the tiles' headers record. The merge has no
//! EXR code of its own. Tiles must come from the same scene (hash of its files), seed and
//! settings, which every EXR records ([`identity`]).
//!
//! These tiles are a farm's jobs; the renderer's own 16-pixel work buckets (`render.rs`) are a
//! different, finer split inside each job.

mod error;
pub mod identity;
pub mod merge;

pub use self::error::FarmError;
pub use self::identity::{file_digest, file_digests, load_options_text, scene_hash, scene_hash_of};
pub use self::merge::merge_tiles;

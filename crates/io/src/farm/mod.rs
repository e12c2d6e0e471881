//! Rendering one image on many machines: `lumis render --tile I/N` renders a fixed strip of
//! the image ([`lumis_core::film::TileSpec`]) into an EXR tile, and `lumis merge` ([`merge`]) assembles the tiles
//! into the file a single `lumis render` would have written, byte for byte.
//!
//! Why the bytes can match: every pixel's samples depend only on the seed and the pixel, never
//! on the tile or thread that rendered it; a tile keeps the film's floats before exposure
//! (see `output::provenance`); and the merge finishes them with the same functions as a single
//! render (automatic exposure over the whole image, the half conversion) and writes the same
//! header, the tile-only attributes removed. Tiles must come from the same scene (hash of its
//! files), seed and settings, which every EXR records ([`identity`]).
//!
//! These tiles are a farm's jobs; the renderer's own 16-pixel work buckets (`render.rs`) are a
//! different, finer split inside each job.

mod error;
pub mod identity;
pub mod merge;

pub use self::error::FarmError;
pub use self::identity::scene_hash;
pub use self::merge::merge_tiles;

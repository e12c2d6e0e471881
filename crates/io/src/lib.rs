//! lumis-io: everything lumis reads and writes.
//!
//! Files come in through [`formats::load`] (TOML, `.scn`/`.m`, OBJ+MTL, glTF/GLB), which fills
//! `lumis_core`'s scene builder; rays come in through [`rays`]; what a render is asked for on
//! top of its scene (settings, exposure, extra layers) is decided in [`request`]. A finished
//! film goes out through [`output`] (the develop step, OpenEXR with its header schema, PNG,
//! staged atomic writes), and [`farm`] splits a render into tiles and merges them back into
//! the same film; [`display`] streams a render into a viewer (tev) as it runs. Nothing in
//! `lumis_core` knows of files: the flow is core → io → the commands.

pub mod display;
pub mod farm;
pub mod files;
pub mod formats;
pub mod output;
pub mod rays;
pub mod request;

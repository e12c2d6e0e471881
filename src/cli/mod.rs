//! The `lumis` command line, one module per subcommand; `main.rs` only parses and dispatches.
//!
//! Everything here is binary-only: the libraries (`lumis_core`, `lumis_io`) know nothing of clap, and the
//! flags' value sets are mirrored onto library enums in [`values`].

pub mod accel;
pub mod accuracy;
pub mod environment;
pub mod frame;
pub mod hits;
pub mod info;
pub mod interrupt;
pub mod merge;
pub mod overrides;
pub mod passes;
pub mod progress;
pub mod render;
pub mod stats;
pub mod threads;
pub mod values;
pub mod window;

//! The integration tests of the `lumis` command and of the libraries through it, as one test
//! binary (one link instead of ~35): a module per former test file, the shared helpers in
//! [`common`]. `cargo test NAME` still selects tests by name, e.g. `cargo test hard_cases::`.

mod common;
mod npy_rays;
/// The `queries` fuzz target's checker, shared by `fuzz_regressions` and `query_fuzz`.
#[path = "../../fuzz/src/queries/mod.rs"]
mod queries;
mod support_io;

mod accel_agreement;
mod accuracy_options;
mod adaptive;
mod all_hits;
mod assets_render;
mod bad_input;
mod bad_input_deps;
mod batch_in_flight;
mod cli;
mod cli_exr;
mod cli_flags;
mod cli_models;
mod contains;
mod cryptomatte;
mod docs;
mod effects;
mod environment;
mod exr_compositing;
mod exr_passes;
mod exr_reread;
mod exr_roundtrip;
mod farm;
mod frames;
mod fuzz_regressions;
mod gltf_bad_input;
mod gltf_instancing;
mod gltf_instancing_bad;
mod gltf_instancing_hidden;
mod gltf_loading;
mod gltf_materials;
mod gltf_views;
mod hard_cases;
mod hits;
mod hits_all;
mod instance_ids;
mod instances;
mod live_view;
mod memory_bombs;
mod module_flow;
mod no_debug_output;
mod non_regular_files;
mod obj_mtl;
mod output_safety;
mod output_targets;
mod packets;
mod paper_scenes;
mod png_output;
mod query_fuzz;
mod ray_domain;
mod render_known_answers;
mod replay;
mod scene_loading;
mod scn_loading;
mod toml_instances;
mod toml_models;
mod watertight;

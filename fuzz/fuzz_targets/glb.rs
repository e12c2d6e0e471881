//! A binary glTF (GLB) file, loaded as `lumis render scene.glb` loads it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("glb", data));

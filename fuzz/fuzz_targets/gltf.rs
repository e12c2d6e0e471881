//! A glTF JSON file, loaded as `lumis render scene.gltf` loads it (a fixed 64-byte buffer beside it).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("gltf", data));

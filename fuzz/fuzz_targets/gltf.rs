//! A glTF JSON file, loaded as `lumis render scene.gltf` loads it (a fixed 64-byte buffer beside it).
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    put("buf.bin", &[0u8; 64]);
    load(&put("scene.gltf", data));
});

//! A binary glTF (GLB) file, loaded as `lumis render scene.glb` loads it.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    load(&put("scene.glb", data));
});

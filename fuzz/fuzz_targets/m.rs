//! A `.m` mesh, read through a fixed `.scn` scene that places it with `model`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    put("scene.scn", b"model mesh.m 1 0 0 -5\n");
    put("mesh.m", data);
    load(&lumis_fuzz::scratch().join("scene.scn"));
});

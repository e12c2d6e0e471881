//! A `.scn` scene of the paper'\''s format, with a fixed `.m` mesh beside it for `model`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    put("tri.m", b"Vertex 1 0 0 0\nVertex 2 1 0 0\nVertex 3 0 1 0\nFace 1 1 2 3\n");
    load(&put("scene.scn", data));
});

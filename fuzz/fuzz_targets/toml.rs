//! A TOML scene, loaded as `lumis render scene.toml` loads it (a fixed OBJ beside it for `[[mesh]] file`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    put("tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    load(&put("scene.toml", data));
});

//! An OBJ model, loaded as `lumis render model.obj` loads it, with a fixed MTL beside it.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    put("m.mtl", b"newmtl red\nKd 1 0 0\nnewmtl glass\nKs 1 1 1\nNi 1.5\nillum 7\n");
    load(&put("model.obj", data));
});

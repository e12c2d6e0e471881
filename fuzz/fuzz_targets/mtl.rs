//! An MTL library, read through a fixed OBJ that names it and uses its materials.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::{load, put};

fuzz_target!(|data: &[u8]| {
    put(
        "model.obj",
        b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\nusemtl glass\nf 3 2 1\n",
    );
    put("m.mtl", data);
    load(&lumis_fuzz::scratch().join("model.obj"));
});

//! An MTL library, read through a fixed OBJ that names it and uses its materials.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("mtl", data));

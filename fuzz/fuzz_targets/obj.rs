//! An OBJ model, loaded as `lumis render model.obj` loads it, with a fixed MTL beside it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("obj", data));

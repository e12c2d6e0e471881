//! A TOML scene, loaded as `lumis render scene.toml` loads it (a fixed OBJ beside it for `[[mesh]] file`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("toml", data));

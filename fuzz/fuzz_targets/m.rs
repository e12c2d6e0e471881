//! A `.m` mesh, read through a fixed `.scn` scene that places it with `model`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("m", data));

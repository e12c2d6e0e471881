//! A rays `.npy` file, read by `lumis_io::rays::read_rays` as `lumis hits --rays` reads it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("npy", data));

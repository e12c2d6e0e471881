//! A Radiance `.hdr` environment map, named by a fixed TOML scene's `[environment]`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("hdr", data));

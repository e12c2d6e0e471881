//! A `.scn` scene of the paper'\''s format, with a fixed `.m` mesh beside it for `model`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("scn", data));

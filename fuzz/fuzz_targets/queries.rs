//! Ray queries on a decoded scene through every accelerator, traversal and precision, against
//! brute force and an exact oracle (fuzz/src/queries/).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lumis_fuzz::run("queries", data));

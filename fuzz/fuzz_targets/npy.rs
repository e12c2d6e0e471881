//! A rays `.npy` file, read by `lumis::rays::read_rays` as `lumis hits --rays` reads it.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lumis_fuzz::put;

fuzz_target!(|data: &[u8]| {
    let _ = lumis::rays::read_rays(&put("rays.npy", data));
});

//! Fuzz target `xyz`: see `src/lib.rs` for what it calls.
#![no_main]

use ellipsoid_splat_fuzz::Target;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| Target::Xyz.run(data));

//! cargo-fuzz target `rftb_args`: see `plytrace_fuzz::rftb_args`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::rftb_args(data);
});

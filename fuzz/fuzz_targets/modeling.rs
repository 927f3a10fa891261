//! cargo-fuzz target `modeling`: see `plytrace_fuzz::modeling`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::modeling(data);
});

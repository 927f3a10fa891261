//! cargo-fuzz target `pipeline`: see `plytrace_fuzz::pipeline`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::pipeline(data);
});

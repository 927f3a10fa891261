//! cargo-fuzz target `object_files`: see `plytrace_fuzz::object_files`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::object_files(data);
});

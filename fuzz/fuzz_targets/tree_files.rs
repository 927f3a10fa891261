//! cargo-fuzz target `tree_files`: see `plytrace_fuzz::tree_files`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::tree_files(data);
});

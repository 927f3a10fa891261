//! cargo-fuzz target `patch_files`: see `plytrace_fuzz::patch_files`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::patch_files(data);
});

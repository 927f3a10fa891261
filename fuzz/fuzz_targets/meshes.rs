//! cargo-fuzz target `meshes`: see `plytrace_fuzz::meshes`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::meshes(data);
});

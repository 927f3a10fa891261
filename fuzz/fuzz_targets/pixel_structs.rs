//! cargo-fuzz target `pixel_structs`: see `plytrace_fuzz::pixel_structs`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::pixel_structs(data);
});

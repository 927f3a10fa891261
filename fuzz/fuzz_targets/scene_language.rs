//! cargo-fuzz target `scene_language`: see `plytrace_fuzz::scene_language`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plytrace_fuzz::scene_language(data);
});

//! `mkdet <input_file> <output_file>`: the mkdet program of the manual
//! (004 appendix B, the mkdet manual page); see
//! [`run_convert`].

use plytrace::api::program::tools::{ConvertKind, run_convert};

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run_convert(ConvertKind::Det, &args)
}

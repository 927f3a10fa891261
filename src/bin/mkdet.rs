//! `mkdet <input_file> <output_file>`: the mkdet program of the manual
//! (004 appendix B, the mkdet manual page); see [`plytrace::convert`].

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    plytrace::convert::main(plytrace::scene::object_file::ConvertKind::Det, &args)
}

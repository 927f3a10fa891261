//! rftb4, the anti-aliasing polygon tiler of method 4 (Garcia 1986, 004
//! appendix, the rftb manual page; chapter 5). See [`plytrace::rftb`].

fn main() -> std::process::ExitCode {
    plytrace::rftb::main(plytrace::rftb::Program::Rftb4)
}

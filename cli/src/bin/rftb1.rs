//! rftb1, the anti-aliasing polygon tiler of method 1 (Garcia 1986, 004
//! appendix, the rftb manual page; chapter 5). See
//! [`run_rftb`].

use plytrace::api::program::tools::{Rftb, run_rftb};

fn main() -> std::process::ExitCode {
    run_rftb(Rftb::Rftb1)
}

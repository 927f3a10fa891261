//! getrgb: the R, G and B separations of an rftb4 pixel-struct file
//! (Garcia 1986, 004 appendix, the getrgb manual page). See
//! [`run_getrgb`].

use plytrace::api::program::tools::run_getrgb;

fn main() -> std::process::ExitCode {
    run_getrgb()
}

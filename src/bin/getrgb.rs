//! getrgb: the R, G and B separations of an rftb4 pixel-struct file
//! (Garcia 1986, 004 appendix, the getrgb manual page). See
//! [`plytrace::rftb`].

fn main() -> std::process::ExitCode {
    plytrace::rftb::getrgb_main()
}

//! The converters `mkdet`, `mkpcl` and `mkvcl` of the mkdet manual page
//! (004 appendix B):
//!
//! ```text
//! mkdet <input_file> <output_file>
//! mkpcl <input_file> <output_file>
//! mkvcl <input_file> <output_file>
//! ```
//!
//! The programs `src/bin/mkdet.rs` etc. and the subcommand `plytrace mkdet`
//! are all [`main`]; the conversion itself is
//! [`crate::scene::object_file::convert`].

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use crate::error::printable;
use crate::scene::object_file::{self, ConvertKind};

/// The program's name.
pub fn name(kind: ConvertKind) -> &'static str {
    match kind {
        ConvertKind::Det => "mkdet",
        ConvertKind::Pcl => "mkpcl",
        ConvertKind::Vcl => "mkvcl",
    }
}

/// The synopsis and a line of description.
pub fn usage(kind: ConvertKind) -> String {
    let what = match kind {
        ConvertKind::Det => "convert ASCII object geometric files to binary form",
        ConvertKind::Pcl => "convert ASCII polygon color files to binary form",
        ConvertKind::Vcl => "convert ASCII vertex color files to binary form",
    };
    format!(
        "usage: {} <input_file> <output_file>\n{} - {what}\n",
        name(kind),
        name(kind)
    )
}

/// Writes `text` to stderr, each line escaped and truncated; errors (a
/// closed stderr) are ignored.
fn to_stderr(text: &str) {
    let mut e = std::io::stderr().lock();
    for line in text.trim_end_matches('\n').split('\n') {
        if writeln!(e, "{}", printable(line, 1000)).is_err() {
            return;
        }
    }
}

/// Runs the converter `kind` with `args` (the arguments after the program
/// name): 0 on success, 1 when the conversion fails, 2 for bad usage.
pub fn main(kind: ConvertKind, args: &[String]) -> ExitCode {
    match args {
        [h] if h == "--help" || h == "-h" => {
            // A closed stdout ends the help quietly.
            let _ = std::io::stdout().lock().write_all(usage(kind).as_bytes());
            ExitCode::SUCCESS
        }
        [input, output] => match convert(kind, Path::new(input), Path::new(output)) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                to_stderr(&format!("error: {e}"));
                ExitCode::FAILURE
            }
        },
        _ => {
            to_stderr(&usage(kind));
            ExitCode::from(2)
        }
    }
}

/// Converts `input` to `output`: the input must be a regular file and the
/// output a regular file or absent ([`crate::output::check_target`]).
pub fn convert(kind: ConvertKind, input: &Path, output: &Path) -> crate::Result<()> {
    let meta = std::fs::metadata(input).map_err(|e| crate::Error::io(input, e))?;
    if !meta.is_file() {
        return Err(crate::Error::io(
            input,
            std::io::Error::other("not a regular file"),
        ));
    }
    crate::output::check_target(output)?;
    object_file::convert(kind, input, output)
}

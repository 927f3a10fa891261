//! What the program prints: lines on standard output and error, each
//! escaped and cut (input may hold any bytes), and the one rule that a
//! closed pipe ends printing quietly rather than the program.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use plytrace::Error;
use plytrace::api::program::session::printable;

/// The longest line printed from input, in characters; the rest is cut
/// (see [`printable`]).
pub const MAX_LINE: usize = 1000;

/// Set when stdout is a closed pipe: nothing more is printed there, and the
/// program goes on (the image is still written) and ends with status 0.
pub static STDOUT_GONE: AtomicBool = AtomicBool::new(false);

/// Writes `text` to stdout, each line escaped ([`printable`]), with a
/// final newline when `newline`. A closed pipe (EPIPE) ends printing
/// quietly rather than panicking as `println!` would.
pub fn out_text(text: &str, newline: bool) {
    if STDOUT_GONE.load(Ordering::Relaxed) {
        return;
    }
    let mut o = std::io::stdout().lock();
    let body = text.strip_suffix('\n').unwrap_or(text);
    let ends_line = newline || body.len() < text.len();
    let mut lines = body.split('\n').peekable();
    let mut result = Ok(());
    while let Some(line) = lines.next() {
        let last = lines.peek().is_none();
        let line = printable(line, MAX_LINE);
        result = if !last || ends_line {
            writeln!(o, "{line}")
        } else {
            write!(o, "{line}").and_then(|()| o.flush())
        };
        if result.is_err() {
            break;
        }
    }
    if result.is_err() {
        // EPIPE or another failure of stdout: stop printing there.
        STDOUT_GONE.store(true, Ordering::Relaxed);
    }
}

/// Prints a line (or lines) on stdout; see [`out_text`].
pub fn out(text: &str) {
    out_text(text, true);
}

/// Prints `text` on stderr, each line escaped and cut to [`MAX_LINE`]; a
/// closed stderr is ignored.
pub fn err(text: &str) {
    let mut e = std::io::stderr().lock();
    for line in text.strip_suffix('\n').unwrap_or(text).split('\n') {
        if writeln!(e, "{}", printable(line, MAX_LINE)).is_err() {
            return;
        }
    }
}

/// Reports an error on stderr.
pub fn report(e: &Error) {
    err(&format!("error: {e}"));
}

/// Writes a whole text (help, version, completions, the man page) to
/// stdout. A closed pipe (`plytrace --help | head`) is not an error; any
/// other failure (a full disk) is reported, and the status is 1.
pub fn print_document(text: &[u8]) -> std::process::ExitCode {
    let mut o = std::io::stdout().lock();
    match o.write_all(text).and_then(|()| o.flush()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::ExitCode::SUCCESS,
        Err(e) => {
            err(&format!("error: cannot write to standard output: {e}"));
            std::process::ExitCode::FAILURE
        }
    }
}

/// Writes `data`, output a script goes on with (the image of `-o -`, the
/// list of `merge --missing`), to stdout. Any failure, a closed pipe
/// included, means it did not arrive whole: reported, and the status is 1.
pub fn print_data(data: &[u8], what: &str) -> std::process::ExitCode {
    let mut o = std::io::stdout().lock();
    match o.write_all(data).and_then(|()| o.flush()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            err(&format!(
                "error: cannot write {what} to standard output: {e}"
            ));
            std::process::ExitCode::FAILURE
        }
    }
}

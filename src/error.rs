//! Diagnostics: every error about an input names its file, line and column
//! and says what was expected (developers' guide, "Bad input").
//!
//! The library returns [`Error`]; only the binary turns it into an exit status.

use std::fmt;
use std::path::{Path, PathBuf};

/// A place in an input file. Lines and columns count from 1; a column of 0
/// means "the whole line" (used for binary files, where `line` is 0 and the
/// byte offset is given in the message instead).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file as the user named it (or `<stdin>`, `<command line>`).
    pub file: PathBuf,
    /// 1-based line, 0 when not meaningful.
    pub line: usize,
    /// 1-based column, 0 when not meaningful.
    pub column: usize,
}

impl Location {
    /// A location at `line`, `column` of `file`.
    pub fn new(file: impl Into<PathBuf>, line: usize, column: usize) -> Self {
        Location {
            file: file.into(),
            line,
            column,
        }
    }

    /// A location naming a file only.
    pub fn file(file: impl Into<PathBuf>) -> Self {
        Location::new(file, 0, 0)
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}",
            printable(&self.file.display().to_string(), MAX_SHOWN_PATH)
        )?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
            if self.column > 0 {
                write!(f, ":{}", self.column)?;
            }
        }
        Ok(())
    }
}

/// An error tied to a place in an input, with the offending source line when
/// it is known so that it can be shown with a caret under the column.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Where the problem is.
    pub location: Location,
    /// What is wrong and what was expected.
    pub message: String,
    /// The text of the offending line, if the input is text.
    pub source_line: Option<String>,
    /// Length of the underline under the column (at least 1).
    pub width: usize,
    /// Where the file that failed was included from (`get`/`call`/`defobj`).
    pub included_from: Vec<Location>,
}

impl Diagnostic {
    /// A diagnostic without source text.
    pub fn new(location: Location, message: impl Into<String>) -> Self {
        Diagnostic {
            location,
            message: message.into(),
            source_line: None,
            width: 1,
            included_from: Vec::new(),
        }
    }

    /// Attach the source line and the width of the offending token.
    pub fn with_source(mut self, line: impl Into<String>, width: usize) -> Self {
        self.source_line = Some(line.into());
        self.width = width.max(1);
        self
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The message may quote input: no control character reaches the
        // terminal (line breaks the program put there are kept).
        write!(
            f,
            "{}: {}",
            self.location,
            escape_controls(&self.message, true)
        )?;
        if let (Some(src), true) = (&self.source_line, self.location.column > 0) {
            let num = self.location.line.to_string();
            let pad = " ".repeat(num.len());
            let src = src.trim_end_matches(['\r', '\n']);
            let (shown, lead, width) = source_window(src, self.location.column, self.width);
            write!(
                f,
                "\n{pad} |\n{num} | {shown}\n{pad} | {lead}{}",
                "^".repeat(width)
            )?;
        }
        let n = self.included_from.len();
        for (i, inc) in self.included_from.iter().enumerate() {
            if n > 2 * CHAIN_ENDS + 1 && i >= CHAIN_ENDS && i < n - CHAIN_ENDS {
                if i == CHAIN_ENDS {
                    write!(
                        f,
                        "\n  ... {} more `call`/`get` levels ...",
                        n - 2 * CHAIN_ENDS
                    )?;
                }
                continue;
            }
            write!(f, "\n  included from {inc}")?;
        }
        Ok(())
    }
}

/// Longest file name shown in a message, in characters.
pub const MAX_SHOWN_PATH: usize = 200;

/// Longest token or line quoted in a message, in characters.
pub const MAX_SHOWN_TOKEN: usize = 80;

/// How many entries are shown at each end of a long include chain.
pub const CHAIN_ENDS: usize = 3;

/// `s` made safe and short for a message: control characters (below 0x20
/// except tab, DEL and the C1 controls) are escaped as `\x1b`, `\x00`,
/// `\u{9b}`, and a text of more than `max` characters is cut to its first
/// `max`, followed by `...` and its length.
pub fn printable(s: &str, max: usize) -> String {
    let count = s.chars().count();
    if count <= max {
        return escape_controls(s, false);
    }
    let head: String = s.chars().take(max).collect();
    format!("{}... ({count} characters)", escape_controls(&head, false))
}

/// Whether `c` is shown escaped.
fn is_escaped(c: char) -> bool {
    (c.is_control() && c != '\t') || c == '\u{7f}'
}

fn escape_char(c: char, out: &mut String) {
    use std::fmt::Write;
    if (c as u32) < 0x100 {
        let _ = write!(out, "\\x{:02x}", c as u32);
    } else {
        let _ = write!(out, "\\u{{{:x}}}", c as u32);
    }
}

/// `s` with its control characters escaped; line breaks kept when
/// `keep_newlines`.
pub fn escape_controls(s: &str, keep_newlines: bool) -> String {
    if !s.chars().any(is_escaped) {
        return s.to_string();
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c == '\n' && keep_newlines {
            out.push(c);
        } else if is_escaped(c) {
            escape_char(c, &mut out);
        } else {
            out.push(c);
        }
    }
    out
}

/// A chain of names (files of nested `call`s), shortened in the middle
/// when long: the first three, `... N more ...`, the last three.
pub fn chain(names: &[String]) -> String {
    let n = names.len();
    if n <= 2 * CHAIN_ENDS + 1 {
        return names.join(" -> ");
    }
    let mut parts: Vec<String> = names[..CHAIN_ENDS].to_vec();
    parts.push(format!("... {} more ...", n - 2 * CHAIN_ENDS));
    parts.extend_from_slice(&names[n - CHAIN_ENDS..]);
    parts.join(" -> ")
}

/// The part of source line `src` shown under a diagnostic: at most
/// [`MAX_SHOWN_TOKEN`] characters around `column`, control characters
/// escaped; with the white-space lead that puts the caret under the column
/// and the caret's width.
fn source_window(src: &str, column: usize, width: usize) -> (String, String, usize) {
    let chars: Vec<char> = src.chars().collect();
    let col = column.saturating_sub(1).min(chars.len());
    let start = col.saturating_sub(MAX_SHOWN_TOKEN / 2);
    let end = (start + MAX_SHOWN_TOKEN).min(chars.len());
    let last = col + width.max(1);
    let mut shown = String::new();
    let mut lead = String::new();
    if start > 0 {
        shown.push_str("...");
        lead.push_str("   ");
    }
    // Shown characters under the token (escapes are wider than one).
    let mut caret = 0;
    for (i, &c) in chars[start..end].iter().enumerate() {
        let before = shown.len();
        if is_escaped(c) {
            escape_char(c, &mut shown);
        } else {
            shown.push(c);
        }
        let added = shown[before..].chars().count();
        let at = start + i;
        if at < col {
            // Tabs are kept so that the caret lines up under the column.
            for _ in 0..added {
                lead.push(if c == '\t' { '\t' } else { ' ' });
            }
        } else if at < last {
            caret += added;
        }
    }
    if end < chars.len() {
        shown.push_str(&format!("... ({} characters)", chars.len()));
    }
    (shown, lead, caret.max(1))
}

/// Everything that can go wrong in the library, by kind: bad input at a
/// place ([`Error::Input`]), a file the system refused ([`Error::Io`]), a
/// request that cannot be honoured ([`Error::Invalid`]), a budget that
/// refused the work before it allocated ([`Error::Budget`], naming the flag
/// that raises it), something this program does not do
/// ([`Error::Unsupported`]), a broken invariant ([`Error::Internal`]) and a
/// stop request ([`Error::Cancelled`]). New kinds may be added: match with
/// a `_` arm.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Malformed input at a known place.
    #[error("{0}")]
    Input(Box<Diagnostic>),
    /// An operating system error on a named file.
    #[error("{}: {source}", printable(&path.display().to_string(), MAX_SHOWN_PATH))]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// A request that cannot be honoured (e.g. an image too large to allocate).
    #[error("{}", escape_controls(.0, true))]
    Invalid(String),
    /// A budget refused the work before it allocated; the message says
    /// what, the limit, and how to raise it.
    #[error("{}", escape_controls(.message, true))]
    Budget {
        /// The command-line flag that raises the limit (`--max-pixels`).
        flag: &'static str,
        /// What was refused, the limit, and the flag.
        message: String,
    },
    /// Something this program does not do (a format variant, an option
    /// not available with another).
    #[error("{}", escape_controls(.0, true))]
    Unsupported(String),
    /// A broken invariant of the library: a bug, never the input's fault.
    #[error("{}", escape_controls(.0, true))]
    Internal(String),
    /// The user stopped the render (Ctrl-C); see [`crate::cancel`].
    #[error("cancelled (Ctrl-C); nothing of this run was written")]
    Cancelled,
}

impl Error {
    /// An input error at `location`.
    pub fn at(location: Location, message: impl Into<String>) -> Self {
        Error::Input(Box::new(Diagnostic::new(location, message)))
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// A budget's refusal of `what` past `limit`, raised by `flag`
    /// (the message of [`exceeded`]).
    pub fn budget(what: &str, limit: impl fmt::Display, flag: &'static str) -> Self {
        Error::Budget {
            flag,
            message: exceeded(what, limit, flag),
        }
    }

    /// The flag that raises the budget that refused the work, if a budget
    /// did.
    pub fn budget_flag(&self) -> Option<&'static str> {
        match self {
            Error::Budget { flag, .. } => Some(flag),
            _ => None,
        }
    }

    /// The diagnostic, if this is an input error.
    pub fn diagnostic(&self) -> Option<&Diagnostic> {
        match self {
            Error::Input(d) => Some(d),
            _ => None,
        }
    }
}

impl From<Diagnostic> for Error {
    fn from(d: Diagnostic) -> Self {
        Error::Input(Box::new(d))
    }
}

/// The message for a budget exceeded: what, the limit, and the flag.
pub fn exceeded(what: &str, limit: impl fmt::Display, flag: &str) -> String {
    format!("{what} exceeds the budget of {limit}; `{flag} N` raises it")
}

/// Result with the library's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagnostic_shows_caret_under_column() {
        let d = Diagnostic::new(Location::new("a.des", 3, 5), "unknown command `foo`")
            .with_source("    foo 1 2", 3);
        let text = d.to_string();
        assert!(
            text.starts_with("a.des:3:5: unknown command `foo`"),
            "{text}"
        );
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[2], "3 |     foo 1 2");
        assert_eq!(lines[3], "  |     ^^^");
    }

    #[test]
    fn printable_escapes_and_truncates() {
        assert_eq!(
            printable("a\x1b[2Jb\0\x7f\tc", 80),
            "a\\x1b[2Jb\\x00\\x7f\tc"
        );
        let long = "x".repeat(1000);
        let p = printable(&long, 80);
        assert!(p.starts_with(&"x".repeat(80)), "{p}");
        assert!(p.ends_with("... (1000 characters)"), "{p}");
        assert_eq!(printable("x\ny\u{9b}", 100), "x\\x0ay\\x9b");
        assert_eq!(printable("abcdef", 3), "abc... (6 characters)");
        assert_eq!(printable("abc", 3), "abc");
    }

    #[test]
    fn long_lines_are_windowed_and_escaped() {
        let line = format!("{}\x1b{}", "a".repeat(5000), "b".repeat(5000));
        let d = Diagnostic::new(Location::new("a.des", 1, 5001), "bad").with_source(line, 5000);
        let text = d.to_string();
        assert!(text.len() < 400, "{}", text.len());
        assert!(!text.contains('\x1b'));
        let lines: Vec<&str> = text.lines().collect();
        let at = lines[2].find("\\x1b").unwrap();
        let caret = lines[3].find('^').unwrap();
        assert_eq!(at, caret, "{text}");
    }

    #[test]
    fn the_caret_covers_an_escaped_token() {
        let d = Diagnostic::new(Location::new("a.des", 1, 1), "bad").with_source("f\x1bo 1", 3);
        let text = d.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[2], "1 | f\\x1bo 1");
        assert_eq!(lines[3], "  | ^^^^^^", "{text}");
    }

    #[test]
    fn a_budget_error_names_its_flag_and_reads_as_before() {
        let e = Error::budget("the image of 9 x 9 pixels", 10, "--max-pixels");
        assert_eq!(e.budget_flag(), Some("--max-pixels"));
        assert_eq!(
            e.to_string(),
            "the image of 9 x 9 pixels exceeds the budget of 10; `--max-pixels N` raises it"
        );
        assert_eq!(Error::Invalid("x".into()).budget_flag(), None);
    }

    #[test]
    fn chains_are_shortened_in_the_middle() {
        let names: Vec<String> = (0..100).map(|i| format!("f{i}")).collect();
        assert_eq!(
            chain(&names),
            "f0 -> f1 -> f2 -> ... 94 more ... -> f97 -> f98 -> f99"
        );
    }
}

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
        write!(f, "{}", self.file.display())?;
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
        write!(f, "{}: {}", self.location, self.message)?;
        if let (Some(src), true) = (&self.source_line, self.location.column > 0) {
            let num = self.location.line.to_string();
            let pad = " ".repeat(num.len());
            let src = src.trim_end_matches(['\r', '\n']);
            // Tabs are kept so that the caret lines up under the column.
            let lead: String = src
                .chars()
                .take(self.location.column - 1)
                .map(|c| if c == '\t' { '\t' } else { ' ' })
                .collect();
            write!(
                f,
                "\n{pad} |\n{num} | {src}\n{pad} | {lead}{}",
                "^".repeat(self.width)
            )?;
        }
        for inc in &self.included_from {
            write!(f, "\n  included from {inc}")?;
        }
        Ok(())
    }
}

/// Everything that can go wrong in the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Malformed input at a known place.
    #[error("{0}")]
    Input(Box<Diagnostic>),
    /// An operating system error on a named file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// A request that cannot be honoured (e.g. an image too large to allocate).
    #[error("{0}")]
    Invalid(String),
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

/// `s` made safe to print: control characters (below 0x20 except tab, DEL
/// and the C1 controls 0x80 to 0x9f) are escaped as `\x1b` or `\u{9b}`, so
/// that input cannot move the cursor or recolour the terminal; and at most
/// `max` characters of `s` are kept, the rest replaced by
/// `... (N bytes)`, N the length of the whole of `s`.
pub fn printable(s: &str, max: usize) -> String {
    let mut out = String::with_capacity(s.len().min(max.saturating_mul(4)) + 16);
    let mut chars = s.chars();
    for c in chars.by_ref().take(max) {
        match c {
            '\t' => out.push(c),
            c if (c as u32) < 0x20 || c == '\x7f' => {
                out.push_str(&format!("\\x{:02x}", c as u32));
            }
            c if (0x80..=0x9f).contains(&(c as u32)) => {
                out.push_str(&format!("\\u{{{:x}}}", c as u32));
            }
            c => out.push(c),
        }
    }
    if chars.next().is_some() {
        out.push_str(&format!("... ({} bytes)", s.len()));
    }
    out
}

/// Result with the library's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printable_escapes_and_truncates() {
        assert_eq!(
            printable("a\x1b[31mb\tc\0\x7f", 100),
            "a\\x1b[31mb\tc\\x00\\x7f"
        );
        assert_eq!(printable("x\ny\u{9b}", 100), "x\\x0ay\\u{9b}");
        assert_eq!(printable("abcdef", 3), "abc... (6 bytes)");
        assert_eq!(printable("abc", 3), "abc");
    }

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
}

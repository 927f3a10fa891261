//! The interactive prompt of the `plytrace` program (part of the binary,
//! not the library): Tab completion of command names (from the command
//! table that `help` and `--help` print) and of file names, and a history
//! kept between sessions in the user's data directory.

use std::path::PathBuf;

use plytrace::scene::commands::COMMANDS;
use rustyline::completion::{Completer, FilenameCompleter, Pair};
use rustyline::highlight::Highlighter;
use rustyline::hint::Hinter;
use rustyline::validate::Validator;
use rustyline::{Context, Helper};

/// The most lines the history file keeps.
pub const HISTORY_LINES: usize = 1000;

/// Completes the first word of a line as a command name and later words
/// as file names (the words after `help` as command names).
pub struct CommandCompleter {
    files: FilenameCompleter,
}

impl CommandCompleter {
    /// A completer over the command table and the file system.
    pub fn new() -> Self {
        CommandCompleter {
            files: FilenameCompleter::new(),
        }
    }
}

/// The command names (and `help`) that start with `prefix`, ignoring case,
/// in the table's order.
pub fn command_candidates(prefix: &str) -> Vec<&'static str> {
    let prefix = prefix.to_ascii_lowercase();
    COMMANDS
        .iter()
        .map(|c| c.name)
        .chain(["help"])
        .filter(|name| name.starts_with(&prefix))
        .collect()
}

/// Where completion of `line` at byte `pos` looks: `Some(start)` of the
/// word to complete as a command name, or `None` for a file name.
fn command_word(line: &str, pos: usize) -> Option<usize> {
    let before = &line[..pos];
    let start = before
        .rfind(|c: char| c.is_whitespace())
        .map_or(0, |i| i + 1);
    let earlier: Vec<&str> = before[..start].split_whitespace().collect();
    match earlier.as_slice() {
        [] => Some(start),
        [first] if first.eq_ignore_ascii_case("help") => Some(start),
        _ => None,
    }
}

impl Completer for CommandCompleter {
    type Candidate = Pair;

    fn complete(
        &self,
        line: &str,
        pos: usize,
        _ctx: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Pair>)> {
        match command_word(line, pos) {
            Some(start) => {
                let pairs = command_candidates(&line[start..pos])
                    .into_iter()
                    .map(|name| Pair {
                        display: name.to_string(),
                        replacement: format!("{name} "),
                    })
                    .collect();
                Ok((start, pairs))
            }
            None => self.files.complete_path(line, pos),
        }
    }
}

impl Hinter for CommandCompleter {
    type Hint = String;
}
impl Highlighter for CommandCompleter {}
impl Validator for CommandCompleter {}
impl Helper for CommandCompleter {}

/// The history file: `$PLYTRACE_HISTORY` if set, else `plytrace/history`
/// in the user's data directory (`$XDG_DATA_HOME`, else
/// `~/.local/share`; `%APPDATA%` on Windows). `None` when there is no
/// home to keep it in.
pub fn history_path() -> Option<PathBuf> {
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty());
    if let Some(p) = var("PLYTRACE_HISTORY") {
        return Some(PathBuf::from(p));
    }
    let data = var("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| var("HOME").map(|h| PathBuf::from(h).join(".local/share")))
        .or_else(|| var("APPDATA").map(PathBuf::from))?;
    Some(data.join("plytrace").join("history"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_word_completes_to_commands_in_table_order() {
        assert_eq!(command_candidates("po"), ["polarview", "popmatrix"]);
        assert_eq!(command_candidates("ORTHO"), ["ortho", "ortho2"]);
        assert!(command_candidates("zz").is_empty());
    }

    #[test]
    fn help_takes_a_command_and_other_commands_take_files() {
        assert_eq!(command_word("pol", 3), Some(0));
        assert_eq!(command_word("  pol", 5), Some(2));
        assert_eq!(command_word("help ro", 7), Some(5));
        assert_eq!(command_word("get sce", 7), None);
        assert_eq!(command_word("help get x", 10), None);
    }

    #[test]
    fn file_names_complete_from_the_directory() {
        let dir = tempfile::tempdir().expect("temp dir");
        std::fs::write(dir.path().join("office2.des"), "").expect("write");
        let line = format!("get {}/off", dir.path().display());
        let c = CommandCompleter::new();
        let (start, found) = c.files.complete_path(&line, line.len()).expect("lists");
        assert_eq!(start, 4);
        assert_eq!(found.len(), 1);
        assert!(found[0].replacement.ends_with("office2.des"));
    }
}

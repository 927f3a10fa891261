//! The interactive prompt of the `plytrace` program (part of the binary,
//! not the library): Tab completion of command names (from the command
//! table that `help` and `--help` print) and of file names, and a history
//! kept between sessions in the user's data directory.

use std::path::{Path, PathBuf};

use plytrace::api::program::files::AtomicFile;
use plytrace::api::program::session::{COMMANDS, read_regular};
use rustyline::completion::{Completer, FilenameCompleter, Pair};
use rustyline::highlight::Highlighter;
use rustyline::hint::Hinter;
use rustyline::history::{FileHistory, History};
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

/// The largest history file read, in bytes (a thousand long lines).
const MAX_HISTORY_BYTES: u64 = 4 << 20;

/// The first line of rustyline's history files (lines escaped: `\\n` for
/// a line feed, `\\\\` for a backslash).
const HISTORY_V2: &str = "#V2";

/// Reads the history file into `history`. Only a regular file is read
/// (a FIFO or device would hang or never end), and a line that is not
/// UTF-8 is kept with its bad bytes replaced rather than ending the
/// reading, as rustyline's own loader does. A missing file is a first
/// session; any other problem is returned for a warning.
pub fn load_history(history: &mut impl History, path: &Path) -> Result<(), String> {
    if std::fs::symlink_metadata(path).is_err() {
        return Ok(());
    }
    let bytes = read_regular(path, MAX_HISTORY_BYTES).map_err(|e| e.to_string())?;
    let mut lines = bytes.split(|b| *b == b'\n').peekable();
    let v2 = lines.next_if(|l| *l == HISTORY_V2.as_bytes()).is_some();
    for line in lines.filter(|l| !l.is_empty()) {
        let line = String::from_utf8_lossy(line);
        let entry = if v2 {
            unescape(&line)
        } else {
            line.into_owned()
        };
        history.add_owned(entry).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn unescape(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match (c, chars.clone().next()) {
            ('\\', Some('n')) => {
                out.push('\n');
                chars.next();
            }
            ('\\', Some('\\')) => {
                out.push('\\');
                chars.next();
            }
            _ => out.push(c),
        }
    }
    out
}

/// Writes `history` to `path` in rustyline's format, atomically (a full
/// disk or a crash leaves the old file), and never through a link or into
/// a FIFO or device.
pub fn save_history(history: &FileHistory, path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    }
    let mut text = format!("{HISTORY_V2}\n");
    for entry in history.iter() {
        text.push_str(&entry.replace('\\', "\\\\").replace('\n', "\\n"));
        text.push('\n');
    }
    let mut file = AtomicFile::create(path).map_err(|e| e.to_string())?;
    file.write_all(text.as_bytes()).map_err(|e| e.to_string())?;
    let staged = file.finish().map_err(|e| e.to_string())?;
    staged.commit().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_that_is_not_utf8_loses_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("history");
        let mut bytes = b"#V2\n".to_vec();
        for i in 0..60 {
            if i % 6 == 3 {
                bytes.extend_from_slice(b"get caf\xe9.des\n"); // Latin-1
            } else {
                bytes.extend_from_slice(format!("translate {i} 0 0\n").as_bytes());
            }
        }
        std::fs::write(&path, &bytes).unwrap();
        let mut h = FileHistory::new();
        load_history(&mut h, &path).unwrap();
        assert_eq!(h.len(), 60);
        assert_eq!(h.iter().nth(3).unwrap(), "get caf\u{fffd}.des");
        assert_eq!(h.iter().last().unwrap(), "translate 59 0 0");
    }

    #[test]
    fn history_round_trips_and_refuses_special_files() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/history");
        let mut h = FileHistory::new();
        for line in ["ident", "a\\b", "two\nlines"] {
            h.add(line).unwrap();
        }
        save_history(&h, &path).unwrap();
        let mut back = FileHistory::new();
        load_history(&mut back, &path).unwrap();
        assert_eq!(
            back.iter().collect::<Vec<_>>(),
            h.iter().collect::<Vec<_>>()
        );
        #[cfg(unix)]
        {
            let fifo = dir.path().join("fifo");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status();
            if made.is_ok_and(|s| s.success()) {
                let e = load_history(&mut FileHistory::new(), &fifo).unwrap_err();
                assert!(e.contains("only regular files"), "{e}");
                assert!(save_history(&h, &fifo).is_err());
            } else {
                panic!("mkfifo is needed for this test");
            }
        }
    }

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

//! The help texts that are not made by clap: the long help's closing
//! sections and the command table of the scene language, which `--help`,
//! the man page and the prompt's `help [CMD]` all print from
//! [`COMMANDS`]. Every line fits 80 columns.

use plytrace::api::program::session::{COMMANDS, printable};

/// The widest line of any help text.
pub const WIDTH: usize = 80;

/// `text` wrapped to [`WIDTH`] columns, each line indented by `indent`
/// spaces.
pub fn wrap(text: &str, indent: usize) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && indent + line.len() + 1 + word.len() > WIDTH {
            out.push_str(&format!("{:indent$}{line}\n", ""));
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        out.push_str(&format!("{:indent$}{line}\n", ""));
    }
    out
}

/// One command of the table: its name and arguments, then what it does.
fn command_entry(name: &str, usage: &str, help: &str) -> String {
    let head = format!("{name} {usage}");
    let mut s = wrap(head.trim_end(), 4);
    s.push_str(&wrap(help, 8));
    s
}

/// The command table's entries, all of them or those of the commands
/// whose name starts with `topic` (the interpreter's prefix rule).
pub fn command_help(topic: Option<&str>) -> String {
    let topic = topic.map(str::to_ascii_lowercase);
    let entries: Vec<String> = COMMANDS
        .iter()
        .filter(|c| {
            topic
                .as_ref()
                .is_none_or(|t| c.name.starts_with(t.as_str()))
        })
        .map(|c| command_entry(c.name, c.usage, c.help))
        .collect();
    match (entries.is_empty(), topic) {
        (true, Some(t)) => format!(
            "no command `{}`; `help` lists them all\n",
            printable(&t, 40)
        ),
        _ => entries.concat(),
    }
}

/// `help` or `help CMD` typed at the prompt, answered; `None` for any
/// other line.
pub fn help_request(line: &str) -> Option<String> {
    let mut words = line.split_whitespace();
    let first = words.next()?;
    if !first.eq_ignore_ascii_case("help") {
        return None;
    }
    Some(command_help(words.next()))
}

/// The sections after the flags in `--help` and the man page.
pub fn after_help() -> String {
    let mut s = String::new();
    s.push_str("Outputs:\n");
    s.push_str(&wrap(
        "Every output of a `run` (the image, --id-image, FNAME.out and FNAME.txt) is \
         checked before the render (directory present; no link, FIFO or device) and \
         written under a temporary name; all are renamed into place together at the \
         end, so a failed or interrupted run leaves nothing. Statistics go to standard \
         output, or to standard error when the image does (-o -).",
        4,
    ));
    s.push_str("\nFiles:\n");
    for (name, what) in [
        (
            "FNAME.png",
            "the image (FNAME from `fname`, else the scene file's name)",
        ),
        (
            "FNAME.out, FNAME.txt",
            "the virtual image tree, with -o on (`setmode o on`); read by rftb1-rftb4",
        ),
        (
            "plytrace.log",
            "one line per run appended in the working directory: UTC date, scene, image, \
             size, polygons tiled, max depth, seconds",
        ),
    ] {
        s.push_str(&command_entry(name, "", what));
    }
    s.push_str("\nExit status:\n");
    s.push_str(&wrap(
        "0 done; 1 an error in the scene, a file or a budget; 2 a bad command line; \
         130, 143, 129 ended by SIGINT (Ctrl-C), SIGTERM, SIGHUP (nothing of the run is \
         left on disk).",
        4,
    ));
    s.push_str(
        "\nCommands of the scene descriptor language (case-insensitive, recognized by\n\
         their first unique characters):\n",
    );
    s.push_str(&command_help(None));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_lines_fit() {
        let text = after_help();
        for line in text.lines() {
            assert!(line.chars().count() <= WIDTH, "{line}");
        }
        assert!(text.contains("translate tx ty tz"), "{text}");
    }

    /// One table: every command the interpreter knows has help text,
    /// `--help` and the prompt's `help` list each of them, completion
    /// offers it, and the interpreter recognizes every name they list.
    #[test]
    fn every_command_has_help_in_every_place() {
        let all = after_help();
        let interp = plytrace::api::program::session::Interpreter::new();
        for c in COMMANDS {
            if let Err(e) = interp.check_source(c.name, std::path::Path::new("help")) {
                let e = e.to_string();
                assert!(
                    !e.contains("unknown command") && !e.contains("ambiguous"),
                    "{e}"
                );
            }
            assert!(!c.help.trim().is_empty(), "`{}` has no help", c.name);
            assert!(
                all.contains(&format!("    {} ", c.name))
                    || all.contains(&format!("    {}\n", c.name))
            );
            assert!(command_help(Some(c.name)).contains(c.help.split_whitespace().next().unwrap()));
            assert!(crate::repl::command_candidates(c.name).contains(&c.name));
        }
    }

    #[test]
    fn a_topic_selects_by_prefix() {
        assert!(command_help(Some("transl")).starts_with("    translate"));
        assert!(command_help(Some("zzz")).contains("no command `zzz`"));
    }
}

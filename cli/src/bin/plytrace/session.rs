//! A session of `plytrace`: the scene read in immediate mode, from a file
//! or standard input, and the interactive command interpreter (004
//! appendix B: "Plytrace is usually operated in interactive mode by
//! simply typing `plytrace <cr>`"), with line editing and history on a
//! terminal.

use std::io::{BufRead, IsTerminal, Read};
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use plytrace::api::program::control;
use plytrace::api::program::files::AtomicFile;
use plytrace::api::program::parts::note_input;
use plytrace::api::program::session::{Flow, Host, Interpreter, MAX_SCENE_BYTES, Scene};
use plytrace::{Error, Result};

use crate::help::help_request;
use crate::host::CliHost;
use crate::repl;
use crate::settings::{STDIN, SceneSource, Settings, StatsTarget};
use crate::stats::SceneCounts;
use crate::term::{err, report};

/// After an error in a scene that had already run: which files the earlier
/// runs wrote (complete; nothing of the failed part was written).
fn report_written(host: &CliHost) {
    if !host.written.is_empty() {
        let names: Vec<String> = host
            .written
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        err(&format!(
            "note: the runs before the error wrote {} (complete); nothing else was written",
            names.join(", ")
        ));
    }
}

/// Reports the error that ended a batch run. The status is what a shell
/// reports for the signal that cancelled it (130 for Ctrl-C, 143 for
/// SIGTERM, 129 for SIGHUP), 1 for any other error.
fn failed(e: &Error, host: &CliHost) -> ExitCode {
    report(e);
    report_written(host);
    match (e, control::ending()) {
        (Error::Cancelled, Some(code)) => ExitCode::from(code),
        (Error::Cancelled, None) => ExitCode::from(130),
        _ => ExitCode::FAILURE,
    }
}

fn print_warnings(interp: &mut Interpreter) {
    for w in interp.take_warnings() {
        err(&w.to_string());
    }
}

/// Reads a scene file (the manual's `get`), or standard input for `-`.
fn load_scene(interp: &mut Interpreter, host: &mut CliHost, source: &SceneSource) -> Result<Flow> {
    let start = Instant::now();
    let path = match source {
        SceneSource::File(p) => p.as_path(),
        _ => Path::new(STDIN),
    };
    host.scanning(path);
    let flow = match source {
        SceneSource::File(p) => interp.execute_file(p, true, host),
        _ => read_stdin().and_then(|text| interp.execute_input(&text, path, Path::new("."), host)),
    };
    print_warnings(interp);
    let flow = flow?;
    host.scanned(path, interp.current(), start.elapsed());
    Ok(flow)
}

/// The interactive session: statements from the prompt (with line
/// editing on a terminal) or from piped standard input.
pub fn interactive(interp: &mut Interpreter, host: &mut CliHost) -> ExitCode {
    let on_terminal = std::io::stdin().is_terminal();
    let mut lines = Lines::default();
    if on_terminal {
        host.say(&format!("plytrace - version {}", env!("CARGO_PKG_VERSION")));
        if let Err(code) = prompt(interp, host, &mut lines) {
            return code;
        }
    } else if let Err(code) = piped(interp, host, &mut lines) {
        return code;
    }
    if let Some(code) = control::ending() {
        ExitCode::from(code)
    } else if lines.failed && !on_terminal {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// The lines of an interactive session so far.
#[derive(Default)]
struct Lines {
    /// The last line's number.
    number: usize,
    /// A line failed.
    failed: bool,
}

impl Lines {
    /// Runs the next line; errors are reported and remembered, the
    /// session goes on.
    fn execute(&mut self, interp: &mut Interpreter, host: &mut CliHost, line: &str) -> Flow {
        self.number += 1;
        if let Some(text) = help_request(line) {
            host.say(text.trim_end());
            return Flow::Continue;
        }
        let stdin_label = Path::new(STDIN);
        let result = interp.execute_source(line, stdin_label, Path::new("."), host);
        print_warnings(interp);
        match result {
            Ok(f) => f,
            Err(Error::Input(mut d)) => {
                for loc in std::iter::once(&mut d.location).chain(d.included_from.iter_mut()) {
                    if loc.file == stdin_label {
                        loc.line = self.number;
                    }
                }
                report(&Error::Input(d));
                self.failed = true;
                Flow::Continue
            }
            Err(e) => {
                report(&e);
                self.failed = true;
                Flow::Continue
            }
        }
    }
}

/// The prompt `Command:` on a terminal, with line editing, completion and
/// the history; `Err` with the exit code when the terminal cannot edit.
fn prompt(interp: &mut Interpreter, host: &mut CliHost, lines: &mut Lines) -> Result<(), ExitCode> {
    let Ok(mut editor) = rustyline::Editor::<repl::CommandCompleter, _>::with_history(
        rustyline::Config::builder()
            .max_history_size(repl::HISTORY_LINES)
            .map_or_else(|_| rustyline::Config::default(), |b| b.build()),
        rustyline::history::FileHistory::new(),
    ) else {
        err("error: cannot open the terminal for line editing");
        return Err(ExitCode::FAILURE);
    };
    editor.set_helper(Some(repl::CommandCompleter::new()));
    let history = repl::history_path();
    if let Some(p) = &history
        && let Err(e) = repl::load_history(editor.history_mut(), p)
    {
        err(&format!(
            "warning: the command history in {} was not read: {e}",
            p.display()
        ));
    }
    let mut interrupted = false;
    loop {
        match editor.readline("Command: ") {
            Ok(line) => {
                interrupted = false;
                let _ = editor.add_history_entry(line.as_str());
                if lines.execute(interp, host, &line) == Flow::Quit || control::ending().is_some() {
                    break;
                }
            }
            // Ctrl-C at the prompt drops the line; twice in a row quits.
            Err(rustyline::error::ReadlineError::Interrupted) if !interrupted => {
                interrupted = true;
                err("(press Ctrl-C again, or type quit, to leave)");
            }
            Err(_) => break,
        }
    }
    if let Some(p) = &history
        && let Err(e) = repl::save_history(editor.history(), p)
    {
        err(&format!(
            "warning: the command history was not kept in {}: {e}",
            p.display()
        ));
    }
    Ok(())
}

/// Statements piped to standard input, a line at a time; `Err` with the
/// exit code on a line that cannot be read.
fn piped(interp: &mut Interpreter, host: &mut CliHost, lines: &mut Lines) -> Result<(), ExitCode> {
    let mut input = std::io::stdin().lock();
    loop {
        let line = match read_line(&mut input, lines.number + 1) {
            Ok(Some(line)) => line,
            Ok(None) => return Ok(()),
            Err(message) => {
                err(&format!("error: {message}"));
                return Err(ExitCode::FAILURE);
            }
        };
        if lines.execute(interp, host, &line) == Flow::Quit || control::ending().is_some() {
            return Ok(());
        }
    }
}

/// A scene from standard input (`plytrace -`), as much as a scene file may
/// hold.
fn read_stdin() -> Result<String> {
    let limit = MAX_SCENE_BYTES;
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(Path::new(STDIN), e))?;
    if bytes.len() as u64 > limit {
        return Err(Error::Invalid(format!(
            "<stdin>: the scene is longer than {limit} bytes, the most a scene file may hold"
        )));
    }
    note_input(&bytes);
    String::from_utf8(bytes).map_err(|e| {
        Error::Invalid(format!(
            "{STDIN}: not a text file: invalid UTF-8 at byte {} (a scene is text)",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// The session a command line asks for: the scene read, then rendered
/// (immediate mode), checked (`--check`) or followed by the prompt.
pub fn run(settings: &Settings, host: &mut CliHost) -> ExitCode {
    let mut interp = Interpreter::new();
    interp.set_budgets(settings.budgets);
    for (letter, value) in &settings.modes {
        if let Err(e) = interp.force_mode(*letter, value) {
            let msg = match e.diagnostic() {
                Some(d) => d.message.clone(),
                None => e.to_string(),
            };
            err(&format!("error: flag -{letter}: {msg}"));
            return ExitCode::from(2);
        }
    }
    let mut counts = SceneCounts::default();
    let mut code = scene_session(settings, &mut interp, host, &mut counts);
    if code == ExitCode::SUCCESS
        && let Some(frames) = settings.frames
    {
        code = check_frames(frames, host.frame);
    }
    if let Some(target) = settings.stats.as_ref().filter(|_| !host.stats_refused) {
        let scene = match &settings.scene {
            SceneSource::File(p) => Some(p.as_path()),
            SceneSource::Stdin => Some(Path::new(STDIN)),
            SceneSource::None => None,
        };
        let doc = crate::stats::document(scene, counts, &host.stats, code == ExitCode::SUCCESS);
        if let Err(e) = write_stats(target, &doc) {
            err(&format!("error: --stats {e}"));
            if code == ExitCode::SUCCESS {
                code = ExitCode::FAILURE;
            }
        }
    }
    // The process ends next, and the system takes its memory back whole:
    // freeing office2's scene block by block took 0.5-1.2 ms at the end
    // of every run. The interpreter owns no file or thread to close.
    std::mem::forget(interp);
    code
}

/// `--part I/N`: on a scene with several `run`s (an animation) the parts
/// are its frames, `I * F / N` to `(I + 1) * F / N - 1` of `F`, each
/// written whole under the name its run gives (as `--frames`); on a scene
/// with one run, the part is a band of its image, in the part file `-o`
/// names. The runs are counted by reading the scene once without
/// rendering. Returns false when this part has nothing to render; an
/// error is reported, with the exit code (2 for flags that do not fit the
/// scene).
fn plan_part(settings: &Settings, host: &mut CliHost) -> std::result::Result<bool, ExitCode> {
    let Some(spec) = host.part else {
        return Ok(true);
    };
    let frames = match &settings.scene {
        SceneSource::File(path) => count_runs(settings, path).map_err(|e| failed(&e, host))?,
        // Standard input is read once: a band of its one run.
        _ => 1,
    };
    let usage = |message: String| {
        err(&format!("error: {message}"));
        ExitCode::from(2)
    };
    if frames <= 1 {
        if host.output.is_none() {
            return Err(usage(format!(
                "--part {spec} writes a part file (PNG): name it with -o, such as \
                 -o parts/{}.png",
                spec.index
            )));
        }
        return Ok(true);
    }
    if host.output.is_some() || settings.frames.is_some() {
        return Err(usage(format!(
            "--part {spec}: this scene is an animation of {frames} frames, and its parts are \
             frames, each written under the name its `run` gives: leave out -o and --frames"
        )));
    }
    let (count, index) = (u64::from(spec.count), u64::from(spec.index));
    let first = (index * u64::from(frames) / count) as u32;
    let end = ((index + 1) * u64::from(frames) / count) as u32;
    host.part = None;
    if first >= end {
        host.say(&format!(
            "Part {spec} of {frames} frames has no frame to render"
        ));
        return Ok(false);
    }
    host.say(&format!(
        "Part {spec} of {frames} frames: frames {first} to {}",
        end - 1
    ));
    host.frames = Some((first, end - 1));
    Ok(true)
}

/// Counts the `run`s of the scene file `path`, reading it without
/// rendering.
fn count_runs(settings: &Settings, path: &Path) -> Result<u32> {
    struct Runs(u32);
    impl Host for Runs {
        fn run(&mut self, _scene: &Scene, _shadows: bool) -> Result<()> {
            self.0 = self.0.saturating_add(1);
            Ok(())
        }
    }
    let mut interp = Interpreter::new();
    interp.set_budgets(settings.budgets);
    for (letter, value) in &settings.modes {
        interp.force_mode(*letter, value)?;
    }
    let mut runs = Runs(0);
    interp.execute_file(path, true, &mut runs)?;
    interp.take_warnings();
    Ok(runs.0)
}

fn scene_session(
    settings: &Settings,
    interp: &mut Interpreter,
    host: &mut CliHost,
    counts: &mut SceneCounts,
) -> ExitCode {
    match plan_part(settings, host) {
        Ok(true) => {}
        Ok(false) => return ExitCode::SUCCESS,
        Err(code) => return code,
    }
    if settings.scene != SceneSource::None {
        match load_scene(interp, host, &settings.scene) {
            Ok(Flow::Quit) => return ExitCode::SUCCESS,
            Ok(Flow::Continue) => {}
            Err(e) => return failed(&e, host),
        }
        let scene = interp.current();
        *counts = SceneCounts {
            objects: scene.objects.len(),
            points: scene.point_count(),
            polygons: scene.polygon_count(),
        };
        // Immediate mode is `get` then `run y` (`run n` with --no-shadows);
        // a scene that says `run` itself (an animation) is rendered as it
        // says, each `run` once.
        if settings.immediate && host.runs > 0 {
            return ExitCode::SUCCESS;
        }
        if settings.immediate {
            return match host.run(interp.current(), settings.shadows) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => failed(&e, host),
            };
        }
    }
    interactive(interp, host)
}

/// Writes the `--stats` document: through a temporary file, never over
/// an input of the run ([`AtomicFile::create`]).
fn write_stats(target: &StatsTarget, doc: &str) -> Result<()> {
    match target {
        StatsTarget::Stderr => {
            // Whole, not cut to a line's length as messages are.
            let _ = std::io::Write::write_all(&mut std::io::stderr().lock(), doc.as_bytes());
            Ok(())
        }
        StatsTarget::File(p) => AtomicFile::create(p)
            .and_then(|mut f| f.write_all(doc.as_bytes()).map(|()| f))
            .and_then(|f| f.finish())
            .and_then(|staged| staged.commit()),
    }
}

/// `--frames A..B` once the session has met `frames` frames (`run`s): a
/// range that starts past the last frame rendered nothing, an error of
/// the command line (status 2); one that ends past it rendered the
/// frames there are, with a warning.
fn check_frames((first, last): (u32, u32), frames: u32) -> ExitCode {
    let asked = match (first, last) {
        (a, u32::MAX) => format!("{a}.."),
        (a, b) if a == b => a.to_string(),
        (a, b) => format!("{a}..{b}"),
    };
    let had = match frames {
        0 => "no frame (`run`)".to_string(),
        1 => "1 frame, frame 0".to_string(),
        n => format!("{n} frames, 0 to {}", n - 1),
    };
    if first >= frames {
        err(&format!(
            "error: --frames {asked}: the scene has {had}; nothing was rendered"
        ));
        return ExitCode::from(2);
    }
    if last != u32::MAX && last >= frames {
        err(&format!(
            "warning: --frames {asked}: the scene has {had}; frames {frames} to {last} do not \
             exist and only frames {first} to {} were rendered",
            frames - 1
        ));
    }
    ExitCode::SUCCESS
}

/// The longest command line read from standard input, in bytes.
const MAX_COMMAND_LINE: u64 = 1 << 20;

/// The next line of commands from standard input, at most
/// [`MAX_COMMAND_LINE`] bytes (an endless line is refused, not held in
/// memory); `None` at the end.
fn read_line(
    input: &mut impl BufRead,
    line_no: usize,
) -> std::result::Result<Option<String>, String> {
    let mut bytes = Vec::new();
    let n = input
        .take(MAX_COMMAND_LINE + 1)
        .read_until(b'\n', &mut bytes)
        .map_err(|e| format!("{STDIN}: {e}"))?;
    if n == 0 {
        return Ok(None);
    }
    if bytes.len() as u64 > MAX_COMMAND_LINE {
        return Err(format!(
            "{STDIN}:{line_no}: the line is longer than {MAX_COMMAND_LINE} bytes; \
             the rest of the input is not read"
        ));
    }
    while bytes.last().is_some_and(|b| *b == b'\n' || *b == b'\r') {
        bytes.pop();
    }
    String::from_utf8(bytes)
        .map(Some)
        .map_err(|_| format!("{STDIN}:{line_no}: the line is not UTF-8 text"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_line_is_refused_without_holding_it() {
        let mut endless = std::io::BufReader::new(std::io::repeat(b'x'));
        let e = read_line(&mut endless, 1).unwrap_err();
        assert!(e.contains("longer than"), "{e}");
        let mut two = std::io::Cursor::new(b"ident\r\nquit".to_vec());
        assert_eq!(read_line(&mut two, 1).unwrap().as_deref(), Some("ident"));
        assert_eq!(read_line(&mut two, 2).unwrap().as_deref(), Some("quit"));
        assert_eq!(read_line(&mut two, 3).unwrap(), None);
        let mut latin1 = std::io::Cursor::new(b"get caf\xe9\n".to_vec());
        assert!(
            read_line(&mut latin1, 1)
                .unwrap_err()
                .contains(":1: the line is not UTF-8")
        );
    }
}

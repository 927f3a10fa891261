//! Files and runs (Garcia 1986, 004 appendix B, the plytrace manual page):
//! `call` and `get` read another scene file (`get` initializing first),
//! `det_dir` names the detail directory of object files, `init` resets
//! everything, `run` renders, `clear`, `wait` and `disp` talk to the
//! display. A name that does not exist as written is tried folded to lower
//! case (the manual: "all input characters are converted to lower case
//! before processing").

use std::path::{Path, PathBuf};

use crate::budget::Budgets;
use crate::error::{Error, Location, MAX_SHOWN_PATH, MAX_SHOWN_TOKEN, Result, printable};
use crate::scene::arguments::Context;
use crate::scene::interpreter::{Caller, Frame, Host, Interpreter};
use crate::scene::lexer::Token;

impl Interpreter {
    /// `det_dir path`, relative to the file that gives it.
    pub(in crate::scene) fn set_det_dir(&mut self, ctx: &Context, dir: &str) {
        self.det_dir = PathBuf::from(dir);
        self.det_base = ctx.dir.clone();
    }

    /// `init`, refused inside an object definition.
    pub(in crate::scene) fn init_command(&mut self, ctx: &Context, cmd: &Token) -> Result<()> {
        if self.active.is_some() {
            return Err(ctx.error(cmd, "`init` inside an object definition"));
        }
        self.init();
        Ok(())
    }

    /// `run [y]`: the host renders the scene; an error in the render names
    /// this statement.
    pub(in crate::scene) fn run(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        shadows: bool,
        host: &mut dyn Host,
    ) -> Result<()> {
        if self.active.is_some() {
            return Err(ctx.error(cmd, "`run` inside an object definition"));
        }
        host.run(self.current(), shadows).map_err(|e| match e {
            Error::Input(mut d) => {
                d.included_from.push(ctx.location(cmd));
                Error::Input(d)
            }
            other => other,
        })
    }

    /// `disp [on|off]`.
    pub(in crate::scene) fn disp(&mut self, on: bool, host: &mut dyn Host) {
        self.scene.display = on;
        host.display(on);
    }

    /// `call`/`get` of `path` named by `token`: the cycle and depth checks,
    /// then the file opened and checked.
    pub(in crate::scene) fn enter_file(
        &mut self,
        ctx: &Context,
        token: &Token,
        path: &Path,
        caller: Caller,
        host: &mut dyn Host,
    ) -> Result<Frame> {
        let shown = printable(&token.text, MAX_SHOWN_TOKEN);
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        if self.files.iter().any(|f| f.canonical == canonical) {
            return Err(ctx.error(
                token,
                format!("`{shown}` is already being read: a `get`/`call` cycle"),
            ));
        }
        let nested = self.files.iter().filter(|f| f.called).count() + 1;
        let limit = self.budgets.call_depth;
        if nested > limit {
            let names: Vec<String> = self
                .files
                .iter()
                .map(|f| &f.named)
                .chain(std::iter::once(&path.to_path_buf()))
                .map(|p| printable(&p.display().to_string(), MAX_SHOWN_PATH))
                .collect();
            return Err(ctx.error(
                token,
                Budgets::exceeded(
                    &format!(
                        "`call` nesting {nested} deep ({})",
                        crate::error::chain(&names)
                    ),
                    limit,
                    "--max-call-depth",
                ),
            ));
        }
        let get = caller.get;
        if get {
            host.scanning(path);
        }
        let location = caller.location.clone();
        self.open_file(path, get, Some(caller))
            .map_err(|e| included_from(e, location, token, ctx))
    }
}

/// `path` if it exists, else `folded()` (the name as written folded to
/// lower case) if that exists, else `path` (whose error then names the
/// file as written).
pub(in crate::scene) fn lower_case_fallback(
    path: PathBuf,
    folded: impl FnOnce() -> PathBuf,
) -> PathBuf {
    if path.exists() {
        return path;
    }
    let lower = folded();
    if lower != path && lower.exists() {
        lower
    } else {
        path
    }
}

/// The extensions of the files `fname` names.
const FNAME_OUTPUTS: [&str; 3] = ["png", "out", "txt"];

/// The stem `fname name` gives the outputs: folded to lower case, as
/// every name read is (004 appendix B: "all input characters are
/// converted to lower case"), unless an output of the name as written
/// already exists (as a name read is taken as written when it exists).
pub(in crate::scene) fn output_stem(name: &str) -> String {
    let lower = name.to_lowercase();
    let exists = |stem: &str| {
        FNAME_OUTPUTS
            .iter()
            .any(|e| Path::new(&format!("{stem}.{e}")).exists())
    };
    if lower != name && exists(name) {
        name.to_string()
    } else {
        lower
    }
}

/// `name` relative to `dir` (the including file's folder) if it exists
/// there or not in the working directory.
pub(in crate::scene) fn resolve(dir: &Path, name: &str) -> PathBuf {
    let p = PathBuf::from(name);
    if p.is_absolute() {
        return p;
    }
    if dir == Path::new(".") {
        return p;
    }
    let beside = dir.join(&p);
    if beside.exists() || !p.exists() {
        beside
    } else {
        p
    }
}

/// An error in an included file, with the statement that included it; a
/// file that cannot be opened is an error at that statement.
fn included_from(e: Error, loc: Location, token: &Token, ctx: &Context) -> Error {
    match e {
        Error::Input(mut d) => {
            d.included_from.push(loc);
            Error::Input(d)
        }
        Error::Io { path, source } => ctx.error(
            token,
            format!(
                "cannot open `{}`: {source}",
                printable(&path.display().to_string(), MAX_SHOWN_PATH)
            ),
        ),
        other => other,
    }
}

//! The command interpreter of the scene descriptor language (Garcia 1986,
//! 004 section 4.3 and the plytrace manual page of the appendix).
//!
//! It keeps the current transformation matrix (CTM) and its 16-deep stack
//! with IRIS GL semantics (see [`crate::math`]), the global and active-object
//! attributes, and builds the [`Scene`]. Commands that render or talk to a
//! display (`run`, `clear`, `wait`) are passed to a [`Host`].
//!
//! Preconditions: none; every input is validated here, and every error names
//! the file, line and column and what was expected.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use super::build::warning_kind;
pub use super::build::{ObjectParts, build_object};
use super::commands::{self, CommandSpec, Lookup};
use super::lexer::{self, Statement, Token};
use super::mesh_import;
use super::model::*;
use super::object_file::{self, ColorEntry, ColorKind, Mesh};
use crate::budget::Budgets;
use crate::error::{
    Diagnostic, Error, Location, MAX_SHOWN_PATH, MAX_SHOWN_TOKEN, Result, printable,
};
use crate::math::{self, Axis, Matrix4};
use crate::modeling::geodesic::{self, Division, Radial, TurnedRadial};

#[path = "generators.rs"]
mod generators;

/// Depth of the matrix stack (004 section 4.3: "a 16-level deep
/// transformation matrix stack"). `defobj` uses one level.
pub const MATRIX_STACK_DEPTH: usize = 16;

/// Largest image side accepted, and largest pixel count: a guard against
/// hostile sizes, not a format limit.
pub const MAX_IMAGE_SIDE: i64 = 1 << 16;
/// Largest number of pixels in an image.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;

/// What the interpreter asks of its surroundings.
pub trait Host {
    /// `run [y]`: render `scene`.
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()>;
    /// `clear`: show the background over the whole viewport.
    fn clear(&mut self, _scene: &Scene) -> Result<()> {
        Ok(())
    }
    /// `wait`.
    fn wait(&mut self) {}
    /// `disp on|off`: the live display is asked for or dismissed.
    fn display(&mut self, _on: bool) {}
    /// A `get` is about to read `file`.
    fn scanning(&mut self, _file: &Path) {}
    /// A `get` of `file` finished; `scene` is the result.
    fn scanned(&mut self, _file: &Path, _scene: &Scene, _elapsed: std::time::Duration) {}
}

/// A host that ignores `run`, `clear` and `wait` (for building scenes).
#[derive(Debug, Default)]
pub struct NoHost;

impl Host for NoHost {
    fn run(&mut self, _scene: &Scene, _shadows: bool) -> Result<()> {
        Ok(())
    }
}

/// Whether to go on after a statement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Read on.
    Continue,
    /// `quit` was given.
    Quit,
}

/// An object between `defobj` and `endobj`.
#[derive(Debug, Clone)]
struct ActiveObject {
    /// The name, case-folded (004 appendix: input is converted to lower
    /// case).
    name: String,
    /// The name as written, tried first for the geometry file.
    written: String,
    number: Option<u32>,
    surface: Surface,
    surface_type: SurfaceType,
    copy_of: Option<(u32, Location)>,
    geodesic: Option<(usize, Division, Location)>,
    radial: Option<(Radial, Location)>,
    /// `radial rotate`: the turn of the radial function (003 section 2).
    turn: Option<(glam::DMat3, Location)>,
    /// A Firebaugh generator (`sphere`, ..., `union`) and where it is.
    generator: Option<(generators::Pending, Location)>,
    /// The first surface command of the block (an error in a CSG block).
    surface_cmd: Option<Location>,
    pcolors: Option<(String, Location)>,
    vcolors: Option<(String, Location)>,
    stack_depth: usize,
    location: Location,
    det_base: PathBuf,
}

/// A file being read (or a text given to [`Interpreter::execute_source`]).
struct Frame {
    file: PathBuf,
    dir: PathBuf,
    source: String,
    statements: Vec<Statement>,
    next: usize,
    /// Whether it is recorded in `Interpreter::files`.
    opened: bool,
    /// The `call`/`get` that named it.
    caller: Option<Caller>,
}

impl Frame {
    fn context(&self) -> Context<'_> {
        Context {
            file: &self.file,
            dir: self.dir.clone(),
            source: &self.source,
        }
    }
}

/// The `call` or `get` statement that opened a frame.
struct Caller {
    location: Location,
    get: bool,
    start: std::time::Instant,
}

/// A file being read, for cycle detection and the call depth.
#[derive(Debug, Clone)]
struct OpenFile {
    canonical: PathBuf,
    named: PathBuf,
    /// Opened by `call`/`get` (not the outermost file).
    called: bool,
}

/// The largest scene file read: a scene is held whole, with its tokens,
/// while it runs, so the limit is smaller than for object files.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// What to do after a statement.
enum Step {
    Continue,
    Quit,
    /// Read `path` next (`call`, or `get` with `init`).
    Enter {
        path: PathBuf,
        get: bool,
        token: Token,
    },
}

/// Where a statement came from, for diagnostics and relative paths.
struct Context<'a> {
    file: &'a Path,
    dir: PathBuf,
    source: &'a str,
}

impl Context<'_> {
    fn error(&self, token: &Token, message: impl Into<String>) -> Error {
        let line = self.source.lines().nth(token.line - 1).unwrap_or("");
        Diagnostic::new(Location::new(self.file, token.line, token.column), message)
            .with_source(line, token.text.chars().count())
            .into()
    }

    fn location(&self, token: &Token) -> Location {
        Location::new(self.file, token.line, token.column)
    }
}

/// The interpreter's state.
#[derive(Debug, Clone)]
pub struct Interpreter {
    scene: Scene,
    ctm: Matrix4,
    stack: Vec<Matrix4>,
    globals: Surface,
    global_type: SurfaceType,
    active: Option<ActiveObject>,
    det_dir: PathBuf,
    det_base: PathBuf,
    files: Vec<OpenFile>,
    /// Polygons of the scene's objects (for [`Budgets::polygons`]).
    polygons: usize,
    overrides: Vec<(char, String)>,
    warnings: Warnings,
    /// Information that is not a warning (what a CSG operation did).
    notes: Vec<Diagnostic>,
    budgets: Budgets,
    /// Geodesic objects by number: the mesh generated and its turned
    /// radial function, for `radial rotate` outside a definition.
    geodesics: std::collections::HashMap<u32, (Arc<Mesh>, TurnedRadial)>,
}

impl Default for Interpreter {
    fn default() -> Self {
        Self::new()
    }
}

fn default_det_dir() -> PathBuf {
    PathBuf::from("det")
}

impl Interpreter {
    /// A fresh interpreter, as after `init`.
    pub fn new() -> Self {
        let scene = Scene::default();
        Interpreter {
            ctm: scene.projection,
            scene,
            stack: Vec::new(),
            globals: Surface::default(),
            global_type: SurfaceType::default(),
            active: None,
            det_dir: default_det_dir(),
            det_base: PathBuf::from("."),
            files: Vec::new(),
            polygons: 0,
            overrides: Vec::new(),
            warnings: Warnings::default(),
            notes: Vec::new(),
            budgets: Budgets::default(),
            geodesics: std::collections::HashMap::new(),
        }
    }

    /// Sets the limits (`--max-polygons`, `--max-call-depth`, ...) checked
    /// while reading scenes; [`Budgets::default`] until this is called.
    /// They survive `init` and `get`.
    pub fn set_budgets(&mut self, budgets: Budgets) {
        self.budgets = budgets;
    }

    /// The limits in force.
    pub fn budgets(&self) -> Budgets {
        self.budgets
    }

    /// The scene as it stands, with the current CTM as its projection.
    pub fn scene(&self) -> Scene {
        let mut s = self.scene.clone();
        s.projection = self.ctm;
        s
    }

    /// The scene as it stands, like [`Self::scene`] but borrowed: a render
    /// or a summary needs no copy of every object.
    pub fn current(&mut self) -> &Scene {
        self.scene.projection = self.ctm;
        &self.scene
    }

    /// [`Interpreter::scene`], moving the scene out: the interpreter is
    /// done with it.
    pub fn into_scene(mut self) -> Scene {
        self.scene.projection = self.ctm;
        std::mem::take(&mut self.scene)
    }

    /// The current transformation matrix.
    pub fn ctm(&self) -> Matrix4 {
        self.ctm
    }

    /// The number of matrices on the stack.
    pub fn stack_depth(&self) -> usize {
        self.stack.len()
    }

    /// The global surface attributes given to new objects.
    pub fn global_surface(&self) -> Surface {
        self.globals
    }

    /// Warnings gathered so far (repaired or skipped input), emptied.
    /// Of each kind of warning only the first [`WARNINGS_SHOWN`] are kept,
    /// followed by one that counts the rest ("... and N more degenerate
    /// polygon warnings").
    pub fn take_warnings(&mut self) -> Vec<Diagnostic> {
        std::mem::take(&mut self.warnings).finish()
    }

    /// Notes gathered so far, emptied: information about input that was
    /// processed as asked (a CSG operation's face counts), never a
    /// problem; the command line does not print them.
    pub fn take_notes(&mut self) -> Vec<Diagnostic> {
        std::mem::take(&mut self.notes)
    }

    /// Records a note (see [`Interpreter::take_notes`]).
    pub(super) fn note(&mut self, note: Diagnostic) {
        const KEPT: usize = 1000;
        if self.notes.len() < KEPT {
            self.notes.push(note);
        }
    }

    /// Records a warning of `kind`.
    fn warn(&mut self, kind: &'static str, warning: Diagnostic) {
        self.warnings.add(kind, warning);
    }

    /// Forces a `setmode` value given on the command line (`-n on`): it is
    /// applied now and again after every statement, so it overrides the
    /// scene file. `letter` is the mode letter or a digit. An empty (or
    /// blank) `value` is the bare form, `setmode v` (004 appendix B:
    /// `setmode <mode> [<on, off>]`, the value optional), which turns an
    /// on/off mode on: `force_mode('v', "")` is `-v` alone. Modes that
    /// take a number or a name (`d`, `e`, `l`, `f`) still need one.
    pub fn force_mode(&mut self, letter: char, value: &str) -> Result<()> {
        let value = value.trim();
        let file = Path::new("<command line>");
        let stmt = vec![
            Token {
                text: "setmode".into(),
                line: 1,
                column: 1,
            },
            Token {
                text: letter.to_string(),
                line: 1,
                column: 9,
            },
            Token {
                text: value.into(),
                line: 1,
                column: 11,
            },
        ];
        let stmt: Statement = if letter.is_ascii_digit() || value.is_empty() {
            stmt[..2].to_vec()
        } else {
            stmt
        };
        let text = stmt
            .iter()
            .map(|t| t.text.as_str())
            .collect::<Vec<_>>()
            .join(" ");
        let ctx = Context {
            file,
            dir: PathBuf::from("."),
            source: &text,
        };
        self.setmode(&ctx, &stmt[0], &stmt[1..])?;
        self.overrides.push((letter, value.to_string()));
        Ok(())
    }

    fn apply_overrides(&mut self) {
        let overrides = std::mem::take(&mut self.overrides);
        for (letter, value) in &overrides {
            // Already validated by force_mode.
            let _ = self.force_mode(*letter, value);
        }
        self.overrides = overrides;
    }

    /// `init`: every parameter to its default, objects and lights deleted.
    pub fn init(&mut self) {
        let files = std::mem::take(&mut self.files);
        let overrides = std::mem::take(&mut self.overrides);
        let warnings = std::mem::take(&mut self.warnings);
        let notes = std::mem::take(&mut self.notes);
        let budgets = self.budgets;
        *self = Interpreter::new();
        self.notes = notes;
        self.budgets = budgets;
        self.files = files;
        self.overrides = overrides;
        self.warnings = warnings;
        self.apply_overrides();
    }

    /// `get file` (with `init`) or `call file` (without), as if typed.
    /// A relative path is looked up beside the including file, then in the
    /// working directory. The file must be a regular file; it is read and
    /// checked whole (every statement's command, argument count and types)
    /// before its first statement runs. Nested `call`s run on a stack of
    /// frames, not by recursion, so that their depth is bounded by
    /// [`Budgets::call_depth`] alone.
    ///
    /// A name that does not exist as written is tried folded to lower case
    /// (004 appendix B: "all input characters are converted to lower case
    /// before processing"): `GET CCUBE.DES` opens `ccube.des`.
    pub fn execute_file(&mut self, path: &Path, init: bool, host: &mut dyn Host) -> Result<Flow> {
        // The file's name folded, in its folder as written; then the whole
        // path as written folded.
        let path = &lower_case_fallback(path.to_path_buf(), || {
            let name = path.file_name().map(|n| n.to_string_lossy().to_lowercase());
            match name {
                Some(n) if path.with_file_name(&n).exists() => path.with_file_name(n),
                _ => PathBuf::from(path.to_string_lossy().to_lowercase()),
            }
        });
        let frame = self.open_file(path, init, None)?;
        let flow = self.run_frames(frame, host)?;
        if self.files.is_empty()
            && let Some(active) = &self.active
        {
            return Err(Error::at(
                active.location.clone(),
                format!(
                    "`defobj {}` has no `endobj` before the end of the input",
                    printable(&active.name, MAX_SHOWN_TOKEN)
                ),
            ));
        }
        Ok(flow)
    }

    /// Executes the statements of `source`, which came from `file`. The
    /// whole text is checked before its first statement runs.
    pub fn execute_source(
        &mut self,
        source: &str,
        file: &Path,
        dir: &Path,
        host: &mut dyn Host,
    ) -> Result<Flow> {
        let statements = lexer::lex(source, file)?;
        let frame = Frame {
            file: file.to_path_buf(),
            dir: dir.to_path_buf(),
            source: source.to_string(),
            statements,
            next: 0,
            opened: false,
            caller: None,
        };
        self.check_frame(&frame)?;
        self.run_frames(frame, host)
    }

    /// Checks a scene text whole without running it: every statement's
    /// command, argument count and argument types, with the parsers the
    /// interpreter uses. `file` names the text in messages.
    pub fn check_source(&self, source: &str, file: &Path) -> Result<()> {
        let statements = lexer::lex(source, file)?;
        let frame = Frame {
            file: file.to_path_buf(),
            dir: PathBuf::from("."),
            source: source.to_string(),
            statements,
            next: 0,
            opened: false,
            caller: None,
        };
        self.check_frame(&frame)
    }

    fn check_frame(&self, frame: &Frame) -> Result<()> {
        let ctx = frame.context();
        for stmt in &frame.statements {
            let (spec, cmd, args) = lookup_statement(&ctx, stmt)?;
            let a = Args {
                ctx: &ctx,
                cmd,
                args,
                spec,
            };
            validate(&a)?;
        }
        Ok(())
    }

    /// Reads, lexes and checks `path`, then (with `init`) initializes and
    /// records the file as open. `caller` is the `call`/`get` that names it.
    fn open_file(&mut self, path: &Path, init: bool, caller: Option<Caller>) -> Result<Frame> {
        let source = object_file::read_regular(path, MAX_SCENE_BYTES)?;
        let source = String::from_utf8(source).map_err(|e| {
            Error::at(
                Location::file(path),
                format!(
                    "not a text file: invalid UTF-8 at byte {}",
                    e.utf8_error().valid_up_to()
                ),
            )
        })?;
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        if self.files.iter().any(|f| f.canonical == canonical) {
            return Err(Error::at(
                Location::file(path),
                "this file includes itself (a `get`/`call` cycle)",
            ));
        }
        let statements = lexer::lex(&source, path)?;
        let dir = path
            .parent()
            .map(Path::to_path_buf)
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or_else(|| PathBuf::from("."));
        let frame = Frame {
            file: path.to_path_buf(),
            dir: dir.clone(),
            source,
            statements,
            next: 0,
            opened: true,
            caller,
        };
        self.check_frame(&frame)?;
        if init {
            self.init();
        }
        if init || self.files.is_empty() {
            self.det_base = dir;
        }
        self.files.push(OpenFile {
            canonical,
            called: frame.caller.is_some(),
            named: path.to_path_buf(),
        });
        Ok(frame)
    }

    /// Runs `base` and every file it calls, on an explicit stack.
    fn run_frames(&mut self, base: Frame, host: &mut dyn Host) -> Result<Flow> {
        let open_before = self.files.len();
        let mut stack = vec![base];
        let result = self.run_stack(&mut stack, host);
        self.files.truncate(open_before);
        result
    }

    fn run_stack(&mut self, stack: &mut Vec<Frame>, host: &mut dyn Host) -> Result<Flow> {
        loop {
            let Some(top) = stack.last_mut() else {
                return Ok(Flow::Continue);
            };
            if top.next >= top.statements.len() {
                if let Some(done) = stack.pop() {
                    if done.opened {
                        self.files.pop();
                    }
                    if let Some(caller) = &done.caller
                        && caller.get
                    {
                        host.scanned(&done.file, self.current(), caller.start.elapsed());
                    }
                }
                continue;
            }
            let index = top.next;
            top.next += 1;
            let enter = {
                let top = &stack[stack.len() - 1];
                let ctx = top.context();
                let stmt = &top.statements[index];
                let step = self
                    .statement(&ctx, stmt, host)
                    .map_err(|e| with_callers(e, stack))?;
                self.apply_overrides();
                match step {
                    Step::Continue => None,
                    Step::Quit => return Ok(Flow::Quit),
                    Step::Enter { path, get, token } => {
                        let caller = Caller {
                            location: ctx.location(&token),
                            get,
                            start: std::time::Instant::now(),
                        };
                        let frame = self
                            .enter_file(&ctx, &token, &path, caller, host)
                            .map_err(|e| with_callers(e, stack))?;
                        Some(frame)
                    }
                }
            };
            if let Some(frame) = enter {
                stack.push(frame);
            }
        }
    }

    /// `call`/`get` of `path` named by `token`: the cycle and depth checks,
    /// then the file opened and checked.
    fn enter_file(
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

    fn statement(&mut self, ctx: &Context, stmt: &Statement, host: &mut dyn Host) -> Result<Step> {
        let (spec, cmd, args) = lookup_statement(ctx, stmt)?;
        self.command(ctx, spec, cmd, args, host)
    }
    fn command(
        &mut self,
        ctx: &Context,
        spec: &CommandSpec,
        cmd: &Token,
        args: &[Token],
        host: &mut dyn Host,
    ) -> Result<Step> {
        let a = Args {
            ctx,
            cmd,
            args,
            spec,
        };
        validate(&a)?;
        if let Some(active) = &mut self.active
            && generators::SURFACE_COMMANDS.contains(&spec.name)
        {
            active.surface_cmd.get_or_insert_with(|| ctx.location(cmd));
        }
        match spec.name {
            name if generators::GENERATORS.contains(&name) => self.add_generator(&a)?,
            "ambient" => {
                a.count(3, 3)?;
                self.scene.ambient = a.color(0)?;
            }
            "background" => {
                a.count(3, 3)?;
                self.scene.background = a.color(0)?;
            }
            "call" | "get" => {
                a.count(1, 1)?;
                return Ok(Step::Enter {
                    path: lower_case_fallback(resolve(&ctx.dir, &args[0].text), || {
                        resolve(&ctx.dir, &args[0].text.to_lowercase())
                    }),
                    get: spec.name == "get",
                    token: args[0].clone(),
                });
            }
            "callobj" => {
                a.count(1, 1)?;
                let n = self.find_object(&a, 0)?;
                let loc = ctx.location(&args[0]);
                match &mut self.active {
                    Some(active) => active.copy_of = Some((n, loc)),
                    None => {
                        self.begin_object(ctx, cmd, format!("#{n}"), None)?;
                        if let Some(active) = &mut self.active {
                            active.copy_of = Some((n, loc));
                        }
                        self.end_object(ctx, cmd)?;
                    }
                }
            }
            "clear" => {
                a.count(0, 0)?;
                host.clear(self.current())?;
            }
            "color" => {
                a.count(3, 3)?;
                let c = a.color(0)?;
                self.surface_mut().color = c;
            }
            "defobj" => {
                a.count(1, 2)?;
                let number = if args.len() == 2 {
                    Some(a.integer(1, 0, u32::MAX as i64)? as u32)
                } else {
                    None
                };
                if let Some(n) = number
                    && self.scene.objects.iter().any(|o| o.number == n)
                {
                    return Err(ctx.error(&args[1], format!("object number {n} is already in use")));
                }
                self.begin_object(ctx, cmd, args[0].text.clone(), number)?;
            }
            "delobj" => {
                a.count(1, usize::MAX)?;
                for i in 0..args.len() {
                    let before = self.scene.objects.len();
                    match a.object_ref(i)? {
                        ObjectRef::Number(n) => self.scene.objects.retain(|o| o.number != n),
                        ObjectRef::Name(name) => self.scene.objects.retain(|o| o.name != name),
                    }
                    if self.scene.objects.len() == before {
                        return Err(ctx.error(
                            &args[i],
                            format!(
                                "no object `{}` is defined",
                                printable(&args[i].text, MAX_SHOWN_TOKEN)
                            ),
                        ));
                    }
                }
                self.polygons = self.scene.polygon_count();
            }
            "depth" => {
                a.count(1, 1)?;
                self.scene.modes.max_level = a.integer(0, 1, 14)? as u32;
            }
            "det_dir" => {
                a.count(1, 1)?;
                self.det_dir = PathBuf::from(&args[0].text);
                self.det_base = ctx.dir.clone();
            }
            "diffuse" => {
                a.count(1, 1)?;
                self.surface_mut().diffuse = a.unit(0)?;
            }
            "disp" => {
                a.count(0, 1)?;
                self.scene.display = if args.is_empty() { true } else { a.on_off(0)? };
                host.display(self.scene.display);
            }
            "endobj" => {
                a.count(0, 0)?;
                self.end_object(ctx, cmd)?;
            }
            "fname" => {
                a.count(1, 1)?;
                self.scene.fname = Some(args[0].text.clone());
            }
            "geodesic" => {
                a.count(1, 2)?;
                let n = a.integer(0, 1, 1024)? as usize;
                let division = division(&a)?;
                let loc = ctx.location(cmd);
                let Some(active) = &mut self.active else {
                    return Err(ctx.error(cmd, "`geodesic` outside an object definition"));
                };
                active.geodesic = Some((n, division, loc));
            }
            "radial" => {
                let loc = ctx.location(cmd);
                match (radial(&a)?, &mut self.active) {
                    (RadialCommand::Function(f), Some(active)) => active.radial = Some((f, loc)),
                    (RadialCommand::Function(_), None) => {
                        return Err(ctx.error(cmd, "`radial` outside an object definition"));
                    }
                    (RadialCommand::Rotate(angle, axis), Some(active)) => {
                        let before = active.turn.as_ref().map_or(glam::DMat3::IDENTITY, |t| t.0);
                        let turned = TurnedRadial {
                            radial: Radial::Sphere,
                            rotation: before,
                        }
                        .turned(angle, axis);
                        active.turn = Some((turned.rotation, loc));
                    }
                    (RadialCommand::Rotate(angle, axis), None) => {
                        self.turn_geodesics(ctx, cmd, angle, axis)?;
                    }
                }
            }
            "getobj" => {
                a.count(1, 1)?;
                self.begin_object(ctx, cmd, args[0].text.clone(), None)?;
                self.end_object(ctx, cmd)?;
            }
            "ident" => {
                a.count(0, 0)?;
                self.ctm = Matrix4::IDENTITY;
            }
            "index" => {
                a.count(1, 1)?;
                let n = a.number(0)?;
                if n <= 0.0 {
                    return Err(ctx.error(&args[0], "expected a positive index of refraction"));
                }
                self.surface_mut().index = n;
            }
            "init" => {
                a.count(0, 0)?;
                if self.active.is_some() {
                    return Err(ctx.error(cmd, "`init` inside an object definition"));
                }
                self.init();
            }
            "light" => {
                a.count(7, 8)?;
                let position = self.ctm.transform_point(a.vec3(0)?);
                let color = a.vec3(3)?;
                if color.min_element() < 0.0 {
                    return Err(ctx.error(&args[3], "light colour components must not be negative"));
                }
                let range = a.number(6)?;
                if range <= 0.0 {
                    return Err(ctx.error(&args[6], "expected a positive light range"));
                }
                let kind = light_kind(&a)?;
                if !position.is_finite() {
                    return Err(ctx.error(cmd, "the light's position is not finite after transformation by the CTM (a projection is still on the CTM, or a number overflowed)"));
                }
                self.scene.lights.push(Light {
                    position,
                    color,
                    range,
                    kind,
                });
            }
            "lookat" => {
                a.count(7, 7)?;
                let m = math::lookat(a.vec3(0)?, a.vec3(3)?, a.number(6)?)
                    .ok_or_else(|| ctx.error(cmd, "viewpoint and reference point coincide"))?;
                self.premultiply(ctx, cmd, m)?;
            }
            "nolight" => {
                a.count(0, 0)?;
                self.scene.lights.clear();
            }
            "ortho" => {
                a.count(6, 6)?;
                let v = a.numbers(6)?;
                a.distinct_pairs(&v)?;
                self.load(ctx, cmd, math::ortho(v[0], v[1], v[2], v[3], v[4], v[5]))?;
            }
            "ortho2" => {
                a.count(4, 4)?;
                let v = a.numbers(4)?;
                a.distinct_pairs(&v)?;
                self.load(ctx, cmd, ortho2(v[0], v[1], v[2], v[3]))?;
            }
            "outmode" => {
                self.scene.outmode = outmode(&a)?;
            }
            "pcolors" | "vcolors" => {
                a.count(1, 1)?;
                let loc = ctx.location(&args[0]);
                let Some(active) = &mut self.active else {
                    return Err(
                        ctx.error(cmd, format!("`{}` outside an object definition", spec.name))
                    );
                };
                let entry = Some((args[0].text.clone(), loc));
                if spec.name == "pcolors" {
                    active.pcolors = entry;
                } else {
                    active.vcolors = entry;
                }
            }
            "perspective" => {
                a.count(4, 4)?;
                let v = a.numbers(4)?;
                if !(v[0] > 0.0 && v[0] < 180.0) {
                    return Err(ctx.error(
                        &args[0],
                        "expected a field of view between 0 and 180 degrees",
                    ));
                }
                if v[1] <= 0.0 {
                    return Err(ctx.error(&args[1], "expected a positive aspect ratio"));
                }
                if v[2] <= 0.0 {
                    return Err(ctx.error(&args[2], "expected a positive near distance"));
                }
                if v[3] <= v[2] {
                    return Err(
                        ctx.error(&args[3], "expected a far distance beyond the near distance")
                    );
                }
                self.load(ctx, cmd, math::perspective(v[0], v[1], v[2], v[3]))?;
            }
            "polarview" => {
                a.count(4, 4)?;
                let v = a.numbers(4)?;
                self.premultiply(ctx, cmd, math::polarview(v[0], v[1], v[2], v[3]))?;
            }
            "popmatrix" => {
                a.count(0, 0)?;
                let floor = self.active.as_ref().map_or(0, |o| o.stack_depth);
                if self.stack.len() <= floor {
                    let why = if floor > 0 {
                        "matrix stack underflow: this would pop the matrix `defobj` saved"
                    } else {
                        "matrix stack underflow: `popmatrix` without a matching `pushmatrix`"
                    };
                    return Err(ctx.error(cmd, why));
                }
                if let Some(m) = self.stack.pop() {
                    self.ctm = m;
                }
            }
            "pushmatrix" => {
                a.count(0, 0)?;
                self.push(ctx, cmd)?;
            }
            "quit" => {
                a.count(0, 0)?;
                return Ok(Step::Quit);
            }
            "reflectance" => {
                a.count(1, 1)?;
                self.surface_mut().reflectance = a.unit(0)?;
            }
            "resolution" => {
                a.count(2, 2)?;
                let h = a.integer(0, 1, MAX_IMAGE_SIDE)?;
                let v = a.integer(1, 1, MAX_IMAGE_SIDE)?;
                check_pixels(ctx, cmd, h, v)?;
                let left = (1024 - h) / 2;
                let bottom = (1024 - v) / 2;
                self.scene.viewport = Viewport {
                    left,
                    right: left + h - 1,
                    bottom,
                    top: bottom + v - 1,
                };
                self.load(
                    ctx,
                    cmd,
                    math::perspective(45.0, h as f64 / v as f64, 0.01, 10000.0),
                )?;
            }
            "rotate" => {
                a.count(2, 2)?;
                let angle = a.number(0)?;
                let axis = axis(&a, 1)?;
                self.premultiply(ctx, cmd, math::rotate(angle, axis))?;
            }
            "run" => {
                a.count(0, 1)?;
                let shadows = run_shadows(&a)?;
                if self.active.is_some() {
                    return Err(ctx.error(cmd, "`run` inside an object definition"));
                }
                host.run(self.current(), shadows).map_err(|e| match e {
                    Error::Input(mut d) => {
                        d.included_from.push(ctx.location(cmd));
                        Error::Input(d)
                    }
                    other => other,
                })?;
            }
            "scale" => {
                a.count(3, 3)?;
                self.premultiply(ctx, cmd, math::scale(a.vec3(0)?))?;
            }
            "setmode" => {
                self.setmode(ctx, cmd, args)?;
            }
            "shininess" => {
                a.count(1, 1)?;
                let n = a.number(0)?;
                if n < 0.0 {
                    return Err(ctx.error(&args[0], "expected a shininess of 0 or more"));
                }
                self.surface_mut().shininess = n;
            }
            "sort" => {
                a.count(0, 1)?;
                self.scene.sort_order = sort_order(&a)?;
            }
            "specular" => {
                a.count(1, 1)?;
                self.surface_mut().specular = a.unit(0)?;
            }
            "threshold" => {
                a.count(1, 1)?;
                let t = a.number(0)?;
                if t < 0.0 {
                    return Err(ctx.error(&args[0], "expected a threshold of 0 or more"));
                }
                self.scene.threshold = t;
            }
            "translate" => {
                a.count(3, 3)?;
                self.premultiply(ctx, cmd, math::translate(a.vec3(0)?))?;
            }
            "transmittance" => {
                a.count(1, 1)?;
                self.surface_mut().transmittance = a.unit(0)?;
            }
            "transparency" => {
                a.count(1, 2)?;
                let t = a.unit(0)?;
                let rolloff = if args.len() == 2 { a.number(1)? } else { 0.0 };
                if rolloff < 0.0 {
                    return Err(ctx.error(&args[1], "expected a roll-off of 0 or more"));
                }
                self.surface_mut().transparency = (t, rolloff);
            }
            "type" => {
                a.count(1, usize::MAX)?;
                let t = surface_type(&a)?;
                match &mut self.active {
                    Some(o) => o.surface_type = t,
                    None => self.global_type = t,
                }
            }
            "viewport" => {
                a.count(4, 4)?;
                let v: Vec<i64> = (0..4)
                    .map(|i| a.integer(i, -MAX_IMAGE_SIDE, MAX_IMAGE_SIDE))
                    .collect::<Result<_>>()?;
                if v[1] < v[0] {
                    return Err(ctx.error(&args[1], "expected right >= left"));
                }
                if v[3] < v[2] {
                    return Err(ctx.error(&args[3], "expected top >= bottom"));
                }
                check_pixels(ctx, cmd, v[1] - v[0] + 1, v[3] - v[2] + 1)?;
                self.scene.viewport = Viewport {
                    left: v[0],
                    right: v[1],
                    bottom: v[2],
                    top: v[3],
                };
            }
            "wait" => {
                a.count(0, 0)?;
                host.wait();
            }
            "window" => {
                a.count(6, 6)?;
                let v = a.numbers(6)?;
                a.distinct_pairs(&v)?;
                if v[4] <= 0.0 || v[5] <= v[4] {
                    return Err(ctx.error(cmd, "expected 0 < near < far"));
                }
                self.load(ctx, cmd, math::window(v[0], v[1], v[2], v[3], v[4], v[5]))?;
            }
            other => {
                return Err(ctx.error(
                    cmd,
                    format!("command `{other}` is in the table but not interpreted"),
                ));
            }
        }
        Ok(Step::Continue)
    }

    fn setmode(&mut self, ctx: &Context, cmd: &Token, args: &[Token]) -> Result<()> {
        let a = Args {
            ctx,
            cmd,
            args,
            spec: commands::spec("setmode"),
        };
        setmode(&a, &mut self.scene.modes, &mut self.scene.scene_file)
    }

    fn surface_mut(&mut self) -> &mut Surface {
        match &mut self.active {
            Some(o) => &mut o.surface,
            None => &mut self.globals,
        }
    }

    fn push(&mut self, ctx: &Context, cmd: &Token) -> Result<()> {
        if self.stack.len() >= MATRIX_STACK_DEPTH {
            return Err(ctx.error(
                cmd,
                format!("matrix stack overflow: more than {MATRIX_STACK_DEPTH} matrices pushed (each open `defobj` holds one)"),
            ));
        }
        self.stack.push(self.ctm);
        Ok(())
    }

    fn premultiply(&mut self, ctx: &Context, cmd: &Token, m: Matrix4) -> Result<()> {
        self.load(ctx, cmd, m.mul(&self.ctm))
    }

    fn load(&mut self, ctx: &Context, cmd: &Token, m: Matrix4) -> Result<()> {
        if !m.is_finite() {
            return Err(ctx.error(
                cmd,
                "the transformation matrix would overflow (non-finite entries)",
            ));
        }
        self.ctm = m;
        Ok(())
    }

    fn begin_object(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        name: String,
        number: Option<u32>,
    ) -> Result<()> {
        if let Some(active) = &self.active {
            return Err(ctx.error(
                cmd,
                format!(
                    "`{}` inside the definition of `{}` begun at {} (missing `endobj`)",
                    printable(&cmd.text, MAX_SHOWN_TOKEN),
                    printable(&active.name, MAX_SHOWN_TOKEN),
                    active.location
                ),
            ));
        }
        self.push(ctx, cmd)?;
        self.active = Some(ActiveObject {
            name: name.to_lowercase(),
            written: name,
            number,
            surface: self.globals,
            surface_type: self.global_type,
            copy_of: None,
            geodesic: None,
            radial: None,
            turn: None,
            generator: None,
            surface_cmd: None,
            pcolors: None,
            vcolors: None,
            stack_depth: self.stack.len(),
            location: ctx.location(cmd),
            det_base: ctx.dir.clone(),
        });
        Ok(())
    }

    fn end_object(&mut self, ctx: &Context, cmd: &Token) -> Result<()> {
        let Some(active) = self.active.take() else {
            return Err(ctx.error(cmd, "`endobj` without `defobj`"));
        };
        // Restore the CTM whatever happens next.
        self.stack.truncate(active.stack_depth);
        let transform = self.ctm;
        let Some(saved) = self.stack.pop() else {
            return Err(ctx.error(
                cmd,
                "matrix stack underflow: the matrix `defobj` saved is gone",
            ));
        };
        self.ctm = saved;
        if let Some((pending, loc)) = active.generator.clone() {
            let end = generators::Ending {
                ctx,
                cmd,
                transform,
                saved,
            };
            return self.end_generated(active, pending, loc, end);
        }

        let generated = match &active.geodesic {
            Some((n, division, loc)) => {
                // Refused before anything is allocated.
                let faces = geodesic::face_count(*n).unwrap_or(usize::MAX);
                self.check_polygons(faces, loc, &format!("`geodesic {n}` ({faces} faces)"))?;
                let radial = TurnedRadial {
                    radial: active.radial.as_ref().map_or(Radial::Sphere, |r| r.0),
                    rotation: active.turn.as_ref().map_or(glam::DMat3::IDENTITY, |t| t.0),
                };
                let mesh = Arc::new(
                    geodesic::geodesic_turned(*n, *division, &radial)
                        .map_err(|e| Error::at(loc.clone(), e))?,
                );
                Some((mesh, radial))
            }
            None => {
                let stray = active.radial.as_ref().map(|r| &r.1);
                if let Some(loc) = stray.or(active.turn.as_ref().map(|t| &t.1)) {
                    return Err(Error::at(
                        loc.clone(),
                        "`radial` deforms a `geodesic`; this object has none",
                    ));
                }
                None
            }
        };
        let turned = generated.as_ref().map(|(mesh, f)| (Arc::clone(mesh), *f));
        let (mesh, mut pcl, mut vcl) = match (generated.map(|g| g.0), &active.copy_of) {
            (Some(mesh), _) => (mesh, None, None),
            (None, Some((n, loc))) => {
                // `callobj` checked the number, but a `delobj` may have
                // deleted the object since.
                let Some(src) = self.scene.objects.iter().find(|o| o.number == *n) else {
                    return Err(Error::at(
                        loc.clone(),
                        format!(
                            "object number {n}, copied here by `callobj`, was deleted before `endobj`"
                        ),
                    ));
                };
                let count = src.polygons.len().max(src.mesh.polygons.len());
                self.check_polygons(count, loc, &format!("`callobj {n}` ({count} polygons)"))?;
                (
                    src.mesh.clone(),
                    src.polygon_colors.clone(),
                    src.vertex_colors.clone(),
                )
            }
            (None, None) => {
                let path = self.find_object_file(&active)?;
                let mesh = if path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("det"))
                {
                    object_file::read_det_within(
                        &path,
                        self.budgets.polygons.saturating_sub(self.polygons),
                    )
                } else {
                    mesh_import::read_mesh(&path)
                };
                // A problem in the file names the statement that read it.
                let mesh = mesh.map_err(|e| match e {
                    Error::Input(mut d) => {
                        d.included_from.push(active.location.clone());
                        Error::Input(d)
                    }
                    other => other,
                })?;
                (Arc::new(mesh), None, None)
            }
        };
        if let Some((name, loc)) = &active.pcolors {
            pcl = Some(Arc::new(self.read_colors(
                &active,
                name,
                loc,
                ColorKind::Polygon,
            )?));
        }
        if let Some((name, loc)) = &active.vcolors {
            vcl = Some(Arc::new(self.read_colors(
                &active,
                name,
                loc,
                ColorKind::Vertex,
            )?));
        }
        if let (Some(p), Some((_, loc))) = (&pcl, &active.pcolors)
            && p.len() != mesh.polygons.len()
        {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "{} polygon colours for {} polygons",
                    p.len(),
                    mesh.polygons.len()
                ),
            ));
        }
        if let (Some(v), Some((_, loc))) = (&vcl, &active.vcolors)
            && v.len() != mesh.vertices.len()
        {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "{} vertex colours for {} vertices",
                    v.len(),
                    mesh.vertices.len()
                ),
            ));
        }
        if active.copy_of.is_none() && active.geodesic.is_none() {
            let count = mesh.polygons.len();
            self.check_polygons(
                count,
                &active.location,
                &format!(
                    "object `{}` ({count} polygons)",
                    printable(&active.written, MAX_SHOWN_TOKEN)
                ),
            )?;
        }
        let number = active.number.unwrap_or_else(|| self.next_free_number());
        let object = build_object(
            ObjectParts {
                number,
                name: active.name.clone(),
                mesh,
                polygon_colors: pcl,
                vertex_colors: vcl,
                transform,
                surface: active.surface,
                surface_type: active.surface_type,
            },
            &mut |msg| {
                let kind = warning_kind(&msg);
                self.warn(kind, Diagnostic::new(ctx.location(cmd), msg));
            },
        )
        .map_err(|msg| ctx.error(cmd, msg))?;
        // Splitting non-planar polygons may have added some.
        self.check_polygons(
            object
                .polygons
                .len()
                .saturating_sub(object.mesh.polygons.len()),
            &active.location,
            "the triangles of split non-planar polygons",
        )?;
        self.polygons += object.polygons.len();
        match turned {
            Some(g) => self.geodesics.insert(object.number, g),
            None => self.geodesics.remove(&object.number),
        };
        self.scene.objects.push(object);
        Ok(())
    }

    /// `radial rotate ANGLE AXIS` outside a definition: turns the radial
    /// function of every geodesic object inside its fixed vertex
    /// directions (Brown's approximate rotation, 003 section 2) and moves
    /// its vertices along them; the faces and their priority order stay.
    fn turn_geodesics(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        angle: f64,
        axis: usize,
    ) -> Result<()> {
        let mut turned = 0;
        for i in 0..self.scene.objects.len() {
            let number = self.scene.objects[i].number;
            let Some((mesh, f)) = self.geodesics.get(&number) else {
                continue;
            };
            // Still the object `geodesic` made (not deleted and replaced).
            if !Arc::ptr_eq(mesh, &self.scene.objects[i].mesh) {
                continue;
            }
            let f = f.turned(angle, axis);
            let mesh = Arc::new(geodesic::reshape(mesh, &f).map_err(|e| ctx.error(cmd, e))?);
            let o = &self.scene.objects[i];
            let object = build_object(
                ObjectParts {
                    number,
                    name: o.name.clone(),
                    mesh: Arc::clone(&mesh),
                    polygon_colors: o.polygon_colors.clone(),
                    vertex_colors: o.vertex_colors.clone(),
                    transform: o.transform,
                    surface: o.surface,
                    surface_type: o.surface_type,
                },
                &mut |_| {},
            )
            .map_err(|msg| ctx.error(cmd, msg))?;
            self.scene.objects[i] = object;
            self.geodesics.insert(number, (mesh, f));
            turned += 1;
        }
        if turned == 0 {
            return Err(ctx.error(
                cmd,
                "`radial rotate` outside a definition turns the geodesic objects; there are none",
            ));
        }
        self.polygons = self.scene.polygon_count();
        Ok(())
    }

    /// Refuses `adding` more polygons when the scene would then have more
    /// than [`Budgets::polygons`].
    fn check_polygons(&self, adding: usize, location: &Location, what: &str) -> Result<()> {
        let limit = self.budgets.polygons;
        let total = self.polygons.saturating_add(adding);
        if total > limit {
            return Err(Error::at(
                location.clone(),
                Budgets::exceeded(
                    &format!(
                        "{what}: the scene's polygons, {} with these, {}",
                        self.polygons,
                        if total == usize::MAX {
                            "too many to count".to_string()
                        } else {
                            total.to_string()
                        }
                    ),
                    limit,
                    "--max-polygons",
                ),
            ));
        }
        Ok(())
    }

    /// The number of the object `callobj` names: by number, or by
    /// (case-folded) name, the last defined of that name.
    fn find_object(&self, a: &Args, i: usize) -> Result<u32> {
        let found = match a.object_ref(i)? {
            ObjectRef::Number(n) => self.scene.objects.iter().find(|o| o.number == n),
            ObjectRef::Name(name) => self.scene.objects.iter().rev().find(|o| o.name == name),
        };
        found.map(|o| o.number).ok_or_else(|| {
            a.ctx.error(
                &a.args[i],
                format!(
                    "no object `{}` is defined",
                    printable(&a.args[i].text, MAX_SHOWN_TOKEN)
                ),
            )
        })
    }

    fn next_free_number(&self) -> u32 {
        let mut used: Vec<u32> = self.scene.objects.iter().map(|o| o.number).collect();
        used.sort_unstable();
        let mut n = 0;
        for u in used {
            if u == n {
                n += 1;
            } else if u > n {
                break;
            }
        }
        n
    }

    fn det_dirs(&self, active: &ActiveObject) -> Vec<PathBuf> {
        let mut dirs = Vec::new();
        if self.det_dir.is_absolute() {
            dirs.push(self.det_dir.clone());
        } else {
            for base in [&self.det_base, &active.det_base, &PathBuf::from(".")] {
                let d = base.join(&self.det_dir);
                if !dirs.contains(&d) {
                    dirs.push(d);
                }
            }
        }
        // Then the directory as written folded to lower case (004
        // appendix B: input is converted to lower case).
        let folded = PathBuf::from(self.det_dir.to_string_lossy().to_lowercase());
        if folded != self.det_dir {
            let bases: Vec<PathBuf> = if folded.is_absolute() {
                vec![PathBuf::new()]
            } else {
                vec![self.det_base.clone(), active.det_base.clone(), ".".into()]
            };
            for base in bases {
                let d = base.join(&folded);
                if !dirs.contains(&d) {
                    dirs.push(d);
                }
            }
        }
        dirs
    }

    fn find_object_file(&self, active: &ActiveObject) -> Result<PathBuf> {
        let mut tried = Vec::new();
        for dir in self.det_dirs(active) {
            for ext in std::iter::once("det").chain(mesh_import::MESH_EXTENSIONS.iter().copied()) {
                for name in [&active.written, &active.name] {
                    let p = dir.join(format!("{name}.{ext}"));
                    if tried.contains(&p) {
                        continue;
                    }
                    if p.is_file() {
                        return Ok(p);
                    }
                    tried.push(p);
                }
            }
        }
        let shown = tried.len().min(6);
        let mut list: Vec<String> = tried[..shown]
            .iter()
            .map(|p| printable(&p.display().to_string(), MAX_SHOWN_PATH))
            .collect();
        if tried.len() > shown {
            list.push(format!("and {} more", tried.len() - shown));
        }
        Err(Error::at(
            active.location.clone(),
            format!(
                "no geometry file for object `{}` (tried {}); set `det_dir`",
                printable(&active.written, MAX_SHOWN_TOKEN),
                list.join(", ")
            ),
        ))
    }

    fn read_colors(
        &self,
        active: &ActiveObject,
        name: &str,
        loc: &Location,
        kind: ColorKind,
    ) -> Result<Vec<ColorEntry>> {
        let ext = match kind {
            ColorKind::Polygon => "pcl",
            ColorKind::Vertex => "vcl",
        };
        let folded = name.to_lowercase();
        for dir in self.det_dirs(active) {
            for name in [name, folded.as_str()] {
                let p = dir.join(format!("{name}.{ext}"));
                if p.is_file() {
                    return object_file::read_colors(&p, kind);
                }
            }
        }
        Err(Error::at(
            loc.clone(),
            format!(
                "colour file `{}.{ext}` not found in the detail directory",
                printable(name, MAX_SHOWN_TOKEN)
            ),
        ))
    }
}

/// How many warnings of one kind are kept; the rest are counted.
pub const WARNINGS_SHOWN: usize = 5;

/// Warnings, the first few of each kind kept and the rest counted.
#[derive(Debug, Clone, Default)]
struct Warnings {
    kept: Vec<Diagnostic>,
    /// Kind, how many, and where the first was.
    counts: Vec<(&'static str, usize, Location)>,
}

impl Warnings {
    fn add(&mut self, kind: &'static str, warning: Diagnostic) {
        let seen = match self.counts.iter_mut().find(|(k, _, _)| *k == kind) {
            Some(entry) => {
                entry.1 += 1;
                entry.1
            }
            None => {
                self.counts.push((kind, 1, warning.location.clone()));
                1
            }
        };
        if seen <= WARNINGS_SHOWN {
            self.kept.push(warning);
        }
    }

    fn finish(self) -> Vec<Diagnostic> {
        let mut out = self.kept;
        for (kind, count, location) in self.counts {
            if count > WARNINGS_SHOWN {
                out.push(Diagnostic::new(
                    Location::file(location.file),
                    format!(
                        "warning: ... and {} more {kind} warnings",
                        count - WARNINGS_SHOWN
                    ),
                ));
            }
        }
        out
    }
}

/// Near and far of `ortho2`'s box: so far apart that nothing is clipped
/// in z.
pub const ORTHO2_DEPTH: f64 = 1e30;

/// `ortho2 left right bottom top`: a 2-D orthographic projection. The
/// manual (004 appendix) says "for 3-D coordinates, the z values are
/// unaffected by this transformation": nothing is clipped in z, so near and
/// far are at -/+[`ORTHO2_DEPTH`] (depth is kept as `-z`, scaled, so that
/// the order of depths is that of [`math::ortho`]).
pub fn ortho2(l: f64, r: f64, b: f64, t: f64) -> Matrix4 {
    math::ortho(l, r, b, t, -ORTHO2_DEPTH, ORTHO2_DEPTH)
}

/// `path` if it exists, else `folded()` (the name as written folded to
/// lower case) if that exists, else `path` (whose error then names the
/// file as written).
fn lower_case_fallback(path: PathBuf, folded: impl FnOnce() -> PathBuf) -> PathBuf {
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

fn resolve(dir: &Path, name: &str) -> PathBuf {
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

/// Checks a statement's argument count and types without running it (the
/// pre-pass over a whole file); the same parsers as the interpreter.
fn validate(a: &Args) -> Result<()> {
    let n = a.args.len();
    match a.spec.name {
        name if generators::GENERATORS.contains(&name) => {
            generators::parse(a)?;
        }
        "ambient" | "background" | "color" => {
            a.count(3, 3)?;
            a.color(0)?;
        }
        "call" | "get" | "det_dir" | "fname" | "getobj" | "pcolors" | "vcolors" => a.count(1, 1)?,
        "callobj" => {
            a.count(1, 1)?;
            a.object_ref(0)?;
        }
        "clear" | "endobj" | "ident" | "init" | "nolight" | "popmatrix" | "pushmatrix" | "quit"
        | "wait" => a.count(0, 0)?,
        "defobj" => {
            a.count(1, 2)?;
            if n == 2 {
                a.integer(1, 0, u32::MAX as i64)?;
            }
        }
        "delobj" => {
            a.count(1, usize::MAX)?;
            for i in 0..n {
                a.object_ref(i)?;
            }
        }
        "depth" => {
            a.count(1, 1)?;
            a.integer(0, 1, 14)?;
        }
        "diffuse" | "reflectance" | "specular" | "transmittance" => {
            a.count(1, 1)?;
            a.unit(0)?;
        }
        "disp" => {
            a.count(0, 1)?;
            if n == 1 {
                a.on_off(0)?;
            }
        }
        "geodesic" => {
            a.count(1, 2)?;
            a.integer(0, 1, 1024)?;
            division(a)?;
        }
        "index" | "shininess" | "threshold" => {
            a.count(1, 1)?;
            a.number(0)?;
        }
        "light" => {
            a.count(7, 8)?;
            a.numbers(7)?;
            light_kind(a)?;
        }
        "lookat" => {
            a.count(7, 7)?;
            a.numbers(7)?;
        }
        "ortho" | "window" => {
            a.count(6, 6)?;
            let v = a.numbers(6)?;
            a.distinct_pairs(&v)?;
        }
        "ortho2" => {
            a.count(4, 4)?;
            let v = a.numbers(4)?;
            a.distinct_pairs(&v)?;
        }
        "outmode" => {
            outmode(a)?;
        }
        "perspective" | "polarview" => {
            a.count(4, 4)?;
            a.numbers(4)?;
        }
        "radial" => {
            radial(a)?;
        }
        "resolution" => {
            a.count(2, 2)?;
            a.integer(0, 1, MAX_IMAGE_SIDE)?;
            a.integer(1, 1, MAX_IMAGE_SIDE)?;
        }
        "rotate" => {
            a.count(2, 2)?;
            a.number(0)?;
            axis(a, 1)?;
        }
        "run" => {
            run_shadows(a)?;
        }
        "scale" | "translate" => {
            a.count(3, 3)?;
            a.numbers(3)?;
        }
        "setmode" => {
            setmode(a, &mut Modes::default(), &mut None)?;
        }
        "sort" => {
            sort_order(a)?;
        }
        "transparency" => {
            a.count(1, 2)?;
            a.unit(0)?;
            if n == 2 {
                a.number(1)?;
            }
        }
        "type" => {
            surface_type(a)?;
        }
        "viewport" => {
            a.count(4, 4)?;
            for i in 0..4 {
                a.integer(i, -MAX_IMAGE_SIDE, MAX_IMAGE_SIDE)?;
            }
        }
        other => {
            return Err(a.ctx.error(
                a.cmd,
                format!("command `{other}` is in the table but not interpreted"),
            ));
        }
    }
    Ok(())
}

/// `geodesic n [equal|angle]`: the division method.
fn division(a: &Args) -> Result<Division> {
    match a.args.get(1).map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(Division::EqualAngle),
        Some(d) if d == "equal" => Ok(Division::Equal),
        Some(d) if d == "angle" => Ok(Division::EqualAngle),
        Some(_) => Err(a.ctx.error(&a.args[1], "expected `equal` or `angle`")),
    }
}

/// What a `radial` statement says.
enum RadialCommand {
    /// The function.
    Function(Radial),
    /// `radial rotate ANGLE x|y|z`: turn it (degrees, axis 0-2).
    Rotate(f64, usize),
}

/// `radial sphere|ellipsoid a b c|bumps amp freq|lobes amp k` or
/// `radial rotate angle x|y|z`.
fn radial(a: &Args) -> Result<RadialCommand> {
    let (ctx, args) = (a.ctx, a.args);
    a.count(1, 4)?;
    let kind = args[0].text.to_ascii_lowercase();
    if kind == "rotate" {
        a.count(3, 3)?;
        let angle = a.number(1)?;
        let axis = match axis(a, 2)? {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        };
        return Ok(RadialCommand::Rotate(angle, axis));
    }
    let (radial, want) = match kind.as_str() {
        "sphere" => (Radial::Sphere, 1),
        "ellipsoid" => {
            a.count(4, 4)?;
            let v = a.vec3(1)?;
            if v.min_element() <= 0.0 {
                return Err(ctx.error(&args[1], "expected positive semi-axes"));
            }
            (Radial::Ellipsoid(v.x, v.y, v.z), 4)
        }
        "bumps" | "lobes" => {
            a.count(3, 3)?;
            let (amp, f) = (a.number(1)?, a.number(2)?);
            if kind == "bumps" {
                (Radial::Bumps(amp, f), 3)
            } else {
                (Radial::Lobes(amp, f), 3)
            }
        }
        _ => {
            return Err(ctx.error(
                &args[0],
                "expected a radial function: sphere, ellipsoid, bumps or lobes, or `rotate`",
            ));
        }
    };
    a.count(want, want)?;
    Ok(RadialCommand::Function(radial))
}

/// The optional `Point|Diffuse` of `light` (any prefix).
fn light_kind(a: &Args) -> Result<LightKind> {
    match a.args.get(7).map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(LightKind::Point),
        Some(k) if !k.is_empty() && "point".starts_with(&k) => Ok(LightKind::Point),
        Some(k) if !k.is_empty() && "diffuse".starts_with(&k) => Ok(LightKind::Diffuse),
        Some(_) => Err(a.ctx.error(&a.args[7], "expected `Point` or `Diffuse`")),
    }
}

/// `outmode c|r|g|b|y|a bits`.
fn outmode(a: &Args) -> Result<OutMode> {
    let (ctx, args) = (a.ctx, a.args);
    a.count(1, 2)?;
    let mode = args[0].text.to_ascii_lowercase();
    if args.len() == 2 && mode != "a" {
        return Err(ctx.error(&args[1], "only outmode `a` takes a second argument"));
    }
    Ok(match mode.as_str() {
        "c" => OutMode::Color,
        "r" => OutMode::Red,
        "g" => OutMode::Green,
        "b" => OutMode::Blue,
        "y" => OutMode::Luminance,
        "a" => {
            if args.len() != 2 {
                return Err(ctx.error(a.cmd, "outmode `a` needs the bits per colour (1-8)"));
            }
            OutMode::Quantized(a.integer(1, 1, 8)? as u8)
        }
        _ => {
            return Err(ctx.error(&args[0], "expected an output mode: c, r, g, b, y or a"));
        }
    })
}

/// The axis letter of `rotate`.
fn axis(a: &Args, i: usize) -> Result<Axis> {
    match a.args[i].text.to_ascii_lowercase().as_str() {
        "x" => Ok(Axis::X),
        "y" => Ok(Axis::Y),
        "z" => Ok(Axis::Z),
        _ => Err(a.ctx.error(&a.args[i], "expected an axis: x, y or z")),
    }
}

/// `run [y]`: whether shadows are wanted.
fn run_shadows(a: &Args) -> Result<bool> {
    a.count(0, 1)?;
    match a.args.first().map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(false),
        Some(y) if y == "y" || y == "yes" => Ok(true),
        Some(n) if n == "n" || n == "no" => Ok(false),
        Some(_) => Err(a.ctx.error(&a.args[0], "expected `y` (shadows) or nothing")),
    }
}

/// `sort [btf|ftb]`.
fn sort_order(a: &Args) -> Result<SortOrder> {
    a.count(0, 1)?;
    match a.args.first().map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(SortOrder::BackToFront),
        Some(s) if s == "btf" => Ok(SortOrder::BackToFront),
        Some(s) if s == "ftb" => Ok(SortOrder::FrontToBack),
        Some(_) => Err(a.ctx.error(&a.args[0], "expected `btf` or `ftb`")),
    }
}

/// `type polygon [open curved concave hidden ltsrc]`.
fn surface_type(a: &Args) -> Result<SurfaceType> {
    a.count(1, usize::MAX)?;
    let mut t = SurfaceType::default();
    for (i, word) in a.args.iter().enumerate() {
        match word.text.to_ascii_lowercase().as_str() {
            "polygon" if i == 0 => {}
            "open" => t.open = true,
            "curved" => t.curved = true,
            "concave" => t.concave = true,
            "hidden" => t.hidden = true,
            "ltsrc" => t.ltsrc = true,
            _ if i == 0 => {
                return Err(a
                    .ctx
                    .error(word, "expected `polygon`, the only surface type"));
            }
            _ => {
                return Err(a.ctx.error(
                    word,
                    "expected a type attribute: open, curved, concave, hidden or ltsrc",
                ));
            }
        }
    }
    Ok(t)
}

/// An object named by its number or (case-folded) name.
#[derive(Debug, Clone, PartialEq, Eq)]
enum ObjectRef {
    Number(u32),
    Name(String),
}

/// `setmode mode [value]` applied to `modes` (and, for `f`, the scene file
/// name). A mode that is on or off is on when no value is given.
fn setmode(a: &Args, modes: &mut Modes, scene_file: &mut Option<String>) -> Result<()> {
    let (ctx, args) = (a.ctx, a.args);
    a.count(1, 2)?;
    let letter_token = &args[0];
    let letter = letter_token.text.to_ascii_lowercase();
    let mut chars = letter.chars();
    let (Some(l), None) = (chars.next(), chars.next()) else {
        return Err(ctx.error(
            letter_token,
            format!(
                "expected a mode letter (b d e f h l n o p s v x) or a digit, found `{}`",
                printable(&letter_token.text, MAX_SHOWN_TOKEN)
            ),
        ));
    };
    if l.is_ascii_digit() {
        a.count(1, 1)?;
        modes.debug = l as u8 - b'0';
        return Ok(());
    }
    // On/off modes: `setmode v` alone means on (004 appendix: `setmode
    // <mode> [<on, off>]`).
    let flag = |i: usize| -> Result<bool> {
        if args.len() > i {
            a.on_off(i)
        } else {
            Ok(true)
        }
    };
    if args.len() < 2 && matches!(l, 'd' | 'e' | 'l' | 'f') {
        return Err(ctx.error(letter_token, format!("mode `{l}` needs a value")));
    }
    let m = modes;
    match l {
        'b' => m.blend = flag(1)?,
        'd' => {
            let d = a.number(1)?;
            if d < 0.0 {
                return Err(ctx.error(&args[1], "expected a detail size of 0 or more"));
            }
            m.min_detail = d;
        }
        'e' => {
            let e = a.number(1)?;
            if !(e > 0.0 && e < 1.0) {
                return Err(ctx.error(&args[1], "expected an epsilon between 0 and 1"));
            }
            m.epsilon = e;
        }
        'f' => *scene_file = Some(args[1].text.clone()),
        'h' => m.shadow_shades = flag(1)?,
        'l' => m.max_level = a.integer(1, 1, 14)? as u32,
        'n' => m.nns = flag(1)?,
        'o' => m.output_tree = flag(1)?,
        'p' => m.boxes_only = flag(1)?,
        's' => m.phong = flag(1)?,
        'v' => m.vertex_shades = flag(1)?,
        'x' => m.expand = flag(1)?,
        'i' => {
            return Err(ctx.error(
                letter_token,
                format!("mode `{l}` can only be given on the command line (-{l})"),
            ));
        }
        _ => {
            return Err(ctx.error(
                letter_token,
                format!(
                    "unknown mode `{}`: expected b, d, e, f, h, l, n, o, p, s, v, x or a digit",
                    printable(&l.to_string(), 4)
                ),
            ));
        }
    }
    Ok(())
}

/// `e`, raised in the top frame of `stack`, with the `call`/`get`
/// statements that led there (innermost first).
fn with_callers(e: Error, stack: &[Frame]) -> Error {
    match e {
        Error::Input(mut d) => {
            for frame in stack.iter().rev() {
                if let Some(caller) = &frame.caller {
                    d.included_from.push(caller.location.clone());
                }
            }
            Error::Input(d)
        }
        other => other,
    }
}

/// The command of a statement and its arguments.
fn lookup_statement<'s>(
    ctx: &Context,
    stmt: &'s Statement,
) -> Result<(&'static CommandSpec, &'s Token, &'s [Token])> {
    let Some((cmd, args)) = stmt.split_first() else {
        return Err(Error::at(Location::file(ctx.file), "empty statement"));
    };
    let shown = printable(&cmd.text, MAX_SHOWN_TOKEN);
    let spec = match commands::lookup(&cmd.text) {
        Lookup::Found(spec) => spec,
        Lookup::Unknown(suggestion) => {
            let hint = suggestion
                .map(|s| format!("; did you mean `{s}`?"))
                .unwrap_or_else(|| "; `plytrace --help` lists the commands".into());
            return Err(ctx.error(cmd, format!("unknown command `{shown}`{hint}")));
        }
        Lookup::Ambiguous(names) => {
            return Err(ctx.error(
                cmd,
                format!(
                    "ambiguous command `{shown}`: it could be {}",
                    names.join(", ")
                ),
            ));
        }
    };
    Ok((spec, cmd, args))
}

fn check_pixels(ctx: &Context, cmd: &Token, w: i64, h: i64) -> Result<()> {
    if w < 1
        || h < 1
        || w > MAX_IMAGE_SIDE
        || h > MAX_IMAGE_SIDE
        || (w as u64) * (h as u64) > MAX_IMAGE_PIXELS
    {
        return Err(ctx.error(
            cmd,
            format!("image of {w} x {h} pixels: each side must be 1 to {MAX_IMAGE_SIDE} and the total at most {MAX_IMAGE_PIXELS} pixels"),
        ));
    }
    Ok(())
}

/// The arguments of one statement, with typed accessors that fail with a
/// located diagnostic.
struct Args<'a> {
    ctx: &'a Context<'a>,
    cmd: &'a Token,
    args: &'a [Token],
    spec: &'a CommandSpec,
}

impl Args<'_> {
    fn count(&self, min: usize, max: usize) -> Result<()> {
        let n = self.args.len();
        if n >= min && n <= max {
            return Ok(());
        }
        let expected = if min == max {
            format!("{min} argument{}", if min == 1 { "" } else { "s" })
        } else if max == usize::MAX {
            format!("at least {min} argument{}", if min == 1 { "" } else { "s" })
        } else {
            format!("{min} to {max} arguments")
        };
        let usage = if self.spec.usage.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.spec.usage)
        };
        let token = if n > max { &self.args[max] } else { self.cmd };
        Err(self.ctx.error(
            token,
            format!("`{}` expects {expected}{usage}, found {n}", self.spec.name),
        ))
    }

    fn number(&self, i: usize) -> Result<f64> {
        let t = &self.args[i];
        match t.text.parse::<f64>() {
            Ok(v) if v.is_finite() && !t.text.to_ascii_lowercase().contains("inf") => Ok(v),
            Ok(_) => Err(self.ctx.error(
                t,
                format!(
                    "expected a finite number, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )),
            Err(_) => Err(self.ctx.error(
                t,
                format!(
                    "expected a number, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )),
        }
    }

    fn numbers(&self, n: usize) -> Result<Vec<f64>> {
        (0..n).map(|i| self.number(i)).collect()
    }

    fn vec3(&self, i: usize) -> Result<DVec3> {
        Ok(DVec3::new(
            self.number(i)?,
            self.number(i + 1)?,
            self.number(i + 2)?,
        ))
    }

    fn unit(&self, i: usize) -> Result<f64> {
        let v = self.number(i)?;
        if !(0.0..=1.0).contains(&v) {
            return Err(self.ctx.error(
                &self.args[i],
                format!("expected a value from 0 to 1, found {v}"),
            ));
        }
        Ok(v)
    }

    fn color(&self, i: usize) -> Result<DVec3> {
        Ok(DVec3::new(
            self.unit(i)?,
            self.unit(i + 1)?,
            self.unit(i + 2)?,
        ))
    }

    fn integer(&self, i: usize, min: i64, max: i64) -> Result<i64> {
        let t = &self.args[i];
        let v: i64 = t.text.parse().map_err(|_| {
            self.ctx.error(
                t,
                format!(
                    "expected a whole number, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )
        })?;
        if v < min || v > max {
            return Err(self.ctx.error(
                t,
                format!("expected a whole number from {min} to {max}, found {v}"),
            ));
        }
        Ok(v)
    }

    /// An object number, or a name (case-folded).
    fn object_ref(&self, i: usize) -> Result<ObjectRef> {
        let t = &self.args[i];
        if t.text
            .starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+')
        {
            return Ok(ObjectRef::Number(
                self.integer(i, 0, u32::MAX as i64)? as u32
            ));
        }
        Ok(ObjectRef::Name(t.text.to_lowercase()))
    }

    fn on_off(&self, i: usize) -> Result<bool> {
        let t = &self.args[i];
        match t.text.to_ascii_lowercase().as_str() {
            "on" | "1" | "true" | "yes" => Ok(true),
            "off" | "0" | "false" | "no" => Ok(false),
            _ => Err(self.ctx.error(
                t,
                format!(
                    "expected `on` or `off`, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )),
        }
    }

    /// For projections: left != right, bottom != top, near != far.
    fn distinct_pairs(&self, v: &[f64]) -> Result<()> {
        for pair in (0..v.len()).step_by(2) {
            if v[pair] == v[pair + 1] {
                return Err(self.ctx.error(
                    &self.args[pair + 1],
                    "expected different values for the two sides of the volume",
                ));
            }
        }
        Ok(())
    }
}

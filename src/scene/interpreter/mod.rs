//! The command interpreter of the scene descriptor language (Garcia 1986,
//! 004 section 4.3 and the plytrace manual page of the appendix).
//!
//! It keeps the current transformation matrix (CTM) and its 16-deep stack
//! with IRIS GL semantics (see [`crate::math`]), the global and active-object
//! attributes, and builds the [`Scene`]. Commands that render or talk to a
//! display (`run`, `clear`, `wait`) are passed to a [`Host`].
//!
//! A file is lexed ([`super::lexer`]) and parsed whole into commands
//! (`scene::parse`, `scene::command`) before its first statement runs;
//! [`Interpreter`] then runs them on a stack of frames (one per
//! `call`/`get`), each command by the handler of its concern
//! (the submodules below).
//!
//! Preconditions: none; every input is validated, and every error names
//! the file, line and column and what was expected.
//!
//! The handlers of the commands, grouped by concern, are its submodules:
//! - `view`: viewing, projections, transforms and the matrix stack;
//! - `objects`: `defobj` ... `endobj`, `callobj`, `delobj`, geodesics;
//! - `deleting`: the objects `delobj` statements in a row mark, which
//!   leave together before the next other statement;
//! - `generators`: the modeling commands (Firebaugh's primitives, CSG);
//! - `surface`: surface attributes of the active object or the globals;
//! - `lighting`: lights, `setmode` and the scene-wide settings;
//! - `files`: `call`, `get`, `det_dir`, `init`, `run`, the display.
//!
//! # How a file flows through the language
//!
//! The scene language flows one way too: `lexer` (words with line and
//! column) --> `parse` (one pass per statement: the word looked up in the
//! `commands` table, the arguments read into a typed `command::Command`, one
//! variant per command) --> `interpreter` (a whole file is parsed before its
//! first statement runs; `call`/`get` push frames) --> its handler
//! submodules, by concern (`view`, `objects`, `generators`, `surface`,
//! `lighting`, `files`) --> `build` (an object placed in world
//! coordinates). Since a file is parsed whole first, `read_ahead` starts
//! reading the object files its definitions will need, in statement order,
//! on all the pool's threads but one (the interpreter, which builds each
//! object, keeps a core), while the statements before them run; the
//! statements of one file that read one path share one read (and its
//! `Arc<Mesh>`), which the first of them does itself if no thread has
//! started it, and a statement whose file another thread is reading reads
//! the files queued after it rather than wait. The interpreter takes a read only for the very path it
//! looks up and only if it succeeded within that statement's budget;
//! anything else it reads again in turn, so errors do not change. A run
//! (one file or console line, with what it calls) looks each object file up
//! once per name and folders (`Interpreter::object_file`, found or not); a
//! statement whose file was not found looks again for its error's list of
//! paths tried. Objects
//! leave the scene only through `Interpreter::retain_objects` (`delobj`,
//! a CSG's operands), which lowers the polygon count and tells
//! `FreeNumbers` (the set of used numbers behind `defobj`'s numbering and
//! its check that a given number is free) which numbers left. `delobj`
//! statements in a row only mark their objects (`interpreter::deleting`,
//! numbers and names looked up once); they leave together before any other
//! statement runs, when a run of statements ends and when the scene is
//! handed out. The reading's notes (the inputs
//! an output may not overwrite, the contents' hashes in the outputs'
//! fingerprint) are held on the reading thread (`input_guard::recording`)
//! and entered when the interpreter takes the file, in statement order. The `commands` table is the one list of names, the
//! manual's/added mark that decides abbreviations, usage and help: the
//! parser, the prompt's `help`, its completion and `--help` all read it, and
//! each entry's `Verb` is the type the parser matches on exhaustively.

mod active;
mod deleting;
mod files;
mod generators;
mod lighting;
mod objects;
mod read_ahead;
mod surface;
mod view;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use self::active::ActiveObject;
use self::active::Pending;
use super::arguments::Context;
use super::command::{Command, Parsed};
use super::lexer::{self, Token};
use super::object_file;
use super::parse;
use crate::budget::Budgets;
use crate::error::{Diagnostic, Error, Location, MAX_SHOWN_TOKEN, Result, printable};
use crate::math::{self, Matrix4};
use crate::model::*;
use crate::modeling::csg::Op;
use crate::modeling::geodesic::TurnedRadial;
use crate::modeling::patch::Form;

pub use self::view::{ORTHO2_DEPTH, ortho2};
pub use super::build::{ObjectParts, build_object};
pub use super::parse::MAX_IMAGE_SIDE;

/// Depth of the matrix stack (004 section 4.3: "a 16-level deep
/// transformation matrix stack"). `defobj` uses one level.
pub const MATRIX_STACK_DEPTH: usize = 16;

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

/// A file being read (or a text given to [`Interpreter::execute_source`]),
/// parsed.
pub(super) struct Frame {
    pub file: PathBuf,
    pub dir: PathBuf,
    pub source: String,
    pub commands: Vec<Parsed>,
    pub next: usize,
    /// Whether it is recorded in `Interpreter::files`.
    pub opened: bool,
    /// The `call`/`get` that named it.
    pub caller: Option<Caller>,
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
pub(super) struct Caller {
    pub location: Location,
    pub get: bool,
    pub start: std::time::Instant,
}

/// A file being read, for cycle detection and the call depth.
#[derive(Debug, Clone)]
pub(super) struct OpenFile {
    pub canonical: PathBuf,
    pub named: PathBuf,
    /// Opened by `call`/`get` (not the outermost file).
    pub called: bool,
}

/// The largest scene file read: a scene is held whole, with its commands,
/// while it runs, so the limit is smaller than for object files.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// What to do after a statement.
pub(super) enum Step {
    Continue,
    Quit,
    /// Read `path` next (`call`, or `get` with `init`).
    Enter {
        path: PathBuf,
        get: bool,
        token: Token,
    },
}

/// The interpreter's state.
#[derive(Debug, Clone)]
pub struct Interpreter {
    pub(super) scene: Scene,
    pub(super) ctm: Matrix4,
    pub(super) stack: Vec<Matrix4>,
    pub(super) globals: Surface,
    pub(super) global_type: SurfaceType,
    pub(super) active: Option<ActiveObject>,
    pub(super) det_dir: PathBuf,
    pub(super) det_base: PathBuf,
    pub(super) files: Vec<OpenFile>,
    /// Polygons of the scene's objects (for [`Budgets::polygons`]).
    pub(super) polygons: usize,
    pub(super) overrides: Vec<(char, String)>,
    warnings: Warnings,
    /// Information that is not a warning (what a CSG operation did).
    notes: Vec<Diagnostic>,
    pub(super) budgets: Budgets,
    /// Geodesic objects by number: the mesh generated and its turned
    /// radial function, for `radial rotate` outside a definition.
    pub(super) geodesics: std::collections::HashMap<u32, (Arc<Mesh>, TurnedRadial)>,
    /// The objects' numbers, for the next free one.
    pub(super) numbers: objects::FreeNumbers,
    /// The objects `delobj` statements in a row marked, until they go.
    pub(super) doomed: Option<deleting::Doomed>,
    /// Object files read ahead of their statements.
    read_ahead: read_ahead::ReadAhead,
    /// Object files found in this run.
    found_files: FoundFiles,
}

/// The object files looked up in one run (one scene file, or one line of
/// the console, with what it calls), by the name as written, the detail
/// directory, the folder that set it and the folder of the definition;
/// `None` for one not found. A scene of a thousand `defobj cube` looks
/// `cube.det` up once, not a thousand times (a `stat` each, on the
/// interpreter's thread), as the read-ahead reads it once. The next run
/// looks files up again, so it finds the files as they are then.
type FoundFiles = std::collections::HashMap<(String, PathBuf, PathBuf, PathBuf), Option<PathBuf>>;

impl Default for Interpreter {
    fn default() -> Self {
        Self::new()
    }
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
            det_dir: PathBuf::from("det"),
            det_base: PathBuf::from("."),
            files: Vec::new(),
            polygons: 0,
            overrides: Vec::new(),
            warnings: Warnings::default(),
            notes: Vec::new(),
            budgets: Budgets::default(),
            geodesics: std::collections::HashMap::new(),
            numbers: objects::FreeNumbers::default(),
            doomed: None,
            read_ahead: read_ahead::ReadAhead::default(),
            found_files: FoundFiles::new(),
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
        self.settle_deletions();
        self.scene.projection = self.ctm;
        &self.scene
    }

    /// [`Interpreter::scene`], moving the scene out: the interpreter is
    /// done with it.
    pub fn into_scene(mut self) -> Scene {
        self.settle_deletions();
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
    pub(super) fn warn(&mut self, kind: &'static str, warning: Diagnostic) {
        self.warnings.add(kind, warning);
    }

    /// `init`: every parameter to its default, objects and lights deleted.
    pub fn init(&mut self) {
        let files = std::mem::take(&mut self.files);
        let overrides = std::mem::take(&mut self.overrides);
        let warnings = std::mem::take(&mut self.warnings);
        let notes = std::mem::take(&mut self.notes);
        let budgets = self.budgets;
        let read_ahead = std::mem::take(&mut self.read_ahead);
        let found_files = std::mem::take(&mut self.found_files);
        *self = Interpreter::new();
        self.read_ahead = read_ahead;
        self.found_files = found_files;
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
        let path = &self::files::lower_case_fallback(path.to_path_buf(), || {
            let name = path.file_name().map(|n| n.to_string_lossy().to_lowercase());
            match name {
                Some(n) if path.with_file_name(&n).exists() => path.with_file_name(n),
                _ => PathBuf::from(path.to_string_lossy().to_lowercase()),
            }
        });
        let open_before = self.files.len();
        let frame = self.open_file(path, init, None)?;
        let flow = self.run_frames(frame, host);
        // After an error or a `quit` the file is still listed (its frame
        // never ended); the next `execute_file` of it would be refused as
        // a cycle.
        let stopped = self.files.len() > open_before;
        self.files.truncate(open_before);
        let flow = flow?;
        if !stopped {
            self.check_end_of_input()?;
        }
        Ok(flow)
    }

    /// Refuses the end of a whole input (a scene file, or a text read as
    /// one) inside `defobj`: a `defobj` must have its `endobj` in the
    /// input that opened it. Inside a called file it is not the end yet.
    fn check_end_of_input(&self) -> Result<()> {
        match &self.active {
            Some(active) if self.files.is_empty() => Err(Error::at(
                active.location.clone(),
                format!(
                    "`defobj {}` has no `endobj` before the end of the input",
                    printable(&active.name, MAX_SHOWN_TOKEN)
                ),
            )),
            _ => Ok(()),
        }
    }

    /// Executes `source` as a whole input, as [`Self::execute_file`] does a
    /// file's text: at most [`MAX_SCENE_BYTES`], and refused if it ends
    /// inside `defobj` (unless it `quit`s). [`Self::execute_source`] runs
    /// a piece of a longer input, such as one line typed at the prompt.
    pub fn execute_input(
        &mut self,
        source: &str,
        file: &Path,
        dir: &Path,
        host: &mut dyn Host,
    ) -> Result<Flow> {
        if source.len() as u64 > MAX_SCENE_BYTES {
            return Err(Error::at(
                Location::file(file),
                format!(
                    "the scene has {} bytes, more than the {MAX_SCENE_BYTES} bytes a scene may have",
                    source.len()
                ),
            ));
        }
        let flow = self.execute_source(source, file, dir, host)?;
        if flow == Flow::Continue {
            self.check_end_of_input()?;
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
        let frame = parse_text(source.to_string(), file, dir)?;
        self.start_reading_ahead(&frame.commands, dir);
        self.run_frames(frame, host)
    }

    /// Checks a scene text whole without running it: every statement's
    /// command, argument count and argument types, with the parser the
    /// interpreter uses. `file` names the text in messages.
    pub fn check_source(&self, source: &str, file: &Path) -> Result<()> {
        parse_text(source.to_string(), file, Path::new(".")).map(drop)
    }

    /// Reads, lexes and parses `path`, then (with `init`) initializes and
    /// records the file as open. `caller` is the `call`/`get` that names it.
    pub(super) fn open_file(
        &mut self,
        path: &Path,
        init: bool,
        caller: Option<Caller>,
    ) -> Result<Frame> {
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
        let dir = path
            .parent()
            .map(Path::to_path_buf)
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or_else(|| PathBuf::from("."));
        let mut frame = parse_text(source, path, &dir)?;
        frame.opened = true;
        frame.caller = caller;
        if init {
            self.init();
        }
        if init || self.files.is_empty() {
            self.det_base = dir.clone();
        }
        self.start_reading_ahead(&frame.commands, &dir);
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
        self.settle_deletions();
        self.files.truncate(open_before);
        // What a run did not read (after an error, a `quit`) is dropped:
        // a later run finds and reads the files as they are then.
        self.read_ahead.clear();
        self.found_files.clear();
        result
    }

    fn run_stack(&mut self, stack: &mut Vec<Frame>, host: &mut dyn Host) -> Result<Flow> {
        loop {
            let Some(top) = stack.last_mut() else {
                return Ok(Flow::Continue);
            };
            if top.next >= top.commands.len() {
                if let Some(done) = stack.pop() {
                    if done.opened {
                        self.files.pop();
                    }
                    if let Some(caller) = &done.caller
                        && caller.get
                    {
                        host.scanned(&done.file, self.current(), caller.start.elapsed());
                    }
                    // A scene file's statements, freed on the pool: the
                    // last file ends after its `run`, and freeing office2's
                    // took 0.25 ms after the image was written.
                    rayon::spawn(move || drop(done));
                }
                continue;
            }
            let index = top.next;
            top.next += 1;
            let enter = {
                let top = &stack[stack.len() - 1];
                let ctx = top.context();
                let step = self
                    .execute(&ctx, &top.commands[index], host)
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

    /// Runs one command: each by the handler of its concern, in
    /// [`super::interpreter`].
    fn execute(&mut self, ctx: &Context, parsed: &Parsed, host: &mut dyn Host) -> Result<Step> {
        let Parsed { word, command } = parsed;
        if command.sets_surface()
            && let Some(active) = &mut self.active
        {
            active.surface_cmd.get_or_insert_with(|| ctx.location(word));
        }
        let verb = command.verb();
        use Command as C;
        if !matches!(command, C::Delobj(_)) {
            self.settle_deletions();
        }
        match command {
            // Viewing and transforms (exec/view.rs).
            C::Ident => self.ctm = Matrix4::IDENTITY,
            C::Lookat { eye, center, twist } => self.lookat(ctx, word, *eye, *center, *twist)?,
            C::Ortho(v) => self.load(ctx, word, math::ortho(v[0], v[1], v[2], v[3], v[4], v[5]))?,
            C::Ortho2(v) => self.load(ctx, word, ortho2(v[0], v[1], v[2], v[3]))?,
            C::Perspective(v) => self.perspective(ctx, word, v)?,
            C::Polarview(v) => {
                self.premultiply(ctx, word, math::polarview(v[0], v[1], v[2], v[3]))?;
            }
            C::Popmatrix => self.popmatrix(ctx, word)?,
            C::Pushmatrix => self.push(ctx, word)?,
            C::Resolution { h, v } => self.resolution(ctx, word, *h, *v)?,
            C::Rotate { angle, axis } => {
                self.premultiply(ctx, word, math::rotate(*angle, *axis))?
            }
            C::Scale(s) => self.premultiply(ctx, word, math::scale(*s))?,
            C::Translate(t) => self.premultiply(ctx, word, math::translate(*t))?,
            C::Viewport(v) => self.viewport(ctx, word, v)?,
            C::Window(v) => self.window(ctx, word, v)?,
            // Objects and modeling (exec/objects.rs, exec/generators.rs).
            C::Callobj(r) => self.callobj(ctx, word, r)?,
            C::Defobj { name, number } => self.defobj(ctx, word, name, number.as_ref())?,
            C::Delobj(refs) => self.delobj(ctx, refs)?,
            C::Endobj => self.end_object(ctx, word)?,
            C::Getobj(name) => self.getobj(ctx, word, name)?,
            C::Geodesic { n, division } => self.geodesic(ctx, word, *n, *division)?,
            C::Radial(r) => self.radial(ctx, word, *r)?,
            C::Sphere(p) | C::Cylinder(p) | C::Superquadric(p) => {
                self.add_generator(ctx, word, verb, Pending::Primitive(p.clone()))?;
            }
            C::Bezier(f) => {
                self.add_generator(ctx, word, verb, Pending::patches(Form::Bezier, f))?
            }
            C::Hermite(f) => {
                self.add_generator(ctx, word, verb, Pending::patches(Form::Hermite, f))?
            }
            C::Lathe { n, points } => self.lathe(ctx, word, *n, points)?,
            C::Extrude { depth, points } => self.extrude(ctx, word, *depth, points)?,
            C::Union(o) => self.add_generator(ctx, word, verb, Pending::csg(Op::Union, o))?,
            C::Intersection(o) => {
                self.add_generator(ctx, word, verb, Pending::csg(Op::Intersection, o))?;
            }
            C::Difference(o) => {
                self.add_generator(ctx, word, verb, Pending::csg(Op::Difference, o))?;
            }
            // Surfaces (exec/surface.rs).
            C::Color(c) => self.surface_mut().color = *c,
            C::Diffuse(k) => self.surface_mut().diffuse = *k,
            C::Specular(k) => self.surface_mut().specular = *k,
            C::Reflectance(k) => self.surface_mut().reflectance = *k,
            C::Transmittance(k) => self.surface_mut().transmittance = *k,
            C::Index(n) => self.index(ctx, n)?,
            C::Shininess(n) => self.shininess(ctx, n)?,
            C::Transparency { t, rolloff } => self.transparency(ctx, *t, rolloff.as_ref())?,
            C::Type(t) => self.surface_type(*t),
            C::Pcolors(file) | C::Vcolors(file) => self.color_file(ctx, word, verb, file)?,
            // Lights and modes (exec/lighting.rs).
            C::Ambient(c) => self.scene.ambient = *c,
            C::Background(c) => self.scene.background = *c,
            C::Light {
                position,
                color,
                range,
                kind,
            } => self.light(ctx, word, *position, color, range, *kind)?,
            C::Nolight => self.scene.lights.clear(),
            C::Depth(d) => self.scene.modes.max_level = *d,
            C::Setmode(m) => self.setmode(m),
            C::Threshold(t) => self.threshold(ctx, t)?,
            C::Outmode(m) => self.scene.outmode = *m,
            C::Sort(s) => self.scene.sort_order = *s,
            // Files and runs (exec/files.rs).
            C::Call(file) => return Ok(include(ctx, file, false)),
            C::Get(file) => return Ok(include(ctx, file, true)),
            C::DetDir(dir) => self.set_det_dir(ctx, dir),
            C::Fname(name) => self.scene.fname = Some(self::files::output_stem(name)),
            C::Init => self.init_command(ctx, word)?,
            C::Run { shadows } => self.run(ctx, word, *shadows, host)?,
            C::Clear => host.clear(self.current())?,
            C::Wait => host.wait(),
            C::Disp(on) => self.disp(*on, host),
            C::Quit => return Ok(Step::Quit),
        }
        Ok(Step::Continue)
    }
}

/// Lexes and parses `source`, which came from `file` in `dir`.
fn parse_text(source: String, file: &Path, dir: &Path) -> Result<Frame> {
    let statements = lexer::lex(&source, file)?;
    let mut frame = Frame {
        file: file.to_path_buf(),
        dir: dir.to_path_buf(),
        source,
        commands: Vec::new(),
        next: 0,
        opened: false,
        caller: None,
    };
    frame.commands = parse::parse_all(&frame.context(), statements)?;
    Ok(frame)
}

/// `call file` or `get file`: the file to read next.
fn include(ctx: &Context, file: &super::arguments::Spanned<String>, get: bool) -> Step {
    use self::files::{lower_case_fallback, resolve};
    let text = &file.value;
    Step::Enter {
        path: lower_case_fallback(resolve(&ctx.dir, text), || {
            resolve(&ctx.dir, &text.to_lowercase())
        }),
        get,
        token: file.token.clone(),
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

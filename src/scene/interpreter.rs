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

use super::commands::{self, CommandSpec, Lookup};
use super::lexer::{self, Statement, Token};
use super::mesh_import;
use super::model::*;
use super::object_file::{self, ColorEntry, ColorKind, Mesh};
use crate::budget::Budgets;
use crate::error::{Diagnostic, Error, Location, Result};
use crate::geometry::polygon::{self, PolygonDefect};
use crate::math::{self, Axis, Matrix4};
use crate::modeling::geodesic::{self, Division, Radial};

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
    /// `clear`.
    fn clear(&mut self, _scene: &Scene) {}
    /// `wait`.
    fn wait(&mut self) {}
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
    name: String,
    number: Option<u32>,
    surface: Surface,
    surface_type: SurfaceType,
    copy_of: Option<(u32, Location)>,
    geodesic: Option<(usize, Division, Location)>,
    radial: Option<(Radial, Location)>,
    pcolors: Option<(String, Location)>,
    vcolors: Option<(String, Location)>,
    stack_depth: usize,
    location: Location,
    det_base: PathBuf,
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
    files: Vec<PathBuf>,
    overrides: Vec<(char, String)>,
    warnings: Vec<Diagnostic>,
    budgets: Budgets,
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
            overrides: Vec::new(),
            warnings: Vec::new(),
            budgets: Budgets::default(),
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
    pub fn take_warnings(&mut self) -> Vec<Diagnostic> {
        std::mem::take(&mut self.warnings)
    }

    /// Forces a `setmode` value given on the command line (`-n on`): it is
    /// applied now and again after every statement, so it overrides the
    /// scene file. `letter` is the mode letter or a digit.
    pub fn force_mode(&mut self, letter: char, value: &str) -> Result<()> {
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
        let stmt: Statement = if letter.is_ascii_digit() {
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
        let budgets = self.budgets;
        *self = Interpreter::new();
        self.budgets = budgets;
        self.files = files;
        self.overrides = overrides;
        self.warnings = warnings;
        self.apply_overrides();
    }

    /// `get file` (with `init`) or `call file` (without), as if typed.
    /// A relative path is looked up beside the including file, then in the
    /// working directory.
    pub fn execute_file(&mut self, path: &Path, init: bool, host: &mut dyn Host) -> Result<Flow> {
        let source = std::fs::read(path).map_err(|e| Error::io(path, e))?;
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
        if self.files.contains(&canonical) {
            return Err(Error::at(
                Location::file(path),
                "this file includes itself (a `get`/`call` cycle)",
            ));
        }
        if init {
            self.init();
        }
        let dir = path
            .parent()
            .map(Path::to_path_buf)
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or_else(|| PathBuf::from("."));
        if init || self.files.is_empty() {
            self.det_base = dir.clone();
        }
        self.files.push(canonical);
        let result = self.execute_source(&source, path, &dir, host);
        self.files.pop();
        let flow = result?;
        if self.files.is_empty()
            && let Some(active) = &self.active
        {
            return Err(Error::at(
                active.location.clone(),
                format!(
                    "`defobj {}` has no `endobj` before the end of the input",
                    active.name
                ),
            ));
        }
        Ok(flow)
    }

    /// Executes the statements of `source`, which came from `file`.
    pub fn execute_source(
        &mut self,
        source: &str,
        file: &Path,
        dir: &Path,
        host: &mut dyn Host,
    ) -> Result<Flow> {
        let statements = lexer::lex(source, file)?;
        let ctx = Context {
            file,
            dir: dir.to_path_buf(),
            source,
        };
        for stmt in &statements {
            let flow = self.statement(&ctx, stmt, host)?;
            self.apply_overrides();
            if flow == Flow::Quit {
                return Ok(Flow::Quit);
            }
        }
        Ok(Flow::Continue)
    }

    fn statement(&mut self, ctx: &Context, stmt: &Statement, host: &mut dyn Host) -> Result<Flow> {
        let cmd = &stmt[0];
        let spec = match commands::lookup(&cmd.text) {
            Lookup::Found(spec) => spec,
            Lookup::Unknown(suggestion) => {
                let hint = suggestion
                    .map(|s| format!("; did you mean `{s}`?"))
                    .unwrap_or_else(|| "; `plytrace --help` lists the commands".into());
                return Err(ctx.error(cmd, format!("unknown command `{}`{hint}", cmd.text)));
            }
            Lookup::Ambiguous(names) => {
                return Err(ctx.error(
                    cmd,
                    format!(
                        "ambiguous command `{}`: it could be {}",
                        cmd.text,
                        names.join(", ")
                    ),
                ));
            }
        };
        let args = &stmt[1..];
        self.command(ctx, spec, cmd, args, host)
    }

    fn command(
        &mut self,
        ctx: &Context,
        spec: &CommandSpec,
        cmd: &Token,
        args: &[Token],
        host: &mut dyn Host,
    ) -> Result<Flow> {
        let a = Args {
            ctx,
            cmd,
            args,
            spec,
        };
        match spec.name {
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
                let path = resolve(&ctx.dir, &args[0].text);
                let canonical = path.canonicalize().unwrap_or_else(|_| path.clone());
                if self.files.contains(&canonical) {
                    return Err(ctx.error(
                        &args[0],
                        format!(
                            "`{}` is already being read: a `get`/`call` cycle",
                            args[0].text
                        ),
                    ));
                }
                let get = spec.name == "get";
                let start = std::time::Instant::now();
                if get {
                    host.scanning(&path);
                }
                let result = self.execute_file(&path, get, host);
                let flow =
                    result.map_err(|e| included_from(e, ctx.location(&args[0]), &args[0], ctx))?;
                if get {
                    host.scanned(&path, &self.scene(), start.elapsed());
                }
                return Ok(flow);
            }
            "callobj" => {
                a.count(1, 1)?;
                let n = a.integer(0, 0, u32::MAX as i64)? as u32;
                if !self.scene.objects.iter().any(|o| o.number == n) {
                    return Err(ctx.error(&args[0], format!("no object number {n} is defined")));
                }
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
                host.clear(&self.scene());
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
                    let n = a.integer(i, 0, u32::MAX as i64)? as u32;
                    let before = self.scene.objects.len();
                    self.scene.objects.retain(|o| o.number != n);
                    if self.scene.objects.len() == before {
                        return Err(ctx.error(&args[i], format!("no object number {n} is defined")));
                    }
                }
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
                let division = match args.get(1).map(|t| t.text.to_ascii_lowercase()) {
                    None => Division::EqualAngle,
                    Some(d) if d == "equal" => Division::Equal,
                    Some(d) if d == "angle" => Division::EqualAngle,
                    Some(_) => return Err(ctx.error(&args[1], "expected `equal` or `angle`")),
                };
                let loc = ctx.location(cmd);
                let Some(active) = &mut self.active else {
                    return Err(ctx.error(cmd, "`geodesic` outside an object definition"));
                };
                active.geodesic = Some((n, division, loc));
            }
            "radial" => {
                a.count(1, 4)?;
                let kind = args[0].text.to_ascii_lowercase();
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
                            "expected a radial function: sphere, ellipsoid, bumps or lobes",
                        ));
                    }
                };
                a.count(want, want)?;
                let loc = ctx.location(cmd);
                let Some(active) = &mut self.active else {
                    return Err(ctx.error(cmd, "`radial` outside an object definition"));
                };
                active.radial = Some((radial, loc));
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
                let kind = match args.get(7).map(|t| t.text.to_ascii_lowercase()) {
                    None => LightKind::Point,
                    Some(k) if !k.is_empty() && "point".starts_with(&k) => LightKind::Point,
                    Some(k) if !k.is_empty() && "diffuse".starts_with(&k) => LightKind::Diffuse,
                    Some(_) => return Err(ctx.error(&args[7], "expected `Point` or `Diffuse`")),
                };
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
                self.load(ctx, cmd, math::ortho2(v[0], v[1], v[2], v[3]))?;
            }
            "outmode" => {
                a.count(1, 2)?;
                let mode = args[0].text.to_ascii_lowercase();
                let bits_ok = |m: &str| m == "a";
                if args.len() == 2 && !bits_ok(&mode) {
                    return Err(ctx.error(&args[1], "only outmode `a` takes a second argument"));
                }
                self.scene.outmode = match mode.as_str() {
                    "c" => OutMode::Color,
                    "r" => OutMode::Red,
                    "g" => OutMode::Green,
                    "b" => OutMode::Blue,
                    "y" => OutMode::Luminance,
                    "a" => {
                        if args.len() != 2 {
                            return Err(
                                ctx.error(cmd, "outmode `a` needs the bits per colour (1-8)")
                            );
                        }
                        OutMode::Quantized(a.integer(1, 1, 8)? as u8)
                    }
                    _ => {
                        return Err(
                            ctx.error(&args[0], "expected an output mode: c, r, g, b, y or a")
                        );
                    }
                };
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
                return Ok(Flow::Quit);
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
                let axis = match args[1].text.to_ascii_lowercase().as_str() {
                    "x" => Axis::X,
                    "y" => Axis::Y,
                    "z" => Axis::Z,
                    _ => return Err(ctx.error(&args[1], "expected an axis: x, y or z")),
                };
                self.premultiply(ctx, cmd, math::rotate(angle, axis))?;
            }
            "run" => {
                a.count(0, 1)?;
                let shadows = match args.first().map(|t| t.text.to_ascii_lowercase()) {
                    None => false,
                    Some(y) if y == "y" || y == "yes" => true,
                    Some(n) if n == "n" || n == "no" => false,
                    Some(_) => return Err(ctx.error(&args[0], "expected `y` (shadows) or nothing")),
                };
                if self.active.is_some() {
                    return Err(ctx.error(cmd, "`run` inside an object definition"));
                }
                host.run(&self.scene(), shadows)
                    .map_err(|e| included_from(e, ctx.location(cmd), cmd, ctx))?;
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
                self.scene.sort_order = match args.first().map(|t| t.text.to_ascii_lowercase()) {
                    None => SortOrder::BackToFront,
                    Some(s) if s == "btf" => SortOrder::BackToFront,
                    Some(s) if s == "ftb" => SortOrder::FrontToBack,
                    Some(_) => return Err(ctx.error(&args[0], "expected `btf` or `ftb`")),
                };
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
                let mut t = SurfaceType::default();
                for (i, word) in args.iter().enumerate() {
                    match word.text.to_ascii_lowercase().as_str() {
                        "polygon" if i == 0 => {}
                        "open" => t.open = true,
                        "curved" => t.curved = true,
                        "concave" => t.concave = true,
                        "hidden" => t.hidden = true,
                        "ltsrc" => t.ltsrc = true,
                        _ if i == 0 => {
                            return Err(
                                ctx.error(word, "expected `polygon`, the only surface type")
                            );
                        }
                        _ => {
                            return Err(ctx.error(
                                word,
                                "expected a type attribute: open, curved, concave, hidden or ltsrc",
                            ));
                        }
                    }
                }
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
            other => unreachable!("command `{other}` is in the table but not interpreted"),
        }
        Ok(Flow::Continue)
    }

    fn setmode(&mut self, ctx: &Context, cmd: &Token, args: &[Token]) -> Result<()> {
        let a = Args {
            ctx,
            cmd,
            args,
            spec: commands::spec("setmode"),
        };
        a.count(1, 2)?;
        let letter_token = &args[0];
        let letter = letter_token.text.to_ascii_lowercase();
        let mut chars = letter.chars();
        let (Some(l), None) = (chars.next(), chars.next()) else {
            return Err(ctx.error(
                letter_token,
                "expected a mode letter (b d e h l n o p s v x) or a digit",
            ));
        };
        if l.is_ascii_digit() {
            a.count(1, 1)?;
            self.scene.modes.debug = l as u8 - b'0';
            return Ok(());
        }
        if args.len() < 2 && !matches!(l, 'i' | 'f') {
            return Err(ctx.error(letter_token, format!("mode `{l}` needs a value")));
        }
        let m = &mut self.scene.modes;
        match l {
            'b' => m.blend = a.on_off(1)?,
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
            'h' => m.shadow_shades = a.on_off(1)?,
            'l' => m.max_level = a.integer(1, 1, 14)? as u32,
            'n' => m.nns = a.on_off(1)?,
            'o' => m.output_tree = a.on_off(1)?,
            'p' => m.boxes_only = a.on_off(1)?,
            's' => m.phong = a.on_off(1)?,
            'v' => m.vertex_shades = a.on_off(1)?,
            'x' => m.expand = a.on_off(1)?,
            'i' | 'f' => {
                return Err(ctx.error(
                    letter_token,
                    format!("mode `{l}` can only be given on the command line (-{l})"),
                ));
            }
            _ => {
                return Err(ctx.error(
                    letter_token,
                    format!(
                        "unknown mode `{l}`: expected b, d, e, h, l, n, o, p, s, v, x or a digit"
                    ),
                ));
            }
        }
        Ok(())
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
                    cmd.text, active.name, active.location
                ),
            ));
        }
        self.push(ctx, cmd)?;
        self.active = Some(ActiveObject {
            name,
            number,
            surface: self.globals,
            surface_type: self.global_type,
            copy_of: None,
            geodesic: None,
            radial: None,
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
            return Err(ctx.error(cmd, "matrix stack underflow: the matrix `defobj` saved is gone"));
        };
        self.ctm = saved;

        let generated = match &active.geodesic {
            Some((n, division, loc)) => {
                let radial = active.radial.as_ref().map_or(Radial::Sphere, |r| r.0);
                Some(Arc::new(
                    geodesic::geodesic(*n, *division, radial)
                        .map_err(|e| Error::at(loc.clone(), e))?,
                ))
            }
            None => {
                if let Some((_, loc)) = &active.radial {
                    return Err(Error::at(
                        loc.clone(),
                        "`radial` deforms a `geodesic`; this object has none",
                    ));
                }
                None
            }
        };
        let (mesh, mut pcl, mut vcl) = match (generated, &active.copy_of) {
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
                    object_file::read_det(&path)?
                } else {
                    mesh_import::read_mesh(&path)?
                };
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
                self.warnings.push(Diagnostic::new(ctx.location(cmd), msg));
            },
        )
        .map_err(|msg| ctx.error(cmd, msg))?;
        self.scene.objects.push(object);
        Ok(())
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
        dirs
    }

    fn find_object_file(&self, active: &ActiveObject) -> Result<PathBuf> {
        let mut tried = Vec::new();
        for dir in self.det_dirs(active) {
            for ext in std::iter::once("det").chain(mesh_import::MESH_EXTENSIONS.iter().copied()) {
                let p = dir.join(format!("{}.{ext}", active.name));
                if p.is_file() {
                    return Ok(p);
                }
                tried.push(p);
            }
        }
        let tried: Vec<String> = tried.iter().map(|p| p.display().to_string()).collect();
        Err(Error::at(
            active.location.clone(),
            format!(
                "no geometry file for object `{}` (tried {}); set `det_dir`",
                active.name,
                tried.join(", ")
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
        for dir in self.det_dirs(active) {
            let p = dir.join(format!("{name}.{ext}"));
            if p.is_file() {
                return object_file::read_colors(&p, kind);
            }
        }
        Err(Error::at(
            loc.clone(),
            format!("colour file `{name}.{ext}` not found in the detail directory"),
        ))
    }
}

/// What `endobj` needs to build an [`Object`].
pub struct ObjectParts {
    /// Object number.
    pub number: u32,
    /// Name.
    pub name: String,
    /// Geometry in object coordinates.
    pub mesh: Arc<Mesh>,
    /// Polygon colours.
    pub polygon_colors: Option<Arc<Vec<ColorEntry>>>,
    /// Vertex colours.
    pub vertex_colors: Option<Arc<Vec<ColorEntry>>>,
    /// Object to world.
    pub transform: Matrix4,
    /// Surface attributes.
    pub surface: Surface,
    /// Type attributes.
    pub surface_type: SurfaceType,
}

/// Transforms an object to world coordinates and computes its planes
/// (004 section 4.3). Degenerate polygons (fewer than three distinct
/// vertices, zero area) are skipped and non-planar ones split into a
/// triangle fan, each with a warning through `warn`. A transform with a
/// negative determinant (a mirror image) reverses the vertex order so that
/// polygons stay clockwise from outside. Fails on non-finite coordinates.
pub fn build_object(parts: ObjectParts, warn: &mut dyn FnMut(String)) -> Result<Object, String> {
    let ObjectParts {
        number,
        name,
        mesh,
        polygon_colors,
        vertex_colors,
        transform,
        surface,
        surface_type,
    } = parts;
    let vertices: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|v| transform.transform_point(*v))
        .collect();
    if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
        return Err(format!(
            "object `{name}`: vertex {} is not finite after transformation by the CTM (a projection is still on the CTM, or a number overflowed; scenes usually `pushmatrix` and `ident` before defining objects)",
            i + 1
        ));
    }
    let mirrored = linear_determinant(&transform) < 0.0;
    let mut polygons = Vec::with_capacity(mesh.polygons.len());
    let mut source_polygon = Vec::with_capacity(mesh.polygons.len());
    for (pi, indices) in mesh.polygons.iter().enumerate() {
        let mut indices = indices.clone();
        if mirrored {
            indices.reverse();
        }
        let points: Vec<DVec3> = indices.iter().map(|&i| vertices[i as usize]).collect();
        match polygon::outward_plane(&points) {
            Ok(plane) => {
                polygons.push(Polygon { indices, plane });
                source_polygon.push(pi as u32);
            }
            Err(PolygonDefect::TooFewVertices(n)) => warn(format!(
                "warning: object `{name}` polygon {}: only {n} distinct vertices; skipped",
                pi + 1
            )),
            Err(PolygonDefect::ZeroArea) => warn(format!(
                "warning: object `{name}` polygon {}: zero area; skipped",
                pi + 1
            )),
            Err(PolygonDefect::NonPlanar(off)) => {
                warn(format!(
                    "warning: object `{name}` polygon {}: not planar (off by {off:.2e} of its size); split into triangles",
                    pi + 1
                ));
                for k in 1..indices.len() - 1 {
                    let tri = vec![indices[0], indices[k], indices[k + 1]];
                    let pts: Vec<DVec3> = tri.iter().map(|&i| vertices[i as usize]).collect();
                    if let Ok(plane) = polygon::outward_plane(&pts) {
                        polygons.push(Polygon {
                            indices: tri,
                            plane,
                        });
                        source_polygon.push(pi as u32);
                    }
                }
            }
        }
    }
    let vertex_normals = surface_type.curved.then(|| {
        let faces: Vec<(Vec<u32>, DVec3)> = polygons
            .iter()
            .map(|p| (p.indices.clone(), p.normal()))
            .collect();
        polygon::vertex_normals(vertices.len(), &faces)
    });
    let (lo, hi) = mesh.vertices.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(*v), hi.max(*v)),
    );
    let (lo, hi) = if mesh.vertices.is_empty() {
        (DVec3::ZERO, DVec3::ZERO)
    } else {
        (lo, hi)
    };
    let mut bbox_corners = [DVec3::ZERO; 8];
    for (i, c) in bbox_corners.iter_mut().enumerate() {
        let p = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        *c = transform.transform_point(p);
    }
    Ok(Object {
        number,
        name,
        mesh,
        polygon_colors,
        vertex_colors,
        transform,
        vertices,
        polygons,
        source_polygon,
        vertex_normals,
        bbox_corners,
        surface,
        surface_type,
    })
}

fn linear_determinant(m: &Matrix4) -> f64 {
    let a = &m.m;
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
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
        Error::Io { path, source } if source.kind() == std::io::ErrorKind::NotFound => {
            ctx.error(token, format!("cannot open `{}`: {source}", path.display()))
        }
        other => other,
    }
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
            Ok(_) => Err(self
                .ctx
                .error(t, format!("expected a finite number, found `{}`", t.text))),
            Err(_) => Err(self
                .ctx
                .error(t, format!("expected a number, found `{}`", t.text))),
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
            self.ctx
                .error(t, format!("expected a whole number, found `{}`", t.text))
        })?;
        if v < min || v > max {
            return Err(self.ctx.error(
                t,
                format!("expected a whole number from {min} to {max}, found {v}"),
            ));
        }
        Ok(v)
    }

    fn on_off(&self, i: usize) -> Result<bool> {
        let t = &self.args[i];
        match t.text.to_ascii_lowercase().as_str() {
            "on" | "1" | "true" | "yes" => Ok(true),
            "off" | "0" | "false" | "no" => Ok(false),
            _ => Err(self
                .ctx
                .error(t, format!("expected `on` or `off`, found `{}`", t.text))),
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

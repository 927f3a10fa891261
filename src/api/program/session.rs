//! The scene descriptor language's interpreter as a program drives it
//! (004 appendix B): statements from a file, a text or the prompt, each
//! `run` handed to a [`Host`], and the command table that the help texts
//! and the prompt's completion are made from.

/// The interpreter of the scene descriptor language: it reads statements,
/// builds the scene and asks its [`Host`] to render on `run`.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::session::{Flow, Interpreter, NoHost};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut interp = Interpreter::new();
/// let text = "resolution 32 16\nbackground 1 0 0\n";
/// let flow = interp.execute_source(text, Path::new("s.des"), Path::new("."), &mut NoHost)?;
/// assert_eq!(flow, Flow::Continue);
/// let scene = interp.scene();
/// assert_eq!((scene.viewport.width(), scene.viewport.height()), (32, 16));
/// assert!(interp.check_source("resolution 32", Path::new("s.des")).is_err(), "one number short");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::Interpreter;

/// What the interpreter asks of the program around it: above all, to
/// render the scene on `run` (`run y` casts shadows).
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::session::{Host, Interpreter, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// struct Runs(Vec<(u32, u32, bool)>);
/// impl Host for Runs {
///     fn run(&mut self, scene: &Scene, shadows: bool) -> plytrace::Result<()> {
///         self.0.push((scene.viewport.width(), scene.viewport.height(), shadows));
///         Ok(())
///     }
/// }
/// let mut host = Runs(Vec::new());
/// let text = "resolution 8 4\nrun\nresolution 2 2\nrun y\n";
/// Interpreter::new().execute_source(text, Path::new("s.des"), Path::new("."), &mut host)?;
/// assert_eq!(host.0, [(8, 4, false), (2, 2, true)]);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::Host;

/// A [`Host`] that renders nothing (for reading a scene).
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::session::{Interpreter, NoHost};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut interp = Interpreter::new();
/// interp.execute_source("resolution 4 4\nrun\n", Path::new("s.des"), Path::new("."), &mut NoHost)?;
/// assert_eq!(interp.scene().viewport.width(), 4);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::NoHost;

/// Whether a session goes on after a statement: `quit` ends it.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::session::{Flow, Interpreter, NoHost};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut interp = Interpreter::new();
/// let flow = interp.execute_source("quit\n", Path::new("s.des"), Path::new("."), &mut NoHost)?;
/// assert_eq!(flow, Flow::Quit);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::Flow;

/// The world a `run` renders, as the interpreter built it: the viewport,
/// the modes of `setmode`, the objects, lights and surfaces (the
/// library's model, which [`crate::api::Scene`] wraps for callers who
/// build scenes in code).
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::session::{Interpreter, NoHost, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// let mut interp = Interpreter::new();
/// let text = "resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n";
/// interp.execute_source(text, Path::new("cube.des"), &dir, &mut NoHost)?;
/// let scene: Scene = interp.scene();
/// assert_eq!(scene.objects.len(), 1);
/// assert_eq!(scene.polygon_count(), 6, "a cube's faces");
/// assert!(Scene::default().objects.is_empty());
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::Scene;

/// Every command of the scene descriptor language, with its usage and
/// help text: `help`, `--help` and the prompt's Tab completion list them.
///
/// ```
/// use plytrace::api::program::session::{CommandSpec, COMMANDS};
///
/// let run: &CommandSpec = COMMANDS.iter().find(|c| c.name == "run").unwrap();
/// assert!(run.manual, "`run` is on the manual page");
/// assert!(COMMANDS.iter().all(|c| !c.help.is_empty()));
/// ```
#[doc(inline)]
pub use crate::scene::commands::COMMANDS;

/// One entry of [`COMMANDS`].
///
/// ```
/// use plytrace::api::program::session::COMMANDS;
///
/// let names: Vec<&str> = COMMANDS.iter().map(|c| c.name).collect();
/// assert!(names.contains(&"defobj") && names.contains(&"lookat"));
/// ```
#[doc(inline)]
pub use crate::scene::commands::CommandSpec;

/// The most bytes a scene file (or a scene on standard input) may hold.
///
/// ```
/// use plytrace::api::program::session::MAX_SCENE_BYTES;
///
/// assert_eq!(MAX_SCENE_BYTES, 16 << 20);
/// ```
#[doc(inline)]
pub use crate::scene::interpreter::MAX_SCENE_BYTES;

/// Reads a regular file of at most `limit` bytes, as the interpreter
/// reads its files: a directory, device or FIFO is refused, and so is a
/// longer file.
///
/// ```
/// use plytrace::api::program::session::{read_regular, MAX_SCENE_BYTES};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-read_regular", std::process::id()));
/// std::fs::write(&path, b"0123456789").map_err(|e| plytrace::Error::io(&path, e))?;
/// let whole = read_regular(&path, MAX_SCENE_BYTES);
/// let short = read_regular(&path, 9);
/// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// assert_eq!(whole?, b"0123456789");
/// assert!(short.is_err(), "longer than the limit");
/// assert!(read_regular(&std::env::temp_dir(), MAX_SCENE_BYTES).is_err(), "a directory");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::object_file::read_regular;

/// A text made safe and short for a message: control characters escaped,
/// and cut after `max` characters.
///
/// ```
/// use plytrace::api::program::session::printable;
///
/// assert_eq!(printable("a\x1b[2Jb", 40), "a\\x1b[2Jb");
/// assert_eq!(printable("abcdef", 3), "abc... (6 characters)");
/// ```
#[doc(inline)]
pub use crate::error::printable;

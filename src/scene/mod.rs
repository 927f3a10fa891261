//! Scene description (Garcia 1986, 004 section 4.3 and appendix): the
//! scene descriptor language, object files and the scene model it builds.

mod arguments;
pub mod build;
mod command;
pub mod commands;
pub mod interpreter;
pub mod lexer;
pub mod mesh_import;

pub mod object_file;
mod parse;

pub use crate::model::Scene;
pub use interpreter::{Flow, Host, Interpreter, NoHost};

use std::path::Path;

use crate::error::Result;

/// [`load`], also returning the notes ([`Interpreter::take_notes`]:
/// information that is not a warning, such as a CSG operation's figures).
#[allow(clippy::type_complexity)]
pub fn load_with_notes(
    path: &Path,
) -> Result<(
    Scene,
    Vec<crate::error::Diagnostic>,
    Vec<crate::error::Diagnostic>,
)> {
    let mut interp = Interpreter::new();
    interp.execute_file(path, true, &mut NoHost)?;
    let warnings = interp.take_warnings();
    let notes = interp.take_notes();
    Ok((interp.into_scene(), warnings, notes))
}

/// Reads a scene file as `get file` would, ignoring `run`, `clear` and
/// `wait`; returns the scene and the warnings.
pub fn load(path: &Path) -> Result<(Scene, Vec<crate::error::Diagnostic>)> {
    let mut interp = Interpreter::new();
    interp.execute_file(path, true, &mut NoHost)?;
    let warnings = interp.take_warnings();
    Ok((interp.into_scene(), warnings))
}

//! One `run` of the scene language with its files (004 appendix B,
//! `run`): the outputs created before anything is rendered, the picture
//! made by the path the settings choose (vector drawing, the virtual image
//! tree streamed in bands or kept whole, the ray tracer, one part of the
//! image), and every file committed together or not at all. A program
//! says what to write in a [`RunSpec`] and prints the [`RunReport`]; a
//! [`RunObserver`] sees the rows go by (a progress bar) and the warnings.
//!
//! ```
//! # use std::path::Path;
//! use plytrace::api::program::display::LiveDisplay;
//! use plytrace::api::program::pipeline::{RenderOptions, Reuse};
//! use plytrace::api::program::run::{run, RunSpec, Unobserved};
//! use plytrace::api::program::session::{Interpreter, NoHost};
//!
//! # fn main() -> Result<(), plytrace::Error> {
//! # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
//! # let mut interp = Interpreter::new();
//! # interp.execute_source("resolution 16 16\nsetmode o on\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
//! # let scene = interp.scene();
//! let tmp = std::env::temp_dir().join(format!("plytrace-doc-{}-run", std::process::id()));
//! std::fs::create_dir_all(&tmp).map_err(|e| plytrace::Error::io(&tmp, e))?;
//! let spec = RunSpec {
//!     image: tmp.join("cube.png"),
//!     id_image: None,
//!     tree_stem: Some(tmp.join("cube").display().to_string()),
//!     options: RenderOptions::default(),
//!     hidden_line: false,
//!     raytrace: false,
//!     part: None,
//! };
//! let report = run(&scene, &spec, &Reuse::default(), &mut LiveDisplay::default(), &mut Unobserved)?;
//! assert_eq!(report.size, (16, 16));
//! assert_eq!(report.written.len(), 3, "the image and the tree's two files");
//! let all_there = report.written.iter().all(|p| p.exists());
//! std::fs::remove_dir_all(&tmp).map_err(|e| plytrace::Error::io(&tmp, e))?;
//! assert!(all_there);
//! # Ok(())
//! # }
//! ```

/// What a run writes and how it renders.
pub use crate::run::RunSpec;

/// A part of the image (`--part I/N`): which, and what its file says of
/// the whole.
pub use crate::run::PartRun;

/// What a run made: the render, the image's size, the files committed.
pub use crate::run::RunReport;

/// Sees a run as it goes: its rows and warnings.
pub use crate::run::RunObserver;

/// An observer that sees nothing.
pub use crate::run::Unobserved;

/// Renders a scene as a [`RunSpec`] says and commits its files together.
pub use crate::run::run;

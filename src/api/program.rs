//! What the programs of the system use beside the scenes and renders of
//! [`crate::api`]: the `plytrace` program (the interpreter's session and
//! its prompt, every flag's render option, the run's output files, parts
//! and their merge, signals) and the manual's other programs (rftb1-rftb4,
//! getrgb, mkdet, mkpcl, mkvcl; 004 appendix B), which are each a line
//! over an entry point of [`tools`]. They use this module like any other
//! program would.
//!
//! ```
//! use std::path::Path;
//! use plytrace::api::program::session::{Interpreter, NoHost};
//! use plytrace::api::program::pipeline::{plan_with, Plan, RenderOptions, Reuse};
//!
//! # fn main() -> Result<(), plytrace::Error> {
//! let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
//! let mut interp = Interpreter::new();
//! let text = "resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n";
//! interp.execute_source(text, Path::new("cube.des"), &dir, &mut NoHost)?;
//! let plan = plan_with(&interp.scene(), &RenderOptions::default(), &Reuse::default())?;
//! assert!(matches!(plan, Plan::Tree(_)), "the depth sort scan converts the tree");
//! # Ok(())
//! # }
//! ```

pub mod control;
pub mod display;
pub mod files;
pub mod parts;
pub mod pipeline;
pub mod rows;
pub mod run;
pub mod session;
pub mod tools;

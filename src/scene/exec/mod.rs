//! The handlers of the scene descriptor language's commands (Garcia 1986,
//! 004 appendix B, the plytrace manual page), grouped by concern: what
//! each [`Command`](super::command::Command) does to the interpreter's
//! state once it has been parsed. [`super::interpreter`] dispatches to
//! them.
//!
//! - [`view`]: viewing, projections, transforms and the matrix stack;
//! - [`objects`]: `defobj` ... `endobj`, `callobj`, `delobj`, geodesics;
//! - [`generators`]: the modeling commands (Firebaugh's primitives, CSG);
//! - [`surface`]: surface attributes of the active object or the globals;
//! - [`lighting`]: lights, `setmode` and the scene-wide settings;
//! - [`files`]: `call`, `get`, `det_dir`, `init`, `run`, the display.

pub(super) mod files;
pub(super) mod generators;
pub(super) mod lighting;
pub(super) mod objects;
pub(super) mod surface;
pub(super) mod view;

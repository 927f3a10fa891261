//! plytrace: a list-priority renderer after A. Garcia, *Efficient Rendering
//! of Synthetic Images* (MIT 1986), with the visible-surface methods of
//! Donovan (1973), Brown (1978) and Firebaugh.
//!
//! The library's face is [`api`]: a scene read from a scene descriptor
//! file or built in code, rendered to pixels or vector graphics, and (in
//! [`api::program`]) what the `plytrace` program and the manual's other
//! programs use. Behind it, the modules follow the pipeline of Garcia's
//! figure 3.2: scene (language, object files) -> geometry (transform,
//! cull, clip, project) -> visibility (sorting) -> shading -> the virtual
//! image tree -> raster (scan conversion) -> output; `ARCHITECTURE.md`
//! describes them. They are not part of the documented API: those still
//! public are so for the integration tests, benches, examples and fuzz
//! targets, and are hidden from the documentation.
#![warn(missing_docs)]

pub mod api;
// Public for the tests, benches and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod budget;
// Public for the tests and the Python crate; not part of the API.
#[doc(hidden)]
pub mod cancel;
pub(crate) mod convert;
// Public for the tests; not part of the API.
#[doc(hidden)]
pub mod display;
// Public for the tests; not part of the API.
#[doc(hidden)]
pub mod emit;
// Public for the tests and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod error;
// Public for the tests, benches and examples; not part of the API.
#[doc(hidden)]
pub mod geometry;
// Public for the tests and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod image_tree;
pub(crate) mod input_guard;
// Public for the tests; not part of the API.
#[doc(hidden)]
pub mod math;
// Public for the tests, benches, examples and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod model;
// Public for the tests, benches and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod modeling;
// Public for the tests and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod output;
// Public for the tests; not part of the API.
#[doc(hidden)]
pub mod part;
pub(crate) mod precision;
pub(crate) mod profile;
// Public for the tests, benches and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod raster;
// Public for the tests and benches; not part of the API.
#[doc(hidden)]
pub mod raytrace;
// Public for the tests, benches and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod render;
// Public for the fuzz targets; not part of the API.
#[doc(hidden)]
pub mod rftb;
// Public for the tests, benches, examples and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod scene;
// Public for the tests and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod shading;
pub(crate) mod shadow;
pub(crate) mod signals;
// Public for the tests, benches and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod tree;
// Public for the tests and benches; not part of the API.
#[doc(hidden)]
pub mod vector;
// Public for the tests, benches and fuzz targets; not part of the API.
#[doc(hidden)]
pub mod visibility;

pub use error::{Error, Result};

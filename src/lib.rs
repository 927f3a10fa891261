//! plytrace: a list-priority renderer after A. Garcia, *Efficient Rendering
//! of Synthetic Images* (MIT 1986), with the visible-surface methods of
//! Donovan (1973), Brown (1978) and Firebaugh.
//!
//! The modules follow the pipeline of Garcia's figure 3.2:
//! [`scene`] (language, object files) -> [`geometry`] (transform, cull,
//! clip, project) -> [`visibility`] (sorting) -> [`shading`] ->
//! [`raster`] (scan conversion) -> [`output`]; [`render`] runs them in
//! order. [`math`] and the precision policy depend on nothing.
#![warn(missing_docs)]

pub mod api;
pub mod budget;
pub mod cancel;
pub mod convert;
pub mod display;
pub mod emit;
pub mod error;
pub mod geometry;
pub mod image_tree;
pub(crate) mod input_guard;
pub mod math;
pub mod model;
pub mod modeling;
pub mod output;
pub mod part;
pub(crate) mod precision;
pub(crate) mod profile;
pub mod raster;
pub mod raytrace;
pub mod render;
pub mod rftb;
pub mod scene;
pub mod shading;
pub(crate) mod shadow;
pub mod signals;
pub mod tree;
pub mod vector;
pub mod visibility;

pub use error::{Error, Result};

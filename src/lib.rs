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
//! describes them. They are private; the benches, fuzz targets and the
//! tests of internal details reach them through the hidden
//! `internal` module, which is not part of the API.
#![warn(missing_docs)]
// The modules behind `api` are private and documented for the developers
// (`cargo doc --document-private-items`), so their docs may link to each other.
#![allow(rustdoc::private_intra_doc_links)]

pub mod api;
mod budget;
mod cancel;
mod convert;
mod display;
mod emit;
mod error;
mod geometry;
mod image_tree;
mod input_guard;
mod math;
mod model;
mod modeling;
mod output;
mod part;
mod precision;
mod profile;
mod raster;
mod raytrace;
mod render;
mod rftb;
mod run;
mod scene;
mod shading;
mod shadow;
mod signals;
mod threads;
mod tree;
mod vector;
mod visibility;

pub use error::{Error, Result};

/// The pipeline's stages, for the benches, the fuzz targets and the tests
/// of internal details; not part of the API (no stability promised).
#[doc(hidden)]
pub mod internal {
    #[allow(missing_docs)]
    pub mod budget {
        pub use crate::budget::*;
    }
    #[allow(missing_docs)]
    pub mod cancel {
        pub use crate::cancel::*;
    }
    #[allow(missing_docs)]
    pub mod display {
        pub use crate::display::*;
    }
    #[allow(missing_docs)]
    pub mod emit {
        pub use crate::emit::*;
    }
    #[allow(missing_docs)]
    pub mod error {
        pub use crate::error::*;
    }
    #[allow(missing_docs)]
    pub mod geometry {
        pub use crate::geometry::*;
    }
    #[allow(missing_docs)]
    pub mod image_tree {
        pub use crate::image_tree::*;
    }
    #[allow(missing_docs)]
    pub mod math {
        pub use crate::math::*;
    }
    #[allow(missing_docs)]
    pub mod model {
        pub use crate::model::*;
    }
    #[allow(missing_docs)]
    pub mod modeling {
        pub use crate::modeling::*;
    }
    #[allow(missing_docs)]
    pub mod output {
        pub use crate::output::*;
    }
    #[allow(missing_docs)]
    pub mod part {
        pub use crate::part::*;
    }
    #[allow(missing_docs)]
    pub mod raster {
        pub use crate::raster::*;
    }
    #[allow(missing_docs)]
    pub mod raytrace {
        pub use crate::raytrace::*;
    }
    #[allow(missing_docs)]
    pub mod render {
        pub use crate::render::*;
    }
    #[allow(missing_docs)]
    pub mod rftb {
        pub use crate::rftb::*;
    }
    #[allow(missing_docs)]
    pub mod scene {
        pub use crate::scene::*;
    }
    #[allow(missing_docs)]
    pub mod shading {
        pub use crate::shading::*;
    }
    #[allow(missing_docs)]
    pub mod tree {
        pub use crate::tree::*;
    }
    #[allow(missing_docs)]
    pub mod vector {
        pub use crate::vector::*;
    }
    #[allow(missing_docs)]
    pub mod visibility {
        pub use crate::visibility::*;
    }
}

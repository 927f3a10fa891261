//! The small public face of the library: a [`Scene`] read from a scene
//! descriptor file or built in code from arrays, and [`fn@render`],
//! [`render_vector`] and [`render_rows`] to turn it into pixels or vector
//! graphics. Everything the `plytrace` program does with a scene goes
//! through the modules behind it (Garcia 1986, figure 3.2: scene →
//! geometry → visibility → virtual image tree → scan conversion); this
//! module only gathers what a caller needs and checks what it is given.
//!
//! ```
//! use plytrace::api::{Camera, Light, Material, MeshData, Options, Scene, VectorFormat};
//!
//! let cube = MeshData::new(
//!     vec![[-1., -1., -1.], [1., -1., -1.], [1., 1., -1.], [-1., 1., -1.],
//!          [-1., -1., 1.], [1., -1., 1.], [1., 1., 1.], [-1., 1., 1.]],
//!     vec![vec![0, 3, 2, 1], vec![4, 5, 6, 7], vec![0, 1, 5, 4],
//!          vec![2, 3, 7, 6], vec![1, 2, 6, 5], vec![0, 4, 7, 3]],
//! );
//! let mut scene = Scene::new(Camera::looking_at([4., -6., 3.], [0., 0., 0.]), 64, 64);
//! scene.add_light(Light::point([5., -5., 8.], [1., 1., 1.]))?;
//! scene.add_mesh("cube", &cube, &Material::color([0.2, 0.6, 1.0]))?;
//! let image = plytrace::api::render(&scene, &Options::default())?;
//! assert_eq!((image.width, image.height, image.rgb.len()), (64, 64, 64 * 64 * 3));
//! let png = image.to_png()?;
//! let svg = plytrace::api::render_vector(&scene, &Options::default(), VectorFormat::Svg)?;
//! assert!(png.starts_with(b"\x89PNG") && svg.starts_with(b"<?xml"));
//! # Ok::<(), plytrace::Error>(())
//! ```

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::math::{self, Matrix4};
use crate::model::{self, LightKind, Surface, SurfaceType, Viewport};
use crate::model::{ColorEntry, Mesh};
use crate::render::{self, RenderOptions, RenderStats};
use crate::scene::build::{ObjectParts, build_object};

pub mod program;
mod projected;

pub use projected::{Layered, PaintOrder, Patch, PlacedSegment, Projected, Ring, SegmentPiece};

mod camera;
mod checks;
mod image;
mod light;
mod material;
mod mesh_data;
mod options;
mod rendering;
mod scene;

pub use camera::{Camera, Projection};
use checks::*;
pub use image::Image;
pub use light::Light;
pub use material::Material;
pub use mesh_data::MeshData;
pub use options::Options;
pub use rendering::{render, render_rows, render_vector};
pub use scene::Scene;

/// Limits on the work of a render (the program's `--max-*` flags): the
/// image's pixels, polygons, tree nodes, splits, memory, rays. A render
/// over one stops with an error that names the flag that raises it.
///
/// ```
/// use plytrace::api::{render, Budgets, Camera, Options, Scene};
///
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 64, 64);
/// let tight = Budgets { pixels: 1000, ..Budgets::default() };
/// let e = render(&scene, &Options::default().with_budgets(tight)).unwrap_err();
/// assert!(e.to_string().contains("--max-pixels"));
/// assert!(Budgets::default().pixels >= 64 * 64);
/// ```
#[doc(inline)]
pub use crate::budget::Budgets;

/// The largest side of an image and the most pixels it may have, as the
/// scene language's `resolution` and the program's `--size` allow:
/// [`fn@render`] and [`render_vector`] refuse a size beyond them.
///
/// ```
/// use plytrace::api::{render, Camera, Options, Scene, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
///
/// assert_eq!((MAX_IMAGE_SIDE, MAX_IMAGE_PIXELS), (65536, 1 << 28));
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
/// let wide = Options::default().with_size(65537, 1);
/// assert!(render(&scene, &wide).is_err());
/// ```
pub use crate::scene::interpreter::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};

/// The anti-aliasing methods of [`Options::antialiasing`] (the scan
/// conversion methods of the virtual image tree).
///
/// ```
/// use plytrace::api::{render, Antialiasing, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
/// scene.set_background([0., 1., 0.])?;
/// let options = Options::default().with_antialiasing(Antialiasing::Supersample(2));
/// let image = render(&scene, &options)?;
/// assert!(image.rgb.chunks(3).all(|p| p == [0, 255, 0]));
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::raster::scan::Method as Antialiasing;
/// The vector formats of [`render_vector`]; [`VectorFormat::from_path`]
/// picks one by a file name's extension.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::VectorFormat;
///
/// assert_eq!(VectorFormat::from_path(Path::new("cube.SVG")), Some(VectorFormat::Svg));
/// assert_eq!(VectorFormat::from_path(Path::new("cube.tex")), Some(VectorFormat::Tikz));
/// assert_eq!(VectorFormat::from_path(Path::new("cube.png")), None);
/// ```
#[doc(inline)]
pub use crate::vector::Format as VectorFormat;

#[cfg(test)]
mod tests;

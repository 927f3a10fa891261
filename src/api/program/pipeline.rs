//! A `run` as the program renders it: the options of every flag, the plan
//! (a virtual image tree to scan convert, or an image painted by an
//! image-space algorithm), the scan conversion into any row sink, and
//! the figures the program reports (Garcia 1986, figure 3.2).
//!
//! The examples read this scene, a cube from `tests/data/scenes/det`:
//!
//! ```
//! use std::path::Path;
//! use plytrace::api::program::session::{Interpreter, NoHost};
//!
//! # fn main() -> Result<(), plytrace::Error> {
//! let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
//! let mut interp = Interpreter::new();
//! let text = "resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n";
//! interp.execute_source(text, Path::new("cube.des"), &dir, &mut NoHost)?;
//! assert_eq!(interp.scene().polygon_count(), 6);
//! # Ok(())
//! # }
//! ```

/// The options of a render, one for each of the program's flags that
/// decide the pixels (`--size`, `--visibility`, `--supersample`, ...).
///
/// ```
/// use plytrace::api::program::pipeline::{Algorithm, RenderOptions};
///
/// let options = RenderOptions { size: Some((8, 8)), visibility: Some(Algorithm::ZBuffer), ..RenderOptions::default() };
/// assert_eq!(options.threads, 0, "all cores unless --threads");
/// assert!(options.visibility.is_some());
/// ```
#[doc(inline)]
pub use crate::render::RenderOptions;

/// The figures of a render (004 appendix B: "the total number of
/// polygons tiled, maximum recursion level, and the elapsed time"), and
/// the program's own.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, scan_into, Plan, Reuse, RenderOptions, RenderStats};
/// use plytrace::api::program::rows::FrameBuffer;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let Plan::Tree(prepared) = plan_with(&scene, &RenderOptions::default(), &Reuse::default())? else {
///     unreachable!("the depth sort")
/// };
/// let stats: RenderStats = scan_into(*prepared, &mut FrameBuffer::new(16, 16, [0.0; 3]))?.stats;
/// assert!(stats.polygons_tiled > 0 && stats.polygons_tiled <= 6, "the cube's visible faces");
/// assert_eq!(RenderStats::default().polygons_tiled, 0);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::RenderStats;

/// A rendered image (a frame buffer with the ids of the polygons painted
/// where) and its figures.
///
/// ```
/// use plytrace::api::program::pipeline::{RenderStats, Rendered};
///
/// let rendered = Rendered::empty(RenderStats { polygons_tiled: 3, ..RenderStats::default() });
/// assert_eq!((rendered.frame.width, rendered.stats.polygons_tiled), (0, 3));
/// assert!(rendered.tree.is_none());
/// ```
#[doc(inline)]
pub use crate::render::Rendered;

/// What a render comes to before its pixels: a tree to scan convert, or
/// an image already painted.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Algorithm, Plan, Reuse, RenderOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let z = RenderOptions { visibility: Some(Algorithm::ZBuffer), ..RenderOptions::default() };
/// match plan_with(&scene, &z, &Reuse::default())? {
///     Plan::Painted(rendered) => assert_eq!(rendered.frame.width, 16),
///     Plan::Tree(_) => unreachable!("the z-buffer paints the image itself"),
/// }
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::Plan;

/// A virtual image tree ready for scan conversion: its records and the
/// scan converter's options (size, method).
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Plan, Prepared, Reuse, RenderOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let options = RenderOptions { size: Some((20, 10)), ..RenderOptions::default() };
/// let Plan::Tree(prepared) = plan_with(&scene, &options, &Reuse::default())? else { unreachable!() };
/// let prepared: Prepared = *prepared;
/// assert_eq!((prepared.scan.width, prepared.scan.height), (20, 10));
/// assert!(!prepared.picture.records.is_empty());
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::Prepared;

/// Plans the render of a scene with `options`; `orders` keeps Brown's
/// priority orders from one frame of an animation to the next.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Algorithm, Plan, Reuse, RenderOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let plan = plan_with(&scene, &RenderOptions::default(), &Reuse::default())?;
/// assert!(matches!(plan, Plan::Tree(_)));
/// let z = RenderOptions { visibility: Some(Algorithm::ZBuffer), ..RenderOptions::default() };
/// assert!(matches!(plan_with(&scene, &z, &Reuse::default())?, Plan::Painted(_)));
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::plan_with;

/// Scan converts a prepared tree into a row sink, top to bottom.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, scan_into, Plan, Reuse, RenderOptions};
/// use plytrace::api::program::rows::FrameBuffer;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let Plan::Tree(prepared) = plan_with(&scene, &RenderOptions::default(), &Reuse::default())? else { unreachable!() };
/// let mut frame = FrameBuffer::new(16, 16, [0.0; 3]);
/// scan_into(*prepared, &mut frame)?;
/// assert_ne!(frame.color[8 * 16 + 8], [0.0; 3], "the cube in the middle");
/// assert_eq!(frame.color[0], [0.0; 3], "the black background in the corner");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::scan_into;

/// Scan converts the rows `rows` of a prepared tree alone (a part of the
/// image), each as the whole image has it.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, scan_rows_into, Plan, Reuse, RenderOptions};
/// use plytrace::api::program::rows::{Row, RowSink};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// struct Ys(Vec<u32>);
/// impl RowSink for Ys {
///     fn row(&mut self, row: &Row<'_>) -> plytrace::Result<()> {
///         self.0.push(row.y);
///         Ok(())
///     }
/// }
/// let Plan::Tree(prepared) = plan_with(&scene, &RenderOptions::default(), &Reuse::default())? else { unreachable!() };
/// let mut ys = Ys(Vec::new());
/// scan_rows_into(*prepared, 4..7, &mut ys)?;
/// assert_eq!(ys.0, [4, 5, 6]);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::scan_rows_into;

/// The visible-surface algorithm a render of a scene uses: the option's,
/// else the scene's (NNS, unless `setmode n off` asks for the simple
/// depth sort).
///
/// ```
/// use plytrace::api::program::pipeline::{chosen_algorithm, Algorithm, RenderOptions};
/// use plytrace::api::program::session::Scene;
///
/// let mut scene = Scene::default();
/// assert_eq!(chosen_algorithm(&scene, &RenderOptions::default()), Algorithm::Nns);
/// scene.modes.nns = false; // setmode n off
/// assert_eq!(chosen_algorithm(&scene, &RenderOptions::default()), Algorithm::DepthSort);
/// let nns = RenderOptions { visibility: Some(Algorithm::Nns), ..RenderOptions::default() };
/// assert_eq!(chosen_algorithm(&scene, &nns), Algorithm::Nns);
/// ```
#[doc(inline)]
pub use crate::render::chosen_algorithm;

/// Bytes per pixel of a whole frame kept in memory, for
/// [`crate::api::Budgets::check_frame`].
///
/// ```
/// use plytrace::api::Budgets;
/// use plytrace::api::program::pipeline::FRAME_BYTES_PER_PIXEL;
///
/// let budgets = Budgets { frame_memory: 1 << 20, ..Budgets::default() };
/// assert!(budgets.check_frame(256, 256, FRAME_BYTES_PER_PIXEL).is_ok());
/// assert!(budgets.check_frame(1024, 1024, FRAME_BYTES_PER_PIXEL).is_err());
/// ```
#[doc(inline)]
pub use crate::render::FRAME_BYTES_PER_PIXEL;

/// Renders a `run` into a vector file (SVG, PDF, TikZ, by the file's
/// extension) or, with `hidden_line`, the hidden-line drawing as an
/// image; returns the staged file, the figures and, with `setmode o on`,
/// the tree.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::files::AtomicFile;
/// use plytrace::api::program::pipeline::{render_vector_run, RenderOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-run.svg", std::process::id()));
/// let file = AtomicFile::create(&path)?;
/// let (staged, stats, tree) = render_vector_run(Some(file), &scene, &RenderOptions::default(), false)?;
/// staged.expect("a file was given").commit()?;
/// let svg = std::fs::read_to_string(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// assert!(svg.contains("<svg") && tree.is_none());
/// assert!(stats.polygons_listed > 0);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::vector::render_run as render_vector_run;

/// The visible-surface algorithms (`--visibility`).
///
/// ```
/// use plytrace::api::program::pipeline::Algorithm;
///
/// assert_eq!("z-buffer".parse::<Algorithm>(), Ok(Algorithm::ZBuffer));
/// assert_eq!(Algorithm::Nns.to_string(), "nns");
/// assert_eq!(Algorithm::ALL.len(), 7);
/// ```
#[doc(inline)]
pub use crate::visibility::Algorithm;

/// What a frame leaves to the next `run` of a session: Brown's priority
/// orders (003 sections 2-3), the shadow casters with the shadows on
/// whole polygons while no object or light changes (a camera moving
/// through a still world), and the depth order of level 1's faces, where
/// the next NNS sort starts. Frames are the same with or without it.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Algorithm, Plan, RenderOptions, Reuse};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\nlight 2 3 9 1 1 1 100 Point\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let reuse = Reuse::default();
/// let brown = RenderOptions { visibility: Some(Algorithm::Brown), ..RenderOptions::default() };
/// let first = plan_with(&scene, &brown, &reuse)?;
/// let again = plan_with(&scene, &brown, &reuse)?;
/// assert!(matches!((first, again), (Plan::Painted(_), Plan::Painted(_))));
/// // Frames of one world with shadows: its casters are built in the
/// // first two (the first keeps none), then kept.
/// let shadows = RenderOptions { shadows: true, ..RenderOptions::default() };
/// for _ in 0..4 {
///     plan_with(&scene, &shadows, &reuse)?;
/// }
/// assert_eq!(reuse.worlds(), 2);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::render::Reuse;

/// The figures of the Newell-Newell-Sancha sort (000 sections 3-4).
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Algorithm, NnsStats, Plan, Reuse, RenderOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let nns = RenderOptions { visibility: Some(Algorithm::Nns), ..RenderOptions::default() };
/// let Plan::Tree(prepared) = plan_with(&scene, &nns, &Reuse::default())? else { unreachable!() };
/// let stats: NnsStats = prepared.stats.nns.expect("the NNS sort ran");
/// assert_eq!(stats.splits, 0, "a convex cube needs no splits");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::visibility::nns::NnsStats;

/// How refraction is rendered (`--refraction`).
///
/// ```
/// use plytrace::api::program::pipeline::{Refraction, RenderOptions};
///
/// assert_eq!(RenderOptions::default().refraction, Refraction::Auto);
/// assert_eq!(Refraction::default(), Refraction::Auto);
/// ```
#[doc(inline)]
pub use crate::image_tree::Refraction;

/// The illumination model (`--shading`).
///
/// ```
/// use plytrace::api::program::pipeline::{RenderOptions, ShadingModel};
///
/// assert_eq!(RenderOptions::default().shading, ShadingModel::Garcia);
/// assert_ne!(ShadingModel::Donovan, ShadingModel::Garcia);
/// ```
#[doc(inline)]
pub use crate::shading::ShadingModel;

/// The options of `--raytrace`.
///
/// ```
/// use plytrace::api::program::pipeline::RayTraceOptions;
///
/// let options = RayTraceOptions { samples: 2, ..RayTraceOptions::default() };
/// assert_eq!(options.samples, 2);
/// assert!(options.max_rays > 0);
/// ```
#[doc(inline)]
pub use crate::raytrace::RayTraceOptions;

/// Renders a scene by ray tracing (`--raytrace`): the frame and the
/// figures of the rays cast.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{ray_trace, RayTraceOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let (frame, rays) = ray_trace(&scene, &RayTraceOptions::default())?;
/// assert_eq!((frame.width, frame.height), (16, 16));
/// assert_eq!(rays.primary, 16 * 16, "one ray per pixel");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::raytrace::render as ray_trace;

/// The virtual image tree as a stream of records, the form of the
/// `setmode o on` files (`.out`, binary, and `.txt`).
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Plan, Reuse, RecordStream, RenderOptions};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let Plan::Tree(prepared) = plan_with(&scene, &RenderOptions::default(), &Reuse::default())? else { unreachable!() };
/// let records: &RecordStream = &prepared.picture;
/// assert!(!records.to_bytes().is_empty());
/// assert!(records.to_text().lines().count() >= records.records.len());
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::tree::RecordStream;

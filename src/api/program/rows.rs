//! Where the scan converter's rows go: a frame buffer kept whole, or any
//! [`RowSink`] (a PNG written band by band, a part file, a progress bar
//! in front of either), and which rows a part of an image has.

/// An image of colours (0 to 1) and the ids of the polygons painted, rows
/// from the top; a [`RowSink`] that keeps every row.
///
/// ```
/// use plytrace::api::program::rows::{FrameBuffer, Row, RowSink};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut frame = FrameBuffer::new(2, 2, [0.0, 0.0, 1.0]);
/// assert_eq!(frame.pixel(1, 1), [0.0, 0.0, 1.0]);
/// frame.row(&Row::colors(1, &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))?;
/// assert_eq!((frame.pixel(0, 1), frame.pixel(1, 0)), ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]));
/// assert_eq!(frame.id(0, 0), 0, "no polygon");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::raster::frame_buffer::FrameBuffer;

/// One finished row of the image: its index from the top and its
/// colours (with the ids and coverage where the scan converter keeps
/// them).
///
/// ```
/// use plytrace::api::program::rows::Row;
///
/// let colors = [[0.5f32, 0.5, 0.5]; 4];
/// let row = Row::colors(3, &colors);
/// assert_eq!((row.y, row.rgb.len()), (3, 4));
/// ```
#[doc(inline)]
pub use crate::raster::scan::Row;

/// Takes the rows of an image in order, as the scan converter finishes
/// them; an error stops the scan conversion.
///
/// ```
/// use plytrace::api::program::rows::{Row, RowSink};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// struct Brightest(f32);
/// impl RowSink for Brightest {
///     fn row(&mut self, row: &Row<'_>) -> plytrace::Result<()> {
///         for p in row.rgb {
///             self.0 = self.0.max(p[0] + p[1] + p[2]);
///         }
///         Ok(())
///     }
/// }
/// let mut sink = Brightest(0.0);
/// sink.row(&Row::colors(0, &[[0.1, 0.2, 0.3], [1.0, 1.0, 1.0]]))?;
/// assert_eq!(sink.0, 3.0);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::raster::scan::RowSink;

/// The rows (from the top) of part `index` of `count` of a prepared
/// tree's image (`--part I/N`): the parts have about equal work, cover
/// every row once, in order, and every process finds the same rows.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::pipeline::{plan_with, Plan, RenderOptions, Reuse};
/// use plytrace::api::program::rows::part_rows;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let Plan::Tree(prepared) = plan_with(&scene, &RenderOptions::default(), &Reuse::default())? else { unreachable!() };
/// let parts: Vec<_> = (0..3).map(|i| part_rows(&prepared.picture, &prepared.scan, i, 3)).collect();
/// assert_eq!((parts[0].start, parts[2].end), (0, 16));
/// assert!(parts.windows(2).all(|w| w[0].end == w[1].start), "every row once, in order");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::raster::scan::part_rows;

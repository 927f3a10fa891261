//! The live display of `disp on` (the manual's "attached device"): a
//! window, with the `display` feature, that shows the image level by
//! level of the virtual image tree as it is scan converted.

/// The session's display: off, asked for, unavailable in this build, or
/// a window.
///
/// ```
/// use plytrace::api::program::display::LiveDisplay;
///
/// let mut live = LiveDisplay::new();
/// assert!(!live.wanted(), "not asked for");
/// assert!(live.observer(16, 16).unwrap().is_none(), "no window opened");
/// assert!(live.request(false).is_none());
/// ```
#[doc(inline)]
pub use crate::display::LiveDisplay;

/// Receives the picture as the tree is shown level by level; any
/// `FnMut(&PartialFrame)` is one.
///
/// ```
/// use plytrace::api::program::display::{show_painted, PartialFrame};
/// use plytrace::api::program::pipeline::{RenderStats, Rendered};
///
/// let rendered = Rendered::empty(RenderStats::default());
/// let mut last = Vec::new();
/// show_painted(&rendered, &mut |f: &PartialFrame<'_>| last.push(f.is_last()));
/// assert_eq!(last, [true], "a painted image is one frame, the final one");
/// ```
#[doc(inline)]
pub use crate::display::FrameObserver;

/// The image after one more level of the virtual image tree.
///
/// ```
/// use plytrace::api::program::display::PartialFrame;
/// use plytrace::api::program::rows::FrameBuffer;
///
/// let frame = FrameBuffer::new(2, 2, [0.0; 3]);
/// let partial = PartialFrame { level: 1, levels: 2, frame: &frame };
/// assert!(!partial.is_last());
/// ```
#[doc(inline)]
pub use crate::display::PartialFrame;

/// Scan converts a prepared tree level by level, one frame per level to
/// the observer; the last frame is the final image, returned.
///
/// ```
/// # use std::path::Path;
/// # use plytrace::api::program::session::{Interpreter, NoHost};
/// use plytrace::api::program::display::{scan_levels, PartialFrame};
/// use plytrace::api::program::pipeline::{plan_with, Plan, RenderOptions, Reuse};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
/// # let mut interp = Interpreter::new();
/// # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
/// # let scene = interp.scene();
/// let Plan::Tree(prepared) = plan_with(&scene, &RenderOptions::default(), &Reuse::default())? else { unreachable!() };
/// let mut levels = Vec::new();
/// let rendered = scan_levels(*prepared, &mut |f: &PartialFrame<'_>| levels.push((f.level, f.is_last())))?;
/// assert_eq!(levels.last(), Some(&(1, true)), "no mirrors: one level");
/// assert_eq!(rendered.frame.width, 16);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::display::scan_levels;

/// Shows an image painted whole (an image-space algorithm's) as the one
/// and final frame.
///
/// ```
/// use plytrace::api::program::display::{show_painted, PartialFrame};
/// use plytrace::api::program::pipeline::{RenderStats, Rendered};
///
/// let rendered = Rendered::empty(RenderStats::default());
/// let mut frames = 0;
/// show_painted(&rendered, &mut |f: &PartialFrame<'_>| {
///     assert_eq!(f.frame.width, 0);
///     frames += 1;
/// });
/// assert_eq!(frames, 1);
/// ```
#[doc(inline)]
pub use crate::display::show_painted;

//! The live display of the plytrace manual page (004 appendix: `disp on`
//! "display virtual image tree on attached device", `wait` "waits for
//! `<return>` before continuing"; 004 section 6.1: "real-time display of the
//! virtual image tree creation process").
//!
//! The library side is a frame callback, [`FrameObserver`]: after the tree
//! is built, [`scan_levels`] scan converts it cut at level 1, 2, ... and
//! hands each partial frame to the observer, the last one being the final
//! image, bit for bit. A window (the `window` module, behind the cargo feature
//! `display`) is one observer; tests are another. [`LiveDisplay`] is the
//! session's state: `disp on` asks for the window, which opens at the next
//! `run`; without the feature or without a display it says so once and
//! the images still go to their files.

#[cfg(feature = "display")]
pub mod window;

use crate::error::Result;
use crate::raster::frame_buffer::FrameBuffer;
use crate::raster::scan;
use crate::render::{self, Prepared, Rendered};
use crate::tree::RecordStream;

/// The image after one more level of the virtual image tree.
#[derive(Debug, Clone, Copy)]
pub struct PartialFrame<'a> {
    /// The deepest level painted (1 for the visible surfaces alone).
    pub level: u32,
    /// The tree's depth: the frame of this level is the final image.
    pub levels: u32,
    /// The picture: levels `1..=level` of the tree.
    pub frame: &'a FrameBuffer,
}

impl PartialFrame<'_> {
    /// Whether this is the final image.
    pub fn is_last(&self) -> bool {
        self.level == self.levels
    }
}

/// Receives the picture as the tree is shown level by level.
pub trait FrameObserver {
    /// One more level is painted.
    fn frame(&mut self, frame: &PartialFrame<'_>);
}

impl<F: FnMut(&PartialFrame<'_>)> FrameObserver for F {
    fn frame(&mut self, frame: &PartialFrame<'_>) {
        self(frame)
    }
}

/// The records of levels `1..=level` of `stream`.
fn cut(stream: &RecordStream, level: u32) -> RecordStream {
    RecordStream {
        records: stream
            .records
            .iter()
            .filter(|r| u32::from(r.level) <= level)
            .cloned()
            .collect(),
        background: stream.background,
        front_to_back: stream.front_to_back,
        blended: stream.blended,
    }
}

/// Scan converts a prepared tree level by level: one frame per level of
/// the tree, handed to `observer`; the last is the final image, which is
/// returned.
pub fn scan_levels(prepared: Prepared, observer: &mut dyn FrameObserver) -> Result<Rendered> {
    let levels = prepared.stats.max_depth.max(1);
    let (w, h) = (prepared.scan.width, prepared.scan.height);
    for level in 1..levels {
        let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
        let partial = cut(&prepared.picture, level);
        scan::scan_convert(&partial, &prepared.scan, &mut frame)?;
        observer.frame(&PartialFrame {
            level,
            levels,
            frame: &frame,
        });
    }
    let rendered = render::scan_into_frame(prepared)?;
    observer.frame(&PartialFrame {
        level: levels,
        levels,
        frame: &rendered.frame,
    });
    Ok(rendered)
}

/// Hands an image painted without the tree (Brown's order, the
/// image-space algorithms) to `observer` as its one frame.
pub fn show_painted(rendered: &Rendered, observer: &mut dyn FrameObserver) {
    observer.frame(&PartialFrame {
        level: 1,
        levels: 1,
        frame: &rendered.frame,
    });
}

/// Renders `scene` (as [`render::plan_with`]), showing it level by level.
pub fn render_observed(
    scene: &crate::scene::Scene,
    options: &render::RenderOptions,
    reuse: &render::Reuse,
    observer: &mut dyn FrameObserver,
) -> Result<Rendered> {
    match render::plan_with(scene, options, reuse)? {
        render::Plan::Tree(prepared) => scan_levels(*prepared, observer),
        render::Plan::Painted(r) => {
            show_painted(&r, observer);
            Ok(*r)
        }
    }
}

/// Why there is no window.
const NO_FEATURE: &str = "disp on: this plytrace was built without the live display \
     (cargo build --features display); the images are written to files only";

/// The session's display: off, asked for, unavailable, or a window.
#[derive(Default)]
pub struct LiveDisplay {
    /// `disp on` was given (and not `disp off` since).
    requested: bool,
    /// The user was told there is no display: not tried again.
    told: bool,
    #[cfg(feature = "display")]
    window: Option<window::Window>,
}

impl LiveDisplay {
    /// A display not asked for.
    pub fn new() -> LiveDisplay {
        LiveDisplay::default()
    }

    /// `disp on` or `disp off`. Returns the message to show, once a
    /// session, when no window can be had in this build.
    pub fn request(&mut self, on: bool) -> Option<String> {
        self.requested = on;
        #[cfg(feature = "display")]
        if !on {
            self.window = None;
        }
        if on && !cfg!(feature = "display") && !self.told {
            self.told = true;
            return Some(NO_FEATURE.into());
        }
        None
    }

    /// Whether a `run` should show its image (`disp on` was given).
    pub fn wanted(&self) -> bool {
        self.requested && !self.told && cfg!(feature = "display")
    }

    /// The window for an image of `width` x `height`, opened (or resized)
    /// now; `Err` with the message to show, once, when none can be opened.
    #[cfg(feature = "display")]
    pub fn observer(
        &mut self,
        width: u32,
        height: u32,
    ) -> std::result::Result<Option<&mut dyn FrameObserver>, String> {
        if !self.wanted() {
            return Ok(None);
        }
        let fits = self
            .window
            .as_ref()
            .is_some_and(|w| w.size() == (width, height) && w.is_open());
        if !fits {
            self.window = None;
            match window::Window::open(width, height) {
                Ok(w) => self.window = Some(w),
                Err(e) => {
                    // Said once; not tried again this session.
                    self.told = true;
                    return Err(format!(
                        "disp on: cannot open a window ({e}); the images are written to files only"
                    ));
                }
            }
        }
        Ok(self.window.as_mut().map(|w| w as &mut dyn FrameObserver))
    }

    /// The window, when there is none in this build: never.
    #[cfg(not(feature = "display"))]
    pub fn observer(
        &mut self,
        _width: u32,
        _height: u32,
    ) -> std::result::Result<Option<&mut dyn FrameObserver>, String> {
        Ok(None)
    }

    /// `wait`: waits for a key in the window, if one is open; false when
    /// there is none (the caller waits for return on the terminal).
    pub fn wait(&mut self) -> bool {
        #[cfg(feature = "display")]
        if let Some(w) = &mut self.window
            && w.is_open()
        {
            w.wait_key();
            return true;
        }
        false
    }
}

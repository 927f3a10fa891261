//! How to render: size, anti-aliasing (Garcia 1986, section 3.5: the
//! scan conversion methods), shadows (section 4.7), threads and budgets.

use super::*;

/// How to render.
///
/// ```
/// use plytrace::api::{render, Antialiasing, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 640, 480);
/// let options = Options::default()
///     .with_size(16, 12)
///     .with_antialiasing(Antialiasing::Point)
///     .with_threads(1);
/// let image = render(&scene, &options)?;
/// assert_eq!((image.width, image.height), (16, 12), "the size given, not the scene's");
/// assert!(Options::default().shadows);
/// # Ok(())
/// # }
/// ```
///
/// New fields may be added: start from [`Options::default`] (or
/// [`Options::new`]) and change what you need with the `with_` methods or
/// by assigning a field.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Options {
    /// Image size overriding the scene's.
    pub size: Option<(u32, u32)>,
    /// Anti-aliasing; `None` is the best for the scene (method 4).
    pub antialiasing: Option<Antialiasing>,
    /// Shadows from the lights that cast them (the manual's `run y`).
    pub shadows: bool,
    /// Worker threads; 0 is all cores. The image does not depend on it.
    pub threads: usize,
    /// Limits on the work, as the program's `--max-*` flags.
    pub budgets: Budgets,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            size: None,
            antialiasing: None,
            shadows: true,
            threads: 0,
            budgets: Budgets::default(),
        }
    }
}

impl Options {
    /// The defaults: the scene's size and best anti-aliasing, shadows on,
    /// all cores, the default budgets.
    pub fn new() -> Self {
        Options::default()
    }

    /// These options with the image size `width` x `height`, overriding
    /// the scene's.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.size = Some((width, height));
        self
    }

    /// These options with anti-aliasing `aa`.
    pub fn with_antialiasing(mut self, aa: Antialiasing) -> Self {
        self.antialiasing = Some(aa);
        self
    }

    /// These options with shadows on or off.
    pub fn with_shadows(mut self, shadows: bool) -> Self {
        self.shadows = shadows;
        self
    }

    /// These options with `threads` worker threads (0: all cores).
    pub fn with_threads(mut self, threads: usize) -> Self {
        self.threads = threads;
        self
    }

    /// These options with the limits `budgets`.
    pub fn with_budgets(mut self, budgets: Budgets) -> Self {
        self.budgets = budgets;
        self
    }

    pub(super) fn render_options(&self) -> RenderOptions {
        RenderOptions {
            size: self.size,
            shadows: self.shadows,
            aa: self.antialiasing,
            threads: self.threads,
            budgets: self.budgets,
            ..RenderOptions::default()
        }
    }
}

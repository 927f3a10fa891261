//! Budgets: the limits that keep hostile or runaway input from exhausting
//! the machine. Each is checked before the work or the allocation it
//! bounds, and each error names the flag that raises it.

/// The limits of one session; the defaults fit a 2-core, 24 GiB machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budgets {
    /// Polygons in the scene, read and generated (`--max-polygons`).
    pub polygons: usize,
    /// Nesting of `call` (`--max-call-depth`).
    pub call_depth: usize,
    /// Fragments of the virtual image tree (`--max-tree-nodes`).
    pub tree_nodes: usize,
    /// Face splits of one NNS sort before it falls back
    /// (`--max-splits`).
    pub splits: usize,
    /// Pixels of one image (`--max-pixels`).
    pub pixels: u64,
    /// Bytes of a whole frame held in memory (`--max-frame-memory`, in
    /// MiB): the image-space algorithms and the outputs that need every
    /// pixel at once (PPM, the id image, `clear`). The default picture
    /// streams bands of rows and is bounded by `pixels` alone.
    pub frame_memory: u64,
    /// Average records per pixel that one scan conversion tiles, each
    /// counted by its bounding box within the image (`--max-overdraw`):
    /// scan conversion time grows with it, and the node budget alone
    /// allows 500,000 records each covering the whole image.
    pub overdraw: u64,
    /// Pair tests of one modeling operation (`--max-pair-tests`): the
    /// face pairs a CSG operation clips, the edge pairs an outline's
    /// simplicity check compares, the patch edge pairs the continuity
    /// check compares. Each is near-linear on sound input (spatial
    /// indexes); the budget bounds the hostile cases where they are not.
    pub pair_tests: u64,
    /// Bytes of one generated object's vertices and polygons
    /// (`--max-model-memory`, in MiB), counted before it is built: a
    /// polygon count under `polygons` may still hold millions of
    /// vertices (a cylinder's caps) or of points.
    pub model_memory: u64,
    /// Rays one ray-traced render may cast, shadow rays included
    /// (`--max-rays`): each glass surface spawns two rays, so the rays
    /// of one primary ray grow as 2^depth.
    pub rays: u64,
    /// Pixel samples one image-space painting may take (`--max-samples`):
    /// the pixels each polygon covers plus a visit per row and vertex,
    /// summed over the polygons, estimated before painting. The z-buffer,
    /// the scan-line algorithm and Brown's painter take a sample per
    /// polygon per pixel it covers, so their time grows with it.
    pub samples: u64,
    /// Polygon-window tests of one Warnock subdivision
    /// (`--max-window-tests`): each window classifies the polygons its
    /// parent passed it, counted as the work goes.
    pub window_tests: u64,
    /// Ray-polygon tests of one ray-cast render (`--max-ray-tests`): the
    /// polygons of the hierarchy's leaves each ray meets, counted as the
    /// work goes.
    pub ray_tests: u64,
}

/// The default of [`Budgets::rays`]: about a minute of tracing on 2 cores
/// at the slowest rate measured on the bundled scenes (0.7 to 2.8 million
/// rays a second), and twice what the biggest of them (`gallery.des`)
/// casts at 512 x 512 with 4 x 4 rays a pixel (22 million).
pub const DEFAULT_RAYS: u64 = 50_000_000;

/// The default of [`Budgets::samples`]: 15 to 35 seconds of painting on
/// 2 cores at the rates measured on triangle soups (the z-buffer about
/// 0.7 billion samples a second per core, the scan-line algorithm and
/// Brown's painter 0.3), a depth complexity of 380 at 5120 x 5120.
pub const DEFAULT_SAMPLES: u64 = 10_000_000_000;

/// The default of [`Budgets::window_tests`]: about 30 seconds of
/// Warnock's subdivision (one thread, 70 to 100 ns a test measured).
pub const DEFAULT_WINDOW_TESTS: u64 = 400_000_000;

/// The default of [`Budgets::ray_tests`]: about 10 seconds of ray casting
/// on 2 cores (60 ns a test of CPU time measured on a soup of large
/// triangles); the bundled scenes take 8 to 12
/// tests a ray.
pub const DEFAULT_RAY_TESTS: u64 = 300_000_000;

impl Default for Budgets {
    fn default() -> Self {
        Budgets {
            polygons: 4_000_000,
            call_depth: 64,
            tree_nodes: 500_000,
            splits: 200_000,
            pixels: 1 << 30,
            frame_memory: 1 << 30,
            overdraw: 4096,
            pair_tests: 50_000_000,
            model_memory: 1 << 30,
            rays: DEFAULT_RAYS,
            samples: DEFAULT_SAMPLES,
            window_tests: DEFAULT_WINDOW_TESTS,
            ray_tests: DEFAULT_RAY_TESTS,
        }
    }
}

impl Budgets {
    /// Refuses a `width` x `height` frame of `bytes_per_pixel` that
    /// passes [`Budgets::frame_memory`], before it is allocated.
    pub fn check_frame(&self, width: u32, height: u32, bytes_per_pixel: u64) -> Result<(), String> {
        let need = u64::from(width) * u64::from(height) * bytes_per_pixel;
        if need <= self.frame_memory {
            return Ok(());
        }
        Err(format!(
            "{}; the streamed picture (depth-sort or nns, PNG output) has no such limit",
            Budgets::exceeded(
                &format!(
                    "a whole {width} x {height} frame in memory ({} MiB)",
                    need.div_ceil(1 << 20)
                ),
                format!("{} MiB", self.frame_memory >> 20),
                "--max-frame-memory"
            )
        ))
    }

    /// The message for a budget exceeded: what, the limit, and the flag.
    pub fn exceeded(what: &str, limit: impl std::fmt::Display, flag: &str) -> String {
        crate::error::exceeded(what, limit, flag)
    }
}

/// Work counted against one budget as it is done, by any number of
/// threads, for the work that cannot be estimated before it starts (the
/// windows of Warnock's subdivision, the polygons a ray meets). It also
/// answers the stop request ([`crate::cancel`]): the worker asks
/// [`Meter::stopped`] between small steps and gives up when told.
#[derive(Debug)]
pub struct Meter {
    what: &'static str,
    limit: u64,
    flag: &'static str,
    spent: std::sync::atomic::AtomicU64,
    over: std::sync::atomic::AtomicBool,
}

impl Meter {
    /// Units a worker counts on its own before it adds them to the
    /// shared count ([`Meter::add_batched`]): a few milliseconds of work.
    pub const BLOCK: u64 = 1 << 16;

    /// A meter of `limit` units of `what` (a noun phrase, for the
    /// message), raised by `flag`.
    pub fn new(what: &'static str, limit: u64, flag: &'static str) -> Meter {
        Meter {
            what,
            limit,
            flag,
            spent: std::sync::atomic::AtomicU64::new(0),
            over: std::sync::atomic::AtomicBool::new(false),
        }
    }

    /// Counts `n` units; whether the work may go on (not past the budget,
    /// no stop requested).
    pub fn add(&self, n: u64) -> bool {
        use std::sync::atomic::Ordering::Relaxed;
        let spent = self.spent.fetch_add(n, Relaxed).saturating_add(n);
        if spent > self.limit {
            self.over.store(true, Relaxed);
        }
        !self.stopped()
    }

    /// Counts `n` units in the worker's own `pending`, handed to the
    /// shared count by blocks of [`Meter::BLOCK`]; whether the work may
    /// go on. The worker hands in what is left with [`Meter::add`].
    pub fn add_batched(&self, pending: &mut u64, n: u64) -> bool {
        *pending = pending.saturating_add(n);
        if *pending >= Self::BLOCK {
            return self.add(std::mem::take(pending));
        }
        !self.stopped()
    }

    /// Whether the work must stop: past the budget, or a stop requested.
    pub fn stopped(&self) -> bool {
        self.over.load(std::sync::atomic::Ordering::Relaxed) || crate::cancel::requested()
    }

    /// The units counted so far.
    pub fn spent(&self) -> u64 {
        self.spent.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// How the work ended: [`crate::error::Error::Cancelled`] on a stop
    /// request, the budget's error past it, else `Ok`.
    pub fn result(&self) -> crate::error::Result<()> {
        crate::cancel::check()?;
        if self.over.load(std::sync::atomic::Ordering::Relaxed) {
            return Err(crate::error::Error::budget(
                &format!("the count of {}", self.what),
                self.limit,
                self.flag,
            ));
        }
        Ok(())
    }
}

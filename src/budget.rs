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
}

/// The default of [`Budgets::rays`]: about a minute of tracing on 2 cores
/// at the slowest rate measured on the bundled scenes (0.7 to 2.8 million
/// rays a second), and twice what the biggest of them (`gallery.des`)
/// casts at 512 x 512 with 4 x 4 rays a pixel (22 million).
pub const DEFAULT_RAYS: u64 = 50_000_000;

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
        format!("{what} exceeds the budget of {limit}; `{flag} N` raises it")
    }
}

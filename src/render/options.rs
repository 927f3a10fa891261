//! What one render is asked to do beyond the scene, and the figures it
//! reports (the statistics of Garcia 1986, 004 chapter 6, table 6.2).

use std::time::Duration;

use crate::geometry::view::GeometryStats;
use crate::raster::scan::{Method, ScanStats};
use crate::visibility::nns::NnsStats;
use crate::visibility::{Algorithm, brown};

/// Options of one render beyond the scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderOptions {
    /// Image size overriding the scene's viewport.
    pub size: Option<(u32, u32)>,
    /// `run y`: cast shadows from Point lights (004 section 4.7); `run n`
    /// (false) paints no shadow, which the image-space algorithms need.
    pub shadows: bool,
    /// The visible-surface algorithm; by default the scene's (`setmode n`).
    pub visibility: Option<Algorithm>,
    /// Time the parts of the tree builder (table 6.2, `--profile`).
    pub profile: bool,
    /// The refraction matrix (`--refraction`).
    pub refraction: crate::image_tree::Refraction,
    /// The scan conversion method (`--aa`, `--supersample`); `None` is the
    /// best for the scene ([`super::best_method`]).
    pub aa: Option<Method>,
    /// Worker threads for scan conversion (0: all cores).
    pub threads: usize,
    /// The illumination model (`--shading`); Donovan's brings his
    /// transparency rule (3) to the scan converter.
    pub shading: crate::shading::ShadingModel,
    /// Limits on the tree (nodes) and the NNS sort (splits).
    pub budgets: crate::budget::Budgets,
}

/// Memory a whole-frame (image-space) render needs per pixel, at most:
/// the frame buffer's colour and id, and the depth or hit each algorithm
/// keeps beside it.
pub const PAINTED_BYTES_PER_PIXEL: u64 = 40;

/// Memory per pixel of a finished frame kept whole (colour and id).
pub const FRAME_BYTES_PER_PIXEL: u64 = 16;

/// Figures of one render.
#[derive(Debug, Clone, Default)]
pub struct RenderStats {
    /// The algorithm used.
    pub algorithm: Option<Algorithm>,
    /// Polygons in the sorted list (pieces after splitting included).
    pub polygons_listed: usize,
    /// Polygons that covered at least one pixel.
    pub polygons_tiled: usize,
    /// Deepest level of the virtual image tree reached.
    pub max_depth: u32,
    /// Geometry stage counters.
    pub geometry: GeometryStats,
    /// NNS counters, when it ran.
    pub nns: Option<NnsStats>,
    /// Time in the geometry stage.
    pub geometry_time: Duration,
    /// Time sorting (or building the ray caster's hierarchy).
    pub sort_time: Duration,
    /// Time shading.
    pub shading_time: Duration,
    /// Time painting (or casting rays).
    pub paint_time: Duration,
    /// The scan conversion method, for the tree path.
    pub method: Option<Method>,
    /// Scan conversion figures (fragments of method 4).
    pub scan: ScanStats,
    /// Branches of the tree pruned by its node budget.
    pub pruned: usize,
    /// What the tree builder had to give up (budgets), for the user.
    pub warnings: Vec<String>,
    /// Brown's order: objects sorted and reused (`--visibility brown`).
    pub brown: Option<brown::BrownStats>,
    /// Ray tracer figures (`--raytrace`, or `--refraction exact`).
    pub raytrace: Option<crate::raytrace::RayStats>,
    /// Which refraction model was used, in words, when the scene refracts.
    pub refraction: Option<String>,
}

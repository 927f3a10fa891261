//! The rendering pipeline of Garcia 1986 (004 figure 3.2): geometry ->
//! visibility -> the virtual image tree -> one stream of tree records ->
//! scan conversion -> a frame buffer.
//!
//! The list-priority algorithms (the simple depth sort and NNS) always go
//! through the tree ([`crate::image_tree`]), even at level 1, and the tree
//! always leaves as records ([`crate::emit`]): the picture is the scan
//! conversion of a front-to-back record stream ([`crate::raster::scan`]),
//! and `setmode o` writes the same tree in the scene's order and blending.
//! So light kinds and `-o on` never change the picture.
//!
//! Brown's priority order and the image-space algorithms (z-buffer,
//! scan-line, Warnock, ray casting) paint level 1 themselves, point
//! sampled; they refuse, naming what they cannot do, a scene that needs
//! the tree: the objects with reflectance or transmittance (below level
//! 1), transparency, curved objects under Gouraud or Phong shading, and
//! shadows (`run y`; without them, `run n`, these algorithms render every
//! scene that has none of the others).
//!
//! # Animation and the live display
//!
//! - Brown's order (`visibility::brown`) depends on vertex directions and the
//!   viewing axis only. `modeling::geodesic::TurnedRadial` turns a radial
//!   function inside fixed directions and `reshape` moves vertices along
//!   them; the interpreter keeps, per geodesic object number, its generated
//!   mesh and turned function for `radial rotate` outside `defobj`.
//!   `brown::PriorityCache` (inside `render::Reuse`, owned by the caller of
//!   `render::plan_with`; the CLI keeps one per session) stores each object's order with its
//!   directions, faces, centre and axis, and reuses it when all are equal
//!   (directions within `SAME_DIRECTION`); `RenderStats::brown` counts sorted
//!   and reused objects.
//! - A camera moving through a still world (`render::Reuse`, kept by the
//!   CLI from `run` to `run`): `shadow::CasterReuse` keeps the last frame's
//!   caster index, with the shadows kept on whole polygons, while a keyed
//!   hash (SipHash with a per-process key) of everything they depend on is
//!   unchanged: every object's points, polygons and planes, which objects
//!   are hidden, open or concave, the Point lights' positions and the
//!   tolerance. A world's first frame keeps only the hash, so a still frees
//!   its index with its tree; the second frame of the same world builds it
//!   again and keeps it. Worlds over 2^20 polygons are not kept. A frame is the same
//!   with or without it (`tests/walkthrough.rs` renders each frame of a path
//!   both ways). From the second `run` on, the program lets jemalloc keep
//!   freed pages for 5 s, so frames reuse each other's pages.
//! - The live display observes, never steers: `display::scan_levels` scan
//!   converts the picture's records cut at each level (`record.level <= k`)
//!   and hands each frame to a `FrameObserver`, then the full stream (the
//!   image written). The window is one observer; the interpreter tells the
//!   host about `disp` through `Host::display`.

use std::time::Instant;

use crate::error::Result;
use crate::geometry::view::View;
use crate::model::Scene;
use crate::raster::frame_buffer::FrameBuffer;
use crate::raster::scan::{self, Method, RowSink};
use crate::visibility::{Algorithm, brown};

mod effects;
mod image_space;
mod options;
mod tree;
pub mod vector;

pub use effects::{bounding_box_scene, has_point_light, needs_tree, scene_scale, tree_effects};
pub use options::{FRAME_BYTES_PER_PIXEL, PAINTED_BYTES_PER_PIXEL, RenderOptions, RenderStats};
pub use tree::{Prepared, prepare, refraction_model};

/// A rendered image and what is painted where.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// The frame buffer; its ids index `polygons` plus one.
    pub frame: FrameBuffer,
    /// For id `k` (1-based), `polygons[k - 1]` = (object index, polygon
    /// index in the object's `polygons`).
    pub polygons: Vec<(u32, u32)>,
    /// For id `k`, `shadows[k - 1]` is the light whose shadow it is (for
    /// shadow polygons); empty when no shadows were cast.
    pub shadows: Vec<Option<u32>>,
    /// The virtual image tree in file form, with `setmode o on`.
    pub tree: Option<crate::tree::RecordStream>,
    /// The run-time profile, with [`RenderOptions::profile`] (tree path).
    pub profile: Option<crate::profile::Profile>,
    /// Figures.
    pub stats: RenderStats,
}

impl Rendered {
    /// A render whose picture went elsewhere (a vector file): no frame,
    /// only its figures.
    pub fn empty(stats: RenderStats) -> Rendered {
        Rendered {
            frame: FrameBuffer::new(0, 0, [0.0; 3]),
            polygons: Vec::new(),
            shadows: Vec::new(),
            tree: None,
            profile: None,
            stats,
        }
    }

    /// The (object index, polygon index) painted at pixel `x`, row `y` from
    /// the top, or `None` for background.
    pub fn polygon_at(&self, x: u32, y: u32) -> Option<(u32, u32)> {
        let id = self.frame.id(x, y);
        (id > 0).then(|| self.polygons[id as usize - 1])
    }
}

impl Rendered {
    fn with_frame(mut self, frame: FrameBuffer) -> Rendered {
        self.frame = frame;
        self
    }
}

/// The algorithm `options` and `scene` ask for: NNS unless either says
/// otherwise (`setmode n off` or `-n off` is the simple depth sort).
pub fn chosen_algorithm(scene: &Scene, options: &RenderOptions) -> Algorithm {
    options.visibility.unwrap_or(if scene.modes.nns {
        Algorithm::Nns
    } else {
        Algorithm::DepthSort
    })
}

/// Renders `scene` into a frame buffer.
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<Rendered> {
    match plan(scene, options)? {
        Plan::Tree(prepared) => scan_into_frame(*prepared),
        Plan::Painted(rendered) => Ok(*rendered),
    }
}

/// Scan converts a prepared tree into a frame buffer of its size.
pub fn scan_into_frame(prepared: Prepared) -> Result<Rendered> {
    let (w, h) = (prepared.scan.width, prepared.scan.height);
    let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
    let rendered = scan_into(prepared, &mut frame)?;
    Ok(rendered.with_frame(frame))
}

/// What a render comes to before its pixels: a tree ready for scan
/// conversion into any [`RowSink`] (the list-priority algorithms), or an
/// image already painted (the image-space algorithms and Brown's order).
pub enum Plan {
    /// Records to scan convert.
    Tree(Box<Prepared>),
    /// A finished image.
    Painted(Box<Rendered>),
}

/// Prepares the render of `scene`. With `setmode p on` every object is
/// replaced by its bounding box and nothing is reflected or refracted
/// (004 appendix, SETMODE COMMANDS).
pub fn plan(scene: &Scene, options: &RenderOptions) -> Result<Plan> {
    plan_with(scene, options, &Reuse::default())
}

/// What a frame of an animation leaves to the next: Brown's priority
/// orders, used again with no re-sort when only the radii changed (003
/// sections 2-3), and the shadow casters with the shadows cast on whole
/// polygons, used again while no object or light changed (a camera
/// moving through a still world), and the order of level 1's faces by
/// depth, where the next frame's NNS sort starts. A frame is the same,
/// byte for byte, with or without them.
#[derive(Default)]
pub struct Reuse {
    orders: brown::PriorityCache,
    casters: crate::image_tree::CasterReuse,
    sort_orders: crate::visibility::nns::PriorOrder,
}

impl Reuse {
    /// How many times a world's shadow casters were built: twice per
    /// world shown in several frames (the first frame keeps none, so a
    /// still holds nothing past its tree), not once per frame.
    pub fn worlds(&self) -> usize {
        self.casters.built()
    }

    /// Says whether more frames follow the next (a scene's `run` with
    /// more after it): the first frame of a world then keeps its shadow
    /// casters for them, and the second does not build them again. A
    /// frame is the same either way.
    pub fn frames_follow(&self, more: bool) {
        self.casters.frames_follow(more);
        self.sort_orders.frames_follow(more);
    }

    /// How many NNS sorts of level 1 started from the order of the frame
    /// before (an insertion pass) rather than from scratch.
    pub fn warm_sorts(&self) -> usize {
        self.sort_orders.warm_starts()
    }
}

/// [`plan`], with what the previous frame left in `reuse`.
pub fn plan_with(scene: &Scene, options: &RenderOptions, reuse: &Reuse) -> Result<Plan> {
    if scene.modes.boxes_only {
        let mut boxes = bounding_box_scene(scene);
        boxes.modes.boxes_only = false;
        boxes.modes.max_level = 1;
        let mut plain = *options;
        plain.size = Some(
            options
                .size
                .unwrap_or((scene.viewport.width(), scene.viewport.height())),
        );
        return plan_with(&boxes, &plain, reuse);
    }
    let view = View::for_scene(scene, options.size)?;
    let algorithm = chosen_algorithm(scene, options);
    let stats = RenderStats {
        algorithm: Some(algorithm),
        max_depth: 1,
        ..RenderStats::default()
    };
    if matches!(algorithm, Algorithm::DepthSort | Algorithm::Nns) {
        let prepared = prepare(
            scene,
            &view,
            algorithm,
            options,
            stats,
            reuse,
            &crate::threads::Pool::new(options.threads)?,
        );
        crate::cancel::check()?;
        return Ok(Plan::Tree(Box::new(prepared)));
    }
    let painted = image_space::paint(scene, &view, algorithm, options, &reuse.orders, stats)?;
    Ok(Plan::Painted(Box::new(painted)))
}

/// The method `options` ask for, or the best for the scene: multi-level
/// masks (004 section 5.9), the only method that blends every level of
/// the tree, shadows on partly diffuse mirrors and both branches of a
/// polygon that reflects and transmits.
pub fn best_method(options: &RenderOptions) -> Method {
    options.aa.unwrap_or(Method::Multilevel)
}

/// Scan converts the rows `rows` (from the top) of a prepared tree into
/// `sink`, each row exactly as the whole image has it, and leaves the
/// tree for more: the parts of an image from one tree.
pub fn scan_rows(
    prepared: &Prepared,
    rows: std::ops::Range<u32>,
    sink: &mut dyn RowSink,
) -> Result<scan::ScanStats> {
    let (picture, options) = (&prepared.picture, &prepared.scan);
    match &prepared.exact {
        Some(layer) => {
            let mut layered = crate::raytrace::exact::LayeredSink::new(sink, layer);
            scan::scan_convert_rows(picture, options, rows, &mut layered)
        }
        None => scan::scan_convert_rows(picture, options, rows, sink),
    }
}

/// Scan converts a prepared tree into `sink`. The result's frame buffer is
/// empty: the rows went to the sink.
pub fn scan_into(prepared: Prepared, sink: &mut dyn RowSink) -> Result<Rendered> {
    let rows = 0..prepared.scan.height;
    scan_rows_into(prepared, rows, sink)
}

/// [`scan_into`] for the rows `rows` (from the top) of the image alone:
/// a part of the image, each row exactly as the whole image has it.
pub fn scan_rows_into(
    prepared: Prepared,
    rows: std::ops::Range<u32>,
    sink: &mut dyn RowSink,
) -> Result<Rendered> {
    let t = Instant::now();
    let scanned = scan_rows(&prepared, rows, sink)?;
    let mut stats = prepared.stats;
    stats.paint_time = t.elapsed();
    stats.polygons_tiled = scanned.polygons_tiled;
    stats.scan = scanned;
    if let Some(p) = &prepared.profile {
        p.add(crate::profile::Category::Misc, stats.paint_time);
    }
    let rendered = Rendered {
        frame: FrameBuffer::new(0, 0, [0.0; 3]),
        polygons: prepared
            .sources
            .iter()
            .map(|s| (s.object, s.polygon))
            .collect(),
        shadows: prepared.sources.iter().map(|s| s.shadow_of).collect(),
        tree: prepared.file,
        profile: prepared.profile,
        stats,
    };
    // The records, one small block or two each, are freed on the pool
    // while the image file is finished (0.16-0.3 ms for office2).
    let (records, sources) = (prepared.picture, prepared.sources);
    rayon::spawn(move || drop((records, sources)));
    Ok(rendered)
}

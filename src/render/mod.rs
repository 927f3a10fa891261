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

use std::time::Instant;

use glam::{DVec2, DVec3};

use crate::emit::{self, Emit, Source};
use crate::error::{Error, Result};
use crate::geometry::view::{self, ScreenPolygon, View};
use crate::model::{Color, Scene, SortOrder};
use crate::raster::frame_buffer::{FrameBuffer, PaintItem, PaintMode};
use crate::raster::scan::{self, Method, RowSink, ScanOptions};
use crate::tree::RecordStream;
use crate::visibility::ray_cast::RayCaster;
use crate::visibility::z_buffer::{self, DepthItem};
use crate::visibility::{Algorithm, brown, depth_sort, scan_line, warnock};

mod options;
pub mod vector;

pub use options::{FRAME_BYTES_PER_PIXEL, PAINTED_BYTES_PER_PIXEL, RenderOptions, RenderStats};

use crate::shading::{
    facet_shade, phong_vertices, transparency_of, vertex_shades, vertex_transparency,
};

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

/// The algorithm `options` and `scene` ask for.
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
    plan_with(scene, options, &brown::PriorityCache::new())
}

/// [`plan`], with Brown's priority orders of the previous frame in
/// `orders`: an animation's later frames reuse them with no re-sort when
/// only the radii changed (003 sections 2-3).
pub fn plan_with(
    scene: &Scene,
    options: &RenderOptions,
    orders: &brown::PriorityCache,
) -> Result<Plan> {
    if scene.modes.boxes_only {
        let boxes = bounding_box_scene(scene);
        let mut plain = *options;
        plain.size = Some(
            options
                .size
                .unwrap_or((scene.viewport.width(), scene.viewport.height())),
        );
        let mut boxes = boxes;
        boxes.modes.boxes_only = false;
        boxes.modes.max_level = 1;
        return plan_with(&boxes, &plain, orders);
    }
    let view = View::for_scene(scene, options.size)?;
    let (width, height) = (view.width as u32, view.height as u32);
    let algorithm = chosen_algorithm(scene, options);
    let mut stats = RenderStats {
        algorithm: Some(algorithm),
        max_depth: 1,
        ..RenderStats::default()
    };
    if matches!(algorithm, Algorithm::DepthSort | Algorithm::Nns) {
        let prepared = prepare(scene, &view, algorithm, options, stats);
        crate::cancel::check()?;
        return Ok(Plan::Tree(Box::new(prepared)));
    }
    refuse_tree_effects(scene, options, algorithm)?;
    options
        .budgets
        .check_frame(width, height, PAINTED_BYTES_PER_PIXEL)
        .map_err(Error::Invalid)?;
    let mut frame = FrameBuffer::new(width, height, scene.background.as_vec3().to_array());
    if algorithm == Algorithm::RayCast {
        let polygons = ray_cast(scene, &view, &mut frame, &mut stats);
        return Ok(Plan::Painted(Box::new(Rendered {
            frame,
            polygons,
            shadows: Vec::new(),
            tree: None,
            profile: None,
            stats,
        })));
    }

    let t = Instant::now();
    let visible: Vec<usize> = (0..scene.objects.len())
        .filter(|&i| !scene.objects[i].surface_type.hidden)
        .collect();
    let per_object = algorithm == Algorithm::Brown;
    let mut lists: Vec<Vec<ScreenPolygon>> = Vec::new();
    if per_object {
        for &i in &visible {
            let mut one = Vec::new();
            view::expand_object(scene, i, &view, &mut one, &mut stats.geometry);
            if !one.is_empty() {
                lists.push(one);
            }
        }
    } else {
        let mut all = Vec::new();
        for &i in &visible {
            view::expand_object(scene, i, &view, &mut all, &mut stats.geometry);
        }
        lists.push(all);
    }
    stats.geometry_time = t.elapsed();

    let t = Instant::now();
    let order = scene.sort_order;
    // The painting list: screen points and source polygon.
    let sorted: Vec<(Vec<DVec3>, (u32, u32), bool)> = match algorithm {
        Algorithm::Brown => {
            let mut counts = brown::BrownStats::default();
            let lists = lists
                .into_iter()
                .map(|l| brown_sorted(scene, &view, l, orders, &mut counts))
                .collect();
            stats.brown = Some(counts);
            simple_sorted_lists(lists, order)
        }
        Algorithm::ZBuffer | Algorithm::ScanLine => lists
            .pop()
            .unwrap_or_default()
            .into_iter()
            .map(|p| (p.points, (p.object, p.polygon), p.back_facing))
            .collect(),
        // Warnock's classes assume convex polygons.
        Algorithm::Warnock => lists
            .pop()
            .unwrap_or_default()
            .into_iter()
            .flat_map(|p| {
                let id = (p.object, p.polygon);
                let back = p.back_facing;
                crate::geometry::polygon::triangulate_if_needed(&p.points)
                    .into_iter()
                    .map(move |t| (t, id, back))
            })
            .collect(),
        Algorithm::RayCast | Algorithm::DepthSort | Algorithm::Nns => {
            unreachable!("handled above")
        }
    };
    stats.sort_time = t.elapsed();
    stats.polygons_listed = sorted.len();

    let t = Instant::now();
    let mut shades = ShadeCache::default();
    let colors: Vec<[f32; 3]> = sorted
        .iter()
        .map(|(_, (o, p), back)| shades.get(scene, &view, *o, *p, *back))
        .collect();
    stats.shading_time = t.elapsed();

    let t = Instant::now();
    stats.polygons_tiled = if matches!(
        algorithm,
        Algorithm::ZBuffer | Algorithm::ScanLine | Algorithm::Warnock
    ) {
        let items: Vec<DepthItem> = sorted
            .iter()
            .zip(&colors)
            .enumerate()
            .map(|(k, ((points, _, _), color))| DepthItem {
                points: points.clone(),
                color: *color,
                id: k as u32 + 1,
            })
            .collect();
        match algorithm {
            Algorithm::ZBuffer => z_buffer::paint(&mut frame, &items),
            Algorithm::ScanLine => scan_line::paint(&mut frame, &items),
            _ => warnock::paint(&mut frame, &items),
        }
    } else {
        let items: Vec<PaintItem> = sorted
            .iter()
            .zip(&colors)
            .enumerate()
            .map(|(k, ((points, (o, p), back), color))| PaintItem {
                points: points.iter().map(|q| DVec2::new(q.x, q.y)).collect(),
                color: *color,
                id: k as u32 + 1,
                transparency: transparency_of(scene, view.eye, *o, *p, *back) as f32,
                phong: phong_vertices(
                    scene,
                    view.eye,
                    *o,
                    *p,
                    *back,
                    &points
                        .iter()
                        .map(|q| view.unproject(*q).unwrap_or(DVec3::ZERO))
                        .collect::<Vec<_>>(),
                    Color::ZERO,
                    1.0,
                ),
                vertex_colors: scene.modes.vertex_shades.then(|| {
                    let world: Vec<DVec3> = points
                        .iter()
                        .map(|q| view.unproject(*q).unwrap_or(DVec3::ZERO))
                        .collect();
                    vertex_shades(scene, view.eye, *o, *p, *back, &world)
                        .into_iter()
                        .map(|c| c.as_vec3().to_array())
                        .collect()
                }),
                vertex_transparency: if scene.modes.vertex_shades {
                    let world: Vec<DVec3> = points
                        .iter()
                        .map(|q| view.unproject(*q).unwrap_or(DVec3::ZERO))
                        .collect();
                    vertex_transparency(scene, view.eye, *o, *p, *back, &world)
                } else {
                    None
                },
            })
            .collect();
        let mode = match order {
            SortOrder::BackToFront => PaintMode::Overwrite,
            SortOrder::FrontToBack => PaintMode::FirstWins,
        };
        frame.paint(&items, mode)
    };
    stats.paint_time = t.elapsed();

    Ok(Plan::Painted(Box::new(Rendered {
        frame,
        polygons: sorted.iter().map(|(_, id, _)| *id).collect(),
        shadows: Vec::new(),
        tree: None,
        profile: None,
        stats,
    })))
}

/// The method `options` ask for, or the best for the scene: multi-level
/// masks (004 section 5.9), the only method that blends every level of
/// the tree, shadows on partly diffuse mirrors and both branches of a
/// polygon that reflects and transmits.
pub fn best_method(options: &RenderOptions) -> Method {
    options.aa.unwrap_or(Method::Multilevel)
}

/// Whether `method` wants pre-blended shades (methods 1-3: no levels).
fn wants_pre_blending(method: Method) -> bool {
    matches!(method, Method::Area | Method::Mask | Method::Hybrid)
}

/// A tree ready for scan conversion: the picture's record stream (front to
/// back) and, with `setmode o on`, the file's (the scene's order and
/// blending).
pub struct Prepared {
    /// The records the picture is made from.
    pub picture: RecordStream,
    /// Each picture record's source polygon.
    pub sources: Vec<Source>,
    /// The tree as `setmode o` writes it.
    pub file: Option<RecordStream>,
    /// How to scan convert the picture.
    pub scan: ScanOptions,
    /// The profile, with `--profile`.
    pub profile: Option<crate::profile::Profile>,
    /// Figures so far.
    pub stats: RenderStats,
    /// With exact refraction: the ray-traced refracted branches, added to
    /// the picture's rows.
    pub exact: Option<crate::raytrace::exact::ExactLayer>,
}

/// Builds the virtual image tree and emits it as records.
pub fn prepare(
    scene: &Scene,
    view: &View,
    algorithm: Algorithm,
    options: &RenderOptions,
    mut stats: RenderStats,
) -> Prepared {
    let t = Instant::now();
    let profile = crate::profile::Profile::new(options.profile);
    // `--threads N` bounds the tree's parallel work too (shadows); the
    // tree does not depend on it.
    let pool = (options.threads > 0)
        .then(|| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(options.threads)
                .build()
                .ok()
        })
        .flatten();
    let (refraction, said) = refraction_model(scene, view, options.refraction);
    stats.refraction = said;
    let build = || {
        crate::image_tree::build_profiled(
            scene,
            view,
            crate::image_tree::TreeOptions {
                max_level: scene.modes.max_level,
                threshold: scene.threshold,
                nns: algorithm == Algorithm::Nns,
                shadows: options.shadows,
                refraction,
                explicit_shadow_shades: scene.modes.shadow_shades,
                shading: options.shading,
                budgets: options.budgets,
            },
            &profile,
        )
    };
    let tree = within(&pool, build);
    stats.sort_time = t.elapsed();
    stats.geometry = tree.geometry;
    stats.max_depth = tree.max_depth;
    stats.nns = tree.nns;
    stats.pruned = tree.pruned;
    stats.warnings = tree.warnings.clone();
    let t = Instant::now();
    let (width, height) = (view.width as u32, view.height as u32);
    let method = best_method(options);
    let emit = |order, blended| Emit {
        order,
        blended,
        width,
        height,
    };
    // Donovan's transparency rule (000 section 6, rule (3)) blends a
    // surface with the colour behind it, so his picture is painted back to
    // front, pre-blended (the overwriting principle of 004 section 4.10),
    // by every method (see [`crate::raster::scan`]).
    let picture_how = match options.shading {
        crate::shading::ShadingModel::Donovan => emit(SortOrder::BackToFront, true),
        crate::shading::ShadingModel::Garcia => {
            emit(SortOrder::FrontToBack, wants_pre_blending(method))
        }
    };
    let file = scene.modes.output_tree.then(|| {
        let how = emit(scene.sort_order, scene.modes.blend);
        within(&pool, || emit::records(scene, &tree, how, view).0)
    });
    // The tree is kept past its records only for exact refraction.
    let (picture, sources, tree) = if refraction == crate::image_tree::Refraction::Exact {
        let (p, s) = within(&pool, || emit::records(scene, &tree, picture_how, view));
        (p, s, Some(tree))
    } else {
        let (p, s) = within(&pool, || {
            emit::records_freeing(scene, tree, picture_how, view)
        });
        (p, s, None)
    };
    stats.shading_time = t.elapsed();
    profile.add(crate::profile::Category::Shading, t.elapsed());
    stats.polygons_listed = picture.records.len();
    stats.method = Some(method);
    let scan = ScanOptions {
        width,
        height,
        method,
        act_lines: 16,
        paint_background: true,
        transparency: match options.shading {
            crate::shading::ShadingModel::Garcia => scan::TransparencyRule::Garcia,
            crate::shading::ShadingModel::Donovan => scan::TransparencyRule::Donovan,
        },
        threads: options.threads,
        ids: true,
        max_overdraw: options.budgets.overdraw,
    };
    // Exact refraction: the refracted branches ray traced before the
    // picture's scan conversion (a failure there is the picture's too).
    let mut exact = None;
    if let Some(tree) = &tree {
        let made = crate::raytrace::exact::layer(
            scene,
            view,
            tree,
            &scan,
            options.shadows,
            options.shading,
        );
        match made {
            Ok(layer) => exact = layer,
            Err(e) => stats
                .warnings
                .push(format!("exact refraction left out: {e}")),
        }
    }
    stats.raytrace = exact.as_ref().map(|l| l.stats);
    Prepared {
        picture,
        sources,
        file,
        scan,
        exact,
        profile: options.profile.then_some(profile),
        stats,
    }
}

/// Runs `f` in `pool` (`--threads N`), or in rayon's global pool.
fn within<R: Send>(pool: &Option<rayon::ThreadPool>, f: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(pool) => pool.install(f),
        None => f(),
    }
}

/// The refraction model for `scene` (resolving `auto`: exact when the
/// linearized matrix is off by more than a pixel through a transmitting
/// polygon, [`crate::raytrace::exact::linear_error`]) and, when
/// the scene refracts, the model in words for the statistics.
pub fn refraction_model(
    scene: &Scene,
    view: &View,
    asked: crate::image_tree::Refraction,
) -> (crate::image_tree::Refraction, Option<String>) {
    use crate::image_tree::Refraction;
    let refracts = scene.modes.max_level > 1
        && scene.objects.iter().any(|o| {
            !o.surface_type.hidden
                && (0..o.polygons.len()).any(|p| o.material(p).transmittance > 0.0)
        });
    if !refracts {
        return (asked, None);
    }
    let name = |r: Refraction| format!("{r:?}").to_lowercase();
    if asked != Refraction::Auto {
        return (asked, Some(format!("{} (--refraction)", name(asked))));
    }
    let error = crate::raytrace::exact::linear_error(scene, view);
    let chosen = if error > 1.0 {
        Refraction::Exact
    } else {
        Refraction::Linearized
    };
    let said = format!(
        "{} (the linearized matrix is off by up to {error:.1} pixels through the transmitting \
         polygons; exact above 1)",
        name(chosen)
    );
    (chosen, Some(said))
}

/// Scan converts a prepared tree into `sink`. The result's frame buffer is
/// empty: the rows went to the sink.
pub fn scan_into(prepared: Prepared, sink: &mut dyn RowSink) -> Result<Rendered> {
    let t = Instant::now();
    let scanned = match &prepared.exact {
        Some(layer) => {
            let mut layered = crate::raytrace::exact::LayeredSink::new(sink, layer);
            scan::scan_convert(&prepared.picture, &prepared.scan, &mut layered)?
        }
        None => scan::scan_convert(&prepared.picture, &prepared.scan, sink)?,
    };
    let mut stats = prepared.stats;
    stats.paint_time = t.elapsed();
    stats.polygons_tiled = scanned.polygons_tiled;
    stats.scan = scanned;
    if let Some(p) = &prepared.profile {
        p.add(crate::profile::Category::Misc, stats.paint_time);
    }
    Ok(Rendered {
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
    })
}

/// What of the scene needs the virtual image tree, in words; empty when
/// level 1 painted point by point shows all of it. Each item names the
/// objects concerned (the first few) and what about them needs the tree:
/// reflectance or transmittance traced below level 1, transparency, a
/// curved object smoothly shaded; and shadows, with how to go without.
pub fn tree_effects(scene: &Scene, options: &RenderOptions) -> Vec<String> {
    const NAMED: usize = 3;
    let mut what = Vec::new();
    let named = |o: &crate::model::Object| format!("object `{}` (#{})", o.name, o.number);
    let visible = || scene.objects.iter().filter(|o| !o.surface_type.hidden);
    let list = |items: Vec<String>| {
        let n = items.len();
        let mut shown: Vec<String> = items.into_iter().take(NAMED).collect();
        if n > NAMED {
            shown.push(format!("and {} more", n - NAMED));
        }
        shown.join(", ")
    };
    if needs_tree(scene) {
        let items: Vec<String> = visible()
            .filter_map(|o| {
                let (mut kr, mut kt) = (0.0f64, 0.0f64);
                for p in 0..o.polygons.len() {
                    let m = o.material(p);
                    kr = kr.max(m.reflectance);
                    kt = kt.max(m.transmittance);
                }
                let mut about = Vec::new();
                if kr > 0.0 {
                    about.push(format!("reflectance {kr}"));
                }
                if kt > 0.0 {
                    about.push(format!("transmittance {kt}"));
                }
                (!about.is_empty()).then(|| format!("{} with {}", named(o), about.join(" and ")))
            })
            .collect();
        what.push(format!(
            "mirrors and refracting surfaces traced to depth {} ({})",
            scene.modes.max_level,
            list(items)
        ));
    }
    let transparent: Vec<String> = visible()
        .filter(|o| o.surface.transparency.0 > 0.0)
        .map(|o| {
            format!(
                "{} with transparency {}",
                named(o),
                o.surface.transparency.0
            )
        })
        .collect();
    if !transparent.is_empty() {
        what.push(format!("transparency ({})", list(transparent)));
    }
    for (on, kind, mode) in [
        (scene.modes.vertex_shades, "Gouraud", "setmode v"),
        (scene.modes.phong, "Phong", "setmode s"),
    ] {
        if !on {
            continue;
        }
        let curved: Vec<String> = visible()
            .filter(|o| o.surface_type.curved)
            .map(|o| format!("{} is curved", named(o)))
            .collect();
        what.push(if curved.is_empty() {
            format!("{kind} polygons ({mode})")
        } else {
            format!("{kind} polygons ({mode}; {})", list(curved))
        });
    }
    if options.shadows && has_point_light(scene) {
        what.push(
            "shadows (`run y` with a Point light), which need the tree too: render without \
             them with `run n` (--no-shadows in immediate mode)"
                .into(),
        );
    }
    if options.aa.is_some_and(|m| m != Method::Point) {
        what.push("anti-aliasing (use --aa none)".into());
    }
    what
}

/// Refuses a scene that `algorithm` cannot render whole.
fn refuse_tree_effects(scene: &Scene, options: &RenderOptions, algorithm: Algorithm) -> Result<()> {
    let what = tree_effects(scene, options);
    if what.is_empty() {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "--visibility {} paints level 1 only, point sampled, and cannot render {}; \
         use depth-sort or nns (the virtual image tree) for them",
        algorithm.name(),
        what.join("; ")
    )))
}

impl Rendered {
    fn with_frame(mut self, frame: FrameBuffer) -> Rendered {
        self.frame = frame;
        self
    }
}

type Listed = (Vec<DVec3>, (u32, u32), bool);

/// One object's polygons in Brown's priority order (back to front), for
/// the object's centre (its origin) and the axis towards the eye; the
/// order of the previous frame when it still holds.
fn brown_sorted(
    scene: &Scene,
    view: &View,
    list: Vec<ScreenPolygon>,
    orders: &brown::PriorityCache,
    counts: &mut brown::BrownStats,
) -> Vec<ScreenPolygon> {
    let Some(first) = list.first() else {
        return list;
    };
    let object = &scene.objects[first.object as usize];
    let centre = object.transform.transform_point(DVec3::ZERO);
    let axis = crate::geometry::view::towards_eye(view.eye, centre);
    let faces: Vec<Vec<u32>> = object.polygons.iter().map(|p| p.indices.clone()).collect();
    let (order, reused) = orders.order(
        object.number,
        &object.vertices,
        &faces,
        centre,
        axis,
        object.surface_type.open,
    );
    if reused {
        counts.reused += 1;
    } else {
        counts.sorted += 1;
    }
    let mut rank = vec![0usize; faces.len()];
    for (r, &f) in order.iter().enumerate() {
        rank[f] = r;
    }
    let mut list = list;
    list.sort_by_key(|p| rank[p.polygon as usize]);
    list
}

/// The order of whole lists (objects) by the simple sort of their depth
/// ranges (004 section 4.4, `setmode x off`).
fn list_order(lists: &[Vec<ScreenPolygon>], order: SortOrder) -> Vec<usize> {
    let keys: Vec<f64> = lists
        .iter()
        .map(|l| {
            let range = l
                .iter()
                .map(ScreenPolygon::z_range)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (c, d)| {
                    (a.min(c), b.max(d))
                });
            depth_sort::sort_key(range, order)
        })
        .collect();
    depth_sort::sorted_order(&keys)
}

fn listed(p: ScreenPolygon) -> Listed {
    (p.points, (p.object, p.polygon), p.back_facing)
}

/// Lists already in back-to-front order, ordered among themselves by the
/// simple sort (front to back reverses each list).
fn simple_sorted_lists(mut lists: Vec<Vec<ScreenPolygon>>, order: SortOrder) -> Vec<Listed> {
    let mut out = Vec::new();
    for li in list_order(&lists, order) {
        let mut list = std::mem::take(&mut lists[li]);
        if order == SortOrder::FrontToBack {
            list.reverse();
        }
        out.extend(list.into_iter().map(listed));
    }
    out
}

/// Whether the scene has a shadow-casting light.
pub fn has_point_light(scene: &Scene) -> bool {
    scene
        .lights
        .iter()
        .any(|l| l.kind == crate::model::LightKind::Point)
}

/// Whether the scene has anything to trace below level 1.
pub fn needs_tree(scene: &Scene) -> bool {
    scene.modes.max_level > 1
        && scene.objects.iter().any(|o| {
            !o.surface_type.hidden
                && (0..o.polygons.len()).any(|p| {
                    let m = o.material(p);
                    m.reflectance > 0.0 || m.transmittance > 0.0
                })
        })
}

/// The scene with every object replaced by its bounding box (the eight
/// transformed corners of its object-space box), in the object's colours.
pub fn bounding_box_scene(scene: &Scene) -> Scene {
    let mut out = scene.clone();
    for object in &mut out.objects {
        let corners = object.bbox_corners;
        let centre = corners.iter().copied().sum::<DVec3>() / 8.0;
        // Corner i has x, y, z from bits 0, 1, 2: the six faces.
        let faces: [[u32; 4]; 6] = [
            [0, 2, 6, 4],
            [1, 5, 7, 3],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 1, 3, 2],
            [4, 6, 7, 5],
        ];
        let polygons = faces
            .iter()
            .map(|f| {
                // Clockwise from outside: the Newell normal points inward.
                let pts: Vec<DVec3> = f.iter().map(|&i| corners[i as usize]).collect();
                let n = crate::geometry::polygon::newell_vector(pts.iter().copied());
                let fc = pts.iter().copied().sum::<DVec3>() / 4.0;
                if n.dot(fc - centre) > 0.0 {
                    f.iter().rev().copied().collect()
                } else {
                    f.to_vec()
                }
            })
            .collect();
        let parts = crate::scene::build::ObjectParts {
            number: object.number,
            name: object.name.clone(),
            mesh: std::sync::Arc::new(crate::model::Mesh {
                vertices: corners.to_vec(),
                polygons,
            }),
            polygon_colors: None,
            vertex_colors: None,
            transform: crate::math::Matrix4::IDENTITY,
            surface: object.surface,
            surface_type: object.surface_type,
        };
        if let Ok(b) = crate::scene::build::build_object(parts, &mut |_| {}) {
            *object = b;
        }
    }
    out
}

/// The size of the scene ([`Scene::size`]).
pub fn scene_scale(scene: &Scene) -> f64 {
    scene.size()
}

/// Casts a ray per pixel and paints the faceted shade of what it hits.
fn ray_cast(
    scene: &Scene,
    view: &View,
    frame: &mut FrameBuffer,
    stats: &mut RenderStats,
) -> Vec<(u32, u32)> {
    let t = Instant::now();
    let caster = RayCaster::new(scene);
    stats.sort_time = t.elapsed();
    let t = Instant::now();
    let hits = caster.id_image(frame.width, frame.height);
    stats.paint_time = t.elapsed();
    let mut ids = std::collections::HashMap::new();
    let mut polygons = Vec::new();
    let mut shades = ShadeCache::default();
    for (px, hit) in hits.iter().enumerate() {
        let Some(h) = hit else { continue };
        let key = (h.object, h.polygon);
        let id = *ids.entry(key).or_insert_with(|| {
            polygons.push(key);
            polygons.len() as u32
        });
        let plane = scene.objects[h.object as usize].polygons[h.polygon as usize].plane;
        frame.ids[px] = id;
        frame.color[px] = shades.get(scene, view, h.object, h.polygon, !view.faces_eye(plane));
    }
    stats.polygons_listed = polygons.len();
    stats.polygons_tiled = polygons.len();
    polygons
}

/// Faceted shades, computed once per source polygon and side.
#[derive(Default)]
struct ShadeCache {
    shades: std::collections::HashMap<(u32, u32, bool), [f32; 3]>,
}

impl ShadeCache {
    fn get(
        &mut self,
        scene: &Scene,
        view: &View,
        object: u32,
        polygon: u32,
        back: bool,
    ) -> [f32; 3] {
        *self
            .shades
            .entry((object, polygon, back))
            .or_insert_with(|| {
                facet_shade(scene, view, object, polygon, back)
                    .as_vec3()
                    .to_array()
            })
    }
}

//! Brown's priority order and the image-space algorithms (z-buffer,
//! scan-line, Warnock, ray casting: Firebaugh 001 chapter 9; Brown 1978,
//! 003 sections 2-3): each paints level 1 itself, point sampled, into a
//! frame buffer. The stages: the screen polygons (one list, or one per
//! object for Brown), their painting order, one faceted shade per source
//! polygon, then the painter of the algorithm.

use std::time::Instant;

use glam::{DVec2, DVec3};

use crate::budget::{Budgets, Meter};
use crate::error::{Error, Result};
use crate::geometry::view::{self, ScreenPolygon, View};
use crate::model::{Color, Scene, SortOrder};
use crate::raster::frame_buffer::{BAND, FrameBuffer, PaintItem, PaintMode};
use crate::raster::tiler;
use crate::shading::{
    Materials, facet_shade, phong_vertices, transparency_of, vertex_shades, vertex_transparency,
};
use crate::visibility::ray_cast::RayCaster;
use crate::visibility::z_buffer::{self, DepthItem};
use crate::visibility::{Algorithm, brown, depth_sort, scan_line, warnock};

use super::{PAINTED_BYTES_PER_PIXEL, RenderOptions, RenderStats, Rendered};

/// Paints `scene` by `algorithm` (not a list-priority one), refusing a
/// scene that needs the virtual image tree.
pub(super) fn paint(
    scene: &Scene,
    view: &View,
    algorithm: Algorithm,
    options: &RenderOptions,
    orders: &brown::PriorityCache,
    mut stats: RenderStats,
) -> Result<Rendered> {
    super::effects::refuse_tree_effects(scene, options, algorithm)?;
    let (width, height) = (view.width as u32, view.height as u32);
    options
        .budgets
        .check_frame(width, height, PAINTED_BYTES_PER_PIXEL)
        .map_err(|message| Error::Budget {
            flag: "--max-frame-memory",
            message,
        })?;
    let background = scene.background.as_vec3().to_array();
    let materials = Materials::new(scene);
    let (frame, polygons) = if algorithm == Algorithm::RayCast {
        let mut frame = FrameBuffer::new(width, height, background);
        let polygons = ray_cast(scene, &materials, view, &mut frame, options, &mut stats)?;
        (frame, polygons)
    } else {
        let t = Instant::now();
        let lists = screen_lists(scene, view, algorithm == Algorithm::Brown, &mut stats);
        stats.geometry_time = t.elapsed();
        let t = Instant::now();
        let sorted = painting_list(scene, view, algorithm, lists, orders, &mut stats);
        stats.sort_time = t.elapsed();
        stats.polygons_listed = sorted.len();
        check_samples(algorithm, &sorted, width, height, &options.budgets)?;
        let t = Instant::now();
        let mut shades = ShadeCache::default();
        let colors: Vec<[f32; 3]> = sorted
            .iter()
            .map(|(_, (o, p), back)| shades.get(&materials, view, *o, *p, *back))
            .collect();
        stats.shading_time = t.elapsed();
        let t = Instant::now();
        let mut frame = FrameBuffer::new(width, height, background);
        let painting = Painting {
            materials: &materials,
            view,
            algorithm,
            budgets: &options.budgets,
        };
        stats.polygons_tiled = painting.paint(&sorted, &colors, &mut frame)?;
        stats.paint_time = t.elapsed();
        (frame, sorted.iter().map(|(_, id, _)| *id).collect())
    };
    Ok(Rendered {
        frame,
        polygons,
        shadows: Vec::new(),
        tree: None,
        profile: None,
        stats,
    })
}

/// The visible objects' screen polygons: one list, or one per object.
fn screen_lists(
    scene: &Scene,
    view: &View,
    per_object: bool,
    stats: &mut RenderStats,
) -> Vec<Vec<ScreenPolygon>> {
    let lists = view::expand_objects(&scene.objects, view, &mut stats.geometry);
    if per_object {
        lists.into_iter().filter(|l| !l.is_empty()).collect()
    } else {
        let mut all = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        all.extend(lists.into_iter().flatten());
        vec![all]
    }
}

/// The painting list of `algorithm`: screen points and source polygon.
fn painting_list(
    scene: &Scene,
    view: &View,
    algorithm: Algorithm,
    mut lists: Vec<Vec<ScreenPolygon>>,
    orders: &brown::PriorityCache,
    stats: &mut RenderStats,
) -> Vec<Listed> {
    match algorithm {
        Algorithm::Brown => {
            let mut counts = brown::BrownStats::default();
            let lists = lists
                .into_iter()
                .map(|l| brown_sorted(scene, view, l, orders, &mut counts))
                .collect();
            stats.brown = Some(counts);
            simple_sorted_lists(lists, scene.sort_order)
        }
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
        _ => lists
            .pop()
            .unwrap_or_default()
            .into_iter()
            .map(listed)
            .collect(),
    }
}

/// Refuses, before any painting, a list whose pixel samples
/// ([`tiler::work`]) pass [`Budgets::samples`]: the z-buffer, the
/// scan-line algorithm and Brown's painter sample every polygon at every
/// pixel it covers, and each band of rows looks at every polygon's
/// vertices (or edges) once. Warnock's subdivision counts its own work.
fn check_samples(
    algorithm: Algorithm,
    sorted: &[Listed],
    width: u32,
    height: u32,
    budgets: &Budgets,
) -> Result<()> {
    if algorithm == Algorithm::Warnock {
        return Ok(());
    }
    let bands = f64::from(height.div_ceil(BAND));
    let mut outline = Vec::new();
    let samples: f64 = sorted
        .iter()
        .map(|(points, _, _)| {
            outline.clear();
            outline.extend(points.iter().map(|p| DVec2::new(p.x, p.y)));
            tiler::work(&outline, width, height) + bands * points.len() as f64
        })
        .sum();
    if samples <= budgets.samples as f64 {
        return Ok(());
    }
    Err(Error::budget(
        &format!(
            "painting {} polygons at {width} x {height} by {algorithm} (about {samples:.3e} pixel samples)",
            sorted.len()
        ),
        format!("{} samples", budgets.samples),
        "--max-samples",
    ))
}

/// What the painters of the list need beside it.
struct Painting<'a> {
    materials: &'a Materials<'a>,
    view: &'a View,
    algorithm: Algorithm,
    budgets: &'a Budgets,
}

impl Painting<'_> {
    /// Paints the list with its shades; returns the polygons painted, or
    /// [`Error::Cancelled`] when a stop was requested meanwhile (the
    /// painters stop early, between polygons or rows or windows).
    fn paint(
        &self,
        sorted: &[Listed],
        colors: &[[f32; 3]],
        frame: &mut FrameBuffer,
    ) -> Result<usize> {
        let (materials, view) = (self.materials, self.view);
        if self.algorithm == Algorithm::Brown {
            let items: Vec<PaintItem> = sorted
                .iter()
                .zip(colors)
                .enumerate()
                .map(|(k, (listed, color))| {
                    paint_item(materials, view, listed, *color, k as u32 + 1)
                })
                .collect();
            let mode = match materials.sort_order {
                SortOrder::BackToFront => PaintMode::Overwrite,
                SortOrder::FrontToBack => PaintMode::FirstWins,
            };
            let painted = frame.paint(&items, mode);
            crate::cancel::check()?;
            return Ok(painted);
        }
        let items: Vec<DepthItem> = sorted
            .iter()
            .zip(colors)
            .enumerate()
            .map(|(k, ((points, _, _), color))| DepthItem {
                points: points.clone(),
                color: *color,
                id: k as u32 + 1,
            })
            .collect();
        let painted = match self.algorithm {
            Algorithm::ZBuffer => z_buffer::paint(frame, &items),
            Algorithm::ScanLine => scan_line::paint(frame, &items),
            _ => warnock::paint(frame, &items, self.budgets.window_tests)?,
        };
        crate::cancel::check()?;
        Ok(painted)
    }
}

/// One polygon of Brown's order for the priority painter: its shade,
/// transparency, and with `setmode v`/`s` its vertex shades or Phong data.
fn paint_item(
    materials: &Materials<'_>,
    view: &View,
    listed: &Listed,
    color: [f32; 3],
    id: u32,
) -> PaintItem {
    let (points, (o, p), back) = listed;
    let (o, p, back) = (*o, *p, *back);
    let world: Vec<DVec3> = points
        .iter()
        .map(|q| view.unproject(*q).unwrap_or(DVec3::ZERO))
        .collect();
    let vertex_shades_on = materials.vertex_shades;
    PaintItem {
        points: points.iter().map(|q| DVec2::new(q.x, q.y)).collect(),
        color,
        id,
        transparency: transparency_of(materials, view.eye, o, p, back) as f32,
        phong: phong_vertices(materials, view.eye, o, p, back, &world, Color::ZERO, 1.0),
        vertex_colors: vertex_shades_on.then(|| {
            vertex_shades(materials, view.eye, o, p, back, &world)
                .into_iter()
                .map(|c| c.as_vec3().to_array())
                .collect()
        }),
        vertex_transparency: if vertex_shades_on {
            vertex_transparency(materials, view.eye, o, p, back, &world)
        } else {
            None
        },
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
    let faces: Vec<Vec<u32>> = object.polygons.iter().map(|p| p.indices.to_vec()).collect();
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

/// The order of whole lists (objects), back to front, by the simple sort
/// of their farthest depths (004 section 4.4, `setmode x off`).
fn list_order(lists: &[Vec<ScreenPolygon>]) -> Vec<usize> {
    let keys: Vec<f64> = lists
        .iter()
        .map(|l| {
            let far = l
                .iter()
                .map(|p| p.z_range().1)
                .fold(f64::NEG_INFINITY, f64::max);
            depth_sort::sort_key(far)
        })
        .collect();
    depth_sort::sorted_order(&keys)
}

fn listed(p: ScreenPolygon) -> Listed {
    (p.points, (p.object, p.polygon), p.back_facing)
}

/// Lists already in back-to-front order, ordered among themselves by the
/// simple sort; front to back is the whole back-to-front order reversed.
fn simple_sorted_lists(mut lists: Vec<Vec<ScreenPolygon>>, order: SortOrder) -> Vec<Listed> {
    let mut out = Vec::new();
    for li in list_order(&lists) {
        out.extend(std::mem::take(&mut lists[li]).into_iter().map(listed));
    }
    if order == SortOrder::FrontToBack {
        out.reverse();
    }
    out
}

/// Casts a ray per pixel and paints the faceted shade of what it hits,
/// within [`Budgets::ray_tests`].
fn ray_cast(
    scene: &Scene,
    materials: &Materials<'_>,
    view: &View,
    frame: &mut FrameBuffer,
    options: &RenderOptions,
    stats: &mut RenderStats,
) -> Result<Vec<(u32, u32)>> {
    let t = Instant::now();
    let caster = RayCaster::new(scene);
    stats.sort_time = t.elapsed();
    let t = Instant::now();
    let meter = Meter::new(
        "ray-polygon tests of ray casting",
        options.budgets.ray_tests,
        "--max-ray-tests",
    );
    let hits = caster.id_image_within(frame.width, frame.height, &meter);
    meter.result()?;
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
        frame.color[px] = shades.get(materials, view, h.object, h.polygon, !view.faces_eye(plane));
    }
    stats.polygons_listed = polygons.len();
    stats.polygons_tiled = polygons.len();
    Ok(polygons)
}

/// Faceted shades, computed once per source polygon and side.
#[derive(Default)]
struct ShadeCache {
    shades: std::collections::HashMap<(u32, u32, bool), [f32; 3]>,
}

impl ShadeCache {
    fn get(
        &mut self,
        materials: &Materials<'_>,
        view: &View,
        object: u32,
        polygon: u32,
        back: bool,
    ) -> [f32; 3] {
        *self
            .shades
            .entry((object, polygon, back))
            .or_insert_with(|| {
                facet_shade(materials, view, object, polygon, back)
                    .as_vec3()
                    .to_array()
            })
    }
}

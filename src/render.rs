//! The rendering pipeline of Garcia 1986 (004 figure 3.2, level 1 of the
//! virtual image tree): geometry (cull, clip, project) -> visibility (simple
//! depth sort, object by object or as one composite list, `setmode x`) ->
//! faceted shading -> painting into a frame buffer.
//!
//! The visible-surface algorithm is chosen per run or by `setmode n`
//! ([`crate::visibility::Algorithm`]). Not yet here: reflection and
//! refraction (levels below 1), shadows, Gouraud and Phong polygons,
//! transparency.

use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};

use crate::error::{Error, Result};
use crate::geometry::view::{self, GeometryStats, ScreenPolygon, View};
use crate::raster::frame_buffer::{FrameBuffer, PaintItem, PaintMode};
use crate::scene::model::{Color, Scene, SortOrder};
pub use crate::shading::{
    facet_shade, facet_shade_from, facet_shade_with, interpolate_in_polygon, phong_vertices,
    polygon_material, transparency_of, vertex_shades, vertex_transparency,
};
use crate::visibility::nns::{self, NnsFace, NnsStats};
use crate::visibility::ray_cast::RayCaster;
use crate::visibility::z_buffer::{self, DepthItem};
use crate::visibility::{Algorithm, brown, depth_sort, scan_line, warnock};

/// Options of one render beyond the scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderOptions {
    /// Image size overriding the scene's viewport.
    pub size: Option<(u32, u32)>,
    /// `run y`: compute shadows (not yet implemented; recorded).
    pub shadows: bool,
    /// The visible-surface algorithm; by default the scene's (`setmode n`).
    pub visibility: Option<Algorithm>,
    /// Time the parts of the tree builder (table 6.2, `--profile`).
    pub profile: bool,
    /// The refraction matrix (`--refraction`).
    pub refraction: crate::image_tree::Refraction,
}

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
}

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

/// Renders `scene`. With `setmode p on` every object is replaced by its
/// bounding box (004 appendix, SETMODE COMMANDS).
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<Rendered> {
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
        return render(&boxes, &plain);
    }
    let (width, height) = options
        .size
        .unwrap_or((scene.viewport.width(), scene.viewport.height()));
    let view = View::new(scene, width, height).ok_or_else(|| {
        Error::Invalid(
            "the final CTM is singular: it has no centre of projection to view from".into(),
        )
    })?;
    let algorithm = chosen_algorithm(scene, options);
    let mut stats = RenderStats {
        algorithm: Some(algorithm),
        max_depth: 1,
        ..RenderStats::default()
    };
    let mut frame = FrameBuffer::new(width, height, scene.background.as_vec3().to_array());
    if matches!(algorithm, Algorithm::DepthSort | Algorithm::Nns)
        && (needs_tree(scene)
            || scene.modes.output_tree
            || (options.shadows && has_point_light(scene)))
    {
        return Ok(paint_tree(scene, &view, algorithm, options, frame, stats));
    }
    if algorithm == Algorithm::RayCast {
        let polygons = ray_cast(scene, &view, &mut frame, &mut stats);
        return Ok(Rendered {
            frame,
            polygons,
            shadows: Vec::new(),
            tree: None,
            profile: None,
            stats,
        });
    }

    let t = Instant::now();
    let visible: Vec<usize> = (0..scene.objects.len())
        .filter(|&i| !scene.objects[i].surface_type.hidden)
        .collect();
    let per_object =
        (algorithm == Algorithm::DepthSort && !scene.modes.expand) || algorithm == Algorithm::Brown;
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
        Algorithm::DepthSort => simple_sorted(lists, order),
        Algorithm::Brown => {
            let lists = lists
                .into_iter()
                .map(|l| brown_sorted(scene, &view, l))
                .collect();
            simple_sorted_lists(lists, order)
        }
        Algorithm::Nns => {
            let all = lists.pop().unwrap_or_default();
            let (list, nns_stats) = nns_sorted(scene, &view, all, order);
            stats.nns = Some(nns_stats);
            list
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
        Algorithm::RayCast => unreachable!("handled above"),
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

    Ok(Rendered {
        frame,
        polygons: sorted.iter().map(|(_, id, _)| *id).collect(),
        shadows: Vec::new(),
        tree: None,
        profile: None,
        stats,
    })
}

type Listed = (Vec<DVec3>, (u32, u32), bool);

/// One object's polygons in Brown's priority order (back to front), for
/// the object's centre (its origin) and the axis towards the eye.
fn brown_sorted(scene: &Scene, view: &View, list: Vec<ScreenPolygon>) -> Vec<ScreenPolygon> {
    let Some(first) = list.first() else {
        return list;
    };
    let object = &scene.objects[first.object as usize];
    let centre = object.transform.transform_point(DVec3::ZERO);
    let axis = crate::geometry::view::towards_eye(view.eye, centre);
    let faces: Vec<Vec<u32>> = object.polygons.iter().map(|p| p.indices.clone()).collect();
    let order = brown::priority_order(
        &object.vertices,
        &faces,
        centre,
        axis,
        object.surface_type.open,
    );
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

/// The simple depth sort: lists (objects) by their depth range, then the
/// polygons of each list.
fn simple_sorted(mut lists: Vec<Vec<ScreenPolygon>>, order: SortOrder) -> Vec<Listed> {
    let mut sorted = Vec::new();
    for li in list_order(&lists, order) {
        let list = std::mem::take(&mut lists[li]);
        let keys: Vec<f64> = list
            .iter()
            .map(|p| depth_sort::sort_key(p.z_range(), order))
            .collect();
        let mut slots: Vec<Option<ScreenPolygon>> = list.into_iter().map(Some).collect();
        for k in depth_sort::sorted_order(&keys) {
            sorted.push(listed(slots[k].take().expect("a permutation")));
        }
    }
    sorted
}

/// The NNS sort of the composite list; non-convex polygons are cut into
/// triangles first. Front to back is the reverse of back to front.
fn nns_sorted(
    scene: &Scene,
    view: &View,
    all: Vec<ScreenPolygon>,
    order: SortOrder,
) -> (Vec<Listed>, NnsStats) {
    let mut back = std::collections::HashMap::new();
    let mut faces = Vec::with_capacity(all.len());
    for p in all {
        back.insert((p.object, p.polygon), p.back_facing);
        for world in crate::geometry::polygon::triangulate_if_needed(&p.world) {
            faces.push(NnsFace {
                object: p.object,
                polygon: p.polygon,
                world,
            });
        }
    }
    let epsilon = scene.modes.epsilon * scene_scale(scene).max(f64::MIN_POSITIVE);
    let (mut list, stats) = nns::sort(faces, view, epsilon);
    if order == SortOrder::FrontToBack {
        list.reverse();
    }
    let listed = list
        .into_iter()
        .map(|f| {
            let id = (f.object, f.polygon);
            let points = f.world.iter().map(|p| view.project(*p)).collect();
            (points, id, back[&id])
        })
        .collect();
    (listed, stats)
}

/// The tree in the file form of 004 figure 4.14: faceted records with the
/// pre-blended shades under `setmode b on`, the own shades otherwise;
/// restore polygons as special records.
fn tree_file(
    scene: &Scene,
    tree: &crate::image_tree::VirtualImageTree,
    order: &[usize],
    vertex_blend: &[Option<Vec<Color>>],
    width: u32,
    height: u32,
) -> crate::tree::RecordStream {
    use crate::tree::{Record, RecordStream, Shades};
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let records = order
        .iter()
        .map(|&n| {
            let f = &tree.nodes[n];
            let points = f
                .screen
                .iter()
                .map(|p| [(p.x / width as f64) as f32, (p.y / height as f64) as f32])
                .collect();
            let c = if scene.modes.blend {
                f.blended
            } else {
                f.shade
            };
            let phong = (f.kind == crate::image_tree::FragmentKind::Polygon)
                .then(|| {
                    let (offset, weight) = if scene.modes.blend {
                        (f.blended - f.shade * f.weight, f.weight)
                    } else {
                        (Color::ZERO, 1.0)
                    };
                    phong_vertices(
                        scene,
                        f.eye,
                        f.object,
                        f.polygon,
                        f.back_facing,
                        &f.world,
                        offset,
                        weight,
                    )
                })
                .flatten();
            if let Some(ph) = phong {
                let t = byte(transparency_of(
                    scene,
                    f.eye,
                    f.object,
                    f.polygon,
                    f.back_facing,
                ));
                let stride = ph.stride();
                let vertices: Vec<&[f32]> = ph.attrs.chunks(stride).collect();
                let fb = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
                // One highlight colour per light (figure 4.14): the mean
                // of the vertices' intensities.
                let light_colors = (0..ph.lights)
                    .map(|l| {
                        let mean = |c: usize| {
                            vertices.iter().map(|v| v[6 + 6 * l + c]).sum::<f32>()
                                / vertices.len() as f32
                        };
                        [fb(mean(0)), fb(mean(1)), fb(mean(2))]
                    })
                    .collect();
                let shades = Shades::Phong(crate::tree::PhongShades {
                    shininess: ph.shininess as f64,
                    light_colors,
                    rgbt: vertices
                        .iter()
                        .map(|v| [fb(v[0]), fb(v[1]), fb(v[2]), t])
                        .collect(),
                    normals: vertices
                        .iter()
                        .map(|v| {
                            (0..ph.lights)
                                .map(|l| [v[3 + 6 * l], v[4 + 6 * l], v[5 + 6 * l]])
                                .collect()
                        })
                        .collect(),
                });
                return Record {
                    level: f.level.min(u16::MAX as u32) as u16,
                    points,
                    shades,
                };
            }
            let shades = match (f.kind, &vertex_blend[n]) {
                (crate::image_tree::FragmentKind::Restore, _) => Shades::Special,
                (_, Some(vs)) => Shades::Gouraud(
                    vs.iter()
                        .map(|v| {
                            // Without pre-blending, the fragment's own shades.
                            let own = if scene.modes.blend {
                                *v
                            } else {
                                (*v - (f.blended - f.shade * f.weight))
                                    / f.weight.max(f64::MIN_POSITIVE)
                            };
                            [byte(own.x), byte(own.y), byte(own.z)]
                        })
                        .collect(),
                ),
                _ => Shades::Faceted([byte(c.x), byte(c.y), byte(c.z)]),
            };
            Record {
                level: f.level.min(u16::MAX as u32) as u16,
                points,
                shades,
            }
        })
        .collect();
    let _ = (width, height);
    RecordStream {
        background: Some(scene.background.as_vec3().to_array().map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)),
        front_to_back: scene.sort_order == SortOrder::FrontToBack,
        blended: scene.modes.blend,
        records,
    }
}

/// Gouraud vertex shades of every polygon fragment of the tree
/// (`setmode v on`), pre-blended: a fragment's vertex shade is its parent's
/// blended shade at that screen point, interpolated as in 004 figure 4.16
/// (along the two parent edges crossing the point's row, then across),
/// plus `k` times its own vertex shade. `None` for other fragments, or all
/// when vertex shades are off.
fn gouraud_tree_shades(
    scene: &Scene,
    tree: &crate::image_tree::VirtualImageTree,
) -> Vec<Option<Vec<Color>>> {
    let mut out: Vec<Option<Vec<Color>>> = vec![None; tree.nodes.len()];
    if !scene.modes.vertex_shades {
        return out;
    }
    // Parents are pushed before their children.
    for n in 0..tree.nodes.len() {
        let f = &tree.nodes[n];
        if f.kind != crate::image_tree::FragmentKind::Polygon {
            continue;
        }
        let own = vertex_shades(scene, f.eye, f.object, f.polygon, f.back_facing, &f.world);
        let blended = match f.parent.and_then(|p| out[p].as_ref().map(|vs| (p, vs))) {
            Some((p, parent_shades)) => {
                let parent = &tree.nodes[p];
                f.screen
                    .iter()
                    .zip(&own)
                    .map(|(s, c)| {
                        interpolate_in_polygon(&parent.screen, parent_shades, s.x, s.y)
                            + *c * f.weight
                    })
                    .collect()
            }
            None => {
                let base = f.blended - f.shade * f.weight;
                own.iter().map(|c| base + *c * f.weight).collect()
            }
        };
        out[n] = Some(blended);
    }
    out
}

/// Whether the scene has a shadow-casting light.
pub fn has_point_light(scene: &Scene) -> bool {
    scene
        .lights
        .iter()
        .any(|l| l.kind == crate::scene::model::LightKind::Point)
}

/// Whether the scene has anything to trace below level 1.
pub fn needs_tree(scene: &Scene) -> bool {
    scene.modes.max_level > 1
        && scene.objects.iter().any(|o| {
            !o.surface_type.hidden
                && (0..o.polygons.len()).any(|p| {
                    let m = polygon_material(o, p);
                    m.reflectance > 0.0 || m.transmittance > 0.0
                })
        })
}

/// Builds the virtual image tree and paints it with pre-blended shades.
fn paint_tree(
    scene: &Scene,
    view: &View,
    algorithm: Algorithm,
    options: &RenderOptions,
    mut frame: FrameBuffer,
    mut stats: RenderStats,
) -> Rendered {
    let t = Instant::now();
    let profile = crate::profile::Profile::new(options.profile);
    let tree = crate::image_tree::build_profiled(
        scene,
        view,
        crate::image_tree::TreeOptions {
            max_level: scene.modes.max_level,
            threshold: scene.threshold,
            nns: algorithm == Algorithm::Nns,
            shadows: options.shadows,
            refraction: options.refraction,
            explicit_shadow_shades: scene.modes.shadow_shades,
            ..Default::default()
        },
        &profile,
    );
    stats.sort_time = t.elapsed();
    stats.geometry = tree.geometry;
    stats.max_depth = tree.max_depth;
    let order = tree.output_order(scene.sort_order);
    let vertex_blend = gouraud_tree_shades(scene, &tree);
    let items: Vec<PaintItem> = order
        .iter()
        .enumerate()
        .map(|(k, &n)| {
            let f = &tree.nodes[n];
            PaintItem {
                points: f.screen.iter().map(|q| DVec2::new(q.x, q.y)).collect(),
                color: f
                    .blended
                    .clamp(DVec3::ZERO, DVec3::ONE)
                    .as_vec3()
                    .to_array(),
                id: k as u32 + 1,
                phong: if f.kind == crate::image_tree::FragmentKind::Polygon {
                    phong_vertices(
                        scene,
                        f.eye,
                        f.object,
                        f.polygon,
                        f.back_facing,
                        &f.world,
                        f.blended - f.shade * f.weight,
                        f.weight,
                    )
                } else {
                    None
                },
                vertex_transparency: if vertex_blend[n].is_some() {
                    vertex_transparency(scene, f.eye, f.object, f.polygon, f.back_facing, &f.world)
                } else {
                    None
                },
                vertex_colors: vertex_blend[n].as_ref().map(|vs| {
                    vs.iter()
                        .map(|c| c.clamp(DVec3::ZERO, DVec3::ONE).as_vec3().to_array())
                        .collect()
                }),
                transparency: if f.kind == crate::image_tree::FragmentKind::Polygon {
                    // At level n the eye seen by the fragment is mapped back;
                    // the view direction only matters for the roll-off.
                    transparency_of(scene, view.eye, f.object, f.polygon, f.back_facing) as f32
                } else {
                    0.0
                },
            }
        })
        .collect();
    stats.polygons_listed = items.len();
    let t = Instant::now();
    let mode = match scene.sort_order {
        SortOrder::BackToFront => PaintMode::Overwrite,
        SortOrder::FrontToBack => PaintMode::FirstWins,
    };
    stats.polygons_tiled = frame.paint(&items, mode);
    stats.paint_time = t.elapsed();
    profile.add(crate::profile::Category::Misc, t.elapsed());
    let size = (frame.width, frame.height);
    Rendered {
        frame,
        polygons: order
            .iter()
            .map(|&n| (tree.nodes[n].object, tree.nodes[n].polygon))
            .collect(),
        shadows: order
            .iter()
            .map(|&n| match tree.nodes[n].kind {
                crate::image_tree::FragmentKind::Shadow { light } => Some(light),
                _ => None,
            })
            .collect(),
        tree: scene
            .modes
            .output_tree
            .then(|| tree_file(scene, &tree, &order, &vertex_blend, size.0, size.1)),
        profile: options.profile.then_some(profile),
        stats,
    }
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
        let parts = crate::scene::interpreter::ObjectParts {
            number: object.number,
            name: object.name.clone(),
            mesh: std::sync::Arc::new(crate::scene::object_file::Mesh {
                vertices: corners.to_vec(),
                polygons,
            }),
            polygon_colors: None,
            vertex_colors: None,
            transform: crate::math::Matrix4::IDENTITY,
            surface: object.surface,
            surface_type: object.surface_type,
        };
        if let Ok(b) = crate::scene::interpreter::build_object(parts, &mut |_| {}) {
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

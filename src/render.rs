//! The rendering pipeline of Garcia 1986 (004 figure 3.2, level 1 of the
//! virtual image tree): geometry (cull, clip, project) -> visibility (simple
//! depth sort, object by object or as one composite list, `setmode x`) ->
//! faceted shading -> painting into a frame buffer.
//!
//! Not yet here: reflection and refraction (levels below 1), shadows, the
//! NNS sorter, Gouraud and Phong polygons, transparency.

use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};

use crate::error::{Error, Result};
use crate::geometry::view::{self, GeometryStats, ScreenPolygon, View};
use crate::raster::frame_buffer::{FrameBuffer, PaintItem, PaintMode};
use crate::scene::model::{Color, Object, Scene, SortOrder};
use crate::shading::{self, Material};
use crate::visibility::depth_sort;

/// Options of one render beyond the scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderOptions {
    /// Image size overriding the scene's viewport.
    pub size: Option<(u32, u32)>,
    /// `run y`: compute shadows (not yet implemented; recorded).
    pub shadows: bool,
}

/// Figures of one render.
#[derive(Debug, Clone, Default)]
pub struct RenderStats {
    /// Polygons in the sorted list.
    pub polygons_listed: usize,
    /// Polygons that covered at least one pixel.
    pub polygons_tiled: usize,
    /// Deepest level of the virtual image tree reached.
    pub max_depth: u32,
    /// Geometry stage counters.
    pub geometry: GeometryStats,
    /// Time in the geometry stage.
    pub geometry_time: Duration,
    /// Time sorting.
    pub sort_time: Duration,
    /// Time shading.
    pub shading_time: Duration,
    /// Time painting.
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

/// Renders `scene`.
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<Rendered> {
    let (width, height) = options
        .size
        .unwrap_or((scene.viewport.width(), scene.viewport.height()));
    let view = View::new(scene, width, height).ok_or_else(|| {
        Error::Invalid(
            "the final CTM is singular: it has no centre of projection to view from".into(),
        )
    })?;
    let mut stats = RenderStats {
        max_depth: 1,
        ..RenderStats::default()
    };

    let t = Instant::now();
    let visible: Vec<usize> = (0..scene.objects.len())
        .filter(|&i| !scene.objects[i].surface_type.hidden)
        .collect();
    let mut lists: Vec<Vec<ScreenPolygon>> = Vec::new();
    if scene.modes.expand {
        let mut all = Vec::new();
        for &i in &visible {
            view::expand_object(scene, i, &view, &mut all, &mut stats.geometry);
        }
        lists.push(all);
    } else {
        for &i in &visible {
            let mut one = Vec::new();
            view::expand_object(scene, i, &view, &mut one, &mut stats.geometry);
            if !one.is_empty() {
                lists.push(one);
            }
        }
    }
    stats.geometry_time = t.elapsed();

    let t = Instant::now();
    let order = scene.sort_order;
    let key_of = |range: (f64, f64)| depth_sort::sort_key(range, order);
    // Objects by the depth range of their polygons, then polygons within.
    let list_keys: Vec<f64> = lists
        .iter()
        .map(|l| {
            key_of(
                l.iter()
                    .map(ScreenPolygon::z_range)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (c, d)| {
                        (a.min(c), b.max(d))
                    }),
            )
        })
        .collect();
    let mut sorted: Vec<ScreenPolygon> = Vec::new();
    for li in depth_sort::sorted_order(&list_keys) {
        let list = std::mem::take(&mut lists[li]);
        let keys: Vec<f64> = list.iter().map(|p| key_of(p.z_range())).collect();
        let mut slots: Vec<Option<ScreenPolygon>> = list.into_iter().map(Some).collect();
        for k in depth_sort::sorted_order(&keys) {
            sorted.push(slots[k].take().expect("a permutation"));
        }
    }
    stats.sort_time = t.elapsed();
    stats.polygons_listed = sorted.len();

    let t = Instant::now();
    let items: Vec<PaintItem> = sorted
        .iter()
        .enumerate()
        .map(|(k, p)| PaintItem {
            points: p.points.iter().map(|q| DVec2::new(q.x, q.y)).collect(),
            color: facet_shade(scene, &view, p).as_vec3().to_array(),
            id: k as u32 + 1,
        })
        .collect();
    stats.shading_time = t.elapsed();

    let t = Instant::now();
    let mut frame = FrameBuffer::new(width, height, scene.background.as_vec3().to_array());
    let mode = match order {
        SortOrder::BackToFront => PaintMode::Overwrite,
        SortOrder::FrontToBack => PaintMode::FirstWins,
    };
    stats.polygons_tiled = frame.paint(&items, mode);
    stats.paint_time = t.elapsed();

    Ok(Rendered {
        frame,
        polygons: sorted.iter().map(|p| (p.object, p.polygon)).collect(),
        stats,
    })
}

/// The material of polygon `pi` of `object`, with its `.pcl` entry or the
/// average of its vertices' `.vcl` entries.
pub fn polygon_material(object: &Object, pi: usize) -> Material {
    let s = &object.surface;
    let base = Material {
        color: s.color,
        diffuse: s.diffuse,
        specular: s.specular,
        shininess: s.shininess,
        reflectance: s.reflectance,
        transmittance: s.transmittance,
    };
    if let Some(pcl) = &object.polygon_colors {
        let source = object.source_polygon[pi] as usize;
        return base.with_entry(&pcl[source]);
    }
    if let Some(vcl) = &object.vertex_colors {
        let idx = &object.polygons[pi].indices;
        let n = idx.len() as f64;
        let mut avg = vcl[idx[0] as usize];
        let sum = |f: &dyn Fn(usize) -> f64| idx.iter().map(|&i| f(i as usize)).sum::<f64>() / n;
        avg.color = idx.iter().map(|&i| vcl[i as usize].color).sum::<DVec3>() / n;
        avg.diffuse = sum(&|i| vcl[i].diffuse);
        avg.reflectance = sum(&|i| vcl[i].reflectance);
        avg.transmittance = sum(&|i| vcl[i].transmittance);
        return base.with_entry(&avg);
    }
    base
}

/// One shade for the whole polygon (faceted): the illumination model at the
/// centroid of the world polygon, with its plane normal turned towards the
/// viewer.
pub fn facet_shade(scene: &Scene, view: &View, p: &ScreenPolygon) -> Color {
    let object = &scene.objects[p.object as usize];
    let polygon = &object.polygons[p.polygon as usize];
    let material = polygon_material(object, p.polygon as usize);
    if object.surface_type.ltsrc {
        return material.color;
    }
    let centroid = polygon
        .indices
        .iter()
        .map(|&i| object.vertices[i as usize])
        .sum::<DVec3>()
        / polygon.indices.len() as f64;
    let normal = if p.back_facing {
        -polygon.normal()
    } else {
        polygon.normal()
    };
    shading::shade(
        &material,
        centroid,
        normal,
        view.to_eye(centroid),
        &scene.lights,
        scene.ambient,
    )
}

//! Exact refraction for the virtual image tree (`--refraction exact`): the
//! hybrid Garcia proposes in 004 section 6.4, rays where the linear maps
//! of section 4.6 are wrong.
//!
//! The tree is built without refracted branches (the builder's
//! [`crate::image_tree::Refraction::Exact`]). Every fragment that would
//! have had one (a "site": a front-facing polygon fragment that transmits,
//! below `depth`, its weight `k kt` above `threshold`) gets a ray-traced
//! layer instead, made before the picture's scan conversion, and added to
//! the picture's rows as they leave the scan converter:
//!
//! ```text
//! records --scan (the picture's method)--> rows --+--> + mask * layer --> sink
//! records, sites white, all else black --scan--> mask (coverage)
//! records --point scan--> ids --> the site at each pixel centre
//!    --rays (raytrace::RayTracer::refracted)--> layer = k kt L
//! ```
//!
//! The mask is the picture's stream with its colours replaced (sites and
//! the shadows on them 1, everything else 0) and scan converted by the same method, so it is the
//! sites' visible coverage, anti-aliased as the picture is, and dimmed by
//! transparent polygons in front as the branch would be. The layer holds,
//! per pixel, the weighted colour of the refracted ray of the site seen at
//! the pixel centre (or at a neighbour's, on a site's edge). Data flows one
//! way: nothing downstream of the records sees the tree.
//!
//! [`linear_error`] estimates how far off the linearized matrix is, in
//! pixels, through the transmitting polygons (at their corners, and at
//! the refracted objects' vertices, where the linear map and Snell's law
//! part): `auto` (the default) uses exact refraction when it is off by
//! more than a pixel.

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::emit::{self, Emit};
use crate::error::Result;
use crate::geometry::view::View;
use crate::image_tree::{FragmentKind, VirtualImageTree};
use crate::model::{Color, Scene, SortOrder};
use crate::raster::frame_buffer::FrameBuffer;
use crate::raster::scan::{self, Method, Row, RowSink, ScanOptions};

use super::{Counter, Ray, RayStats, RayTracer};

/// The ray-traced refracted branches of a tree, ready to be added to the
/// picture's rows.
#[derive(Debug, Clone)]
pub struct ExactLayer {
    width: u32,
    /// `mask * layer` per pixel, rows from the top.
    add: Vec<[f32; 3]>,
    /// With a tree file: `layer` per pixel (where the mask is not 0), the
    /// colour [`crate::raytrace::branch_records`] writes as records.
    pub(crate) traced: Option<Vec<[f32; 3]>>,
    /// Figures of the rays.
    pub stats: RayStats,
    /// Sites (fragments whose refracted branch is ray traced).
    pub sites: usize,
}

/// Whether tree node `n` is a site: a front-facing polygon fragment whose
/// refracted branch the tree would trace.
pub(crate) fn is_site(scene: &Scene, tree: &VirtualImageTree, n: usize) -> bool {
    let f = &tree.nodes[n];
    if f.kind != FragmentKind::Polygon || f.back_facing || f.level >= scene.modes.max_level {
        return false;
    }
    let m = scene.objects[f.object as usize].material(f.polygon as usize);
    m.transmittance > 0.0 && f.weight * m.transmittance > scene.threshold
}

/// How [`layer`] traces: the picture's options, and what else it keeps.
#[derive(Debug, Clone, Copy)]
pub struct LayerOptions {
    /// Shadow rays.
    pub shadows: bool,
    /// The illumination model.
    pub shading: crate::shading::ShadingModel,
    /// The ray budget (`--max-rays`).
    pub max_rays: u64,
    /// Keep the layer's colours before the mask (for a tree file).
    pub keep_traced: bool,
}

/// The layer of `tree` (built with exact refraction) for a picture scan
/// converted with `picture` options; `None` when nothing refracts.
pub fn layer(
    scene: &Scene,
    view: &View,
    tree: &VirtualImageTree,
    picture: &ScanOptions,
    how: LayerOptions,
) -> Result<Option<ExactLayer>> {
    let sites: Vec<bool> = (0..tree.nodes.len())
        .map(|n| is_site(scene, tree, n))
        .collect();
    let count = sites.iter().filter(|&&s| s).count();
    if count == 0 {
        return Ok(None);
    }
    let (w, h) = (picture.width, picture.height);
    let emit = |blended| Emit {
        order: SortOrder::FrontToBack,
        blended,
        width: w,
        height: h,
    };
    // The mask: sites white (weight 1 after the record's `k`), all else
    // black; flat shades only.
    let mut flat = crate::shading::Materials::new(scene);
    flat.vertex_shades = false;
    flat.phong = false;
    flat.background = Color::ZERO;
    let white = white_tree(tree, &sites);
    let blended = matches!(picture.method, Method::Area | Method::Mask | Method::Hybrid);
    let (mask_stream, _) = emit::records(&flat, &white, emit(blended), view);
    let mask = scan_frame(&mask_stream, picture, picture.method, false)?;
    // The site at each pixel centre.
    let (id_stream, _) = emit::records(&flat, &white, emit(false), view);
    let ids = scan_frame(&id_stream, picture, Method::Point, true)?;
    let tracer =
        RayTracer::new(scene, *view, how.shadows, how.shading).with_ray_limit(how.max_rays);
    let start = std::time::Instant::now();
    let sites = Sites {
        tree,
        sites: &sites,
        order: tree.output_order(SortOrder::FrontToBack),
    };
    let rows = trace_rows(&tracer, &sites, &mask, &ids);
    // Past the ray budget or on a stop request, the rays came back black.
    tracer.stopped()?;
    let mut stats = RayStats::default();
    let mut add = Vec::with_capacity(w as usize * h as usize);
    for (r, c) in rows {
        stats.add(&c);
        stats.primary += c.rays;
        add.extend(r);
    }
    let traced = how.keep_traced.then(|| unmasked(&add, &mask));
    stats.trace_time = start.elapsed();
    Ok(Some(ExactLayer {
        width: w,
        add,
        traced,
        stats,
        sites: count,
    }))
}

/// The tree with its colours replaced for the mask: sites (and the
/// shadows on them) white, everything else black.
fn white_tree(tree: &VirtualImageTree, sites: &[bool]) -> VirtualImageTree {
    let mut white = tree.clone();
    // A shadow on a site stands for the site where it lies.
    let shows_site = |n: usize| {
        sites[n]
            || (matches!(tree.nodes[n].kind, FragmentKind::Shadow { .. })
                && tree.nodes[n].parent().is_some_and(|p| sites[p]))
    };
    let on: Vec<bool> = (0..tree.nodes.len()).map(shows_site).collect();
    // Pre-blended, a fragment carries its parent's shade: below a site
    // (its reflection) the mask stays 1. Parents come before children.
    let mut under = vec![false; tree.nodes.len()];
    for n in 0..tree.nodes.len() {
        under[n] = on[n] || tree.nodes[n].parent().is_some_and(|p| under[p]);
    }
    for (n, f) in white.nodes.iter_mut().enumerate() {
        f.shade = if on[n] && f.weight > 0.0 {
            Color::ONE / f.weight
        } else {
            Color::ZERO
        };
        f.blended = if under[n] { Color::ONE } else { Color::ZERO };
    }
    white
}

/// The sites of a tree and the front-to-back order its records follow.
struct Sites<'a> {
    tree: &'a VirtualImageTree,
    sites: &'a [bool],
    order: Vec<usize>,
}

impl Sites<'_> {
    /// The record seen, or the nearest of its ancestors that is a site (a
    /// shadow on a site, or the site's reflection, shows the site too).
    fn site_of(&self, id: u32) -> Option<usize> {
        let mut n = *self.order.get((id as usize).checked_sub(1)?)?;
        while !self.sites[n] {
            n = self.tree.nodes[n].parent()?;
        }
        Some(n)
    }
}

/// Traces the refracted ray of the site seen at each pixel under the
/// mask: `mask * layer` per row, and each row's figures.
fn trace_rows(
    tracer: &RayTracer<'_>,
    sites: &Sites<'_>,
    mask: &FrameBuffer,
    ids: &FrameBuffer,
) -> Vec<(Vec<[f32; 3]>, Counter)> {
    let (w, h) = (mask.width, mask.height);
    (0..h)
        .into_par_iter()
        .map(|row| {
            let mut counter = Counter::default();
            let out = (0..w)
                .map(|col| {
                    let k = (row * w + col) as usize;
                    let m = mask.color[k][0];
                    if m <= 0.0 {
                        return [0.0; 3];
                    }
                    let site = neighbourhood(col, row, w, h)
                        .find_map(|(x, y)| sites.site_of(ids.ids[(y * w + x) as usize]));
                    let Some(n) = site else {
                        return [0.0; 3];
                    };
                    let c = site_colour(tracer, sites.tree, n, col, row, &mut counter);
                    (c * m as f64).as_vec3().to_array()
                })
                .collect();
            (out, counter)
        })
        .collect()
}

/// The layer before the mask, where the mask is not 0.
fn unmasked(add: &[[f32; 3]], mask: &FrameBuffer) -> Vec<[f32; 3]> {
    add.iter()
        .zip(&mask.color)
        .map(|(a, m)| {
            if m[0] > 0.0 {
                a.map(|v| v / m[0])
            } else {
                [0.0; 3]
            }
        })
        .collect()
}

/// The pixel itself, then its eight neighbours.
fn neighbourhood(col: u32, row: u32, w: u32, h: u32) -> impl Iterator<Item = (u32, u32)> {
    const STEPS: [(i64, i64); 9] = [
        (0, 0),
        (-1, 0),
        (1, 0),
        (0, -1),
        (0, 1),
        (-1, -1),
        (1, -1),
        (-1, 1),
        (1, 1),
    ];
    STEPS.into_iter().filter_map(move |(dx, dy)| {
        let (x, y) = (col as i64 + dx, row as i64 + dy);
        (x >= 0 && y >= 0 && x < w as i64 && y < h as i64).then_some((x as u32, y as u32))
    })
}

/// `k kt L`: the refracted ray of site `n` through the centre of pixel
/// `(col, row)` (row 0 at the top). The eye ray meets the site's plane
/// in virtual coordinates; the point is mapped back to world space by the
/// affine map the fragment's virtual and world vertices define (its
/// level's product of mirror reflections), and the ray goes on from there
/// as the eye of the fragment sees it.
fn site_colour(
    tracer: &RayTracer<'_>,
    tree: &VirtualImageTree,
    n: usize,
    col: u32,
    row: u32,
    counter: &mut Counter,
) -> Color {
    let f = &tree.nodes[n];
    let view = tracer.view();
    let Some((o, d)) = view.ray(col as f64 + 0.5, view.height - row as f64 - 0.5) else {
        return Color::ZERO;
    };
    let objects = &tracer.scene.objects;
    let points = f.points(objects);
    let Some(pv) = plane_hit(&points, o, d) else {
        return Color::ZERO;
    };
    let t = ((pv - o).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    let Some(pw) = map_in_plane(&points, &tree.world(objects, f), pv) else {
        return Color::ZERO;
    };
    let eye = tree.eye(f);
    let dir = if eye.w != 0.0 {
        pw - eye.truncate() / eye.w
    } else {
        -eye.truncate()
    };
    let rest = dir.normalize_or_zero() * d.length() * (1.0 - t);
    let ray = Ray {
        origin: pw,
        dir: rest,
        level: f.level,
        weight: f.weight,
        eye,
        exclude: None,
        bends: 0,
    };
    let object = &tracer.scene.objects[f.object as usize];
    let kt = object.material(f.polygon as usize).transmittance;
    tracer.refracted(&ray, (f.object, f.polygon), pw, rest, counter) * (kt * f.weight)
}

/// Where the line `o + t d` meets the plane of `points`.
fn plane_hit(points: &[DVec3], o: DVec3, d: DVec3) -> Option<DVec3> {
    let n = crate::geometry::polygon::newell_vector(points.iter().copied()).try_normalize()?;
    let denom = n.dot(d);
    if denom == 0.0 {
        return None;
    }
    let t = n.dot(points[0] - o) / denom;
    Some(o + d * t)
}

/// `p` (in the plane of `from`) mapped by the affine map taking the
/// points `from` to the points `to`, fitted on the first vertex and the
/// two others spanning the largest triangle.
fn map_in_plane(from: &[DVec3], to: &[DVec3], p: DVec3) -> Option<DVec3> {
    if from.len() < 3 || from.len() != to.len() {
        return None;
    }
    let mut best = (0.0, 1, 2);
    for i in 1..from.len() {
        for j in i + 1..from.len() {
            let a = (from[i] - from[0])
                .cross(from[j] - from[0])
                .length_squared();
            if a > best.0 {
                best = (a, i, j);
            }
        }
    }
    let (_, i, j) = best;
    let (e1, e2, q) = (from[i] - from[0], from[j] - from[0], p - from[0]);
    let (a11, a12, a22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = a11 * a22 - a12 * a12;
    if det <= 0.0 {
        return None;
    }
    let (b1, b2) = (q.dot(e1), q.dot(e2));
    let u = (b1 * a22 - b2 * a12) / det;
    let v = (a11 * b2 - a12 * b1) / det;
    Some(to[0] + (to[i] - to[0]) * u + (to[j] - to[0]) * v)
}

/// Scan converts `stream` into a frame buffer with `method`.
fn scan_frame(
    stream: &crate::tree::RecordStream,
    picture: &ScanOptions,
    method: Method,
    ids: bool,
) -> Result<FrameBuffer> {
    let mut frame = FrameBuffer::new(picture.width, picture.height, [0.0; 3]);
    // The layer's coverage and ids come from front-to-back streams, and
    // the layer is added to the picture (a refracted branch is additive in
    // either illumination model): Garcia's rule here, even when the
    // picture paints Donovan's transparency back to front.
    let options = ScanOptions {
        method,
        ids,
        paint_background: true,
        transparency: scan::TransparencyRule::Garcia,
        ..*picture
    };
    scan::scan_convert(stream, &options, &mut frame)?;
    Ok(frame)
}

/// A sink adding the layer to each row on its way to `inner`.
pub struct LayeredSink<'a> {
    /// Where the rows go.
    pub inner: &'a mut dyn RowSink,
    /// The layer.
    pub layer: &'a ExactLayer,
    buffer: Vec<[f32; 3]>,
}

impl<'a> LayeredSink<'a> {
    /// Adds `layer` to the rows going to `inner`.
    pub fn new(inner: &'a mut dyn RowSink, layer: &'a ExactLayer) -> Self {
        LayeredSink {
            inner,
            layer,
            buffer: Vec::new(),
        }
    }
}

impl RowSink for LayeredSink<'_> {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        let w = self.layer.width as usize;
        let at = row.y as usize * w;
        self.buffer.clear();
        self.buffer.extend(
            row.rgb
                .iter()
                .zip(&self.layer.add[at..at + row.rgb.len()])
                .map(|(a, b)| [0, 1, 2].map(|c| (a[c] + b[c]).clamp(0.0, 1.0))),
        );
        self.inner.row(&Row {
            rgb: &self.buffer,
            ..*row
        })
    }

    fn wants_pixel_structs(&self) -> bool {
        self.inner.wants_pixel_structs()
    }
}

/// How far, in pixels, the linearized refraction matrix (004 section
/// 6.4.3) puts what is seen through the scene's front-facing transmitting
/// polygons from where exact Snell refraction puts it. The largest error
/// over two kinds of sample; 0 when nothing transmits.
///
/// - Through the polygon: at each corner and edge midpoint (a tenth of the
///   way in) the exact refracted ray is cast to the first polygon it
///   meets, and that point, mapped by the polygon's linearized matrix,
///   should project onto the sample itself (the virtual image of a point
///   seen through it lies on the eye ray through it). Where the refracted
///   ray meets nothing (a pond with no floor) this sample says nothing.
/// - The refracted objects: every vertex (a bounded, evenly strided
///   selection in large scenes) beyond the polygon's plane is seen where
///   the exact path from the eye to it crosses the plane (Snell's law,
///   solved on the line between the feet of the eye and the vertex,
///   [`snell_crossing`]); if that crossing lies inside the polygon, the
///   vertex mapped by the linearized matrix should project onto it. This
///   is where the linear map and the exact refraction part: the
///   linearization is exact only for the ray through the polygon's centre,
///   so a cube under water off that ray, or deep, moves.
///
/// An eye at infinity (an orthographic projection) sees every point along
/// parallel rays, which the matrix maps exactly: only the first kind of
/// sample is taken.
pub fn linear_error(scene: &Scene, view: &View) -> f64 {
    if scene.modes.max_level < 2 {
        return 0.0;
    }
    let polygons = crate::geometry::bvh::WorldPolygons::new(scene);
    let mut worst: f64 = 0.0;
    for (oi, object) in scene.objects.iter().enumerate() {
        if object.surface_type.hidden {
            continue;
        }
        for (pi, poly) in object.polygons.iter().enumerate() {
            let m = object.material(pi);
            if m.transmittance <= 0.0 {
                continue;
            }
            let plane = if view.faces_eye(poly.plane) {
                poly.plane
            } else if object.surface_type.open {
                -poly.plane
            } else {
                continue;
            };
            let points: Vec<DVec3> = poly
                .indices
                .iter()
                .map(|&i| object.vertices[i as usize])
                .collect();
            let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
            let eta = 1.0 / object.surface.index;
            let Some(matrix) = crate::math::refraction(plane, -view.to_eye(centre), eta) else {
                continue;
            };
            let id = (oi as u32, pi as u32);
            // The corners and edge midpoints, pulled a tenth of the way
            // in (a corner on a wall sees along the wall).
            let n = points.len();
            let samples = (0..n).flat_map(|k| [points[k], (points[k] + points[(k + 1) % n]) / 2.0]);
            for c in samples {
                let c = centre + (c - centre) * 0.9;
                worst = worst.max(corner_error(&polygons, view, plane, eta, &matrix, c, id));
            }
            worst = worst.max(refracted_points_error(
                scene, view, plane, eta, &matrix, &points,
            ));
        }
    }
    worst
}

/// Vertices of the scene examined per transmitting polygon by
/// [`refracted_points_error`], at most (evenly strided beyond that).
const REFRACTED_SAMPLES: usize = 4096;

/// [`linear_error`] at the vertices of the scene beyond `plane` that are
/// seen through the polygon `outline` (on the plane).
fn refracted_points_error(
    scene: &Scene,
    view: &View,
    plane: DVec4,
    eta: f64,
    matrix: &crate::math::Matrix4,
    outline: &[DVec3],
) -> f64 {
    if view.eye.w.abs() < 1e-12 {
        return 0.0;
    }
    let eye = view.eye.truncate() / view.eye.w;
    let total: usize = scene
        .objects
        .iter()
        .filter(|o| !o.surface_type.hidden)
        .map(|o| o.vertices.len())
        .sum();
    let stride = total.div_ceil(REFRACTED_SAMPLES).max(1);
    let mut worst: f64 = 0.0;
    let vertices = scene
        .objects
        .iter()
        .filter(|o| !o.surface_type.hidden)
        .flat_map(|o| o.vertices.iter().copied());
    for p in vertices.step_by(stride) {
        let Some(c) = snell_crossing(eye, p, plane, eta) else {
            continue;
        };
        if !inside_outline(outline, plane.truncate(), c) {
            continue;
        }
        let q = matrix.transform_point(p);
        let (a, b) = (view.project(q), view.project(c));
        let e = ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt();
        if e.is_finite() {
            worst = worst.max(e);
        }
    }
    worst
}

/// Where the refracted path from `eye` (in front of `plane`, unit normal
/// towards it) to `p` (beyond it) crosses the plane, by Snell's law
/// `sin t1 = sin t2 / eta` (`eta` = index on the eye's side over the far
/// side's): on the line between the feet of the two points, where the
/// sines balance, by bisection (the balance grows along the line). `None`
/// when `p` is not beyond the plane.
pub fn snell_crossing(eye: DVec3, p: DVec3, plane: DVec4, eta: f64) -> Option<DVec3> {
    let n = plane.truncate();
    let (he, hp) = (n.dot(eye) + plane.w, -(n.dot(p) + plane.w));
    let small = 1e-9 * (1.0 + eye.length() + p.length());
    if !(he > small && hp > small && eta > 0.0) {
        return None;
    }
    let (a, b) = (eye - n * he, p + n * hp);
    let d = (b - a).length();
    if d <= small {
        return Some(a);
    }
    let sine = |x: f64, h: f64| x / (x * x + h * h).sqrt();
    let balance = |u: f64| eta * sine(u * d, he) - sine((1.0 - u) * d, hp);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if balance(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(a + (b - a) * (0.5 * (lo + hi)))
}

/// Whether `c` (on the plane of the convex or concave `outline`, normal
/// `normal`) is inside it: even-odd, in the projection that drops the
/// normal's largest axis.
fn inside_outline(outline: &[DVec3], normal: DVec3, c: DVec3) -> bool {
    let [u, v, _] = crate::geometry::polygon::projection_axes(normal);
    let g = |q: DVec3| (q.to_array()[u], q.to_array()[v]);
    let (px, py) = g(c);
    let mut odd = false;
    let n = outline.len();
    for k in 0..n {
        let (xa, ya) = g(outline[k]);
        let (xb, yb) = g(outline[(k + 1) % n]);
        if (ya > py) != (yb > py) && px < xa + (py - ya) / (yb - ya) * (xb - xa) {
            odd = !odd;
        }
    }
    odd
}

/// [`linear_error`] at one corner `c`.
fn corner_error(
    polygons: &crate::geometry::bvh::WorldPolygons,
    view: &View,
    plane: DVec4,
    eta: f64,
    matrix: &crate::math::Matrix4,
    c: DVec3,
    id: (u32, u32),
) -> f64 {
    let d = -view.to_eye(c) * view_depth(view);
    let t = super::optics::refract(d, plane.truncate(), eta).direction();
    let Some(hit) = polygons.cast(c, t, false, &|p, front| {
        (front || p.open) && (p.object, p.polygon) != id
    }) else {
        return 0.0;
    };
    let q = matrix.transform_point(c + t * hit.t);
    let (a, b) = (view.project(q), view.project(c));
    let e = ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt();
    if e.is_finite() { e } else { 0.0 }
}

/// A length that reaches past the scene from the eye: the far plane's
/// distance along the view axis.
fn view_depth(view: &View) -> f64 {
    view.ray(view.width / 2.0, view.height / 2.0)
        .map_or(1.0, |(o, d)| (o + d).length() + d.length())
}

//! A Whitted ray tracer over the same scene model and illumination model
//! as the virtual image tree: the reference renderer of Garcia 1986's
//! comparison (004 chapter 6, table 6.1) and the exact refraction of his
//! proposed hybrid (004 section 6.4: rays where the linear maps are
//! wrong).
//!
//! Rays start on the near plane and end on the far plane ([`View::ray`]);
//! a ray that bends keeps the rest of its length, so the far plane bounds
//! the unfolded ray as it bounds the virtual images (004 section 4.4).
//! Polygons are found through the project's one BVH
//! ([`crate::geometry::bvh`]). At a hit:
//!
//! - the own shade is the tree's: with faceted shading (the default) the
//!   illumination model (004 section 4.8, [`crate::shading`]) at the
//!   polygon's centroid, seen from the eye mapped along the ray (the
//!   mirrored eye below a mirror, exactly the tree's `T^-1` eye); with
//!   `setmode v` or `s`, the model at the hit point. Shadow rays
//!   ([`RayTracer::blocked`]) drop the terms of the Point lights they find
//!   blocked, as the tree's shadow polygons do (004 section 4.7);
//! - transparency `k_t` (004 section 4.9) adds `k_t` times what the ray
//!   meets going on; with Donovan's shading, his rule (3) (000 section 6)
//!   instead: the own shade if it is the brighter, else
//!   `(1 - k_t) own + k_t behind` ([`donovan_rule_3`]), as the scan
//!   converter's painter applies it;
//! - below `depth` and while the product of coefficients stays above
//!   `threshold` (the tree's cut-offs), a front face adds `kr` times the
//!   mirrored ray and `kt` times the refracted ray (exact Snell,
//!   [`optics::refract`]; past the critical angle the transmitted part is
//!   totally reflected).
//!
//! Differences from a textbook Whitted tracer, all to match the tree: a
//! secondary ray that meets nothing adds nothing (a mirror reflecting
//! empty space shows its own shade, not the background); back faces are
//! skipped unless `type open`, except the inside faces of a transmitting
//! solid, which a refracted ray leaves through: there it bends back into
//! air (index 1; no own shade, no second `kt`). Media do not nest.
//!
//! # Design notes
//!
//! `geometry::bvh` is the one BVH over world polygons (median splits on box
//! centres, leaves of 4; a nearest/any-hit ray query and a convex-volume
//! query). `visibility::ray_cast` (the oracle) and `raytrace` cast through
//! it. The shadow casters have their own hierarchies (`shadow::CasterIndex`):
//! `f32` boxes in the coordinates of the faces of a cube around each light,
//! and, for the volumes those cannot take, world boxes; the second is
//! still a copy of this one, not yet moved onto it.
//!
//! `raytrace::RayTracer` is a Whitted tracer that shades exactly as the
//! tree does: faceted shades at the polygon's centroid seen from the eye
//! mapped along the ray (under mirrors this is the tree's `T^-1` eye),
//! shadowed lights subtracted as the shadow polygons' shades are, `k_t`
//! transparency, `kr`/`kt` branches below `depth` and above `threshold`; a
//! secondary ray that meets nothing adds nothing (as an empty branch). Rays
//! keep their near-to-far length across bends (the far plane bounds the
//! unfolded ray). One thread gives the same image as many (rayon over rows,
//! no shared state).
//!
//! `--refraction exact` keeps data flowing one way:
//!
//! ```text
//! tree (no refracted branches) --emit--> records --scan (picture)--> rows --(+ mask * layer)--> sink
//! records, sites white, rest black --scan (same method)--> mask (coverage, anti-aliased)
//! records --point scan--> ids --> site at each pixel --rays--> layer = k kt L
//! ```
//!
//! A "site" is a fragment whose refracted branch the tree would have
//! traced. The layer and mask are made in `render::prepare`, before the
//! picture's scan conversion; `scan_into` wraps the sink in
//! `raytrace::exact::LayeredSink`, which adds `mask * layer` to each row.
//! The scan converters and the record format are unchanged. A tree file
//! (`setmode o`) gets the layer as records (`raytrace::branch_records`):
//! per site, the special record if it also reflects, then one record a
//! pixel (the pixel's square cut to the site's outline, in the layer's
//! colour before the mask), spliced into the file's order; past the tree
//! budget the file is emitted from a second tree built with the linearized
//! matrix. `auto` (the
//! default) measures the linearized matrix's error in pixels through each
//! transmitting polygon (`exact::linear_error`): near its corners (the exact
//! refracted ray is cast to what it meets, that point mapped by the
//! linearized matrix must project onto the corner) and at the scene's
//! vertices beyond its plane (where Snell's law crosses the plane,
//! `exact::snell_crossing`, against where the matrix projects the vertex),
//! and picks exact above one pixel.

pub mod branch_records;
pub mod exact;
pub mod optics;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::geometry::bvh::{Hit, WorldPolygons};
use crate::geometry::view::View;
use crate::model::{Color, LightKind, Scene};
use crate::raster::frame_buffer::FrameBuffer;
use crate::shading::{FacetTerms, Materials, ShadingModel, shade_with_model};

/// Options of a ray-traced render.
#[derive(Debug, Clone, Copy)]
pub struct RayTraceOptions {
    /// Image size overriding the scene's viewport.
    pub size: Option<(u32, u32)>,
    /// `N`: N x N rays per pixel (`--supersample N`), at the centres of
    /// an N x N grid of subpixels.
    pub samples: u32,
    /// Cast shadow rays to Point lights (`run y`).
    pub shadows: bool,
    /// The illumination model.
    pub shading: ShadingModel,
    /// Worker threads (0: all cores); the image does not depend on it.
    pub threads: usize,
    /// The ray budget (`--max-rays`), shadow rays included.
    pub max_rays: u64,
}

impl Default for RayTraceOptions {
    /// One ray per pixel, no shadows, Garcia's model, all cores.
    fn default() -> Self {
        RayTraceOptions {
            size: None,
            samples: 1,
            shadows: false,
            shading: ShadingModel::Garcia,
            threads: 0,
            max_rays: crate::budget::DEFAULT_RAYS,
        }
    }
}

/// Figures of a ray-traced render.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RayStats {
    /// Rays cast from the eye.
    pub primary: u64,
    /// Every ray cast into the scene (primary, reflected, refracted,
    /// through transparency), shadow rays excluded.
    pub rays: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
    /// Time building the hierarchy.
    pub build_time: Duration,
    /// Time tracing.
    pub trace_time: Duration,
}

impl RayStats {
    /// All rays (shadow rays included) per second of tracing.
    pub fn rays_per_second(&self) -> f64 {
        let s = self.trace_time.as_secs_f64();
        if s > 0.0 {
            (self.rays + self.shadow_rays) as f64 / s
        } else {
            0.0
        }
    }

    fn add(&mut self, c: &Counter) {
        self.rays += c.rays;
        self.shadow_rays += c.shadow_rays;
    }
}

/// Rays cast by one worker.
#[derive(Debug, Clone, Copy, Default)]
pub struct Counter {
    /// Scene rays.
    pub rays: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
}

/// A ray on its way: `origin + t dir`, `t` in `0..=1`.
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    /// Start.
    pub origin: DVec3,
    /// Direction; its length is what is left of the ray.
    pub dir: DVec3,
    /// Tree level of what it meets (1 for rays from the eye).
    pub level: u32,
    /// Product of the coefficients above it.
    pub weight: f64,
    /// The eye as what it meets sees it (homogeneous world point).
    pub eye: DVec4,
    /// The polygon it leaves, never hit again at once.
    pub exclude: Option<(u32, u32)>,
    /// Interfaces crossed without a level (exits, internal reflections),
    /// bounded so that a ray trapped in glass ends.
    pub bends: u32,
}

/// Most interfaces a ray crosses without going down a level.
const MAX_BENDS: u32 = 16;

/// The scene, its polygons' hierarchy and the tree's cut-offs.
pub struct RayTracer<'a> {
    scene: &'a Scene,
    /// The polygons' materials, resolved once.
    materials: Materials<'a>,
    polygons: WorldPolygons,
    view: View,
    shadows: bool,
    shading: ShadingModel,
    max_level: u32,
    threshold: f64,
    /// Per-point shading (`setmode v` or `s`) instead of faceted.
    per_point: bool,
    /// Rays cast by all workers, counted in blocks of [`RAY_BLOCK`].
    spent: AtomicU64,
    /// The ray budget ([`RayTracer::with_ray_limit`]).
    limit: u64,
    /// Set past the budget or on a stop request: every ray then returns
    /// at once, and the render ends with [`RayTracer::stopped`]'s error.
    stop: AtomicBool,
}

/// Rays a worker casts between two additions to the shared count (and
/// looks at the budget and at a stop request): a few milliseconds.
const RAY_BLOCK: u64 = 4096;

impl<'a> RayTracer<'a> {
    /// A tracer of `scene` seen through `view`, with the scene's `depth`
    /// and `threshold`.
    pub fn new(scene: &'a Scene, view: View, shadows: bool, shading: ShadingModel) -> Self {
        RayTracer {
            scene,
            materials: Materials::new(scene),
            polygons: WorldPolygons::new(scene),
            view,
            shadows,
            shading,
            max_level: scene.modes.max_level,
            threshold: scene.threshold,
            per_point: scene.modes.vertex_shades || scene.modes.phong,
            spent: AtomicU64::new(0),
            limit: crate::budget::DEFAULT_RAYS,
            stop: AtomicBool::new(false),
        }
    }

    /// This tracer, stopping past `rays` rays (`--max-rays`; the default
    /// is [`crate::budget::DEFAULT_RAYS`]).
    pub fn with_ray_limit(mut self, rays: u64) -> Self {
        self.limit = rays;
        self
    }

    /// Counts one ray; every [`RAY_BLOCK`] rays, adds them to the shared
    /// count and stops the render past the budget or on a stop request.
    /// Whether tracing goes on.
    fn count(&self, counter: &mut Counter) -> bool {
        if (counter.rays + counter.shadow_rays).is_multiple_of(RAY_BLOCK) {
            let spent = self.spent.fetch_add(RAY_BLOCK, Ordering::Relaxed) + RAY_BLOCK;
            if spent > self.limit || crate::cancel::requested() {
                self.stop.store(true, Ordering::Relaxed);
            }
        }
        !self.stop.load(Ordering::Relaxed)
    }

    /// The error of a render that stopped: the stop request, or the ray
    /// budget passed; `Ok` if it ran to the end.
    pub fn stopped(&self) -> Result<()> {
        if !self.stop.load(Ordering::Relaxed) {
            return Ok(());
        }
        crate::cancel::check()?;
        Err(Error::budget(
            "the ray count of this ray-traced render",
            format!("{} rays", self.limit),
            "--max-rays",
        ))
    }

    /// The view.
    pub fn view(&self) -> &View {
        &self.view
    }

    /// The ray from the eye through screen point `(x, y)` (pixels, y up).
    pub fn primary(&self, x: f64, y: f64) -> Option<Ray> {
        let (origin, dir) = self.view.ray(x, y)?;
        Some(Ray {
            origin,
            dir,
            level: 1,
            weight: 1.0,
            eye: self.view.eye,
            exclude: None,
            bends: 0,
        })
    }

    /// The colour seen along a ray from the eye (the background where it
    /// meets nothing).
    pub fn radiance(&self, ray: &Ray, counter: &mut Counter) -> Color {
        counter.rays += 1;
        if !self.count(counter) {
            return Color::ZERO;
        }
        match self.cast(ray) {
            Some(hit) => self.shade_hit(ray, hit, counter),
            None => self.scene.background,
        }
    }

    /// The colour a secondary ray brings back (nothing where it meets
    /// nothing).
    pub fn secondary(&self, ray: &Ray, counter: &mut Counter) -> Color {
        counter.rays += 1;
        if !self.count(counter) {
            return Color::ZERO;
        }
        match self.cast(ray) {
            Some(hit) => self.shade_hit(ray, hit, counter),
            None => Color::ZERO,
        }
    }

    /// The nearest polygon along `ray`: front faces, back faces of `type
    /// open` objects and of transmitting polygons (the way out of glass).
    pub fn cast(&self, ray: &Ray) -> Option<Hit> {
        let exclude = ray.exclude;
        self.polygons.cast(ray.origin, ray.dir, false, &|p, front| {
            (front || p.open || p.transmittance > 0.0) && exclude != Some((p.object, p.polygon))
        })
    }

    /// The first polygon that does not transmit along `ray`, following
    /// refraction only (at a transmitting polygon the ray goes on in the
    /// refracted direction): the object seen through glass and the point
    /// hit, for tests.
    pub fn seen_through(&self, ray: &Ray) -> Option<(Hit, DVec3)> {
        let mut ray = *ray;
        for _ in 0..MAX_BENDS {
            let hit = self.cast(&ray)?;
            let p = self.polygons.get(hit.object, hit.polygon)?;
            let point = ray.origin + ray.dir * hit.t;
            if p.transmittance <= 0.0 {
                return Some((hit, point));
            }
            let n = p.plane.truncate();
            let front = ray.dir.dot(n) < 0.0;
            let index = self.scene.objects[hit.object as usize].surface.index;
            let eta = if front || p.open { 1.0 / index } else { index };
            let rest = ray.dir * (1.0 - hit.t);
            ray.origin = point;
            ray.dir = optics::refract(rest, n, eta).direction();
            ray.exclude = Some((hit.object, hit.polygon));
        }
        None
    }

    fn shade_hit(&self, ray: &Ray, hit: Hit, counter: &mut Counter) -> Color {
        let p = self
            .polygons
            .get(hit.object, hit.polygon)
            .expect("hits are displayed polygons");
        let n = p.plane.truncate();
        let point = ray.origin + ray.dir * hit.t;
        let rest = ray.dir * (1.0 - hit.t);
        let front = ray.dir.dot(n) < 0.0;
        let id = (hit.object, hit.polygon);
        if !front && !p.open {
            // The inside face of a transmitting solid: back into air.
            return self.leave_glass(ray, id, point, rest, n, counter);
        }
        let back = !front;
        let mut c = self.own_shade(ray, id, point, back, counter);
        let kt_trp = crate::shading::transparency_of(
            &self.materials,
            self.view.eye,
            hit.object,
            hit.polygon,
            back,
        );
        if kt_trp > 0.0 {
            let behind = Ray {
                origin: point,
                dir: rest,
                exclude: Some(id),
                ..*ray
            };
            let seen = if ray.level == 1 {
                self.radiance(&behind, counter)
            } else {
                self.secondary(&behind, counter)
            };
            c = match self.shading {
                ShadingModel::Garcia => c + seen * kt_trp,
                ShadingModel::Donovan => donovan_rule_3(c, seen, kt_trp),
            };
        }
        if ray.level >= self.max_level || back {
            return c;
        }
        let m = self.materials.material(hit.object, hit.polygon);
        if m.reflectance > 0.0 && ray.weight * m.reflectance > self.threshold {
            let child = Ray {
                origin: point,
                dir: optics::reflect(rest, n),
                level: ray.level + 1,
                weight: ray.weight * m.reflectance,
                eye: crate::math::reflection(p.plane).transform(ray.eye),
                exclude: Some(id),
                bends: ray.bends,
            };
            c += self.secondary(&child, counter) * m.reflectance;
        }
        if m.transmittance > 0.0 && ray.weight * m.transmittance > self.threshold {
            c += self.refracted(ray, id, point, rest, counter) * m.transmittance;
        }
        c
    }

    /// What the refracted ray brings back at a front face (the refracted
    /// branch of the tree, resolved exactly): `ray` met polygon `id` at
    /// `point` with `rest` of its length left. Not weighted by `kt`.
    pub fn refracted(
        &self,
        ray: &Ray,
        id: (u32, u32),
        point: DVec3,
        rest: DVec3,
        counter: &mut Counter,
    ) -> Color {
        let Some(p) = self.polygons.get(id.0, id.1) else {
            return Color::ZERO;
        };
        let m = self.materials.material(id.0, id.1);
        let eta = 1.0 / self.materials.resolved[id.0 as usize].index;
        let dir = optics::refract(rest, p.plane.truncate(), eta).direction();
        let child = Ray {
            origin: point,
            dir,
            level: ray.level + 1,
            weight: ray.weight * m.transmittance,
            eye: eye_along(ray.eye, point, dir),
            exclude: Some(id),
            bends: ray.bends,
        };
        self.secondary(&child, counter)
    }

    /// A ray inside a transmitting solid meets its face `id` from within:
    /// it leaves into air, or is totally reflected back in.
    fn leave_glass(
        &self,
        ray: &Ray,
        id: (u32, u32),
        point: DVec3,
        rest: DVec3,
        n: DVec3,
        counter: &mut Counter,
    ) -> Color {
        if ray.bends >= MAX_BENDS {
            return Color::ZERO;
        }
        let index = self.scene.objects[id.0 as usize].surface.index;
        let dir = optics::refract(rest, n, index).direction();
        let child = Ray {
            origin: point,
            dir,
            eye: eye_along(ray.eye, point, dir),
            exclude: Some(id),
            bends: ray.bends + 1,
            ..*ray
        };
        self.secondary(&child, counter)
    }

    /// The own shade at a hit: faceted (the tree's) or at the point, less
    /// the Point lights a shadow ray finds blocked.
    fn own_shade(
        &self,
        ray: &Ray,
        id: (u32, u32),
        point: DVec3,
        back: bool,
        counter: &mut Counter,
    ) -> Color {
        let blocked = self.blocked(id, point, back, counter);
        if self.per_point {
            let object = &self.scene.objects[id.0 as usize];
            let m = self.materials.material(id.0, id.1);
            if self.materials.resolved[id.0 as usize].unshaded {
                return m.color;
            }
            let normal = object.polygons[id.1 as usize].normal();
            let normal = if back { -normal } else { normal };
            let lights: Vec<_> = (0..self.scene.lights.len())
                .filter(|j| !blocked.contains(&(*j as u32)))
                .map(|j| self.scene.lights[j])
                .collect();
            let to_eye = crate::geometry::view::direction_to_eye(ray.eye, point);
            return shade_with_model(
                self.shading,
                &m,
                point,
                normal,
                to_eye,
                &lights,
                self.scene.ambient,
            );
        }
        let terms = FacetTerms::new(
            &self.materials,
            ray.eye,
            id.0,
            id.1,
            back,
            None,
            self.shading,
        );
        if blocked.is_empty() {
            terms.shade()
        } else {
            terms.without(&blocked)
        }
    }

    /// The Point lights (indices, increasing) that something hides from
    /// `point` on polygon `id` (004 section 4.7's casters: polygons facing
    /// the light, back faces of `type open` objects too; never the target,
    /// nor its own object unless `type concave`). Lights behind the
    /// surface are not tested: they add nothing anyway.
    pub fn blocked(
        &self,
        id: (u32, u32),
        point: DVec3,
        back: bool,
        counter: &mut Counter,
    ) -> Vec<u32> {
        if !self.shadows {
            return Vec::new();
        }
        let object = &self.scene.objects[id.0 as usize];
        let normal = object.polygons[id.1 as usize].normal();
        let normal = if back { -normal } else { normal };
        let skip_object = (!object.surface_type.concave).then_some(id.0);
        let mut out = Vec::new();
        for (j, light) in self.scene.lights.iter().enumerate() {
            if light.kind != LightKind::Point || normal.dot(light.position - point) <= 0.0 {
                continue;
            }
            counter.shadow_rays += 1;
            self.count(counter);
            let dir = (point - light.position) * (1.0 - 1e-9);
            let hit = self.polygons.cast(light.position, dir, true, &|p, front| {
                (front || p.open) && (p.object, p.polygon) != id && Some(p.object) != skip_object
            });
            if hit.is_some() {
                out.push(j as u32);
            }
        }
        out
    }

    /// The colour of pixel `(col, row)` (row 0 at the top): the mean of
    /// `n x n` rays through the centres of its subpixels, each clamped.
    pub fn pixel(&self, col: u32, row: u32, n: u32, counter: &mut Counter) -> [f32; 3] {
        let h = self.view.height;
        let mut sum = Color::ZERO;
        for j in 0..n {
            for i in 0..n {
                let x = col as f64 + (i as f64 + 0.5) / n as f64;
                let y = h - row as f64 - (j as f64 + 0.5) / n as f64;
                if let Some(ray) = self.primary(x, y) {
                    sum += self.radiance(&ray, counter).clamp(DVec3::ZERO, DVec3::ONE);
                } else {
                    sum += self.scene.background;
                }
            }
        }
        (sum / (n * n) as f64).as_vec3().to_array()
    }

    /// Every pixel, rows from the top, in parallel over rows; the result
    /// does not depend on the thread count.
    /// Stops early, with [`RayTracer::stopped`]'s error, past the ray
    /// budget or on a stop request.
    pub fn image(&self, n: u32, counter: &mut RayStats) -> Result<Vec<[f32; 3]>> {
        let (w, h) = (self.view.width as u32, self.view.height as u32);
        let rows: Vec<(Vec<[f32; 3]>, Counter)> = (0..h)
            .into_par_iter()
            .map(|row| {
                let mut c = Counter::default();
                let pixels = (0..w).map(|col| self.pixel(col, row, n, &mut c)).collect();
                (pixels, c)
            })
            .collect();
        let mut out = Vec::with_capacity(w as usize * h as usize);
        for (pixels, c) in rows {
            counter.add(&c);
            out.extend(pixels);
        }
        counter.primary += u64::from(w) * u64::from(h) * u64::from(n * n);
        self.stopped()?;
        Ok(out)
    }
}

/// The eye of a ray bent at `point` into `dir`: on the line of the new
/// ray, as far back as the old eye was (at infinity: along `-dir`).
fn eye_along(eye: DVec4, point: DVec3, dir: DVec3) -> DVec4 {
    let u = dir.normalize_or_zero();
    if eye.w != 0.0 {
        let d = (eye.truncate() / eye.w - point).length();
        (point - u * d).extend(1.0)
    } else {
        (-u).extend(0.0)
    }
}

/// Renders `scene` with the ray tracer: the frame buffer (no ids) and the
/// figures.
pub fn render(scene: &Scene, options: &RayTraceOptions) -> Result<(FrameBuffer, RayStats)> {
    let view = View::for_scene(scene, options.size)?;
    let (width, height) = (view.width as u32, view.height as u32);
    let mut stats = RayStats::default();
    let t = Instant::now();
    let tracer = RayTracer::new(scene, view, options.shadows, options.shading)
        .with_ray_limit(options.max_rays);
    stats.build_time = t.elapsed();
    let t = Instant::now();
    let n = options.samples.max(1);
    let color =
        crate::threads::Pool::new(options.threads)?.install(|| tracer.image(n, &mut stats))?;
    stats.trace_time = t.elapsed();
    let mut frame = FrameBuffer::new(width, height, [0.0; 3]);
    frame.color = color;
    Ok((frame, stats))
}

/// Donovan's transparency rule (3) (000 section 6): the face's own shade
/// `own` (`I_a`) if it is brighter than `behind` (`I_b`), else
/// `(1 - w) I_a + w I_b`; "brighter" compares Rec. 601 luminances, as the
/// scan converter's painter does.
pub fn donovan_rule_3(own: Color, behind: Color, w: f64) -> Color {
    let luminance = |c: Color| 0.299 * c.x + 0.587 * c.y + 0.114 * c.z;
    if luminance(own) > luminance(behind) {
        own
    } else {
        own * (1.0 - w) + behind * w
    }
}

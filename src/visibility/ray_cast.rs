//! A ray-cast visibility oracle: for each pixel centre, the nearest polygon
//! along the ray from the eye, found through a bounding volume hierarchy
//! over the world polygons.
//!
//! It shares nothing with the list-priority path but the scene and its
//! projection matrix: rays are made by inverting the projection, polygons
//! are tested in world coordinates, so it is the independent reference the
//! tests compare every other algorithm against (and the `--visibility
//! ray-cast` renderer, and the `--id-image` debugging output).
//!
//! Preconditions: planar polygons (as the scene model guarantees). Back
//! faces (the ray meets the polygon from behind) are skipped unless the
//! object is `type open`, as in the geometry stage; hidden objects are
//! skipped. Only hits between the near and far planes count.

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::budget::Meter;
pub use crate::geometry::bvh::Hit;
use crate::geometry::bvh::{WorldPolygon, WorldPolygons};
use crate::math::Matrix4;
use crate::model::Scene;

/// The scene's polygons, their hierarchy ([`crate::geometry::bvh`], the
/// project's one BVH) and the inverse projection that makes the rays.
#[derive(Debug, Clone)]
pub struct RayCaster {
    polygons: WorldPolygons,
    unproject: Option<Matrix4>,
}

impl RayCaster {
    /// Builds the hierarchy for `scene`.
    pub fn new(scene: &Scene) -> RayCaster {
        RayCaster {
            polygons: WorldPolygons::new(scene),
            unproject: scene.projection.inverse(),
        }
    }

    /// The nearest front-facing polygon hit by `origin + t * dir`, `t` in
    /// `0..=1`.
    pub fn cast(&self, origin: DVec3, dir: DVec3) -> Option<Hit> {
        self.cast_excluding(origin, dir, None)
    }

    /// Follows the ray through mirror reflections: at a polygon with a
    /// reflection coefficient, while `level < max_level` and the product of
    /// coefficients stays above `threshold`, the ray goes on from the hit
    /// point in the mirrored direction for the rest of its length (so the
    /// far plane bounds the unfolded ray, as it bounds the virtual images
    /// of 004 section 4.4). Returns the last polygon hit and its level: a
    /// mirror whose reflected ray hits nothing is itself what is seen, as
    /// the painter shows it.
    pub fn trace(
        &self,
        origin: DVec3,
        dir: DVec3,
        max_level: u32,
        threshold: f64,
    ) -> Option<(Hit, u32)> {
        let (mut o, mut d) = (origin, dir);
        let mut exclude = None;
        let mut level = 1;
        let mut weight = 1.0;
        let mut remaining = 1.0;
        let mut last: Option<(Hit, u32)> = None;
        loop {
            let Some(hit) = self.cast_excluding(o, d * remaining, exclude) else {
                return last;
            };
            let k = self
                .polygon(hit.object, hit.polygon)
                .map_or(0.0, |p| p.reflectance);
            if level >= max_level || k <= 0.0 || weight * k <= threshold {
                return Some((hit, level));
            }
            let n = self
                .polygon(hit.object, hit.polygon)
                .expect("just hit")
                .plane
                .truncate();
            o += d * remaining * hit.t;
            remaining *= 1.0 - hit.t;
            d = d - n * (2.0 * d.dot(n));
            exclude = Some((hit.object, hit.polygon));
            last = Some((hit, level));
            level += 1;
            weight *= k;
        }
    }

    /// Whether something lies between a Point light and a point on polygon
    /// `target` (the shadow test of a ray tracer, 004 section 4.7): polygons
    /// facing the light block it (back faces too for `type open`); the
    /// target itself never does, nor its object when `skip_object` names it
    /// (a convex object does not shadow itself).
    pub fn occluded(
        &self,
        light: DVec3,
        point: DVec3,
        target: (u32, u32),
        skip_object: Option<u32>,
    ) -> bool {
        let dir = (point - light) * (1.0 - 1e-9);
        self.cast_filtered(light, dir, &|p: &WorldPolygon| {
            (p.object, p.polygon) != target && Some(p.object) != skip_object
        })
        .is_some()
    }

    fn polygon(&self, object: u32, polygon: u32) -> Option<&WorldPolygon> {
        self.polygons.get(object, polygon)
    }

    fn cast_excluding(
        &self,
        origin: DVec3,
        dir: DVec3,
        exclude: Option<(u32, u32)>,
    ) -> Option<Hit> {
        self.cast_filtered(origin, dir, &|p: &WorldPolygon| {
            exclude != Some((p.object, p.polygon))
        })
    }

    /// The nearest hit among the polygons `keep` accepts: front faces, and
    /// back faces of `type open` objects.
    fn cast_filtered(
        &self,
        origin: DVec3,
        dir: DVec3,
        keep: &dyn Fn(&WorldPolygon) -> bool,
    ) -> Option<Hit> {
        self.polygons
            .cast(origin, dir, false, &|p, front| (front || p.open) && keep(p))
    }

    /// The ray through normalized screen point `(x, y)` (each -1..1), from
    /// the near to the far plane, as origin and direction in world space.
    pub fn ray(&self, x: f64, y: f64) -> Option<(DVec3, DVec3)> {
        let inv = self.unproject?;
        let near = inv.transform(DVec4::new(x, y, -1.0, 1.0));
        let far = inv.transform(DVec4::new(x, y, 1.0, 1.0));
        let (o, f) = (near.truncate() / near.w, far.truncate() / far.w);
        (o.is_finite() && f.is_finite()).then_some((o, f - o))
    }

    /// The last polygon seen at every pixel centre when rays follow mirrors
    /// (see [`RayCaster::trace`]), rows from the top, in parallel.
    pub fn traced_image(
        &self,
        width: u32,
        height: u32,
        max_level: u32,
        threshold: f64,
    ) -> Vec<Option<(Hit, u32)>> {
        (0..height)
            .into_par_iter()
            .flat_map_iter(|row| {
                (0..width).map(move |col| {
                    let x = (col as f64 + 0.5) / width as f64 * 2.0 - 1.0;
                    let y = 1.0 - (row as f64 + 0.5) / height as f64 * 2.0;
                    self.ray(x, y)
                        .and_then(|(o, d)| self.trace(o, d, max_level, threshold))
                })
            })
            .collect()
    }

    /// [`RayCaster::id_image`], counting on `meter` a test per polygon
    /// each ray meets in the hierarchy (and one per ray), and leaving
    /// the rest of the image empty once `meter` says stop (past its
    /// budget, or a stop requested: looked at before every ray).
    pub fn id_image_within(&self, width: u32, height: u32, meter: &Meter) -> Vec<Option<Hit>> {
        (0..height)
            .into_par_iter()
            .flat_map_iter(|row| {
                let mut pending = 0;
                let hits: Vec<Option<Hit>> = (0..width)
                    .map(|col| {
                        if meter.stopped() {
                            return None;
                        }
                        let x = (col as f64 + 0.5) / width as f64 * 2.0 - 1.0;
                        let y = 1.0 - (row as f64 + 0.5) / height as f64 * 2.0;
                        let tests = std::cell::Cell::new(1);
                        let hit = self.ray(x, y).and_then(|(o, d)| {
                            self.polygons.cast(o, d, false, &|p, front| {
                                tests.set(tests.get() + 1);
                                front || p.open
                            })
                        });
                        meter.add_batched(&mut pending, tests.get());
                        hit
                    })
                    .collect();
                meter.add(pending);
                hits
            })
            .collect()
    }

    /// The nearest polygon at every pixel centre of a `width` x `height`
    /// image, rows from the top, in parallel.
    pub fn id_image(&self, width: u32, height: u32) -> Vec<Option<Hit>> {
        (0..height)
            .into_par_iter()
            .flat_map_iter(|row| {
                (0..width).map(move |col| {
                    let x = (col as f64 + 0.5) / width as f64 * 2.0 - 1.0;
                    let y = 1.0 - (row as f64 + 0.5) / height as f64 * 2.0;
                    self.ray(x, y).and_then(|(o, d)| self.cast(o, d))
                })
            })
            .collect()
    }
}

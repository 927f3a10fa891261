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

use crate::math::Matrix4;
use crate::scene::model::Scene;

#[derive(Debug, Clone)]
struct WorldPolygon {
    object: u32,
    polygon: u32,
    points: Vec<DVec3>,
    plane: DVec4,
    open: bool,
    /// Reflection coefficient, for rays that follow mirrors.
    reflectance: f64,
    lo: DVec3,
    hi: DVec3,
    /// The axes kept when projecting for the inside test.
    axes: (usize, usize),
}

#[derive(Debug, Clone, Copy)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: `count > 0`, polygons `first..first + count` of `order`;
    /// inner: children `first` and `first + 1`.
    first: u32,
    count: u32,
}

/// The nearest polygon along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// Parameter along the ray (0 at the near plane, 1 at the far plane).
    pub t: f64,
}

/// A bounding volume hierarchy over the scene's polygons.
#[derive(Debug, Clone)]
pub struct RayCaster {
    polygons: Vec<WorldPolygon>,
    order: Vec<u32>,
    nodes: Vec<Node>,
    unproject: Option<Matrix4>,
}

const LEAF_SIZE: usize = 4;

impl RayCaster {
    /// Builds the hierarchy for `scene`.
    pub fn new(scene: &Scene) -> RayCaster {
        let mut polygons = Vec::new();
        for (oi, object) in scene.objects.iter().enumerate() {
            if object.surface_type.hidden {
                continue;
            }
            for (pi, p) in object.polygons.iter().enumerate() {
                let points: Vec<DVec3> = p
                    .indices
                    .iter()
                    .map(|&i| object.vertices[i as usize])
                    .collect();
                let (lo, hi) = bounds(&points);
                let a = p.normal().abs();
                let axes = if a.x >= a.y && a.x >= a.z {
                    (1, 2)
                } else if a.y >= a.z {
                    (2, 0)
                } else {
                    (0, 1)
                };
                polygons.push(WorldPolygon {
                    object: oi as u32,
                    polygon: pi as u32,
                    points,
                    plane: p.plane,
                    open: object.surface_type.open,
                    reflectance: crate::shading::polygon_material(object, pi).reflectance,
                    lo,
                    hi,
                    axes,
                });
            }
        }
        let mut caster = RayCaster {
            order: (0..polygons.len() as u32).collect(),
            polygons,
            nodes: Vec::new(),
            unproject: scene.projection.inverse(),
        };
        if !caster.polygons.is_empty() {
            caster.nodes.push(Node {
                lo: DVec3::ZERO,
                hi: DVec3::ZERO,
                first: 0,
                count: 0,
            });
            caster.build(0, 0, caster.order.len());
        }
        caster
    }

    fn build(&mut self, node: usize, start: usize, end: usize) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for &k in &self.order[start..end] {
            let p = &self.polygons[k as usize];
            lo = lo.min(p.lo);
            hi = hi.max(p.hi);
            let c = (p.lo + p.hi) * 0.5;
            clo = clo.min(c);
            chi = chi.max(c);
        }
        self.nodes[node].lo = lo;
        self.nodes[node].hi = hi;
        let extent = chi - clo;
        if end - start <= LEAF_SIZE || extent.max_element() <= 0.0 {
            self.nodes[node].first = start as u32;
            self.nodes[node].count = (end - start) as u32;
            return;
        }
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        let polygons = &self.polygons;
        let centre = |k: &u32| {
            let p = &polygons[*k as usize];
            (p.lo + p.hi).to_array()[axis]
        };
        self.order[start..end]
            .select_nth_unstable_by(mid - start, |a, b| centre(a).total_cmp(&centre(b)));
        let left = self.nodes.len();
        let blank = Node {
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            first: 0,
            count: 0,
        };
        self.nodes.push(blank);
        self.nodes.push(blank);
        self.nodes[node].first = left as u32;
        self.nodes[node].count = 0;
        self.build(left, start, mid);
        self.build(left + 1, mid, end);
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
        // Polygons are stored object by object, in order.
        let i = self
            .polygons
            .partition_point(|p| (p.object, p.polygon) < (object, polygon));
        self.polygons
            .get(i)
            .filter(|p| p.object == object && p.polygon == polygon)
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

    fn cast_filtered(
        &self,
        origin: DVec3,
        dir: DVec3,
        keep: &dyn Fn(&WorldPolygon) -> bool,
    ) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = DVec3::ONE / dir;
        let mut best: Option<Hit> = None;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            let limit = best.map_or(1.0, |h| h.t);
            if !slab(node.lo, node.hi, origin, inv, limit) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first as usize);
                stack.push(node.first as usize + 1);
                continue;
            }
            for &k in &self.order[node.first as usize..(node.first + node.count) as usize] {
                let p = &self.polygons[k as usize];
                if !keep(p) {
                    continue;
                }
                let n = p.plane.truncate();
                let denom = n.dot(dir);
                if denom == 0.0 || (denom > 0.0 && !p.open) {
                    continue;
                }
                let t = -(n.dot(origin) + p.plane.w) / denom;
                if !(0.0..=1.0).contains(&t) || best.is_some_and(|b| b.t <= t) {
                    continue;
                }
                if inside(&p.points, p.axes, origin + dir * t) {
                    best = Some(Hit {
                        object: p.object,
                        polygon: p.polygon,
                        t,
                    });
                }
            }
        }
        best
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

fn bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

fn slab(lo: DVec3, hi: DVec3, o: DVec3, inv: DVec3, limit: f64) -> bool {
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let tmin = a.min(b);
    let tmax = a.max(b);
    // NaN (0 * inf) means the ray lies in a slab's face plane: keep it.
    let near = [tmin.x, tmin.y, tmin.z, 0.0]
        .into_iter()
        .filter(|v| !v.is_nan())
        .fold(f64::NEG_INFINITY, f64::max);
    let far = [tmax.x, tmax.y, tmax.z, limit]
        .into_iter()
        .filter(|v| !v.is_nan())
        .fold(f64::INFINITY, f64::min);
    near <= far * (1.0 + 1e-12) + 1e-12
}

/// Even-odd point-in-polygon test in the projection that drops one axis.
fn inside(points: &[DVec3], (u, v): (usize, usize), p: DVec3) -> bool {
    let g = |q: DVec3| {
        let a = q.to_array();
        (a[u], a[v])
    };
    let (px, py) = g(p);
    let mut odd = false;
    let n = points.len();
    for i in 0..n {
        let (ax, ay) = g(points[i]);
        let (bx, by) = g(points[(i + 1) % n]);
        if (ay > py) != (by > py) && px < ax + (py - ay) * (bx - ax) / (by - ay) {
            odd = !odd;
        }
    }
    odd
}

//! The project's one bounding volume hierarchy, over the scene's polygons
//! in world coordinates (Garcia 1986, 004 sections 6.4.1-6.4.2: "a
//! hierarchy of bounding volumes" so that a ray or a volume is tested
//! against few polygons; the ray tracer of 004 chapter 6's comparison).
//!
//! [`Bvh`] is the hierarchy itself, over any list of axis-aligned boxes:
//! median splits along the longest axis of the box centres, leaves of at
//! most [`LEAF_SIZE`] items. It answers two questions: the nearest item
//! along a ray segment ([`Bvh::nearest`], the caller tests the items of
//! the leaves it reaches) and the items whose boxes meet a convex volume
//! ([`Bvh::query_planes`]). [`WorldPolygons`] is the scene's polygons with
//! their hierarchy and the ray-polygon test; the ray-cast oracle
//! (`visibility::ray_cast`) and the ray tracer (`raytrace`) both cast
//! through it.
//!
//! Preconditions: planar polygons (the scene model's). A ray is
//! `origin + t dir`, `t` in `0..=1`: the length of `dir` bounds it.

use glam::{DVec3, DVec4};

use crate::model::Scene;

/// Items per leaf, at most.
pub const LEAF_SIZE: usize = 4;

#[derive(Debug, Clone, Copy)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: `count > 0`, items `first..first + count` of `order`;
    /// inner: children `first` and `first + 1`.
    first: u32,
    count: u32,
}

/// A bounding volume hierarchy over axis-aligned boxes.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    /// The items' boxes, for the volume query's tests at the leaves.
    boxes: Vec<(DVec3, DVec3)>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

impl Bvh {
    /// The hierarchy of `boxes` (`(lo, hi)` corners); item `k` is
    /// `boxes[k]`.
    pub fn new(boxes: &[(DVec3, DVec3)]) -> Bvh {
        let mut bvh = Bvh {
            boxes: boxes.to_vec(),
            order: (0..boxes.len() as u32).collect(),
            nodes: Vec::new(),
        };
        if !boxes.is_empty() {
            bvh.nodes.push(Node {
                lo: DVec3::ZERO,
                hi: DVec3::ZERO,
                first: 0,
                count: 0,
            });
            bvh.build(boxes, 0, 0, boxes.len());
        }
        bvh
    }

    fn build(&mut self, boxes: &[(DVec3, DVec3)], node: usize, start: usize, end: usize) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for &k in &self.order[start..end] {
            let (blo, bhi) = boxes[k as usize];
            lo = lo.min(blo);
            hi = hi.max(bhi);
            let c = (blo + bhi) * 0.5;
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
        let centre = |k: &u32| {
            let (blo, bhi) = boxes[*k as usize];
            (blo + bhi).to_array()[axis]
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
        self.build(boxes, left, start, mid);
        self.build(boxes, left + 1, mid, end);
    }

    /// The nearest hit along `origin + t dir`, `t` in `0..=1`: `test(item,
    /// best)` is called for the items of every leaf whose box the segment
    /// meets before the best hit so far (`best`, its `t`), and returns a
    /// hit nearer than `best`, if any. With `first_only`, the search stops
    /// at the first hit (an any-hit query, for shadow rays).
    pub fn nearest<H: Copy>(
        &self,
        origin: DVec3,
        dir: DVec3,
        first_only: bool,
        mut test: impl FnMut(usize, Option<f64>) -> Option<(f64, H)>,
    ) -> Option<(f64, H)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = DVec3::ONE / dir;
        let mut best: Option<(f64, H)> = None;
        let mut stack: Vec<usize> = Vec::with_capacity(64);
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            let limit = best.map_or(1.0, |h| h.0);
            if !slab(node.lo, node.hi, origin, inv, limit) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first as usize);
                stack.push(node.first as usize + 1);
                continue;
            }
            for &k in &self.order[node.first as usize..(node.first + node.count) as usize] {
                if let Some(h) = test(k as usize, best.map(|b| b.0)) {
                    best = Some(h);
                    if first_only {
                        return best;
                    }
                }
            }
        }
        best
    }

    /// The items whose boxes are not wholly outside one of `planes` (a
    /// point `p` is inside a plane `L` when `L . (p, 1) >= 0`), increasing.
    pub fn query_planes(&self, planes: &[DVec4]) -> Vec<usize> {
        let outside = |lo: DVec3, hi: DVec3| {
            planes.iter().any(|pl| {
                let n = pl.truncate();
                let far = DVec3::new(
                    if n.x >= 0.0 { hi.x } else { lo.x },
                    if n.y >= 0.0 { hi.y } else { lo.y },
                    if n.z >= 0.0 { hi.z } else { lo.z },
                );
                n.dot(far) + pl.w < 0.0
            })
        };
        let mut out = Vec::new();
        let mut stack = if self.nodes.is_empty() {
            Vec::new()
        } else {
            vec![0usize]
        };
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            if outside(node.lo, node.hi) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first as usize);
                stack.push(node.first as usize + 1);
            } else {
                let items = &self.order[node.first as usize..(node.first + node.count) as usize];
                out.extend(items.iter().map(|&k| k as usize).filter(|&k| {
                    let (lo, hi) = self.boxes[k];
                    !outside(lo, hi)
                }));
            }
        }
        out.sort_unstable();
        out
    }
}

/// One displayed polygon of the scene in world coordinates.
#[derive(Debug, Clone)]
pub struct WorldPolygon {
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// Its vertices.
    pub points: Vec<DVec3>,
    /// Its plane `[A B C D]`, unit outward normal.
    pub plane: DVec4,
    /// `type open`: seen from both sides.
    pub open: bool,
    /// Its object's `type concave` flag (whether it may shadow itself).
    pub concave: bool,
    /// Reflection coefficient.
    pub reflectance: f64,
    /// Transmission (refraction) coefficient.
    pub transmittance: f64,
    lo: DVec3,
    hi: DVec3,
    /// The axes kept when projecting for the inside test.
    axes: (usize, usize),
}

/// The nearest polygon along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// Parameter along the ray (0 at its origin, 1 at its end).
    pub t: f64,
}

/// The scene's displayed (not hidden) polygons in world coordinates and
/// their hierarchy.
#[derive(Debug, Clone, Default)]
pub struct WorldPolygons {
    polygons: Vec<WorldPolygon>,
    bvh: Bvh,
}

impl WorldPolygons {
    /// The polygons of `scene`'s displayed objects, object by object.
    pub fn new(scene: &Scene) -> WorldPolygons {
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
                let [u, v, _] = super::polygon::projection_axes(p.normal());
                let axes = (u, v);
                let material = object.material(pi);
                polygons.push(WorldPolygon {
                    object: oi as u32,
                    polygon: pi as u32,
                    points,
                    plane: p.plane,
                    open: object.surface_type.open,
                    concave: object.surface_type.concave,
                    reflectance: material.reflectance,
                    transmittance: material.transmittance,
                    lo,
                    hi,
                    axes,
                });
            }
        }
        let boxes: Vec<(DVec3, DVec3)> = polygons.iter().map(|p| (p.lo, p.hi)).collect();
        WorldPolygons {
            bvh: Bvh::new(&boxes),
            polygons,
        }
    }

    /// How many polygons.
    pub fn len(&self) -> usize {
        self.polygons.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.polygons.is_empty()
    }

    /// Polygon `polygon` of object `object`, if displayed.
    pub fn get(&self, object: u32, polygon: u32) -> Option<&WorldPolygon> {
        // Polygons are stored object by object, in order.
        let i = self
            .polygons
            .partition_point(|p| (p.object, p.polygon) < (object, polygon));
        self.polygons
            .get(i)
            .filter(|p| p.object == object && p.polygon == polygon)
    }

    /// The nearest polygon hit by `origin + t dir`, `t` in `0..=1`, among
    /// those `keep(polygon, front)` accepts (`front`: the ray meets the
    /// side its normal points to). Rays in a polygon's plane miss it.
    pub fn cast(
        &self,
        origin: DVec3,
        dir: DVec3,
        first_only: bool,
        keep: &dyn Fn(&WorldPolygon, bool) -> bool,
    ) -> Option<Hit> {
        self.bvh
            .nearest(origin, dir, first_only, |k, best| {
                let p = &self.polygons[k];
                let n = p.plane.truncate();
                let denom = n.dot(dir);
                if denom == 0.0 || !keep(p, denom < 0.0) {
                    return None;
                }
                let t = -(n.dot(origin) + p.plane.w) / denom;
                if !(0.0..=1.0).contains(&t) || best.is_some_and(|b| b <= t) {
                    return None;
                }
                inside(&p.points, p.axes, origin + dir * t).then_some((
                    t,
                    Hit {
                        object: p.object,
                        polygon: p.polygon,
                        t,
                    },
                ))
            })
            .map(|(_, h)| h)
    }
}

fn bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    crate::math::bounds(points.iter().copied())
}

/// Whether the segment `o + t / inv`, `t` in `0..=limit`, meets the box.
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

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_boxes(n: usize) -> Vec<(DVec3, DVec3)> {
        (0..n)
            .map(|i| {
                let lo = DVec3::new(i as f64 * 2.0, 0.0, 0.0);
                (lo, lo + DVec3::ONE)
            })
            .collect()
    }

    #[test]
    fn nearest_finds_the_first_box_along_the_ray_against_brute_force() {
        let boxes = unit_boxes(37);
        let bvh = Bvh::new(&boxes);
        // The "hit" of a box is its entry parameter along +x.
        let o = DVec3::new(-1.0, 0.5, 0.5);
        let d = DVec3::new(100.0, 0.0, 0.0);
        let found = bvh.nearest(o, d, false, |k, best| {
            let t = (boxes[k].0.x - o.x) / d.x;
            (t <= 1.0 && best.is_none_or(|b| t < b)).then_some((t, k))
        });
        assert_eq!(found.map(|f| f.1), Some(0));
        // From the right end, going left.
        let o = DVec3::new(80.0, 0.5, 0.5);
        let d = DVec3::new(-100.0, 0.0, 0.0);
        let found = bvh.nearest(o, d, false, |k, best| {
            let t = (boxes[k].1.x - o.x) / d.x;
            ((0.0..=1.0).contains(&t) && best.is_none_or(|b| t < b)).then_some((t, k))
        });
        assert_eq!(found.map(|f| f.1), Some(36));
    }

    #[test]
    fn query_planes_matches_brute_force() {
        let boxes = unit_boxes(50);
        let bvh = Bvh::new(&boxes);
        // x >= 20.5 and x <= 41.
        let planes = [
            DVec4::new(1.0, 0.0, 0.0, -20.5),
            DVec4::new(-1.0, 0.0, 0.0, 41.0),
        ];
        let brute: Vec<usize> = (0..boxes.len())
            .filter(|&k| boxes[k].1.x >= 20.5 && boxes[k].0.x <= 41.0)
            .collect();
        assert_eq!(bvh.query_planes(&planes), brute);
    }
}

//! The hierarchies of bounding volumes that choose the casters a shadow
//! volume may meet (004 sections 6.4.1-6.4.2: boxes tested against the
//! volume instead of every object against every volume). Per Point light,
//! the casters facing it: on each face of the cube around the light
//! ([`LightFaces`], in [`light_space`] coordinates), and in world
//! coordinates ([`LightTree`]) for the volumes the faces cannot take.
//! Boxes are in `f32`, rounded outward; nodes split at the median.

use glam::{DVec3, DVec4, Vec3};

use super::Scratch;
use super::casters::{Caster, CasterRef, NONE};
use super::light_space;
use crate::model::Object;

/// A caster's box and index, stored in a light's hierarchy in leaf order.
/// The box is in `f32`, rounded outward ([`f32_below`], [`f32_above`]): 32
/// bytes an item instead of 56, and the box still holds the caster, so a
/// query finds every caster it found in `f64` and at most a few more
/// within a rounding of its planes, which the caster's own vertex test and
/// clipping then reject.
#[derive(Clone, Copy)]
struct Item {
    lo: Vec3,
    hi: Vec3,
    caster: u32,
    /// The object of every polygon the caster stands for ([`NONE`] if
    /// several).
    object: u32,
}

/// A node: a leaf when `count > 0` (items `first..first + count`), else
/// children at `first` and `first + 1`. Its box (the union of its items')
/// is in `f32` as theirs.
#[derive(Clone, Copy)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    first: u32,
    count: u32,
    /// The one object all its casters stand for, or [`NONE`]: a query
    /// for a fragment its own object cannot shadow skips the node.
    object: u32,
}

/// The hierarchy of the casters facing one light.
pub(super) struct LightTree {
    items: Vec<Item>,
    nodes: Vec<Node>,
}

/// The casters facing one light in the coordinates of the faces of the
/// cube around it ([`light_space`]), a hierarchy a face, their boxes
/// widened by the tolerance `tol` (a distance).
pub(super) struct LightFaces {
    pub(super) tol: f64,
    faces: Vec<LightTree>,
}

/// Items per leaf.
const LEAF: usize = 4;

/// Casters whose face boxes are made at once ([`LightFaces::new`]).
const FACE_BLOCK: usize = 1 << 20;
/// Casters whose face boxes are made in one task.
const FACE_CHUNK: usize = 4096;

/// `v` in `f32`, each coordinate rounded down: never above `v`'s.
fn f32_below(v: DVec3) -> Vec3 {
    Vec3::from_array(v.to_array().map(|x| {
        let f = x as f32;
        if f64::from(f) > x { f.next_down() } else { f }
    }))
}

/// `v` in `f32`, each coordinate rounded up: never below `v`'s.
fn f32_above(v: DVec3) -> Vec3 {
    Vec3::from_array(v.to_array().map(|x| {
        let f = x as f32;
        if f64::from(f) < x { f.next_up() } else { f }
    }))
}

/// The items, face by face, of the casters `chunk` (numbered from
/// `first`) that face `light`, with their boxes widened by `tol`.
fn face_items(
    objects: &[Object],
    chunk: &[Caster],
    first: usize,
    light: DVec3,
    tol: f64,
    clip: &mut light_space::FaceClip,
) -> Vec<Vec<Item>> {
    let mut faces = vec![Vec::new(); light_space::FACES];
    let mut points = Vec::new();
    for (k, c) in chunk.iter().enumerate() {
        let caster = CasterRef::of(objects, c);
        if !caster.faces(c.open, light) {
            continue;
        }
        points.clear();
        points.extend(caster.points());
        light_space::caster_boxes(&points, light, tol, clip, |f, (lo, hi)| {
            faces[f].push(Item {
                lo: f32_below(lo),
                hi: f32_above(hi),
                caster: (first + k) as u32,
                object: c.single_object,
            });
        });
    }
    faces
}

/// Splits `items[start..end]` at the median of the box centres along the
/// longest axis of their bounds, each axis's length weighted by `weight`.
fn build(
    items: &mut [Item],
    nodes: &mut Vec<Node>,
    weight: DVec3,
    node: usize,
    start: usize,
    end: usize,
) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for it in &items[start..end] {
        lo = lo.min(it.lo);
        hi = hi.max(it.hi);
    }
    if end - start <= LEAF {
        let object = items[start].object;
        let one = items[start..end].iter().all(|it| it.object == object);
        nodes[node] = Node {
            lo,
            hi,
            first: start as u32,
            count: (end - start) as u32,
            object: if one { object } else { NONE },
        };
        return;
    }
    let e = (hi.as_dvec3() - lo.as_dvec3()) * weight;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = (start + end) / 2;
    // Twice the centre, exact in f64.
    let centre = |it: &Item| f64::from(it.lo[axis]) + f64::from(it.hi[axis]);
    items[start..end].select_nth_unstable_by(mid - start, |a, b| {
        centre(a)
            .total_cmp(&centre(b))
            .then(a.caster.cmp(&b.caster))
    });
    let left = nodes.len();
    let blank = Node {
        lo: Vec3::ZERO,
        hi: Vec3::ZERO,
        first: 0,
        count: 0,
        object: NONE,
    };
    nodes.push(blank);
    nodes.push(blank);
    nodes[node] = Node {
        lo,
        hi,
        first: left as u32,
        count: 0,
        object: NONE,
    };
    build(items, nodes, weight, left, start, mid);
    build(items, nodes, weight, left + 1, mid, end);
    if nodes[left].object == nodes[left + 1].object {
        nodes[node].object = nodes[left].object;
    }
}

/// Whether the box is wholly behind one of `planes`.
#[inline]
fn box_outside(planes: &[DVec4], lo: DVec3, hi: DVec3) -> bool {
    planes.iter().any(|pl| {
        let n = pl.truncate();
        // The box corner farthest along the normal.
        let far = DVec3::select(n.cmpge(DVec3::ZERO), hi, lo);
        n.dot(far) + pl.w < 0.0
    })
}

impl LightTree {
    /// The hierarchy of `items`, split along the axes `weight` gives
    /// weight to.
    fn new(mut items: Vec<Item>, weight: DVec3) -> LightTree {
        let mut nodes = Vec::new();
        if !items.is_empty() {
            nodes.push(Node {
                lo: Vec3::ZERO,
                hi: Vec3::ZERO,
                first: 0,
                count: 0,
                object: NONE,
            });
            let n = items.len();
            build(&mut items, &mut nodes, weight, 0, 0, n);
        }
        LightTree { items, nodes }
    }

    /// The hierarchy, in world coordinates, of the `casters` (polygons of
    /// `objects`) that `keep` keeps.
    pub(super) fn of_casters(
        objects: &[Object],
        casters: &[Caster],
        keep: impl Fn(&Caster) -> bool,
    ) -> LightTree {
        let items: Vec<Item> = casters
            .iter()
            .enumerate()
            .filter(|(_, c)| keep(c))
            .map(|(k, c)| {
                let (lo, hi) = CasterRef::of(objects, c).bounds();
                Item {
                    lo: f32_below(lo),
                    hi: f32_above(hi),
                    caster: k as u32,
                    object: c.single_object,
                }
            })
            .collect();
        LightTree::new(items, DVec3::ONE)
    }

    /// The casters whose boxes may meet the volume `planes` within
    /// `bounds`, in caster order, leaving out those that stand only for
    /// polygons of object `skip` (none when it is [`NONE`]).
    pub(super) fn query(
        &self,
        planes: &[DVec4],
        bounds: (DVec3, DVec3),
        skip: u32,
        out: &mut Vec<u32>,
    ) {
        out.clear();
        self.add(planes, bounds, skip, out);
        // The pieces keep the casters' (the scene's) order.
        out.sort_unstable();
    }

    /// [`Self::query`]'s casters added to `out`, in no order.
    fn add(&self, planes: &[DVec4], bounds: (DVec3, DVec3), skip: u32, out: &mut Vec<u32>) {
        let (blo, bhi) = bounds;
        let outside = |lo: Vec3, hi: Vec3| {
            let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
            lo.cmpgt(bhi).any() || hi.cmplt(blo).any() || box_outside(planes, lo, hi)
        };
        let skipped = |object: u32| skip != NONE && object == skip;
        if self.nodes.is_empty() {
            return;
        }
        // Median splits: the depth is at most log2 of the count + 1.
        let mut stack = [0u32; 72];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if skipped(node.object) || outside(node.lo, node.hi) {
                continue;
            }
            if node.count == 0 {
                stack[top] = node.first + 1;
                stack[top + 1] = node.first;
                top += 2;
            } else {
                let leaf = &self.items[node.first as usize..(node.first + node.count) as usize];
                out.extend(
                    leaf.iter()
                        .filter(|it| !skipped(it.object) && !outside(it.lo, it.hi))
                        .map(|it| it.caster),
                );
            }
        }
    }
}

impl LightFaces {
    /// The `casters` (polygons of `objects`) that face `light`, as it
    /// sees them, their boxes widened by `tol`: made a block at a time,
    /// its chunks on all threads (so a block's items are held twice at
    /// most), put together in caster order; then a hierarchy a face.
    pub(super) fn new(
        objects: &[Object],
        casters: &[Caster],
        light: DVec3,
        tol: f64,
    ) -> LightFaces {
        use rayon::prelude::*;
        let mut faces = vec![Vec::new(); light_space::FACES];
        for (b, block) in casters.chunks(FACE_BLOCK).enumerate() {
            let parts: Vec<Vec<Vec<Item>>> = block
                .par_chunks(FACE_CHUNK)
                .enumerate()
                .map_init(light_space::FaceClip::default, |clip, (c, chunk)| {
                    let first = b * FACE_BLOCK + c * FACE_CHUNK;
                    face_items(objects, chunk, first, light, tol, clip)
                })
                .collect();
            for part in parts {
                for (face, items) in faces.iter_mut().zip(part) {
                    face.extend(items);
                }
            }
        }
        LightFaces {
            tol,
            faces: faces
                .into_par_iter()
                .map(|items| LightTree::new(items, DVec3::new(1.0, 1.0, 0.0)))
                .collect(),
        }
    }

    /// The casters that may meet the shadow volume from `light` through
    /// the convex polygon `points` (world coordinates) down to its
    /// `plane` (world coordinates, facing the light), into `s.found` in
    /// caster order; those of object `skip` left out, as
    /// [`LightTree::query`]. A caster counts if it comes within the
    /// tolerance of the volume, or within `beyond` of the plane.
    pub(super) fn query(
        &self,
        points: &[DVec3],
        plane: DVec4,
        light: DVec3,
        beyond: f64,
        skip: u32,
        s: &mut Scratch,
    ) {
        s.found.clear();
        let mut clip = std::mem::take(&mut s.face_clip);
        light_space::target_parts(points, light, &mut clip, |f, part| {
            let Some((lo, hi)) = light_space::face_box(part.iter().copied(), light, f, 0.0) else {
                return;
            };
            let far = light_space::farthest(plane, light, f, lo, hi, beyond);
            let bounds = (lo.with_z(f64::NEG_INFINITY), hi.with_z(far));
            light_space::face_sides(part, light, f, &mut s.face_sides);
            self.faces[f].add(&s.face_sides, bounds, skip, &mut s.found);
        });
        s.face_clip = clip;
        s.found.sort_unstable();
        s.found.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rounded outward, an `f32` box holds the `f64` one: below and above
    /// bracket every value, by one `f32` step at most, and values an
    /// `f32` holds exactly stay as they are.
    #[test]
    fn f32_boxes_round_outward() {
        for x in [
            0.1,
            -0.1,
            1.0 / 3.0,
            -2.7,
            1e-50,
            -1e-50,
            1e300,
            -1e300,
            12345.678,
        ] {
            let v = DVec3::new(x, -x, x * 3.0);
            let (lo, hi) = (f32_below(v).as_dvec3(), f32_above(v).as_dvec3());
            assert!(lo.cmple(v).all() && v.cmple(hi).all(), "{x}: {lo} {v} {hi}");
            let (l, h) = (f32_below(v).x, f32_above(v).x);
            assert!(
                l == h || l.next_up() == h || l == f32::MAX || h == f32::MIN,
                "{x}"
            );
        }
        for x in [0.0, 1.0, -0.5, 1024.0] {
            let v = DVec3::splat(x);
            assert_eq!(f32_below(v).as_dvec3(), v);
            assert_eq!(f32_above(v).as_dvec3(), v);
        }
    }

    /// A caster is 20 bytes and a hierarchy's item 32.
    #[test]
    fn casters_and_items_are_small() {
        assert!(std::mem::size_of::<Caster>() <= 20);
        assert!(std::mem::size_of::<Item>() <= 32);
        assert!(std::mem::size_of::<Node>() <= 36);
    }
}

//! Constructive solid geometry (Firebaugh 001, chapter 8, figures
//! 8.12-8.15): regularized union, intersection and difference of two
//! closed polygon meshes, by binary space partitioning trees.
//!
//! Each operand is put in a BSP tree whose nodes are its faces' planes.
//! Clipping one operand's faces against the other's tree keeps the parts
//! outside (or, with the tree inverted, inside) the other solid; faces
//! lying in a plane of the other tree go to its front or back by the
//! direction of their normal. The sequences are those of the classic
//! BSP Boolean (union: A clipped to B, B clipped to A, the coplanar copies
//! in B removed by clipping B's inverse), as in figure 8.15's ordered
//! binary tree of operations.
//!
//! Coplanar faces (tested in `tests/modeling_csg.rs`): where A and B have
//! faces in one plane facing the same way, the result keeps one copy
//! (A's), so overlapping boxes sharing face planes combine exactly.
//! Solids that touch along a face (coplanar faces facing opposite ways):
//! the union drops both faces (one closed solid, the two touching faces
//! gone), the intersection is empty (an object with no polygons), the
//! difference is A unchanged. Identical operands: union and intersection
//! are A, the difference is empty.
//!
//! The fragments are then joined into a closed mesh: points closer than
//! the tolerance become one, and a point lying on another fragment's edge
//! is inserted into that edge (removing the T-junctions splitting leaves),
//! so every edge is shared by exactly two faces. Non-convex input faces
//! are triangulated first, since a plane may cut them more than twice.

use std::collections::HashMap;

use glam::DVec3;

use crate::geometry::polygon;
use crate::model::Mesh;

/// The Boolean operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// `A ∪ B`.
    Union,
    /// `A ∩ B`.
    Intersection,
    /// `A − B`.
    Difference,
}

/// A face of an operand: points clockwise from outside, a unit normal at
/// each point (for shading), and an attribute carried to the result.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// Points, clockwise seen from outside.
    pub points: Vec<DVec3>,
    /// Shading normal at each point.
    pub normals: Vec<DVec3>,
    /// What the face keeps (the operand's surface), opaque here.
    pub attr: u32,
}

/// A plane `n . p = w`, `n` the outward unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Plane {
    n: DVec3,
    w: f64,
}

impl Plane {
    fn flip(&mut self) {
        self.n = -self.n;
        self.w = -self.w;
    }
}

/// A fragment of an input face.
#[derive(Debug, Clone)]
struct Poly {
    points: Vec<DVec3>,
    normals: Vec<DVec3>,
    plane: Plane,
    attr: u32,
    /// The input face it came from.
    source: u32,
    /// Not cut.
    whole: bool,
}

impl Poly {
    fn flip(&mut self) {
        self.points.reverse();
        self.normals.reverse();
        for n in &mut self.normals {
            *n = -*n;
        }
        self.plane.flip();
    }
}

const COPLANAR: u8 = 0;
const FRONT: u8 = 1;
const BACK: u8 = 2;
const SPANNING: u8 = 3;

/// Splits `p` by `plane`: the coplanar ones go to `cf` or `cb` by the
/// direction of their normal.
fn split(
    plane: &Plane,
    p: Poly,
    eps: f64,
    cf: &mut Vec<Poly>,
    cb: &mut Vec<Poly>,
    front: &mut Vec<Poly>,
    back: &mut Vec<Poly>,
) {
    let mut kind = 0u8;
    let types: Vec<u8> = p
        .points
        .iter()
        .map(|q| {
            let d = plane.n.dot(*q) - plane.w;
            let t = if d < -eps {
                BACK
            } else if d > eps {
                FRONT
            } else {
                COPLANAR
            };
            kind |= t;
            t
        })
        .collect();
    match kind {
        COPLANAR => {
            if plane.n.dot(p.plane.n) > 0.0 {
                cf.push(p)
            } else {
                cb.push(p)
            }
        }
        FRONT => front.push(p),
        BACK => back.push(p),
        _ => {
            let m = p.points.len();
            let (mut f, mut b) = (Vec::new(), Vec::new());
            let (mut fnrm, mut bnrm) = (Vec::new(), Vec::new());
            for i in 0..m {
                let j = (i + 1) % m;
                let (ti, tj) = (types[i], types[j]);
                let (vi, vj) = (p.points[i], p.points[j]);
                let (ni, nj) = (p.normals[i], p.normals[j]);
                if ti != BACK {
                    f.push(vi);
                    fnrm.push(ni);
                }
                if ti != FRONT {
                    b.push(vi);
                    bnrm.push(ni);
                }
                if (ti | tj) == SPANNING {
                    let t = (plane.w - plane.n.dot(vi)) / plane.n.dot(vj - vi);
                    let v = vi.lerp(vj, t);
                    let n = ni.lerp(nj, t).normalize_or(ni);
                    f.push(v);
                    fnrm.push(n);
                    b.push(v);
                    bnrm.push(n);
                }
            }
            if f.len() >= 3 {
                front.push(Poly {
                    points: f,
                    normals: fnrm,
                    whole: false,
                    ..p.clone()
                });
            }
            if b.len() >= 3 {
                back.push(Poly {
                    points: b,
                    normals: bnrm,
                    whole: false,
                    ..p
                });
            }
        }
    }
}

/// How many input faces were kept whole, cut, or dropped entirely.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    /// Faces in the result unchanged.
    pub kept: usize,
    /// Faces in the result in pieces.
    pub split: usize,
    /// Faces not in the result.
    pub removed: usize,
}

/// The result of [`combine`].
#[derive(Debug, Clone, PartialEq)]
pub struct Result {
    /// The faces of the result, clockwise from outside.
    pub faces: Vec<Face>,
    /// Kept, split and removed input faces.
    pub stats: Stats,
}

fn to_polys(faces: Vec<Face>, first_source: u32) -> Vec<Poly> {
    let mut out = Vec::with_capacity(faces.len());
    for (k, f) in faces.into_iter().enumerate() {
        let source = first_source + k as u32;
        let n = -polygon::newell_vector(f.points.iter().copied());
        let Some(n) = n.try_normalize() else {
            continue;
        };
        let centroid = f.points.iter().sum::<DVec3>() / f.points.len() as f64;
        let plane = Plane {
            n,
            w: n.dot(centroid),
        };
        let convex = polygon::is_convex(&f.points);
        if convex {
            out.push(Poly {
                points: f.points,
                normals: f.normals,
                plane,
                attr: f.attr,
                source,
                whole: true,
            });
            continue;
        }
        // Triangles of a non-convex face; their normals found by point.
        let normal_of = |q: DVec3| {
            f.points
                .iter()
                .position(|p| *p == q)
                .map_or(n, |i| f.normals[i])
        };
        for t in polygon::triangulate(&f.points) {
            out.push(Poly {
                points: t.to_vec(),
                normals: t.iter().map(|&q| normal_of(q)).collect(),
                plane,
                attr: f.attr,
                source,
                whole: false,
            });
        }
    }
    out
}

/// The size the tolerances scale with: the largest coordinate.
fn size_of(faces: &[Face]) -> f64 {
    faces
        .iter()
        .flat_map(|f| f.points.iter())
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()))
        .max(f64::MIN_POSITIVE)
}

/// Relative tolerance of plane classification and of joining points.
pub const TOLERANCE: f64 = 1e-9;

/// Why [`combine_within`] stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// More face pairs to test than allowed: the count when it stopped.
    Pairs(u64),
    /// Ctrl-C.
    Cancelled,
}

/// Combines two closed solids given by their faces (unbounded; see
/// [`combine_within`]).
pub fn combine(a: Vec<Face>, b: Vec<Face>, op: Op) -> Result {
    combine_within(a, b, op, u64::MAX).unwrap_or(Result {
        faces: Vec::new(),
        stats: Stats::default(),
    })
}

/// The work done, counted against a budget, with Ctrl-C looked at every
/// few thousand units.
struct Work {
    done: u64,
    max: u64,
}

impl Work {
    fn add(&mut self, n: u64) -> std::result::Result<(), Stop> {
        let before = self.done;
        self.done = self.done.saturating_add(n);
        if self.done > self.max {
            return Err(Stop::Pairs(self.done));
        }
        if before >> 14 != self.done >> 14 && crate::cancel::requested() {
            return Err(Stop::Cancelled);
        }
        Ok(())
    }
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    fn of(points: &[DVec3], pad: f64) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.lo = b.lo.min(*p);
            b.hi = b.hi.max(*p);
        }
        b.lo -= DVec3::splat(pad);
        b.hi += DVec3::splat(pad);
        b
    }

    fn union(self, o: Aabb) -> Aabb {
        Aabb {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    fn overlaps(&self, o: &Aabb) -> bool {
        self.lo.cmple(o.hi).all() && o.lo.cmple(self.hi).all()
    }

    /// Whether the ray `o + t d`, `t >= 0`, meets the box (`inv` = 1/d).
    fn hit_by(&self, o: DVec3, inv: DVec3) -> bool {
        let t1 = (self.lo - o) * inv;
        let t2 = (self.hi - o) * inv;
        let near = t1.min(t2).max_element();
        let far = t1.max(t2).min_element();
        far >= near.max(0.0)
    }
}

/// A bounding volume hierarchy over the faces of one operand: the spatial
/// index that finds the faces near a face, or along a ray, in logarithmic
/// time (a BSP tree of a convex solid is a chain as deep as its faces).
struct Bvh {
    boxes: Vec<Aabb>,
    nodes: Vec<BNode>,
    items: Vec<u32>,
}

struct BNode {
    bounds: Aabb,
    /// Children, or `None` for a leaf holding `items[start..start + count]`.
    children: Option<(u32, u32)>,
    start: u32,
    count: u32,
}

impl Bvh {
    fn new(polys: &[Poly], pad: f64) -> Bvh {
        let boxes: Vec<Aabb> = polys.iter().map(|p| Aabb::of(&p.points, pad)).collect();
        let mut items: Vec<u32> = (0..polys.len() as u32).collect();
        let mut nodes = vec![BNode {
            bounds: Aabb::EMPTY,
            children: None,
            start: 0,
            count: items.len() as u32,
        }];
        let centre = |i: u32| {
            let b = &boxes[i as usize];
            (b.lo + b.hi) * 0.5
        };
        let mut stack = vec![0usize];
        while let Some(id) = stack.pop() {
            let (start, count) = (nodes[id].start as usize, nodes[id].count as usize);
            let slice = &mut items[start..start + count];
            let bounds = slice
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
            nodes[id].bounds = bounds;
            if count <= 4 {
                continue;
            }
            let ext = bounds.hi - bounds.lo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let half = count / 2;
            slice
                .select_nth_unstable_by(half, |a, b| centre(*a)[axis].total_cmp(&centre(*b)[axis]));
            let l = nodes.len();
            for (s, c) in [(start, half), (start + half, count - half)] {
                nodes.push(BNode {
                    bounds: Aabb::EMPTY,
                    children: None,
                    start: s as u32,
                    count: c as u32,
                });
            }
            nodes[id].children = Some((l as u32, l as u32 + 1));
            stack.push(l);
            stack.push(l + 1);
        }
        Bvh {
            boxes,
            nodes,
            items,
        }
    }

    /// The faces whose boxes meet `b`.
    fn query(&self, b: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        if self.items.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(id) = stack.pop() {
            let n = &self.nodes[id as usize];
            if !n.bounds.overlaps(b) {
                continue;
            }
            match n.children {
                Some((l, r)) => {
                    stack.push(l);
                    stack.push(r);
                }
                None => {
                    let items = &self.items[n.start as usize..(n.start + n.count) as usize];
                    out.extend(
                        items
                            .iter()
                            .filter(|&&i| self.boxes[i as usize].overlaps(b)),
                    );
                }
            }
        }
    }

    /// The faces whose boxes the ray from `o` along `d` meets.
    fn along_ray(&self, o: DVec3, d: DVec3, out: &mut Vec<u32>) {
        out.clear();
        if self.items.is_empty() {
            return;
        }
        let inv = d.recip();
        let mut stack = vec![0u32];
        while let Some(id) = stack.pop() {
            let n = &self.nodes[id as usize];
            if !n.bounds.hit_by(o, inv) {
                continue;
            }
            match n.children {
                Some((l, r)) => {
                    stack.push(l);
                    stack.push(r);
                }
                None => {
                    let items = &self.items[n.start as usize..(n.start + n.count) as usize];
                    out.extend(
                        items
                            .iter()
                            .filter(|&&i| self.boxes[i as usize].hit_by(o, inv)),
                    );
                }
            }
        }
    }
}

/// Where a fragment lies with respect to the other solid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    Outside,
    Inside,
    /// On a face of the other solid facing the same way.
    OnSame,
    /// On a face of the other solid facing the other way.
    OnOpposite,
}

/// Ray directions tried in turn (none along an axis or a diagonal, so
/// that rays from the centres of aligned faces miss edges).
const DIRECTIONS: [[f64; 3]; 7] = [
    [0.577_215_66, 0.318_419_77, 0.751_988_27],
    [-0.412_310_56, 0.694_237_11, 0.591_607_98],
    [0.302_119_83, -0.866_025_40, 0.398_942_28],
    [-0.706_016_51, -0.236_067_98, -0.665_191_42],
    [0.915_965_59, 0.141_421_36, -0.375_492_32],
    [-0.123_456_79, 0.987_654_32, -0.096_225_04],
    [0.267_949_19, -0.358_979_31, -0.893_996_66],
];

/// The signed distances from `p` (in the plane of `poly`) to the lines of
/// the polygon's edges, inward positive, the smallest: positive inside.
fn inside_margin(poly: &Poly, p: DVec3) -> f64 {
    let m = poly.points.len();
    let n = poly.plane.n;
    let mut margin = f64::INFINITY;
    for i in 0..m {
        let (a, b) = (poly.points[i], poly.points[(i + 1) % m]);
        let e = b - a;
        let len = e.length();
        if len == 0.0 {
            continue;
        }
        // Clockwise seen from outside, counter-clockwise about -n: the
        // interior lies on the side of (-n) x e = e x n.
        let inward = e.cross(n) / len;
        margin = margin.min(inward.dot(p - a));
    }
    margin
}

/// Where the convex fragment `f` lies with respect to the closed solid
/// `other` (its faces and their index): on one of its faces, else inside
/// or outside by the parity of a ray's crossings, the ray chosen not to
/// pass near an edge; the winding number if every ray does.
fn classify(
    f: &Poly,
    other: &[Poly],
    bvh: &Bvh,
    eps: f64,
    scratch: &mut Vec<u32>,
    work: &mut Work,
) -> std::result::Result<Place, Stop> {
    let c = f.points.iter().sum::<DVec3>() / f.points.len() as f64;
    let tol = eps * 10.0;
    bvh.query(&Aabb::of(&[c], tol), scratch);
    work.add(scratch.len() as u64)?;
    for &g in scratch.iter() {
        let g = &other[g as usize];
        let parallel = g.plane.n.dot(f.plane.n);
        if (g.plane.n.dot(c) - g.plane.w).abs() <= tol
            && parallel.abs() > 1.0 - 1e-9
            && inside_margin(g, c) >= -tol
        {
            return Ok(if parallel > 0.0 {
                Place::OnSame
            } else {
                Place::OnOpposite
            });
        }
    }
    'ray: for d in DIRECTIONS {
        let d = DVec3::from_array(d).normalize();
        bvh.along_ray(c, d, scratch);
        work.add(scratch.len() as u64)?;
        let mut crossings = 0u32;
        for &g in scratch.iter() {
            let g = &other[g as usize];
            let denom = g.plane.n.dot(d);
            let dist = g.plane.w - g.plane.n.dot(c);
            if denom.abs() < 1e-12 {
                if dist.abs() <= tol {
                    continue 'ray;
                }
                continue;
            }
            let t = dist / denom;
            if t < -tol {
                continue;
            }
            let h = c + d * t;
            let margin = inside_margin(g, h);
            if margin < -tol {
                continue;
            }
            if margin <= tol || t <= tol {
                continue 'ray;
            }
            crossings += 1;
        }
        return Ok(if crossings % 2 == 1 {
            Place::Inside
        } else {
            Place::Outside
        });
    }
    // Every ray grazed an edge: the generalized winding number.
    work.add(other.len() as u64)?;
    let mut solid = 0.0;
    for g in other {
        let a = g.points[0] - c;
        for k in 1..g.points.len() - 1 {
            let (b, e) = (g.points[k] - c, g.points[k + 1] - c);
            let (la, lb, le) = (a.length(), b.length(), e.length());
            let num = a.dot(b.cross(e));
            let den = la * lb * le + a.dot(b) * le + a.dot(e) * lb + b.dot(e) * la;
            solid += 2.0 * num.atan2(den);
        }
    }
    Ok(if solid.abs() > std::f64::consts::TAU {
        Place::Inside
    } else {
        Place::Outside
    })
}

/// The fragments of `polys` cut by the planes of the faces of `other`
/// whose boxes meet theirs: the surface of `other` then crosses no
/// fragment's interior, so each lies wholly inside, outside or on it.
fn fragments(
    polys: Vec<Poly>,
    other: &[Poly],
    bvh: &Bvh,
    eps: f64,
    work: &mut Work,
) -> std::result::Result<Vec<Poly>, Stop> {
    let mut out = Vec::with_capacity(polys.len());
    let mut near = Vec::new();
    let (mut cf, mut cb, mut front, mut back) = (vec![], vec![], vec![], vec![]);
    for p in polys {
        bvh.query(&Aabb::of(&p.points, eps), &mut near);
        work.add(near.len() as u64 + 1)?;
        let mut frags = vec![p];
        for &g in &near {
            let g = &other[g as usize];
            let gb = bvh.boxes_of(g, eps);
            let mut next = Vec::with_capacity(frags.len() + 1);
            for f in frags {
                if !Aabb::of(&f.points, eps).overlaps(&gb) {
                    next.push(f);
                    continue;
                }
                work.add(1)?;
                split(&g.plane, f, eps, &mut cf, &mut cb, &mut front, &mut back);
                next.append(&mut cf);
                next.append(&mut cb);
                next.append(&mut front);
                next.append(&mut back);
            }
            frags = next;
        }
        out.append(&mut frags);
    }
    Ok(out)
}

impl Bvh {
    fn boxes_of(&self, g: &Poly, pad: f64) -> Aabb {
        Aabb::of(&g.points, pad)
    }
}

/// Combines two closed solids given by their faces, testing at most
/// `max_pairs` pairs of faces (and of faces and rays): each face is cut
/// by the planes of the other solid's faces near it (found through a
/// bounding volume hierarchy), each fragment classified inside, outside
/// or on the other solid, and kept by the operation:
///
/// | fragment of | union | intersection | difference |
/// |---|---|---|---|
/// | A outside B | kept | | kept |
/// | A inside B | | kept | |
/// | A on B, same way | kept | kept | |
/// | A on B, opposite | | | kept |
/// | B outside A | kept | | |
/// | B inside A | | kept | kept, reversed |
/// | B on A | | | |
pub fn combine_within(
    a: Vec<Face>,
    b: Vec<Face>,
    op: Op,
    max_pairs: u64,
) -> std::result::Result<Result, Stop> {
    let size = size_of(&a).max(size_of(&b));
    let eps = TOLERANCE * size;
    let total = a.len() + b.len();
    let na = a.len() as u32;
    let mut work = Work {
        done: 0,
        max: max_pairs,
    };
    let pa = to_polys(a, 0);
    let pb = to_polys(b, na);
    work.add((pa.len() + pb.len()) as u64)?;
    let (ba, bb) = (Bvh::new(&pa, eps), Bvh::new(&pb, eps));
    let fa = fragments(pa.clone(), &pb, &bb, eps, &mut work)?;
    let fb = fragments(pb.clone(), &pa, &ba, eps, &mut work)?;
    let mut polys = Vec::with_capacity(fa.len() + fb.len());
    let mut scratch = Vec::new();
    for f in fa {
        let place = classify(&f, &pb, &bb, eps, &mut scratch, &mut work)?;
        let keep = matches!(
            (op, place),
            (Op::Union, Place::Outside | Place::OnSame)
                | (Op::Intersection, Place::Inside | Place::OnSame)
                | (Op::Difference, Place::Outside | Place::OnOpposite)
        );
        if keep {
            polys.push(f);
        }
    }
    for mut f in fb {
        let keep = match (op, classify(&f, &pa, &ba, eps, &mut scratch, &mut work)?) {
            (Op::Union, Place::Outside) => true,
            (Op::Intersection, Place::Inside) => true,
            (Op::Difference, Place::Inside) => {
                f.flip();
                true
            }
            _ => false,
        };
        if keep {
            polys.push(f);
        }
    }
    let mut whole = vec![false; total];
    let mut cut = vec![false; total];
    for p in &polys {
        if p.whole {
            whole[p.source as usize] = true;
        } else {
            cut[p.source as usize] = true;
        }
    }
    let mut stats = Stats::default();
    for i in 0..total {
        match (whole[i], cut[i]) {
            (true, _) => stats.kept += 1,
            (false, true) => stats.split += 1,
            _ => stats.removed += 1,
        }
    }
    crate::cancel::check().map_err(|_| Stop::Cancelled)?;
    let faces = stitch(polys, eps * 10.0);
    Ok(Result { faces, stats })
}

/// Joins points closer than `tol` (a grid of cells of that size, each
/// point looked up in its 27 neighbouring cells), returning an id per
/// point and the representative positions.
fn weld(points: &[DVec3], tol: f64) -> (Vec<u32>, Vec<DVec3>) {
    let cell = |p: DVec3| (p / tol).floor().to_array().map(|c| c as i64);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut reps: Vec<DVec3> = Vec::new();
    let mut ids = Vec::with_capacity(points.len());
    for p in points {
        let c = cell(*p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        for &id in list {
                            if reps[id as usize].distance(*p) <= tol {
                                found = Some(id);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        let id = found.unwrap_or_else(|| {
            reps.push(*p);
            let id = (reps.len() - 1) as u32;
            grid.entry(c).or_default().push(id);
            id
        });
        ids.push(id);
    }
    (ids, reps)
}

/// A face as welded point ids with a normal per corner.
struct Loop {
    ids: Vec<u32>,
    normals: Vec<DVec3>,
    attr: u32,
}

/// Welds the fragments and removes T-junctions (see the module doc).
fn stitch(polys: Vec<Poly>, tol: f64) -> Vec<Face> {
    let all: Vec<DVec3> = polys
        .iter()
        .flat_map(|p| p.points.iter().copied())
        .collect();
    let (ids, reps) = weld(&all, tol);
    let mut loops = Vec::with_capacity(polys.len());
    let mut k = 0;
    for p in &polys {
        let mut l = Loop {
            ids: Vec::new(),
            normals: Vec::new(),
            attr: p.attr,
        };
        for n in &p.normals {
            let id = ids[k];
            k += 1;
            if l.ids.last() != Some(&id) {
                l.ids.push(id);
                l.normals.push(*n);
            }
        }
        remove_spikes(&mut l);
        if l.ids.len() >= 3 {
            loops.push(l);
        }
    }
    // Edges without their reverse, and the points at their ends.
    let mut count: HashMap<(u32, u32), i32> = HashMap::new();
    for l in &loops {
        let m = l.ids.len();
        for i in 0..m {
            *count.entry((l.ids[i], l.ids[(i + 1) % m])).or_insert(0) += 1;
        }
    }
    let mut candidates: Vec<u32> = count
        .keys()
        .filter(|(a, b)| !count.contains_key(&(*b, *a)))
        .flat_map(|&(a, b)| [a, b])
        .collect();
    candidates.sort_unstable();
    candidates.dedup();
    // Sorted by x, so that an edge looks only at the points in its x range.
    candidates.sort_by(|a, b| reps[*a as usize].x.total_cmp(&reps[*b as usize].x));
    if !candidates.is_empty() {
        for l in &mut loops {
            insert_t_points(l, &count, &candidates, &reps, tol);
        }
    }
    loops
        .into_iter()
        .filter(|l| l.ids.len() >= 3)
        .map(|l| Face {
            points: l.ids.iter().map(|&i| reps[i as usize]).collect(),
            normals: l.normals,
            attr: l.attr,
        })
        .collect()
}

/// Inserts into the unmatched edges of `l` the candidate points (sorted by
/// x) lying on them, in order along the edge, with normals interpolated.
fn insert_t_points(
    l: &mut Loop,
    count: &HashMap<(u32, u32), i32>,
    candidates: &[u32],
    reps: &[DVec3],
    tol: f64,
) {
    let m = l.ids.len();
    let mut ids = Vec::with_capacity(m);
    let mut normals = Vec::with_capacity(m);
    for i in 0..m {
        let (a, b) = (l.ids[i], l.ids[(i + 1) % m]);
        ids.push(a);
        normals.push(l.normals[i]);
        if count.contains_key(&(b, a)) {
            continue;
        }
        let (pa, pb) = (reps[a as usize], reps[b as usize]);
        let ab = pb - pa;
        let len2 = ab.length_squared();
        if len2 == 0.0 {
            continue;
        }
        let (lo, hi) = (pa.x.min(pb.x) - tol, pa.x.max(pb.x) + tol);
        let from = candidates.partition_point(|&c| reps[c as usize].x < lo);
        let to = candidates.partition_point(|&c| reps[c as usize].x <= hi);
        let mut on: Vec<(f64, u32)> = candidates[from..to.max(from)]
            .iter()
            .filter(|&&c| c != a && c != b)
            .filter_map(|&c| {
                let p = reps[c as usize];
                let t = (p - pa).dot(ab) / len2;
                (t > 0.0 && t < 1.0 && (pa + ab * t).distance(p) <= tol).then_some((t, c))
            })
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (na, nb) = (l.normals[i], l.normals[(i + 1) % m]);
        for (t, c) in on {
            ids.push(c);
            normals.push(na.lerp(nb, t).normalize_or(na));
        }
    }
    l.ids = ids;
    l.normals = normals;
    remove_spikes(l);
}

/// Removes from a loop the points repeated in a row and the spikes
/// `a, b, a` (a sliver welded flat, or a point inserted on both of its
/// sides): each would use one edge twice and leave the mesh open.
fn remove_spikes(l: &mut Loop) {
    let mut ids: Vec<u32> = Vec::with_capacity(l.ids.len());
    let mut normals: Vec<DVec3> = Vec::with_capacity(l.ids.len());
    let push = |ids: &mut Vec<u32>, normals: &mut Vec<DVec3>, id: u32, n: DVec3| {
        if ids.last() == Some(&id) {
            return;
        }
        if ids.len() >= 2 && ids[ids.len() - 2] == id {
            ids.pop();
            normals.pop();
            return;
        }
        ids.push(id);
        normals.push(n);
    };
    for (&id, &n) in l.ids.iter().zip(&l.normals) {
        push(&mut ids, &mut normals, id, n);
    }
    // Across the loop's start: rotate the spike or repetition away.
    let mut guard = ids.len();
    while ids.len() >= 3 && guard > 0 {
        guard -= 1;
        let m = ids.len();
        if ids[0] == ids[m - 1] {
            ids.pop();
            normals.pop();
        } else if ids[1] == ids[m - 1] {
            // last, first, second = x, y, x.
            ids.remove(0);
            normals.remove(0);
            ids.pop();
            normals.pop();
        } else if ids[0] == ids[m - 2] {
            // second last, last, first = x, y, x.
            ids.pop();
            normals.pop();
            ids.pop();
            normals.pop();
        } else {
            break;
        }
    }
    if ids.len() < 3 {
        ids.clear();
        normals.clear();
    }
    l.ids = ids;
    l.normals = normals;
}

/// The faces as a mesh: points shared where position (and, with
/// `normals`, the normal) agree. Returns the mesh, the normals, and each
/// polygon's attribute.
pub fn to_mesh(faces: &[Face], with_normals: bool) -> (Mesh, Option<Vec<DVec3>>, Vec<u32>) {
    let mut index: HashMap<[u64; 6], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut normals = Vec::new();
    let mut polygons = Vec::with_capacity(faces.len());
    let mut attrs = Vec::with_capacity(faces.len());
    for f in faces {
        let mut poly = Vec::with_capacity(f.points.len());
        for (p, n) in f.points.iter().zip(&f.normals) {
            let n = if with_normals { *n } else { DVec3::ZERO };
            let key = [
                p.x.to_bits(),
                p.y.to_bits(),
                p.z.to_bits(),
                n.x.to_bits(),
                n.y.to_bits(),
                n.z.to_bits(),
            ];
            let id = *index.entry(key).or_insert_with(|| {
                vertices.push(*p);
                normals.push(n);
                (vertices.len() - 1) as u32
            });
            poly.push(id);
        }
        polygons.push(poly);
        attrs.push(f.attr);
    }
    (
        Mesh::new(vertices, polygons),
        with_normals.then_some(normals),
        attrs,
    )
}

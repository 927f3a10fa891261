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
use crate::scene::object_file::Mesh;

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

/// A BSP tree in an arena; node 0 is the root.
#[derive(Debug, Clone, Default)]
struct Tree {
    nodes: Vec<Node>,
}

#[derive(Debug, Clone, Default)]
struct Node {
    plane: Option<Plane>,
    front: Option<usize>,
    back: Option<usize>,
    polygons: Vec<Poly>,
}

impl Tree {
    fn new(polys: Vec<Poly>, eps: f64) -> Tree {
        let mut t = Tree {
            nodes: vec![Node::default()],
        };
        t.build(polys, eps);
        t
    }

    /// Adds `polys` to the tree (iteratively: a convex solid makes a chain
    /// as deep as its face count).
    fn build(&mut self, polys: Vec<Poly>, eps: f64) {
        let mut work = vec![(0usize, polys)];
        while let Some((id, polys)) = work.pop() {
            if polys.is_empty() {
                continue;
            }
            let plane = *self.nodes[id].plane.get_or_insert(polys[0].plane);
            let (mut cf, mut cb, mut front, mut back) = (vec![], vec![], vec![], vec![]);
            for p in polys {
                split(&plane, p, eps, &mut cf, &mut cb, &mut front, &mut back);
            }
            self.nodes[id].polygons.extend(cf);
            self.nodes[id].polygons.extend(cb);
            for (side, list) in [(true, front), (false, back)] {
                if list.is_empty() {
                    continue;
                }
                let child = if side {
                    self.nodes[id].front
                } else {
                    self.nodes[id].back
                };
                let child = child.unwrap_or_else(|| {
                    self.nodes.push(Node::default());
                    let c = self.nodes.len() - 1;
                    if side {
                        self.nodes[id].front = Some(c);
                    } else {
                        self.nodes[id].back = Some(c);
                    }
                    c
                });
                work.push((child, list));
            }
        }
    }

    /// The parts of `polys` outside the solid (in front of the tree).
    fn clip_polygons(&self, polys: Vec<Poly>, eps: f64) -> Vec<Poly> {
        let mut out = Vec::new();
        let mut work = vec![(0usize, polys)];
        while let Some((id, polys)) = work.pop() {
            let node = &self.nodes[id];
            let Some(plane) = node.plane else {
                out.extend(polys);
                continue;
            };
            let (mut front, mut back) = (vec![], vec![]);
            for p in polys {
                let (mut cf, mut cb) = (vec![], vec![]);
                split(&plane, p, eps, &mut cf, &mut cb, &mut front, &mut back);
                front.extend(cf);
                back.extend(cb);
            }
            match node.front {
                Some(c) => work.push((c, front)),
                None => out.extend(front),
            }
            if let Some(c) = node.back {
                work.push((c, back));
            }
        }
        out
    }

    /// Removes from this tree's polygons the parts inside `other`.
    fn clip_to(&mut self, other: &Tree, eps: f64) {
        for node in &mut self.nodes {
            let polys = std::mem::take(&mut node.polygons);
            node.polygons = other.clip_polygons(polys, eps);
        }
    }

    /// Solid and empty space swapped.
    fn invert(&mut self) {
        for node in &mut self.nodes {
            for p in &mut node.polygons {
                p.flip();
            }
            if let Some(pl) = &mut node.plane {
                pl.flip();
            }
            std::mem::swap(&mut node.front, &mut node.back);
        }
    }

    fn all(self) -> Vec<Poly> {
        self.nodes.into_iter().flat_map(|n| n.polygons).collect()
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

/// Combines two closed solids given by their faces.
pub fn combine(a: Vec<Face>, b: Vec<Face>, op: Op) -> Result {
    let size = size_of(&a).max(size_of(&b));
    let eps = TOLERANCE * size;
    let total = a.len() + b.len();
    let na = a.len() as u32;
    let mut ta = Tree::new(to_polys(a, 0), eps);
    let mut tb = Tree::new(to_polys(b, na), eps);
    let flip_result = match op {
        Op::Union => {
            ta.clip_to(&tb, eps);
            tb.clip_to(&ta, eps);
            tb.invert();
            tb.clip_to(&ta, eps);
            tb.invert();
            false
        }
        Op::Difference => {
            ta.invert();
            ta.clip_to(&tb, eps);
            tb.clip_to(&ta, eps);
            tb.invert();
            tb.clip_to(&ta, eps);
            tb.invert();
            true
        }
        Op::Intersection => {
            ta.invert();
            tb.clip_to(&ta, eps);
            tb.invert();
            ta.clip_to(&tb, eps);
            tb.clip_to(&ta, eps);
            true
        }
    };
    let mut polys = ta.all();
    let mut from_b = tb.all();
    polys.append(&mut from_b);
    if flip_result {
        for p in &mut polys {
            p.flip();
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
    let faces = stitch(polys, eps * 10.0);
    Result { faces, stats }
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
        while l.ids.len() > 1 && l.ids.first() == l.ids.last() {
            l.ids.pop();
            l.normals.pop();
        }
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
        Mesh { vertices, polygons },
        with_normals.then_some(normals),
        attrs,
    )
}

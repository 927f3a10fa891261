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

mod bvh;
mod classify;
mod stitch;

use bvh::*;
use classify::*;
use stitch::*;

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

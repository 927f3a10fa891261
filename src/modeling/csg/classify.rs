//! Inside, outside or on: the classification of a fragment against the
//! other solid of a CSG operation (Firebaugh 001, chapter 8, figures
//! 8.12-8.15), by rays in several directions, and the fragments of a face
//! cut by the other solid's planes.

use super::*;

/// Where a fragment lies with respect to the other solid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Place {
    Outside,
    Inside,
    /// On a face of the other solid facing the same way.
    OnSame,
    /// On a face of the other solid facing the other way.
    OnOpposite,
}

/// Ray directions tried in turn (none along an axis or a diagonal, so
/// that rays from the centres of aligned faces miss edges).
pub(super) const DIRECTIONS: [[f64; 3]; 7] = [
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
pub(super) fn inside_margin(poly: &Poly, p: DVec3) -> f64 {
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
pub(super) fn classify(
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
pub(super) fn fragments(
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
    pub(super) fn boxes_of(&self, g: &Poly, pad: f64) -> Aabb {
        Aabb::of(&g.points, pad)
    }
}

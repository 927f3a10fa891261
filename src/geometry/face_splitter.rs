//! Donovan's face splitter (Donovan 1973, 000 section 4): a planar polygon
//! and a cutting plane in, the pieces on each side out.
//!
//! The polygon is walked as a ring of edges; edges that cross the plane get
//! a new vertex on the line of intersection. The crossing points are sorted
//! along that line, and consecutive pairs (Donovan's "left" and "right"
//! lists, which the alternation property makes pair up) are joined by
//! generated edges; following the ring and the generated edges gives the
//! pieces. So non-convex polygons split into as many rings as the plane
//! makes, not into one ring with zero-width bridges.
//!
//! Vertices within `epsilon` of the plane are snapped onto it and counted
//! with the back side, as if the plane were moved an infinitesimal distance
//! to the front. Then every crossing is transversal, the alternation
//! property holds, and crossings that coincide are ordered by where the
//! moved plane would cut them. This is Donovan's "perturb the scan line"
//! argument (000 section 5) applied to the cutting plane, and it replaces
//! his repair of equal endpoints: no piece has a vertex beyond the plane by
//! less than `epsilon`, so no sliver thinner than that is made.
//!
//! Preconditions: the polygon is planar (or twisted so that its crossings
//! still lie on one line, as Donovan allows), closed and not
//! self-intersecting. The plane is `[A B C D]`, front where
//! `A x + B y + C z + D > 0`. Polygons lying in the plane are reported as
//! [`Split::Coplanar`].

use glam::{DVec3, DVec4};

use super::polygon::newell_vector;

/// Where a polygon lies with respect to a plane.
#[derive(Debug, Clone, PartialEq)]
pub enum Split {
    /// Wholly in front (vertices on the plane allowed).
    Front,
    /// Wholly behind (vertices on the plane allowed).
    Back,
    /// In the plane.
    Coplanar,
    /// Cut: the pieces in front and behind, each a closed loop in the
    /// polygon's own orientation.
    Both {
        /// Pieces in front of the plane.
        front: Vec<Vec<DVec3>>,
        /// Pieces behind the plane.
        back: Vec<Vec<DVec3>>,
    },
}

/// The splitter could not pair the crossings: the polygon is not simple.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NotSimple;

#[derive(Debug, Clone, Copy)]
enum Item {
    /// An original vertex.
    Vertex { point: DVec3 },
    /// A crossing; `into_front` if the ring goes from back to front here.
    Crossing {
        point: DVec3,
        into_front: bool,
        key: (f64, f64),
    },
}

impl Item {
    fn point(&self) -> DVec3 {
        match *self {
            Item::Vertex { point, .. } | Item::Crossing { point, .. } => point,
        }
    }
}

/// Splits `points` by `plane`; `epsilon` is an absolute distance.
pub fn split(points: &[DVec3], plane: DVec4, epsilon: f64) -> Result<Split, NotSimple> {
    let normal = plane.truncate();
    let distance: Vec<f64> = points
        .iter()
        .map(|p| {
            let d = normal.dot(*p) + plane.w;
            if d.abs() <= epsilon { 0.0 } else { d }
        })
        .collect();
    let any_front = distance.iter().any(|&d| d > 0.0);
    let any_back = distance.iter().any(|&d| d < 0.0);
    match (any_front, any_back) {
        (false, false) => return Ok(Split::Coplanar),
        (true, false) => return Ok(Split::Front),
        (false, true) => return Ok(Split::Back),
        (true, true) => {}
    }

    // Direction along the line of intersection with the front side on its
    // left, seen with the polygon counter-clockwise about `poly_normal`.
    let poly_normal = newell_vector(points.iter().copied());
    let along = normal.cross(poly_normal);

    let n = points.len();
    let mut ring: Vec<Item> = Vec::with_capacity(n + 4);
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b) = (points[i], points[j]);
        let (da, db) = (distance[i], distance[j]);
        let (fa, fb) = (da > 0.0, db > 0.0);
        ring.push(Item::Vertex { point: a });
        if fa != fb {
            let t = da / (da - db);
            let point = if t <= 0.0 {
                a
            } else if t >= 1.0 {
                b
            } else {
                a + (b - a) * t
            };
            // Where the plane moved by +delta cuts the edge, to first order.
            let slope = (b - a) / (db - da);
            ring.push(Item::Crossing {
                point,
                into_front: fb,
                key: (along.dot(point), along.dot(slope)),
            });
        }
    }
    let front = pieces(&ring, true)?;
    let back = pieces(&ring, false)?;
    Ok(Split::Both { front, back })
}

/// The pieces on one side: follow the ring on that side, and the line of
/// intersection between an exit and the next entry.
fn pieces(ring: &[Item], front_side: bool) -> Result<Vec<Vec<DVec3>>, NotSimple> {
    let m = ring.len();
    // Crossings sorted along the line, as seen from this side.
    let mut crossings: Vec<usize> = (0..m)
        .filter(|&i| matches!(ring[i], Item::Crossing { .. }))
        .collect();
    let key = |i: usize| match ring[i] {
        Item::Crossing { key, .. } => {
            if front_side {
                key
            } else {
                (-key.0, -key.1)
            }
        }
        Item::Vertex { .. } => unreachable!("only crossings are sorted"),
    };
    crossings.sort_by(|&a, &b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
    });
    let enters =
        |i: usize| matches!(ring[i], Item::Crossing { into_front, .. } if into_front == front_side);
    if !crossings.len().is_multiple_of(2) {
        return Err(NotSimple);
    }
    // Along the line, inside segments run from an exit to an entry.
    let mut bridge = vec![usize::MAX; m];
    for pair in crossings.chunks_exact(2) {
        let (exit, entry) = (pair[0], pair[1]);
        if enters(exit) || !enters(entry) {
            return Err(NotSimple);
        }
        bridge[exit] = entry;
    }
    let mut used = vec![false; m];
    let mut out = Vec::new();
    for &start in &crossings {
        if !enters(start) || used[start] {
            continue;
        }
        let mut loop_points: Vec<DVec3> = Vec::new();
        let mut i = start;
        let mut steps = 0;
        loop {
            if used[i] {
                if i == start {
                    break;
                }
                return Err(NotSimple);
            }
            used[i] = true;
            loop_points.push(ring[i].point());
            steps += 1;
            if steps > 2 * m {
                return Err(NotSimple);
            }
            let is_exit = matches!(ring[i], Item::Crossing { .. }) && !enters(i);
            i = if is_exit { bridge[i] } else { (i + 1) % m };
            if i == usize::MAX {
                return Err(NotSimple);
            }
        }
        loop_points.dedup_by(|a, b| a == b);
        while loop_points.len() > 1 && loop_points.first() == loop_points.last() {
            loop_points.pop();
        }
        if loop_points.len() >= 3 && newell_vector(loop_points.iter().copied()).length() > 0.0 {
            out.push(loop_points);
        }
    }
    Ok(out)
}

/// Clips a polygon to the intersection of the front half-spaces of
/// `planes`, with the splitter (Donovan 000 section 4: "the face splitting
/// algorithm can be used either by the special sorter or the polygon
/// clipper"). A non-convex polygon may come out in several pieces.
pub fn clip_to_planes(
    points: &[DVec3],
    planes: &[DVec4],
    epsilon: f64,
) -> Result<Vec<Vec<DVec3>>, NotSimple> {
    let mut current = vec![points.to_vec()];
    for &plane in planes {
        let mut next = Vec::with_capacity(current.len());
        for poly in current {
            // Most polygons lie wholly on one side: decide without splitting.
            let n = plane.truncate();
            let (lo, hi) = poly
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let d = n.dot(*p) + plane.w;
                    (lo.min(d), hi.max(d))
                });
            if lo >= -epsilon {
                next.push(poly);
                continue;
            }
            if hi <= epsilon {
                continue;
            }
            match split(&poly, plane, epsilon)? {
                Split::Front | Split::Coplanar => next.push(poly),
                Split::Back => {}
                Split::Both { front, .. } => next.extend(front),
            }
        }
        current = next;
        if current.is_empty() {
            break;
        }
    }
    Ok(current)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon::area;
    use proptest::prelude::*;

    fn xy(pts: &[(f64, f64)]) -> Vec<DVec3> {
        pts.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect()
    }

    fn total(polys: &[Vec<DVec3>]) -> f64 {
        polys.iter().map(|p| area(p)).sum()
    }

    /// The plane x = c, front where x > c.
    fn x_plane(c: f64) -> DVec4 {
        DVec4::new(1.0, 0.0, 0.0, -c)
    }

    #[test]
    fn square_split_in_half() {
        let sq = xy(&[(0.0, 0.0), (0.0, 2.0), (2.0, 2.0), (2.0, 0.0)]);
        let Split::Both { front, back } = split(&sq, x_plane(0.5), 1e-9).unwrap() else {
            panic!("not split")
        };
        assert_eq!((front.len(), back.len()), (1, 1));
        assert!((area(&front[0]) - 3.0).abs() < 1e-12);
        assert!((area(&back[0]) - 1.0).abs() < 1e-12);
        // Same orientation as the input.
        let n0 = newell_vector(sq.iter().copied());
        for p in front.iter().chain(&back) {
            assert!(newell_vector(p.iter().copied()).dot(n0) > 0.0);
        }
    }

    #[test]
    fn comb_splits_into_separate_rings() {
        // An E-like comb with three teeth pointing to +x; the plane x = 2
        // cuts all three teeth: three pieces in front, one behind.
        let comb = xy(&[
            (0.0, 0.0),
            (0.0, 5.0),
            (3.0, 5.0),
            (3.0, 4.0),
            (1.0, 4.0),
            (1.0, 3.0),
            (3.0, 3.0),
            (3.0, 2.0),
            (1.0, 2.0),
            (1.0, 1.0),
            (3.0, 1.0),
            (3.0, 0.0),
        ]);
        let Split::Both { front, back } = split(&comb, x_plane(2.0), 1e-9).unwrap() else {
            panic!("not split")
        };
        assert_eq!(front.len(), 3);
        assert_eq!(back.len(), 1);
        for f in &front {
            assert!((area(f) - 1.0).abs() < 1e-12);
        }
        assert!((total(&front) + total(&back) - area(&comb)).abs() < 1e-12);
    }

    #[test]
    fn vertices_on_the_plane() {
        // A diamond cut through two opposite vertices.
        let diamond = xy(&[(0.0, -1.0), (-1.0, 0.0), (0.0, 1.0), (1.0, 0.0)]);
        let Split::Both { front, back } = split(&diamond, x_plane(0.0), 1e-9).unwrap() else {
            panic!("not split")
        };
        assert_eq!((front.len(), back.len()), (1, 1));
        assert_eq!(front[0].len(), 3);
        assert_eq!(back[0].len(), 3);
        assert!((area(&front[0]) - 1.0).abs() < 1e-12);
        // Touching the plane at one vertex only: not split.
        let tri = xy(&[(0.0, 0.0), (1.0, 1.0), (1.0, -1.0)]);
        assert_eq!(split(&tri, x_plane(0.0), 1e-9).unwrap(), Split::Front);
        // An edge in the plane: not split either.
        let sq = xy(&[(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)]);
        assert_eq!(split(&sq, x_plane(0.0), 1e-9).unwrap(), Split::Front);
        assert_eq!(
            split(&sq, DVec4::new(0.0, 0.0, 1.0, 0.0), 1e-9).unwrap(),
            Split::Coplanar
        );
    }

    #[test]
    fn comb_with_teeth_ending_on_the_plane() {
        // Teeth tips exactly on x = 3 and the plane there: nothing in front.
        let comb = xy(&[
            (0.0, 0.0),
            (0.0, 3.0),
            (3.0, 3.0),
            (3.0, 2.0),
            (1.0, 2.0),
            (1.0, 1.0),
            (3.0, 1.0),
            (3.0, 0.0),
        ]);
        assert_eq!(split(&comb, x_plane(3.0), 1e-9).unwrap(), Split::Back);
        // The plane along the inner edges x = 1: the teeth in front, the
        // spine behind, the notch's edge shared.
        let Split::Both { front, back } = split(&comb, x_plane(1.0), 1e-9).unwrap() else {
            panic!("not split")
        };
        assert!((total(&front) - 4.0).abs() < 1e-12, "{front:?}");
        assert!((total(&back) - 3.0).abs() < 1e-12, "{back:?}");
    }

    #[test]
    fn clipper_keeps_the_inside() {
        let big = xy(&[(-5.0, -5.0), (-5.0, 5.0), (5.0, 5.0), (5.0, -5.0)]);
        let planes = [
            DVec4::new(1.0, 0.0, 0.0, 1.0),
            DVec4::new(-1.0, 0.0, 0.0, 1.0),
            DVec4::new(0.0, 1.0, 0.0, 1.0),
            DVec4::new(0.0, -1.0, 0.0, 1.0),
        ];
        let out = clip_to_planes(&big, &planes, 1e-9).unwrap();
        assert_eq!(out.len(), 1);
        assert!((area(&out[0]) - 4.0).abs() < 1e-12);
    }

    /// A random star-shaped (hence simple) polygon around the origin, tilted
    /// into 3D.
    fn star(radii: &[f64], tilt: f64) -> Vec<DVec3> {
        let n = radii.len();
        let (s, c) = tilt.sin_cos();
        radii
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                let (x, y) = (r * a.cos(), r * a.sin());
                DVec3::new(x, y * c, y * s)
            })
            .collect()
    }

    proptest! {
        #[test]
        fn pieces_conserve_area_and_keep_their_sides(
            radii in prop::collection::vec(0.2f64..3.0, 3..14),
            tilt in -1.2f64..1.2,
            nx in -1.0f64..1.0, ny in -1.0f64..1.0, nz in -1.0f64..1.0,
            offset in -2.0f64..2.0,
            snap in 0usize..14,
        ) {
            let poly = star(&radii, tilt);
            let normal = DVec3::new(nx, ny, nz);
            prop_assume!(normal.length() > 0.1);
            let normal = normal.normalize();
            // Sometimes put the plane through a vertex, to exercise snapping.
            let d = if snap < poly.len() { -normal.dot(poly[snap]) } else { offset };
            let plane = normal.extend(d);
            let eps = 1e-9;
            let poly_plane = newell_vector(poly.iter().copied()).normalize();
            match split(&poly, plane, eps).unwrap() {
                Split::Both { front, back } => {
                    let sum = total(&front) + total(&back);
                    prop_assert!((sum - area(&poly)).abs() < 1e-9 * area(&poly).max(1.0), "{} vs {}", sum, area(&poly));
                    for p in front.iter().flatten() {
                        prop_assert!(normal.dot(*p) + d >= -eps);
                    }
                    for p in back.iter().flatten() {
                        prop_assert!(normal.dot(*p) + d <= eps);
                    }
                    for p in front.iter().chain(&back).flatten() {
                        prop_assert!((poly_plane.dot(*p - poly[0])).abs() < 1e-9, "off the polygon's plane");
                    }
                }
                Split::Front => prop_assert!(poly.iter().all(|p| normal.dot(*p) + d >= -eps)),
                Split::Back => prop_assert!(poly.iter().all(|p| normal.dot(*p) + d <= eps)),
                Split::Coplanar => prop_assert!(poly.iter().all(|p| (normal.dot(*p) + d).abs() <= eps)),
            }
        }
    }
}

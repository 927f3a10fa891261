//! The shadow of one light on a polygon as the union of its pieces (004
//! section 4.7 casts one piece per caster; Atherton, Weiler and Greenberg
//! 1978 keep a polygon's shadow as a few outlines of surface detail).
//! Casters that overlap as seen from the light give overlapping pieces,
//! and the casters of a tessellated surface give one piece per facet:
//! their union is the same region in far fewer, larger polygons, so the
//! tree holds fewer fragments, the scan converter tiles fewer records and
//! the overlaps of several lights ([`super::overlap`]) meet fewer pairs.
//!
//! The union is computed in the target's plane, in the two coordinates
//! its normal shows best ([`PlaneFrame`]), by [`boolean`], and comes back
//! as simple polygons without holes. A union that would have more than
//! [`MAX_GROWTH`] times the points of its pieces (a pathological overlay),
//! or that keeps a degenerate hole, is not used: the pieces are kept (as
//! flattened and lifted back into the plane).

use glam::{DVec3, DVec4};

use crate::geometry::boolean::{self, Flat};

/// The most points a union may have, as a multiple of its pieces' points.
const MAX_GROWTH: usize = 4;

/// A plane's points in two coordinates (its normal's largest component
/// dropped, the other two in cyclic order, so that counter-clockwise in
/// them is counter-clockwise about that axis) and back.
#[derive(Debug, Clone, Copy)]
pub struct PlaneFrame {
    plane: DVec4,
    axes: [usize; 3],
}

impl PlaneFrame {
    /// The frame of `plane` (`A x + B y + C z + D = 0`, normal not zero).
    pub fn new(plane: DVec4) -> PlaneFrame {
        let axes = crate::geometry::polygon::projection_axes(plane.truncate());
        PlaneFrame { plane, axes }
    }

    /// The flat ring of `points`, counter-clockwise.
    pub fn counter_clockwise(&self, points: &[DVec3]) -> Vec<Flat> {
        boolean::counter_clockwise(self.flat(points))
    }

    /// The flat ring of `points`, turning as they do.
    pub fn flat(&self, points: &[DVec3]) -> Vec<Flat> {
        points
            .iter()
            .map(|p| [p[self.axes[0]], p[self.axes[1]]])
            .collect()
    }

    /// The points of the plane on a counter-clockwise flat ring,
    /// counter-clockwise about the plane's normal.
    pub fn lift_ring(&self, mut ring: Vec<Flat>) -> Vec<DVec3> {
        let n = self.plane.truncate();
        let [i, j, k] = self.axes;
        if n[k] < 0.0 {
            ring.reverse();
        }
        ring.into_iter()
            .map(|q| {
                let mut p = DVec3::ZERO;
                p[i] = q[0];
                p[j] = q[1];
                p[k] = -(self.plane.w + n[i] * q[0] + n[j] * q[1]) / n[k];
                p
            })
            .collect()
    }
}

/// The union of `pieces`, polygons in the plane `plane`: simple polygons
/// without holes covering the same region, counter-clockwise about the
/// plane's normal. One piece, or none, comes back as it is.
pub fn union(pieces: Vec<Vec<DVec3>>, plane: DVec4) -> Vec<Vec<DVec3>> {
    if pieces.len() < 2 {
        return pieces;
    }
    let frame = PlaneFrame::new(plane);
    let flat = flattened(&frame, pieces);
    let rings = match united(&flat) {
        Some(rings) => rings,
        None => flat,
    };
    rings.into_iter().map(|r| frame.lift_ring(r)).collect()
}

/// Outline loops (see [`super::outline`]) projected onto a target's
/// plane: those that stay within the target, and those to be cut to its
/// outline (of objects that reach beyond its shadow volume's sides).
#[derive(Debug, Default)]
pub struct Loops {
    /// Loops within the target.
    pub within: Vec<Vec<DVec3>>,
    /// Loops to be cut to the target's outline.
    pub cut: Vec<Vec<DVec3>>,
}

impl Loops {
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.within.is_empty() && self.cut.is_empty()
    }
}

/// The union of `pieces` and of the region that `loops` wind around
/// (non-zero), all in the plane `plane`, as [`union`], the loops of
/// `loops.cut` cut to the convex polygon `target` first; `None` when the
/// engine's union cannot be used ([`union`] then keeps the pieces, which
/// loops cannot stand for). The loops may cross themselves and each
/// other; they are turned as a whole, so that the area they wind around
/// counts positive, never one by one (a loop around a hole turns the
/// other way). Cutting a loop to a convex outline, edge by edge
/// (Sutherland-Hodgman), keeps its winding number at every point inside:
/// where the loop leaves, the cut runs along the outline's edge and back.
pub fn union_with_loops(
    pieces: Vec<Vec<DVec3>>,
    loops: Loops,
    plane: DVec4,
    target: &[DVec3],
) -> Option<Vec<Vec<DVec3>>> {
    let frame = PlaneFrame::new(plane);
    let mut flat = flattened(&frame, pieces);
    let within = loops.within.len();
    let mut rings: Vec<Vec<Flat>> = (loops.within.iter().chain(&loops.cut))
        .map(|l| frame.flat(l))
        .collect();
    if rings.iter().map(|r| boolean::twice_area(r)).sum::<f64>() < 0.0 {
        rings.iter_mut().for_each(|r| r.reverse());
    }
    let outline = frame.counter_clockwise(target);
    for ring in &mut rings[within..] {
        *ring = boolean::clip_convex(ring, &outline);
    }
    rings.retain(|r| r.len() >= 3);
    flat.append(&mut rings);
    united(&flat).map(|rings| rings.into_iter().map(|r| frame.lift_ring(r)).collect())
}

/// `pieces` as counter-clockwise flat rings in `frame`, each freed as it
/// is flattened: a ten-million-triangle mesh casts five million pieces on
/// its floor.
fn flattened(frame: &PlaneFrame, pieces: Vec<Vec<DVec3>>) -> Vec<Vec<Flat>> {
    pieces
        .into_iter()
        .map(|p| frame.counter_clockwise(&p))
        .collect()
}

/// The engine's union of the counter-clockwise `rings` as simple rings
/// without holes, unless it has more than [`MAX_GROWTH`] times their
/// points or keeps a degenerate hole.
fn united(rings: &[Vec<Flat>]) -> Option<Vec<Vec<Flat>>> {
    let points: usize = rings.iter().map(Vec::len).sum();
    boolean::without_holes(boolean::union(rings))
        .filter(|out| out.iter().map(Vec::len).sum::<usize>() <= MAX_GROWTH * points)
}

/// The intersection of `a` and `b`, simple polygons in the plane
/// `plane`: simple polygons without holes, counter-clockwise about the
/// plane's normal (none if a degenerate hole was left).
pub fn intersection(a: &[DVec3], b: &[DVec3], plane: DVec4) -> Vec<Vec<DVec3>> {
    let frame = PlaneFrame::new(plane);
    let (a, b) = (frame.counter_clockwise(a), frame.counter_clockwise(b));
    boolean::without_holes(boolean::intersection(&[a], &[b]))
        .unwrap_or_default()
        .into_iter()
        .map(|r| frame.lift_ring(r))
        .collect()
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A plane through `origin` with unit normal `n`, and a map from its
    /// own two coordinates into it.
    pub fn tilted(n: DVec3, origin: DVec3) -> (DVec4, impl Fn(f64, f64) -> DVec3) {
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        (n.extend(-n.dot(origin)), move |x, y| origin + u * x + v * y)
    }

    /// Whether `p` lies strictly inside the polygon `ring` (any
    /// orientation) of the plane with normal `n`, by the winding number;
    /// `None` within `margin` of an edge.
    pub fn inside(ring: &[DVec3], n: DVec3, p: DVec3, margin: f64) -> Option<bool> {
        let mut winding = 0.0;
        for k in 0..ring.len() {
            let (a, b) = (ring[k] - p, ring[(k + 1) % ring.len()] - p);
            let e = b - a;
            let t = (-a.dot(e) / e.length_squared()).clamp(0.0, 1.0);
            if (a + e * t).length() < margin {
                return None;
            }
            winding += a.cross(b).dot(n).atan2(a.dot(b));
        }
        Some(winding.abs() > std::f64::consts::PI)
    }

    fn area(ring: &[DVec3], n: DVec3) -> f64 {
        crate::geometry::polygon::newell_vector(ring.iter().copied()).dot(n) / 2.0
    }

    fn square(at: &impl Fn(f64, f64) -> DVec3, x: f64, y: f64, s: f64) -> Vec<DVec3> {
        vec![at(x, y), at(x + s, y), at(x + s, y + s), at(x, y + s)]
    }

    /// Two overlapping unit squares: one outline of area 2 - 1/4, in the
    /// plane, counter-clockwise about its normal.
    #[test]
    fn two_squares_make_one_outline() {
        for n in [DVec3::Z, -DVec3::X, DVec3::new(0.3, -0.8, 0.5).normalize()] {
            let (plane, at) = tilted(n, DVec3::new(1.0, 2.0, 3.0));
            let got = union(
                vec![square(&at, 0.0, 0.0, 1.0), square(&at, 0.5, 0.5, 1.0)],
                plane,
            );
            assert_eq!(got.len(), 1, "{n}");
            assert_eq!(got[0].len(), 8, "{n}");
            assert!((area(&got[0], n) - 1.75).abs() < 1e-12, "{n}");
            for p in &got[0] {
                assert!((n.dot(*p) + plane.w).abs() < 1e-12);
            }
        }
    }

    /// Eight squares around a ninth left out: a frame with a hole. The
    /// strips have no hole, cover the frame once and the hole never.
    #[test]
    fn a_hole_is_cut_into_strips() {
        let n = DVec3::new(-0.2, 0.4, -0.9).normalize();
        let (plane, at) = tilted(n, DVec3::ZERO);
        let mut pieces = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                if (i, j) != (1, 1) {
                    // Overlapping a little, so the union must merge them.
                    pieces.push(square(&at, i as f64 - 0.05, j as f64 - 0.05, 1.1));
                }
            }
        }
        let got = union(pieces, plane);
        assert!(got.len() >= 2, "a frame needs at least two strips");
        let total: f64 = got.iter().map(|r| area(r, n)).sum();
        assert!(
            (total - (3.1f64.powi(2) - 0.9f64.powi(2))).abs() < 1e-9,
            "{total}"
        );
        for (x, y) in [(1.5, 1.5), (1.1, 1.9), (0.5, 0.5), (2.5, 1.5), (1.5, 2.9)] {
            let owners = got
                .iter()
                .filter(|r| inside(r, n, at(x, y), 1e-9) == Some(true))
                .count();
            let want = usize::from(!(1.05..1.95).contains(&x) || !(1.05..1.95).contains(&y));
            assert_eq!(owners, want, "({x}, {y})");
        }
    }

    /// Pieces of one polygon touching only at a corner: the splitter
    /// refuses the bow tie, the boolean engine clips it.
    #[test]
    fn intersection_takes_what_the_splitter_refuses() {
        let (plane, at) = tilted(DVec3::Z, DVec3::ZERO);
        let bow = [
            at(0.0, 0.0),
            at(1.0, 0.0),
            at(1.0, 1.0),
            at(2.0, 1.0),
            at(2.0, 2.0),
            at(1.0, 2.0),
            at(1.0, 1.0),
            at(0.0, 1.0),
        ];
        let window = square(&at, 0.5, 0.5, 1.0);
        let got = intersection(&bow, &window, plane);
        let total: f64 = got.iter().map(|r| area(r, DVec3::Z).abs()).sum();
        assert!((total - 0.5).abs() < 1e-12, "{total}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// Random triangles and quads in a random plane: a point covered by
        /// some piece is covered by exactly one ring of the union, and a
        /// point covered by none by no ring.
        #[test]
        fn the_union_covers_what_the_pieces_cover_once(
            normal in (-1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0),
            shapes in prop::collection::vec((0.0f64..6.0, 0.0f64..6.0, 0.2f64..2.5, 3usize..5, 0.0f64..6.3), 2..24),
            probes in prop::collection::vec((-1.0f64..9.0, -1.0f64..9.0), 64),
        ) {
            let n = DVec3::new(normal.0, normal.1, normal.2).normalize();
            let (plane, at) = tilted(n, DVec3::new(0.5, -1.0, 2.0));
            let pieces: Vec<Vec<DVec3>> = shapes
                .iter()
                .map(|&(x, y, r, k, turn)| {
                    (0..k)
                        .map(|i| {
                            let a = turn + std::f64::consts::TAU * i as f64 / k as f64;
                            at(x + r * a.cos(), y + r * a.sin())
                        })
                        .collect()
                })
                .collect();
            let got = union(pieces.clone(), plane);
            for (x, y) in probes {
                let p = at(x, y);
                let by_pieces: Option<Vec<bool>> = pieces.iter().map(|r| inside(r, n, p, 1e-6)).collect();
                let by_union: Option<Vec<bool>> = got.iter().map(|r| inside(r, n, p, 1e-6)).collect();
                let (Some(a), Some(b)) = (by_pieces, by_union) else { continue };
                let want = usize::from(a.iter().any(|&c| c));
                prop_assert_eq!(b.iter().filter(|&&c| c).count(), want);
            }
            for r in &got {
                prop_assert!(area(r, n) > 0.0, "counter-clockwise about the normal");
            }
        }
    }
}

//! Polygon planes and checks (Garcia 1986, 004 section 4.3: "polygon plane
//! equations are computed and saved in the object's data structure";
//! vertex normals "by averaging the plane equations of each polygon sharing
//! the given vertex").
//!
//! Convention: vertices are listed clockwise seen from outside in a
//! right-handed system, so the outward normal is the Newell normal of the
//! reversed (counter-clockwise) order.

use glam::{DVec3, DVec4};

use crate::precision;

/// The axes of the projection that shows a plane with normal `normal`
/// best: `[u, v, w]`, `w` the normal's largest component (dropped) and
/// `u, v` the other two in cyclic order, so that counter-clockwise in
/// `(u, v)` is counter-clockwise about `+w`.
pub fn projection_axes(normal: DVec3) -> [usize; 3] {
    let a = normal.abs();
    if a.x >= a.y && a.x >= a.z {
        [1, 2, 0]
    } else if a.y >= a.z {
        [2, 0, 1]
    } else {
        [0, 1, 2]
    }
}

/// Newell's area vector of the loop `points` in the given order: its length
/// is twice the area, its direction follows the right-hand rule (points
/// counter-clockwise around it). Exact for planar polygons, a best fit for
/// others.
pub fn newell_vector(points: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let first = points.clone().next();
    let mut sum = DVec3::ZERO;
    let mut prev: Option<DVec3> = None;
    for p in points.chain(first) {
        if let Some(q) = prev {
            sum.x += (q.y - p.y) * (q.z + p.z);
            sum.y += (q.z - p.z) * (q.x + p.x);
            sum.z += (q.x - p.x) * (q.y + p.y);
        }
        prev = Some(p);
    }
    sum
}

/// The plane through `points` with the unit normal of their Newell
/// vector (right-handed about their order) and through their centroid;
/// `None` when they span no area.
pub fn newell_plane(points: &[DVec3]) -> Option<DVec4> {
    let n = newell_vector(points.iter().copied()).try_normalize()?;
    let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    Some(n.extend(-n.dot(c)))
}

/// Area of a planar polygon given in any order.
pub fn area(points: &[DVec3]) -> f64 {
    newell_vector(points.iter().copied()).length() / 2.0
}

/// The diagonal of the axis-aligned bounding box of `points`: the size
/// that the tolerances of [`outward_plane`] scale with. It lies between the
/// diameter (the largest distance between two points) and `sqrt(3)` times
/// it, and takes one pass over the points (the exact diameter takes a
/// pass over every pair, which a polygon of 200,000 vertices cannot
/// afford). 0 for fewer than two points; NaN coordinates are ignored.
pub fn extent(points: &[DVec3]) -> f64 {
    if points.len() < 2 {
        return 0.0;
    }
    let (lo, hi) = crate::math::bounds(points.iter().copied());
    (hi - lo).max(DVec3::ZERO).length()
}

/// What is wrong with a polygon, if anything.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PolygonDefect {
    /// Fewer than three distinct vertices.
    TooFewVertices(usize),
    /// All vertices on a line (zero area).
    ZeroArea,
    /// Vertices off the best-fit plane by this fraction of the polygon's
    /// size ([`extent`]).
    NonPlanar(f64),
}

/// The outward plane `[A B C D]` (unit normal) of a clockwise-from-outside
/// polygon, or its defect. Vertices closer than the coincidence tolerance
/// count once when counting distinct vertices. Linear in the number of
/// vertices.
pub fn outward_plane(points: &[DVec3]) -> Result<DVec4, PolygonDefect> {
    let diam = extent(points);
    let distinct = distinct_count_up_to_3(points, diam);
    if distinct < 3 {
        return Err(PolygonDefect::TooFewVertices(distinct));
    }
    // Clockwise from outside: reverse for the right-hand rule.
    let n = newell_vector(points.iter().rev().copied());
    let len = n.length();
    // Written so that NaN counts as degenerate.
    if len.partial_cmp(&(precision::DEGENERATE_AREA * diam * diam))
        != Some(std::cmp::Ordering::Greater)
    {
        return Err(PolygonDefect::ZeroArea);
    }
    let normal = n / len;
    let centroid = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let d = -normal.dot(centroid);
    let off = points
        .iter()
        .map(|p| (normal.dot(*p) + d).abs())
        .fold(0.0, f64::max);
    if off > precision::PLANARITY_TOLERANCE * diam {
        return Err(PolygonDefect::NonPlanar(off / diam));
    }
    Ok(normal.extend(d))
}

/// The number of distinct vertices (greedily: a vertex is new when no
/// vertex already counted lies within the tolerance), counted up to 3: the
/// only question asked is whether there are fewer than three, so at most
/// two vertices are ever compared with, and the count is linear.
fn distinct_count_up_to_3(points: &[DVec3], size: f64) -> usize {
    let tol = precision::COINCIDENT_VERTEX * size;
    let mut unique = [DVec3::ZERO; 3];
    let mut count = 0;
    for p in points {
        if !unique[..count].iter().any(|q| q.distance(*p) <= tol) {
            unique[count] = *p;
            count += 1;
            if count == 3 {
                break;
            }
        }
    }
    count
}

/// Vertex normals by averaging the unit normals of the polygons that share
/// each vertex (004 section 4.3). Vertices used by no polygon get zero.
pub fn vertex_normals(vertex_count: usize, polygons: &[(Vec<u32>, DVec3)]) -> Vec<DVec3> {
    let mut sums = vec![DVec3::ZERO; vertex_count];
    for (indices, normal) in polygons {
        for &i in indices {
            sums[i as usize] += *normal;
        }
    }
    sums.into_iter().map(|n| n.normalize_or_zero()).collect()
}

/// Whether a planar polygon is convex (no reflex vertex, within rounding).
pub fn is_convex(points: &[DVec3]) -> bool {
    let n = newell_vector(points.iter().copied());
    let scale = n.length();
    let m = points.len();
    (0..m).all(|i| {
        let (a, b, c) = (points[i], points[(i + 1) % m], points[(i + 2) % m]);
        (b - a).cross(c - b).dot(n) >= -1e-12 * scale * (b - a).length().max((c - b).length())
    })
}

/// Cuts a simple planar polygon into triangles by ear clipping, keeping its
/// orientation. Convex polygons become fans.
///
/// The remaining outline is a linked ring, walked once around and
/// resumed after each ear cut. Only reflex vertices can lie inside an
/// ear, and a vertex that stops being reflex never becomes reflex again,
/// so the ear test looks up the reflex vertices in a grid over the
/// polygon's plane: a polygon of 200,000 vertices is cut in about linear
/// time instead of the cube of its vertex count. When a whole turn finds
/// no ear (a degenerate outline), the vertex reached is cut anyway.
pub fn triangulate(points: &[DVec3]) -> Vec<[DVec3; 3]> {
    let m = points.len();
    if m < 3 {
        return Vec::new();
    }
    if is_convex(points) {
        return (1..m - 1)
            .map(|k| [points[0], points[k], points[k + 1]])
            .collect();
    }
    let n = newell_vector(points.iter().copied());
    let inside = |p: DVec3, a: DVec3, b: DVec3, c: DVec3| {
        (b - a).cross(p - a).dot(n) >= 0.0
            && (c - b).cross(p - b).dot(n) >= 0.0
            && (a - c).cross(p - c).dot(n) >= 0.0
    };
    let mut prev: Vec<usize> = (0..m).map(|i| (i + m - 1) % m).collect();
    let mut next: Vec<usize> = (0..m).map(|i| (i + 1) % m).collect();
    let mut alive = vec![true; m];
    // Reflex beyond rounding, with the tolerance of `is_convex`: nearly
    // collinear vertices (thousands of them on a finely divided circle)
    // stay out of the grid.
    let scale = n.length();
    let reflex_at = |a: DVec3, b: DVec3, c: DVec3| {
        (b - a).cross(c - b).dot(n) < -1e-12 * scale * (b - a).length().max((c - b).length())
    };
    let mut reflex: Vec<bool> = (0..m)
        .map(|i| reflex_at(points[prev[i]], points[i], points[next[i]]))
        .collect();
    let mut grid = ReflexGrid::new(points, n, &reflex);
    let mut out = Vec::with_capacity(m - 2);
    let mut remaining = m;
    let (mut ear, mut stop, mut forced) = (0, 0, false);
    while remaining > 3 {
        let (i, j, k) = (prev[ear], ear, next[ear]);
        let (a, b, c) = (points[i], points[j], points[k]);
        let is_ear = forced
            || (!reflex[j]
                && grid.none_inside(
                    a,
                    b,
                    c,
                    |v| alive[v] && reflex[v],
                    |v| ![a, b, c].contains(&points[v]) && inside(points[v], a, b, c),
                ));
        if is_ear {
            out.push([a, b, c]);
            alive[j] = false;
            next[i] = k;
            prev[k] = i;
            remaining -= 1;
            for v in [i, k] {
                if reflex[v] && !reflex_at(points[prev[v]], points[v], points[next[v]]) {
                    reflex[v] = false;
                }
            }
            // Skip a vertex before the next try, so that the cuts spread
            // around the ring instead of fanning out of one vertex (long
            // slivers whose boxes cover the whole grid).
            ear = next[k];
            stop = ear;
            forced = false;
            continue;
        }
        ear = k;
        // A whole turn without an ear: cut the next vertex anyway.
        forced = ear == stop;
    }
    let j = next[ear];
    out.push([points[ear], points[j], points[next[j]]]);
    out
}

/// The reflex vertices of a polygon bucketed in a square grid over its
/// plane (the two coordinates other than the normal's largest).
struct ReflexGrid {
    cells: Vec<Vec<u32>>,
    side: usize,
    axes: (usize, usize),
    lo: (f64, f64),
    cell: (f64, f64),
    points_2d: Vec<(f64, f64)>,
}

impl ReflexGrid {
    fn new(points: &[DVec3], normal: DVec3, reflex: &[bool]) -> ReflexGrid {
        let a = normal.abs();
        let axes = if a.z >= a.x && a.z >= a.y {
            (0, 1)
        } else if a.y >= a.x {
            (0, 2)
        } else {
            (1, 2)
        };
        let points_2d: Vec<(f64, f64)> = points
            .iter()
            .map(|p| (p.to_array()[axes.0], p.to_array()[axes.1]))
            .collect();
        let count = reflex.iter().filter(|r| **r).count();
        let side = ((count as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let (mut lo, mut hi) = (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        );
        for &(x, y) in &points_2d {
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        let size = |l: f64, h: f64| {
            let s = (h - l) / side as f64;
            if s.is_finite() && s > 0.0 { s } else { 1.0 }
        };
        let mut grid = ReflexGrid {
            cells: vec![Vec::new(); side * side],
            side,
            axes,
            lo: (
                if lo.0.is_finite() { lo.0 } else { 0.0 },
                if lo.1.is_finite() { lo.1 } else { 0.0 },
            ),
            cell: (size(lo.0, hi.0), size(lo.1, hi.1)),
            points_2d,
        };
        for (v, _) in reflex.iter().enumerate().filter(|(_, r)| **r) {
            let (x, y) = grid.points_2d[v];
            let (cx, cy) = (grid.index(x, 0), grid.index(y, 1));
            grid.cells[cy * side + cx].push(v as u32);
        }
        grid
    }

    /// The cell column (`axis` 0) or row (1) of a coordinate, clamped;
    /// NaN goes to cell 0.
    fn index(&self, v: f64, axis: usize) -> usize {
        let (lo, cell) = if axis == 0 {
            (self.lo.0, self.cell.0)
        } else {
            (self.lo.1, self.cell.1)
        };
        (((v - lo) / cell).floor().max(0.0) as usize).min(self.side - 1)
    }

    /// Whether no vertex bucketed in the cells under the triangle's box
    /// passes `hit`; vertices that fail `live` (cut, or no longer reflex)
    /// are dropped from the cells on the way.
    fn none_inside(
        &mut self,
        a: DVec3,
        b: DVec3,
        c: DVec3,
        live: impl Fn(usize) -> bool,
        hit: impl Fn(usize) -> bool,
    ) -> bool {
        let (ax, ay) = (self.axes.0, self.axes.1);
        let coords = [a, b, c].map(|p| (p.to_array()[ax], p.to_array()[ay]));
        let xs = coords.map(|p| p.0);
        let ys = coords.map(|p| p.1);
        let (x0, x1) = (
            self.index(xs.iter().copied().fold(f64::INFINITY, f64::min), 0),
            self.index(xs.iter().copied().fold(f64::NEG_INFINITY, f64::max), 0),
        );
        let (y0, y1) = (
            self.index(ys.iter().copied().fold(f64::INFINITY, f64::min), 1),
            self.index(ys.iter().copied().fold(f64::NEG_INFINITY, f64::max), 1),
        );
        if xs.iter().chain(&ys).any(|v| v.is_nan()) {
            // Unknown position: look everywhere.
            return self
                .cells
                .iter()
                .flatten()
                .all(|&v| !(live(v as usize) && hit(v as usize)));
        }
        for y in y0..=y1 {
            for x in x0..=x1 {
                if self.cells[y * self.side + x]
                    .iter()
                    .any(|&v| hit(v as usize))
                {
                    return false;
                }
            }
        }
        true
    }
}

/// The polygon itself if convex, else its triangles (as loops).
pub fn triangulate_if_needed(points: &[DVec3]) -> Vec<Vec<DVec3>> {
    if is_convex(points) {
        vec![points.to_vec()]
    } else {
        triangulate(points)
            .into_iter()
            .map(|t| t.to_vec())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_cw_from_above() -> Vec<DVec3> {
        // Seen from +z: (-1,-1) -> (-1,1) -> (1,1) -> (1,-1) is clockwise.
        vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
        ]
    }

    #[test]
    fn clockwise_from_above_faces_up() {
        let plane = outward_plane(&square_cw_from_above()).unwrap();
        assert!((plane.truncate() - DVec3::Z).length() < 1e-15);
        assert_eq!(plane.w, 0.0);
        assert!((area(&square_cw_from_above()) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn defects_are_reported() {
        let p = DVec3::ONE;
        assert_eq!(
            outward_plane(&[p, p, DVec3::ZERO]),
            Err(PolygonDefect::TooFewVertices(2))
        );
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        assert_eq!(outward_plane(&line), Err(PolygonDefect::ZeroArea));
        let mut bent = square_cw_from_above();
        bent[2].z = 0.5;
        assert!(matches!(
            outward_plane(&bent),
            Err(PolygonDefect::NonPlanar(_))
        ));
    }

    #[test]
    fn triangulation_keeps_area_and_orientation() {
        // An L shape (non-convex), clockwise from +z.
        let l: Vec<DVec3> = [
            (0.0, 0.0),
            (0.0, 2.0),
            (1.0, 2.0),
            (1.0, 1.0),
            (2.0, 1.0),
            (2.0, 0.0),
        ]
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 0.0))
        .collect();
        assert!(!is_convex(&l));
        assert!(is_convex(&square_cw_from_above()));
        let tris = triangulate(&l);
        assert_eq!(tris.len(), 4);
        let total: f64 = tris.iter().map(|t| area(t)).sum();
        assert!((total - 3.0).abs() < 1e-12);
        let n = newell_vector(l.iter().copied());
        for t in &tris {
            assert!(newell_vector(t.iter().copied()).dot(n) > 0.0);
        }
    }

    #[test]
    fn vertex_normal_is_average_of_faces() {
        let n = vertex_normals(2, &[(vec![0], DVec3::X), (vec![0, 1], DVec3::Y)]);
        let s = 0.5f64.sqrt();
        assert!((n[0] - DVec3::new(s, s, 0.0)).length() < 1e-15);
        assert_eq!(n[1], DVec3::Y);
    }
}

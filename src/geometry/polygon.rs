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

/// Area of a planar polygon given in any order.
pub fn area(points: &[DVec3]) -> f64 {
    newell_vector(points.iter().copied()).length() / 2.0
}

/// The largest distance between two of `points` (the diameter), 0 if fewer
/// than two.
pub fn diameter(points: &[DVec3]) -> f64 {
    let mut d: f64 = 0.0;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            d = d.max(a.distance(*b));
        }
    }
    d
}

/// What is wrong with a polygon, if anything.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PolygonDefect {
    /// Fewer than three distinct vertices.
    TooFewVertices(usize),
    /// All vertices on a line (zero area).
    ZeroArea,
    /// Vertices off the best-fit plane by this fraction of the diameter.
    NonPlanar(f64),
}

/// The outward plane `[A B C D]` (unit normal) of a clockwise-from-outside
/// polygon, or its defect. Consecutive duplicate vertices are ignored when
/// counting distinct vertices.
pub fn outward_plane(points: &[DVec3]) -> Result<DVec4, PolygonDefect> {
    let diam = diameter(points);
    let distinct = distinct_count(points, diam);
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

fn distinct_count(points: &[DVec3], diam: f64) -> usize {
    let tol = precision::COINCIDENT_VERTEX * diam;
    let mut unique: Vec<DVec3> = Vec::new();
    for p in points {
        if !unique.iter().any(|q| q.distance(*p) <= tol) {
            unique.push(*p);
        }
    }
    unique.len()
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
    let mut idx: Vec<usize> = (0..m).collect();
    let mut out = Vec::with_capacity(m - 2);
    let convex_at = |a: DVec3, b: DVec3, c: DVec3| (b - a).cross(c - b).dot(n) > 0.0;
    let inside = |p: DVec3, a: DVec3, b: DVec3, c: DVec3| {
        (b - a).cross(p - a).dot(n) >= 0.0
            && (c - b).cross(p - b).dot(n) >= 0.0
            && (a - c).cross(p - c).dot(n) >= 0.0
    };
    let mut guard = 0;
    while idx.len() > 3 && guard < 4 * m * m {
        guard += 1;
        let k = idx.len();
        let ear = (0..k).find(|&i| {
            let (a, b, c) = (
                points[idx[(i + k - 1) % k]],
                points[idx[i]],
                points[idx[(i + 1) % k]],
            );
            convex_at(a, b, c)
                && idx
                    .iter()
                    .all(|&j| [a, b, c].contains(&points[j]) || !inside(points[j], a, b, c))
        });
        let i = ear.unwrap_or(0);
        out.push([
            points[idx[(i + k - 1) % k]],
            points[idx[i]],
            points[idx[(i + 1) % k]],
        ]);
        idx.remove(i);
    }
    if idx.len() == 3 {
        out.push([points[idx[0]], points[idx[1]], points[idx[2]]]);
    }
    out
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

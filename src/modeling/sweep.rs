//! Sweeps (Firebaugh 001, chapter 8): lathing a profile about the z axis
//! and extruding an outline along z.
//!
//! * `lathe`: a simple polyline `(r, z)` in the x-z plane spun in `n`
//!   steps about z. An end on the axis (`r = 0`) closes the solid there;
//!   an end off the axis is capped with a flat disc. The surface between
//!   two profile points is a conical band of planar quads (triangles at
//!   the axis); vertex normals are the profile's normals (the mean of its
//!   two segments' at inner points) turned about z. A profile whose
//!   last point repeats its first, off the axis, spins into a ring.
//! * `extrude`: a simple closed outline in the x-y plane swept from
//!   `z = 0` to `z = depth`, capped at both ends; flat faces only.

use std::f64::consts::TAU;

use glam::{DVec2, DVec3};

use super::Generated;
use crate::model::Mesh;

/// Twice the signed area of a closed polygon (positive counter-clockwise).
fn twice_area(points: &[DVec2]) -> f64 {
    let m = points.len();
    (0..m)
        .map(|i| points[i].perp_dot(points[(i + 1) % m]))
        .sum()
}

fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether `p` (collinear with `a`-`b`) lies within the segment's box.
fn on_segment(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Whether segments `a`-`b` and `c`-`d` share a point.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on_segment(c, d, a))
        || (d2 == 0.0 && on_segment(c, d, b))
        || (d3 == 0.0 && on_segment(a, b, c))
        || (d4 == 0.0 && on_segment(a, b, d))
}

/// The first pair of edges of the closed polygon `points` that meet other
/// than at a shared corner (1-based edge numbers), if any. Adjacent edges
/// meet only at their corner unless they fold back onto each other.
/// Unbounded; see [`self_intersection_within`].
pub fn self_intersection(points: &[DVec2]) -> Option<(usize, usize)> {
    self_intersection_within(points, u64::MAX).unwrap_or(None)
}

/// Edge pairs compared before an outline is refused (see
/// [`crate::budget::Budgets::pair_tests`]).
pub const DEFAULT_PAIR_TESTS: u64 = 50_000_000;

/// [`self_intersection`] by a sweep in x: the edges sorted by their
/// smallest x, each compared only with the edges whose x range it meets
/// (two per x for a convex outline, so near-linear after the sort on
/// sound outlines). `Err(pairs)` when more than `max_pairs` pairs would
/// be compared (an outline whose edges overlap in x by the thousand).
pub fn self_intersection_within(
    points: &[DVec2],
    max_pairs: u64,
) -> Result<Option<(usize, usize)>, u64> {
    let m = points.len();
    let edge = |i: usize| (points[i], points[(i + 1) % m]);
    let mut order: Vec<(f64, usize)> = (0..m)
        .map(|i| {
            let (a, b) = edge(i);
            (a.x.min(b.x), i)
        })
        .collect();
    order.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    // Active edges: (largest x, index).
    let mut active: Vec<(f64, usize)> = Vec::new();
    let mut first: Option<(usize, usize)> = None;
    let mut pairs = 0u64;
    for &(x0, e) in &order {
        let (c, d) = edge(e);
        let (ylo, yhi) = (c.y.min(d.y), c.y.max(d.y));
        let mut k = 0;
        while k < active.len() {
            let (x1, o) = active[k];
            if x1 < x0 {
                active.swap_remove(k);
                continue;
            }
            k += 1;
            pairs += 1;
            if pairs > max_pairs {
                return Err(pairs);
            }
            let (i, j) = (o.min(e), o.max(e));
            if first.is_some_and(|f| f <= (i + 1, j + 1)) {
                continue;
            }
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            let adjacent = j == i + 1 || (i == 0 && j == m - 1);
            let meet = if adjacent {
                // They share one corner; they overlap when the other end of
                // one lies on the other, collinear.
                let (shared, p, q) = if j == i + 1 { (b, a, d) } else { (a, b, c) };
                orient(p, shared, q) == 0.0 && (p - shared).dot(q - shared) > 0.0
            } else {
                let (olo, ohi) = (a.y.min(b.y), a.y.max(b.y));
                olo <= yhi && ylo <= ohi && segments_meet(a, b, c, d)
            };
            if meet {
                first = Some((i + 1, j + 1));
            }
        }
        active.push((c.x.max(d.x), e));
    }
    Ok(first)
}

/// [`self_intersection_within`] of the `what` under `max_pairs` (`None`:
/// a pre-pass under the default budget, passed when it runs out), its
/// budget error as a message naming the flag.
fn checked(
    points: &[DVec2],
    max_pairs: Option<u64>,
    what: &str,
) -> Result<Option<(usize, usize)>, String> {
    let Some(max_pairs) = max_pairs else {
        // A pre-pass: the crossings it can find within the default budget.
        return Ok(self_intersection_within(points, DEFAULT_PAIR_TESTS).unwrap_or(None));
    };
    self_intersection_within(points, max_pairs).map_err(|pairs| {
        crate::budget::Budgets::exceeded(
            &format!("checking that the {what} is simple ({pairs} edge pairs and more)"),
            max_pairs,
            "--max-pair-tests",
        )
    })
}

/// `extrude DEPTH x1 y1 ... xk yk`: the outline checked (a last point
/// equal to the first dropped; at least 3 distinct points, non-zero area,
/// simple) and made counter-clockwise.
pub fn extrude_outline(points: Vec<DVec2>) -> Result<Vec<DVec2>, String> {
    extrude_outline_within(points, Some(DEFAULT_PAIR_TESTS))
}

/// [`extrude_outline`] comparing at most `max_pairs` edge pairs (`None`:
/// a pre-pass, which passes an outline past the default budget).
pub fn extrude_outline_within(
    mut points: Vec<DVec2>,
    max_pairs: Option<u64>,
) -> Result<Vec<DVec2>, String> {
    points.dedup();
    if points.len() > 1 && points.first() == points.last() {
        points.pop();
    }
    if points.len() < 3 {
        return Err(format!(
            "an extrude outline needs at least 3 distinct points, found {}",
            points.len()
        ));
    }
    let scale = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.length()))
        .max(f64::MIN_POSITIVE);
    let (a, b) = (points[0], points[1]);
    let collinear = points
        .iter()
        .all(|&p| orient(a, b, p).abs() <= 1e-12 * scale * scale);
    if collinear {
        return Err("the extrude outline has zero area (its points are collinear)".into());
    }
    let crossing = checked(&points, max_pairs, "extrude outline")?;
    if let Some((i, j)) = crossing {
        return Err(format!(
            "the extrude outline intersects itself: edges {i} and {j} cross (an outline must be simple)"
        ));
    }
    let area = twice_area(&points);
    if area.abs() <= 1e-12 * scale * scale {
        return Err("the extrude outline has zero area".into());
    }
    if area < 0.0 {
        points.reverse();
    }
    Ok(points)
}

/// Polygons of an extrusion of `k` points: `k` walls and two caps.
pub fn extrude_face_count(k: usize) -> Option<usize> {
    k.checked_add(2)
}

/// Extrudes a checked, counter-clockwise outline (see
/// [`extrude_outline`]) from `z = 0` to `z = depth > 0`.
pub fn extrude(outline: &[DVec2], depth: f64) -> Generated {
    let k = outline.len() as u32;
    let vertices: Vec<DVec3> = outline
        .iter()
        .map(|p| p.extend(0.0))
        .chain(outline.iter().map(|p| p.extend(depth)))
        .collect();
    let mut polygons: Vec<Vec<u32>> = (0..k)
        .map(|i| {
            let j = (i + 1) % k;
            vec![i, k + i, k + j, j]
        })
        .collect();
    // Bottom seen from below: counter-clockwise from above; top reversed.
    polygons.push((0..k).collect());
    polygons.push((0..k).rev().map(|i| k + i).collect());
    Generated {
        mesh: Mesh::new(vertices, polygons),
        normals: None,
        open: false,
    }
}

/// A checked lathe profile: points `(r, z)` ordered so that the closed
/// outline (profile, then the axis) is counter-clockwise in the `r`-`z`
/// plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    points: Vec<DVec2>,
    /// A closed loop off the axis (first point = last): a ring, no caps.
    ring: bool,
}

impl Profile {
    /// Checks `points` (`x` = r, `y` = z): at least two distinct points,
    /// `r >= 0`, `r = 0` only at the ends, the outline closed through the
    /// axis simple and of non-zero area.
    pub fn new(points: Vec<DVec2>) -> Result<Profile, String> {
        Profile::new_within(points, Some(DEFAULT_PAIR_TESTS))
    }

    /// [`Profile::new`] comparing at most `max_pairs` edge pairs (`None`:
    /// a pre-pass, which passes a profile past the default budget).
    pub fn new_within(mut points: Vec<DVec2>, max_pairs: Option<u64>) -> Result<Profile, String> {
        points.dedup();
        if points.len() < 2 {
            return Err("a lathe profile needs at least 2 distinct points".into());
        }
        if points.len() >= 4 && points.first() == points.last() {
            return Profile::ring(points, max_pairs);
        }
        if let Some(i) = points.iter().position(|p| p.x < 0.0) {
            return Err(format!(
                "lathe profile point {}: r = {} is negative",
                i + 1,
                points[i].x
            ));
        }
        let last = points.len() - 1;
        if let Some(i) = (1..last).find(|&i| points[i].x == 0.0) {
            return Err(format!(
                "lathe profile point {}: r = 0 is allowed only at the ends",
                i + 1
            ));
        }
        let closed = closed_outline(&points);
        let scale = closed
            .iter()
            .fold(0.0f64, |m, p| m.max(p.length()))
            .max(f64::MIN_POSITIVE);
        let area = twice_area(&closed);
        if area.abs() <= 1e-12 * scale * scale {
            return Err("the lathe profile encloses no area with the axis".into());
        }
        let crossing = checked(&closed, max_pairs, "lathe profile")?;
        if let Some((i, j)) = crossing {
            return Err(format!(
                "the lathe profile, closed along the axis, intersects itself (its edges {i} and {j} cross)"
            ));
        }
        if area < 0.0 {
            points.reverse();
        }
        Ok(Profile {
            points,
            ring: false,
        })
    }

    /// A closed profile (its last point repeating the first) off the axis:
    /// spun, it makes a ring with no caps.
    fn ring(mut points: Vec<DVec2>, max_pairs: Option<u64>) -> Result<Profile, String> {
        points.pop();
        if let Some(i) = points.iter().position(|p| p.x <= 0.0) {
            return Err(format!(
                "lathe profile point {}: a closed profile must stay off the axis (r > 0)",
                i + 1
            ));
        }
        let scale = points.iter().fold(0.0f64, |m, p| m.max(p.length()));
        let crossing = checked(&points, max_pairs, "closed lathe profile")?;
        if let Some((i, j)) = crossing {
            return Err(format!(
                "the closed lathe profile intersects itself (its edges {i} and {j} cross)"
            ));
        }
        let area = twice_area(&points);
        if area.abs() <= 1e-12 * scale * scale {
            return Err("the closed lathe profile encloses no area".into());
        }
        if area < 0.0 {
            points.reverse();
        }
        Ok(Profile { points, ring: true })
    }

    /// The points, counter-clockwise with the axis.
    pub fn points(&self) -> &[DVec2] {
        &self.points
    }

    /// The cap discs' count: ends off the axis.
    fn caps(&self) -> usize {
        if self.ring {
            return 0;
        }
        [self.points[0], self.points[self.points.len() - 1]]
            .iter()
            .filter(|p| p.x > 0.0)
            .count()
    }

    /// Segments of the profile (a ring's closing one included).
    fn segments(&self) -> usize {
        self.points.len() - usize::from(!self.ring)
    }

    /// Polygons of a lathe of `n` steps: `n` per segment and one per cap.
    pub fn face_count(&self, n: usize) -> Option<usize> {
        n.checked_mul(self.segments())?.checked_add(self.caps())
    }
}

/// The profile closed through the axis: the profile, then its ends'
/// projections on the axis where they are off it.
fn closed_outline(points: &[DVec2]) -> Vec<DVec2> {
    let mut closed = points.to_vec();
    let (first, last) = (points[0], points[points.len() - 1]);
    if last.x > 0.0 {
        closed.push(DVec2::new(0.0, last.y));
    }
    if first.x > 0.0 {
        closed.push(DVec2::new(0.0, first.y));
    }
    closed.dedup();
    if closed.len() > 1 && closed.first() == closed.last() {
        closed.pop();
    }
    closed
}

/// `lathe N r1 z1 ... rk zk`: the profile spun in `n >= 3` steps.
pub fn lathe(profile: &Profile, n: usize) -> Generated {
    let p = profile.points();
    let k = p.len();
    // Counter-clockwise in (r, z): the outward normal of a segment with
    // direction d is (d.y, -d.x).
    let ring = profile.ring;
    let seg_normal = |i: usize| {
        let d = p[(i + 1) % k] - p[i];
        DVec2::new(d.y, -d.x).normalize()
    };
    let profile_normal = |i: usize| -> DVec2 {
        if p[i].x == 0.0 {
            // On the axis: along it.
            return if i == 0 {
                seg_normal(0)
            } else {
                seg_normal(k - 2)
            }
            .y
            .signum()
                * DVec2::Y;
        }
        let mut sum = DVec2::ZERO;
        if i > 0 || ring {
            sum += seg_normal((i + k - 1) % k);
        }
        if i + 1 < k || ring {
            sum += seg_normal(i);
        }
        sum.normalize_or(DVec2::X)
    };
    let angle = |j: usize| TAU * j as f64 / n as f64;
    let mut vertices = Vec::new();
    let mut normals = Vec::new();
    // Index of profile point i at step j.
    let mut ring_start = Vec::with_capacity(k);
    for (i, q) in p.iter().enumerate() {
        ring_start.push(vertices.len() as u32);
        let nrm = profile_normal(i);
        let steps = if q.x == 0.0 { 1 } else { n };
        for j in 0..steps {
            let (c, s) = (angle(j).cos(), angle(j).sin());
            vertices.push(DVec3::new(q.x * c, q.x * s, q.y));
            normals.push(DVec3::new(nrm.x * c, nrm.x * s, nrm.y));
        }
    }
    let at = |i: usize, j: usize| -> u32 {
        if p[i].x == 0.0 {
            ring_start[i]
        } else {
            ring_start[i] + (j % n) as u32
        }
    };
    let mut polygons = Vec::new();
    for i in 0..profile.segments() {
        let i1 = (i + 1) % k;
        for j in 0..n {
            let cell = [at(i, j), at(i1, j), at(i1, j + 1), at(i, j + 1)];
            let mut poly: Vec<u32> = cell.to_vec();
            poly.dedup();
            if poly.first() == poly.last() {
                poly.pop();
            }
            polygons.push(poly);
        }
    }
    // The outline runs counter-clockwise, so the disc at the first point
    // faces -z and the one at the last point +z.
    for (i, up) in [(0, -1.0), (k - 1, 1.0)] {
        if p[i].x > 0.0 && !ring {
            let base = vertices.len() as u32;
            for j in 0..n {
                vertices.push(DVec3::new(
                    p[i].x * angle(j).cos(),
                    p[i].x * angle(j).sin(),
                    p[i].y,
                ));
                normals.push(DVec3::Z * up);
            }
            // Counter-clockwise from above is clockwise from below.
            let ring = (0..n as u32).map(|j| base + j);
            polygons.push(if up < 0.0 {
                ring.collect()
            } else {
                ring.rev().collect()
            });
        }
    }
    Generated {
        mesh: Mesh::new(vertices, polygons),
        normals: Some(normals),
        open: false,
    }
}

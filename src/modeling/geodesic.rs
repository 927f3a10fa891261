//! Geodesic icosahedra (C. M. Brown, *Fast Display of Well-Tesselated
//! Surfaces*, 1978, 003 section 4) and the checks of his appendix section
//! 2: the Angle Condition and the Edge Condition.
//!
//! Each of the 20 faces of an icosahedron inscribed in the unit sphere is
//! divided with `n` divisions per edge into `n^2` triangles whose vertices
//! are projected onto the sphere, by one of two methods:
//!
//! * [`Division::Equal`]: the edges are divided into `n` equal lengths and
//!   the division points joined by lines parallel to the face's edges;
//! * [`Division::EqualAngle`]: the division points subtend equal angles at
//!   the centre; the lines parallel to the edges then meet in small
//!   triangles, whose centroids become the vertices.
//!
//! Both give `10 n^2 + 2` vertices and `20 n^2` faces. A [`Radial`]
//! function then moves every vertex along its direction (its "vertex
//! direction"): the priority order of Brown's algorithms depends on those
//! directions only. Faces are listed clockwise seen from outside, as in a
//! `.det` file.
//!
//! Brown's approximate rotation (003 section 2): the painted surface is a
//! "rubber" approximation of an object that turns *inside* it while the
//! vertex directions stay fixed. [`TurnedRadial`] is a radial function
//! turned by a rotation `R`, `r'(d) = r(R^-1 d)`, and [`reshape`] moves
//! the vertices of an existing surface along their fixed directions to it:
//! linear time, and the priority order stays valid (003 section 3).

use std::collections::HashMap;

use glam::{DMat3, DVec3};

use crate::model::Mesh;

/// How the icosahedral edges are divided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Division {
    /// Equal lengths (Brown's first method).
    Equal,
    /// Equal angles, vertices at the centroids of the small triangles
    /// (Brown's second method).
    EqualAngle,
}

/// A radial spherical function `r(direction) > 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Radial {
    /// `r = 1`.
    Sphere,
    /// The ellipsoid with semi-axes `a`, `b`, `c`.
    Ellipsoid(f64, f64, f64),
    /// `r = 1 + amplitude cos(f lon) sin(f colat)`.
    Bumps(f64, f64),
    /// `r = 1 + amplitude cos(k lon) sin(colat)`.
    Lobes(f64, f64),
}

impl Radial {
    /// The radius in unit direction `d`.
    pub fn radius(&self, d: DVec3) -> f64 {
        let lon = || d.y.atan2(d.x);
        let colat = || d.z.clamp(-1.0, 1.0).acos();
        match *self {
            Radial::Sphere => 1.0,
            Radial::Ellipsoid(a, b, c) => {
                1.0 / ((d.x / a).powi(2) + (d.y / b).powi(2) + (d.z / c).powi(2)).sqrt()
            }
            Radial::Bumps(amp, f) => 1.0 + amp * (f * lon()).cos() * (f * colat()).sin(),
            Radial::Lobes(amp, k) => 1.0 + amp * (k * lon()).cos() * colat().sin(),
        }
    }
}

/// A radial function turned inside the fixed vertex directions (Brown's
/// approximate rotation, 003 section 2): `r'(d) = r(R^-1 d)`, so what the
/// function had in direction `u` it now has in direction `R u`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnedRadial {
    /// The function before turning.
    pub radial: Radial,
    /// The rotation `R` (orthonormal).
    pub rotation: DMat3,
}

impl TurnedRadial {
    /// `radial`, not turned.
    pub fn new(radial: Radial) -> TurnedRadial {
        TurnedRadial {
            radial,
            rotation: DMat3::IDENTITY,
        }
    }

    /// This function turned further by `angle` degrees about the
    /// coordinate axis `axis` (0, 1, 2 for x, y, z), the sense of IRIS GL's
    /// `rotate`: about z, x turns towards y.
    pub fn turned(self, angle: f64, axis: usize) -> TurnedRadial {
        let a = angle.to_radians();
        let r = match axis {
            0 => DMat3::from_rotation_x(a),
            1 => DMat3::from_rotation_y(a),
            _ => DMat3::from_rotation_z(a),
        };
        TurnedRadial {
            radial: self.radial,
            rotation: r * self.rotation,
        }
    }

    /// The radius in unit direction `d`.
    pub fn radius(&self, d: DVec3) -> f64 {
        self.radial.radius(self.rotation.transpose() * d)
    }
}

/// The points `d r(d)` for unit directions `dirs`; fails if the function
/// is not positive and finite in one of them.
fn place(dirs: &[DVec3], f: &TurnedRadial) -> Result<Vec<DVec3>, String> {
    dirs.iter()
        .map(|&d| {
            let r = f.radius(d);
            if r.is_finite() && r > 0.0 {
                Ok(d * r)
            } else {
                Err(format!(
                    "the radial function is {r} in direction ({:.3}, {:.3}, {:.3}); it must be positive",
                    d.x, d.y, d.z
                ))
            }
        })
        .collect()
}

/// `mesh` (a surface about the origin) with every vertex moved along its
/// own direction to the radius of `f`: the faces and the vertex directions
/// are unchanged (003 section 2), in time linear in the vertices.
pub fn reshape(mesh: &Mesh, f: &TurnedRadial) -> Result<Mesh, String> {
    let dirs: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|v| v.try_normalize().ok_or("a vertex lies at the centre"))
        .collect::<Result<_, _>>()?;
    Ok(Mesh {
        vertices: place(&dirs, f)?,
        polygons: mesh.polygons.clone(),
    })
}

/// The 12 vertices of the icosahedron on the unit sphere (003 section 4).
pub fn icosahedron_vertices() -> [DVec3; 12] {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let a = t.sqrt() / 5f64.powf(0.25);
    let b = 1.0 / (t.sqrt() * 5f64.powf(0.25));
    let mut v = [DVec3::ZERO; 12];
    let mut k = 0;
    for s1 in [1.0, -1.0] {
        for s2 in [1.0, -1.0] {
            v[k] = DVec3::new(0.0, s1 * a, s2 * b);
            v[k + 1] = DVec3::new(s1 * b, 0.0, s2 * a);
            v[k + 2] = DVec3::new(s1 * a, s2 * b, 0.0);
            k += 3;
        }
    }
    v
}

/// The 20 faces of the icosahedron, clockwise seen from outside.
pub fn icosahedron_faces() -> Vec<[usize; 3]> {
    let v = icosahedron_vertices();
    let edge = v[0].distance(v[3]).min(v[0].distance(v[1]));
    let adjacent = |i: usize, j: usize| (v[i].distance(v[j]) - edge).abs() < 1e-9;
    let mut faces = Vec::new();
    for i in 0..12 {
        for j in i + 1..12 {
            for k in j + 1..12 {
                if adjacent(i, j) && adjacent(j, k) && adjacent(i, k) {
                    // Clockwise from outside: the normal of (i, j, k) must
                    // point inward.
                    let n = (v[j] - v[i]).cross(v[k] - v[i]);
                    if n.dot(v[i]) > 0.0 {
                        faces.push([i, k, j]);
                    } else {
                        faces.push([i, j, k]);
                    }
                }
            }
        }
    }
    faces
}

/// Fraction along the chord from `A` of the point seen from the centre at
/// fraction `s` of the angle `theta` subtended by the chord.
fn chord_fraction(s: f64, theta: f64) -> f64 {
    let (a, b) = ((s * theta).sin(), ((1.0 - s) * theta).sin());
    a / (a + b)
}

/// The intersection of the coplanar lines `p + s d` and `q + t e`.
fn meet(p: DVec3, d: DVec3, q: DVec3, e: DVec3) -> DVec3 {
    let n = d.cross(e);
    let s = (q - p).cross(e).dot(n) / n.length_squared();
    p + d * s
}

/// The point of the flat face `(a, b, c)` at grid position `(p, q, r)`
/// (weights of `a`, `b`, `c`, summing to `n`), before projection.
fn grid_point(
    a: DVec3,
    b: DVec3,
    c: DVec3,
    (p, q, r): (usize, usize, usize),
    n: usize,
    division: Division,
) -> DVec3 {
    let nf = n as f64;
    match division {
        Division::Equal => (a * p as f64 + b * q as f64 + c * r as f64) / nf,
        Division::EqualAngle => {
            if p == n {
                return a;
            }
            if q == n {
                return b;
            }
            if r == n {
                return c;
            }
            let theta = a.angle_between(b);
            let f = |k: usize| chord_fraction((n - k) as f64 / nf, theta);
            // Line of constant A-weight p: through the points of AB and AC
            // at fraction f(p) from A (parallel to BC); likewise for B, C.
            let la = (a + (b - a) * f(p), c - b);
            let lb = (b + (c - b) * f(q), a - c);
            let lc = (c + (a - c) * f(r), b - a);
            let x = meet(la.0, la.1, lb.0, lb.1);
            let y = meet(lb.0, lb.1, lc.0, lc.1);
            let z = meet(lc.0, lc.1, la.0, la.1);
            (x + y + z) / 3.0
        }
    }
}

/// The number of faces of a geodesic with `n` divisions per edge,
/// `20 n^2`, computed before anything is built so that a budget can refuse
/// it (`None` if it overflows).
pub fn face_count(n: usize) -> Option<usize> {
    n.checked_mul(n)?.checked_mul(20)
}

/// A geodesic icosahedron with `n` divisions per edge, its vertices moved
/// by `radial`. Fails if the radial function is not positive and finite at
/// every vertex.
pub fn geodesic(n: usize, division: Division, radial: Radial) -> Result<Mesh, String> {
    geodesic_turned(n, division, &TurnedRadial::new(radial))
}

/// [`geodesic`] with a turned radial function.
pub fn geodesic_turned(n: usize, division: Division, f: &TurnedRadial) -> Result<Mesh, String> {
    if n == 0 {
        return Err("a geodesic needs at least 1 division per edge".into());
    }
    let Some(faces) = face_count(n) else {
        return Err(format!("a geodesic of {n} divisions per edge is too large"));
    };
    let v = icosahedron_vertices();
    // Points on the icosahedron's edges are shared by two faces (its
    // vertices by five) and found by their rounded direction; points
    // inside a face belong to it alone. Each face's grid is computed once.
    let mut shared: HashMap<[i64; 3], u32> = HashMap::new();
    let mut dirs: Vec<DVec3> = Vec::new();
    let side = n + 1;
    let mut grid: Vec<u32> = vec![u32::MAX; side * side];
    let mut polygons = Vec::with_capacity(faces);
    for [ia, ib, ic] in icosahedron_faces() {
        let (a, b, c) = (v[ia], v[ib], v[ic]);
        grid.fill(u32::MAX);
        // Grid indices: i steps from A towards B, j from A towards C.
        let mut at = |i: usize, j: usize| -> u32 {
            let slot = &mut grid[i * side + j];
            if *slot == u32::MAX {
                let d = grid_point(a, b, c, (n - i - j, i, j), n, division).normalize();
                *slot = if i == 0 || j == 0 || i + j == n {
                    let key = [
                        (d.x * 1e9).round() as i64,
                        (d.y * 1e9).round() as i64,
                        (d.z * 1e9).round() as i64,
                    ];
                    *shared.entry(key).or_insert_with(|| {
                        dirs.push(d);
                        dirs.len() as u32 - 1
                    })
                } else {
                    dirs.push(d);
                    dirs.len() as u32 - 1
                };
            }
            *slot
        };
        for i in 0..n {
            for j in 0..n - i {
                let (p0, p1, p2) = (at(i, j), at(i + 1, j), at(i, j + 1));
                polygons.push(vec![p0, p1, p2]);
                if i + j + 1 < n {
                    let p3 = at(i + 1, j + 1);
                    polygons.push(vec![p1, p3, p2]);
                }
            }
        }
    }
    let vertices = place(&dirs, f)?;
    Ok(Mesh::new(vertices, polygons))
}

/// Fans up to this degree compare every pair of their patch edges.
const SMALL_FAN: usize = 16;

/// `Err` when Ctrl-C asked the check to stop.
fn stop_requested() -> Result<(), String> {
    crate::cancel::check().map_err(|e| e.to_string())
}

/// The smallest angle between two nonadjacent `tangent`s (unit vectors
/// perpendicular to `d`, or zero, which are ignored), in `O(m log m)`
/// rather than over all `m^2` pairs: sorted by their angle about `d`, the
/// closest nonadjacent pair has at most two tangents between them on the
/// shorter arc (a third one would be nonadjacent to the first and closer,
/// as each tangent has only two adjacent ones), so each tangent is
/// compared with the next three in that order.
fn closest_nonadjacent(
    d: DVec3,
    tangent: &[DVec3],
    adjacent: impl Fn(usize, usize) -> bool,
) -> f64 {
    let (u, w) = d.any_orthonormal_pair();
    let mut order: Vec<(f64, usize)> = tangent
        .iter()
        .enumerate()
        .filter(|(_, t)| **t != DVec3::ZERO)
        .map(|(i, t)| (t.dot(w).atan2(t.dot(u)), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let k = order.len();
    let mut best = f64::INFINITY;
    for a in 0..k {
        for step in 1..=3.min(k.saturating_sub(1)) {
            let (i, j) = (order[a].1, order[(a + step) % k].1);
            if i != j && !adjacent(i, j) {
                best = best.min(tangent[i].angle_between(tangent[j]));
            }
        }
    }
    best
}

/// What [`check_tessellation`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TessellationReport {
    /// Every pvertex meets the Angle Condition.
    pub angle_condition: bool,
    /// Every patch meets the Edge Condition.
    pub edge_condition: bool,
    /// Largest angle between adjacent patch edges at a pvertex (radians;
    /// at most pi/2 under the AC).
    pub max_adjacent_angle: f64,
    /// Smallest angle between nonadjacent patch edges (at least pi/2).
    pub min_nonadjacent_angle: f64,
    /// Longest patch edge (radians; under one for the EC).
    pub max_edge: f64,
    /// Largest ratio of longest to shortest edge of a patch (under 1.27).
    pub max_edge_ratio: f64,
    /// Largest number of patches around a pvertex (4 to 8 under the AC).
    pub max_degree: usize,
}

/// Checks Brown's Angle Condition and Edge Condition (003 appendix section
/// 2) for a triangulated surface seen from `centre`: its vertex directions
/// define the patches on the sphere.
pub fn check_tessellation(mesh: &Mesh, centre: DVec3) -> Result<TessellationReport, String> {
    let dirs: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|p| {
            (*p - centre)
                .try_normalize()
                .ok_or("a vertex lies at the centre")
        })
        .collect::<Result<_, _>>()?;
    let mut max_edge: f64 = 0.0;
    let mut max_ratio: f64 = 0.0;
    // Each vertex's outgoing patch edges, in the cyclic order of its patches.
    let mut next: Vec<HashMap<u32, u32>> = vec![HashMap::new(); dirs.len()];
    for (f, poly) in mesh.polygons.iter().enumerate() {
        if f % 4096 == 0 {
            stop_requested()?;
        }
        if poly.len() != 3 {
            return Err("the surface must be triangulated".into());
        }
        let lengths: Vec<f64> = (0..3)
            .map(|k| dirs[poly[k] as usize].angle_between(dirs[poly[(k + 1) % 3] as usize]))
            .collect();
        let (lo, hi) = lengths
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| {
                (lo.min(l), hi.max(l))
            });
        max_edge = max_edge.max(hi);
        max_ratio = max_ratio.max(hi / lo);
        for k in 0..3 {
            let (v, a, b) = (poly[k], poly[(k + 1) % 3], poly[(k + 2) % 3]);
            next[v as usize].insert(a, b);
        }
    }
    let mut max_adjacent: f64 = 0.0;
    let mut min_nonadjacent = f64::INFINITY;
    let mut max_degree = 0;
    for (v, ring) in next.iter().enumerate() {
        if v % 4096 == 0 {
            stop_requested()?;
        }
        if ring.is_empty() {
            continue;
        }
        // Walk the fan around v.
        let start = *ring.keys().min().expect("not empty");
        let mut order = vec![start];
        let mut cur = start;
        while let Some(&n) = ring.get(&cur) {
            if n == start || order.len() > ring.len() {
                break;
            }
            order.push(n);
            cur = n;
        }
        let d = dirs[v];
        let tangent: Vec<DVec3> = order
            .iter()
            .map(|&u| (dirs[u as usize] - d * dirs[u as usize].dot(d)).normalize_or_zero())
            .collect();
        let m = tangent.len();
        max_degree = max_degree.max(m);
        let adjacent = |i: usize, j: usize| {
            let (i, j) = (i.min(j), i.max(j));
            j == i + 1 || (i == 0 && j == m - 1)
        };
        for i in 0..m {
            if m > 1 {
                let j = (i + 1) % m;
                if i < j || m > 2 {
                    max_adjacent = max_adjacent.max(tangent[i].angle_between(tangent[j]));
                }
            }
        }
        if m <= SMALL_FAN {
            for i in 0..m {
                for j in i + 2..m {
                    if !adjacent(i, j) {
                        min_nonadjacent = min_nonadjacent.min(tangent[i].angle_between(tangent[j]));
                    }
                }
            }
        } else {
            min_nonadjacent = min_nonadjacent.min(closest_nonadjacent(d, &tangent, adjacent));
        }
    }
    let right = std::f64::consts::FRAC_PI_2 + 1e-9;
    Ok(TessellationReport {
        angle_condition: max_adjacent <= right
            && min_nonadjacent >= std::f64::consts::FRAC_PI_2 - 1e-9,
        edge_condition: max_edge < 1.0 && max_ratio < 1.27,
        max_adjacent_angle: max_adjacent,
        min_nonadjacent_angle: min_nonadjacent,
        max_edge,
        max_edge_ratio: max_ratio,
        max_degree,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_follow_the_formulas() {
        for n in 1..=5 {
            for div in [Division::Equal, Division::EqualAngle] {
                let m = geodesic(n, div, Radial::Sphere).unwrap();
                assert_eq!(m.vertices.len(), 10 * n * n + 2, "{n} {div:?}");
                assert_eq!(m.polygons.len(), 20 * n * n);
            }
        }
    }

    #[test]
    fn faces_are_clockwise_from_outside() {
        let m = geodesic(3, Division::EqualAngle, Radial::Sphere).unwrap();
        for p in &m.polygons {
            let (a, b, c) = (
                m.vertices[p[0] as usize],
                m.vertices[p[1] as usize],
                m.vertices[p[2] as usize],
            );
            let inward = (b - a).cross(c - a);
            assert!(inward.dot(a + b + c) < 0.0);
        }
    }

    #[test]
    fn equal_angle_is_more_uniform_as_brown_reports() {
        // Brown: for 4 divisions the ratio of largest to smallest solid
        // angle is 1.517 for the first method, 1.146 for the second.
        let ratio = |div| {
            let m = geodesic(4, div, Radial::Sphere).unwrap();
            let solid: Vec<f64> = m
                .polygons
                .iter()
                .map(|p| {
                    let (a, b, c) = (
                        m.vertices[p[0] as usize],
                        m.vertices[p[1] as usize],
                        m.vertices[p[2] as usize],
                    );
                    // Van Oosterom and Strackee.
                    let num = a.dot(b.cross(c)).abs();
                    let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
                    2.0 * num.atan2(den)
                })
                .collect();
            let (lo, hi) = solid
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(l, h), &s| (l.min(s), h.max(s)));
            hi / lo
        };
        let (r1, r2) = (ratio(Division::Equal), ratio(Division::EqualAngle));
        assert!((r1 - 1.517).abs() < 0.01, "{r1}");
        assert!((r2 - 1.146).abs() < 0.01, "{r2}");
    }

    #[test]
    fn geodesics_are_well_tessellated() {
        for n in 1..=4 {
            let m = geodesic(n, Division::EqualAngle, Radial::Bumps(0.3, 3.0)).unwrap();
            let r = check_tessellation(&m, DVec3::ZERO).unwrap();
            assert!(r.angle_condition, "{n}: {r:?}");
            assert!((5..=6).contains(&r.max_degree));
        }
        // The icosahedron itself: edges of arccos(sqrt 5 / 5) radians.
        let r = check_tessellation(
            &geodesic(1, Division::Equal, Radial::Sphere).unwrap(),
            DVec3::ZERO,
        )
        .unwrap();
        assert!((r.max_edge - (5f64.sqrt() / 5.0).acos()).abs() < 1e-12);
        // Its edges (1.107 rad) are longer than the EC allows; the AC holds
        // (72 degrees between adjacent edges, 144 between the others).
        assert!(r.angle_condition && !r.edge_condition);
        assert!((r.max_adjacent_angle.to_degrees() - 72.0).abs() < 1e-9);
        // From 2 divisions on, the Edge Condition holds too.
        let r = check_tessellation(
            &geodesic(2, Division::EqualAngle, Radial::Sphere).unwrap(),
            DVec3::ZERO,
        )
        .unwrap();
        assert!(r.edge_condition, "{r:?}");
    }

    #[test]
    fn a_latitude_longitude_globe_fails_the_angle_condition() {
        // Brown's figure 3A: lines of longitude meeting at the poles.
        let (nlon, nlat) = (12, 6);
        let mut vertices = vec![DVec3::Z, -DVec3::Z];
        for i in 1..nlat {
            let colat = std::f64::consts::PI * i as f64 / nlat as f64;
            for j in 0..nlon {
                let lon = std::f64::consts::TAU * j as f64 / nlon as f64;
                vertices.push(DVec3::new(
                    colat.sin() * lon.cos(),
                    colat.sin() * lon.sin(),
                    colat.cos(),
                ));
            }
        }
        let at = |i: usize, j: usize| (2 + (i - 1) * nlon + j % nlon) as u32;
        let mut polygons = Vec::new();
        for j in 0..nlon {
            polygons.push(vec![0, at(1, j + 1), at(1, j)]);
            polygons.push(vec![1, at(nlat - 1, j), at(nlat - 1, j + 1)]);
            for i in 1..nlat - 1 {
                polygons.push(vec![at(i, j), at(i, j + 1), at(i + 1, j)]);
                polygons.push(vec![at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
            }
        }
        let r = check_tessellation(&Mesh::new(vertices, polygons), DVec3::ZERO).unwrap();
        assert!(!r.angle_condition, "{r:?}");
        assert_eq!(r.max_degree, 12);
    }

    #[test]
    fn turning_moves_vertices_along_fixed_directions() {
        // Lobes along x; turned 90 degrees about z they lie along y.
        let f = TurnedRadial::new(Radial::Lobes(0.4, 2.0));
        let g = f.turned(90.0, 2);
        assert!((f.radius(DVec3::X) - 1.4).abs() < 1e-12);
        assert!((g.radius(DVec3::Y) - 1.4).abs() < 1e-12);
        assert!((g.radius(DVec3::X) - 0.6).abs() < 1e-12);
        // Four quarter turns are the identity.
        let h = (0..4).fold(f, |h, _| h.turned(90.0, 0));
        assert!(h.rotation.abs_diff_eq(DMat3::IDENTITY, 1e-12));
        let m = geodesic(3, Division::EqualAngle, Radial::Lobes(0.4, 2.0)).unwrap();
        let turned = reshape(&m, &g).unwrap();
        assert_eq!(turned.polygons, m.polygons);
        for (a, b) in m.vertices.iter().zip(&turned.vertices) {
            assert!(a.normalize().distance(b.normalize()) < 1e-12);
            assert!((b.length() - g.radius(a.normalize())).abs() < 1e-12);
        }
        // Made turned directly, the same surface.
        let direct = geodesic_turned(3, Division::EqualAngle, &g).unwrap();
        for (a, b) in direct.vertices.iter().zip(&turned.vertices) {
            assert!(a.distance(*b) < 1e-12);
        }
    }

    #[test]
    fn radial_function_must_stay_positive() {
        assert!(geodesic(2, Division::Equal, Radial::Bumps(1.5, 2.0)).is_err());
        let m = geodesic(2, Division::Equal, Radial::Ellipsoid(2.0, 1.0, 0.5)).unwrap();
        for v in &m.vertices {
            let e = (v.x / 2.0).powi(2) + v.y.powi(2) + (v.z / 0.5).powi(2);
            assert!((e - 1.0).abs() < 1e-12);
        }
    }
}

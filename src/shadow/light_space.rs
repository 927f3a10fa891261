//! The casters as a Point light sees them: in the coordinates of the six
//! faces of a cube around the light, after the light buffer of Haines and
//! Greenberg (1986), but exact: it only chooses which casters a shadow
//! volume may meet, and the volume's planes still decide.
//!
//! Face `f` sees the directions `d` from the light whose main axis is
//! `f / 2`, on the side `f % 2` gives. A point there has the coordinates
//! `u = d[b] / w`, `v = d[c] / w` (both within -1..1) and `w = d[a] * side`,
//! its distance along the axis. A shadow volume is the pyramid from the
//! light through its target, so on a face it lies over the target's
//! `(u, v)` box, inside the target's sides (lines there), and no farther
//! in `w` than where that box passes behind the target's plane: a thin
//! volume, which in world coordinates meets the boxes of hundreds of
//! casters along its length, is a small box here. Casters' boxes are
//! widened by the clipper's tolerance, so a caster it would keep a sliver
//! of is always found.

use glam::{DVec3, DVec4};

use crate::geometry::plane_clip::{self, ClipScratch, Clipped};

/// The six faces of the cube around a light.
pub const FACES: usize = 6;

/// How close to the light's plane of a face (in `w`, in tolerances) a
/// point may come before its polygon is taken to cover the whole face:
/// nearer, a tolerance is no longer small against `w`.
const NEAR: f64 = 16.0;

/// A box in a face's coordinates `(u, v, w)`.
pub type FaceBox = (DVec3, DVec3);

/// The main axis, the two others, and the side of face `f`.
fn axes(f: usize) -> (usize, usize, usize, f64) {
    let a = f / 2;
    let side = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
    (a, (a + 1) % 3, (a + 2) % 3, side)
}

/// The box on face `f` of the polygon `points` (world coordinates) seen
/// from `light`, holding every point within `tol` of the polygon that the
/// face sees; `None` when no such point is on the face. A polygon
/// reaching within [`NEAR`] tolerances of the face's plane through the
/// light covers the whole face.
pub fn face_box(
    points: impl Iterator<Item = DVec3>,
    light: DVec3,
    f: usize,
    tol: f64,
) -> Option<FaceBox> {
    let (a, b, c, side) = axes(f);
    let near = NEAR * tol;
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let mut close = false;
    for p in points {
        let d = (p - light).to_array();
        let w = d[a] * side;
        lo.z = lo.z.min(w);
        hi.z = hi.z.max(w);
        if w <= near {
            close = true;
            continue;
        }
        let uv = DVec3::new(d[b] / w, d[c] / w, 0.0);
        (lo.x, lo.y) = (lo.x.min(uv.x), lo.y.min(uv.y));
        (hi.x, hi.y) = (hi.x.max(uv.x), hi.y.max(uv.y));
    }
    if hi.z <= -near {
        return None;
    }
    if close {
        lo.z = lo.z.min(0.0);
        return Some((
            DVec3::new(-1.0, -1.0, lo.z - tol),
            DVec3::new(1.0, 1.0, hi.z + tol),
        ));
    }
    // A point within `tol` of one at distance `w` has its (u, v) within
    // about tol / w * sqrt(2) of that point's, on the face: widened by
    // twice that at the nearest point.
    let m = 2.0 * tol / lo.z;
    let (lo, hi) = (lo - DVec3::new(m, m, tol), hi + DVec3::new(m, m, tol));
    if lo.x > 1.0 || lo.y > 1.0 || hi.x < -1.0 || hi.y < -1.0 {
        return None;
    }
    let clamp = |x: f64| x.clamp(-1.0, 1.0);
    Some((
        DVec3::new(clamp(lo.x), clamp(lo.y), lo.z),
        DVec3::new(clamp(hi.x), clamp(hi.y), hi.z),
    ))
}

/// Buffers for [`caster_boxes`].
#[derive(Default)]
pub struct FaceClip {
    planes: Vec<DVec4>,
    scratch: ClipScratch,
    pieces: Vec<Vec<DVec3>>,
}

/// The faces that see polygon `points` (world coordinates) from `light`,
/// each given to `add` with the box of its part within `tol` of the face's
/// pyramid ([`face_box`]). A polygon well inside one face's pyramid (every
/// point farther than `tol` from its sides) is only in that face;
/// others are clipped to each face's pyramid widened by `tol`, so that a
/// wall passing beside the light has on each face the box of the part
/// that face sees.
pub fn caster_boxes(
    points: &[DVec3],
    light: DVec3,
    tol: f64,
    clip: &mut FaceClip,
    mut add: impl FnMut(usize, FaceBox),
) {
    if let Some(f) = only_face(points, light, tol)
        && let Some(b) = face_box(points.iter().copied(), light, f, tol)
    {
        add(f, b);
        return;
    }
    face_parts(points, light, tol, clip, |f, part| {
        let b = match part {
            Part::One(piece) => face_box(piece.iter().copied(), light, f, tol),
            Part::Many(pieces) => face_box(pieces.iter().flatten().copied(), light, f, tol),
            Part::Unclipped => face_box(points.iter().copied(), light, f, tol),
        };
        if let Some(b) = b {
            add(f, b);
        }
    });
}

/// The parts of the convex polygon `points` (world coordinates) that the
/// faces of the cube around `light` see, each given to `add` with its
/// face: the polygon clipped to the face's pyramid.
pub fn target_parts(
    points: &[DVec3],
    light: DVec3,
    clip: &mut FaceClip,
    mut add: impl FnMut(usize, &[DVec3]),
) {
    if let Some(f) = only_face(points, light, 0.0) {
        add(f, points);
        return;
    }
    face_parts(points, light, 0.0, clip, |f, part| match part {
        Part::One(piece) => add(f, piece),
        // Not convex after all: the whole polygon, which holds its parts.
        Part::Many(_) | Part::Unclipped => add(f, points),
    });
}

/// What is left of a polygon in a face's pyramid, when something is.
enum Part<'a> {
    One(&'a [DVec3]),
    /// Several pieces: the polygon was not convex.
    Many(&'a [Vec<DVec3>]),
    /// The clipper could not clip it.
    Unclipped,
}

/// The part of polygon `points` (world coordinates) in each face's
/// pyramid from `light` widened by `tol`, given to `add` with its face.
fn face_parts(
    points: &[DVec3],
    light: DVec3,
    tol: f64,
    clip: &mut FaceClip,
    mut add: impl FnMut(usize, Part<'_>),
) {
    for f in 0..FACES {
        pyramid(light, f, tol, &mut clip.planes);
        let part = match plane_clip::clip_to_planes(
            points,
            &clip.planes,
            0.0,
            &mut clip.scratch,
            &mut clip.pieces,
        ) {
            Ok(Clipped::Empty) => continue,
            Ok(Clipped::One) => Part::One(clip.scratch.piece()),
            Ok(Clipped::Many) => Part::Many(&clip.pieces),
            Err(_) => Part::Unclipped,
        };
        add(f, part);
    }
}

/// The face whose pyramid holds every point of `points` farther than
/// `tol` from its sides and [`NEAR`] tolerances from the light's plane,
/// if there is one.
fn only_face(points: &[DVec3], light: DVec3, tol: f64) -> Option<usize> {
    let d = points.first()? - light;
    let a = (0..3).max_by(|&i, &j| d[i].abs().total_cmp(&d[j].abs()))?;
    let f = 2 * a + usize::from(d[a] < 0.0);
    let (a, b, c, side) = axes(f);
    let inside = |p: &DVec3| {
        let d = (*p - light).to_array();
        let w = d[a] * side;
        w > NEAR * tol && w - d[b].abs() > 2.0 * tol && w - d[c].abs() > 2.0 * tol
    };
    points.iter().all(inside).then_some(f)
}

/// The four sides of face `f`'s pyramid from `light`, each moved out by
/// `tol`, facing inwards, into `out`.
fn pyramid(light: DVec3, f: usize, tol: f64, out: &mut Vec<DVec4>) {
    out.clear();
    let (a, b, c, side) = axes(f);
    for (k, sign) in [(b, 1.0), (b, -1.0), (c, 1.0), (c, -1.0)] {
        // w - sign d[k] >= 0, normalized.
        let mut n = DVec3::ZERO;
        n[a] = side;
        n[k] = -sign;
        let n = n / std::f64::consts::SQRT_2;
        out.push(n.extend(-n.dot(light) + tol));
    }
}

/// The sides of the convex polygon `points` (world coordinates) seen from
/// `light` on face `f`, as planes in the face's coordinates (`w` free)
/// facing inwards, into `out`; nothing when a point of it is not in front
/// of the light's plane of the face (its picture there is unbounded).
pub fn face_sides(points: &[DVec3], light: DVec3, f: usize, out: &mut Vec<DVec4>) {
    out.clear();
    let (a, b, c, side) = axes(f);
    let uv = |p: DVec3| {
        let d = (p - light).to_array();
        let w = d[a] * side;
        (w > 0.0).then(|| [d[b] / w, d[c] / w])
    };
    let n = points.len();
    let (mut twice_area, mut longest) = (0.0, 0.0f64);
    for i in 0..n {
        let (Some(p), Some(q)) = (uv(points[i]), uv(points[(i + 1) % n])) else {
            out.clear();
            return;
        };
        twice_area += p[0] * q[1] - p[1] * q[0];
        // Left of p -> q: (q - p) x (x - p) >= 0.
        let (du, dv) = (q[0] - p[0], q[1] - p[1]);
        longest = longest.max(du.abs()).max(dv.abs());
        out.push(DVec4::new(-dv, du, 0.0, dv * p[0] - du * p[1]));
    }
    // Seen nearly edge on, its turn is lost in rounding: no sides.
    if twice_area.abs() <= 1e-9 * longest * longest {
        out.clear();
    } else if twice_area < 0.0 {
        for pl in out.iter_mut() {
            *pl = -*pl;
        }
    }
}

/// How far (in `w`) a point over the box `lo..hi` of face `f`'s `(u, v)`
/// may lie before it is farther than `beyond` behind the world `plane`
/// (unit normal, facing `light`): a point `(u, v, w)` has the plane's value
/// `w (n . d(u, v)) + (its value at the light)`, with `d = (1, u, v)` along
/// the face's axes, at most `w g + (value at the light)` where `g` is the
/// largest `n . d` over the box. Unbounded when `g` is not negative.
pub fn farthest(plane: DVec4, light: DVec3, f: usize, lo: DVec3, hi: DVec3, beyond: f64) -> f64 {
    let (a, b, c, side) = axes(f);
    let n = plane.truncate().to_array();
    let most = |k: f64, l: f64, h: f64| (k * l).max(k * h);
    let g = n[a] * side + most(n[b], lo.x, hi.x) + most(n[c], lo.y, hi.y);
    let at_light = plane.truncate().dot(light) + plane.w;
    if g < 0.0 {
        (at_light + beyond) / -g
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A direction's face coordinates, worked by hand: (1, 2, 4) from the
    /// origin is on face +z (4), u = 1/4, v = 2/4.
    #[test]
    fn a_point_has_the_coordinates_of_its_face() {
        let p = [DVec3::new(1.0, 2.0, 4.0)];
        let (lo, hi) = face_box(p.into_iter(), DVec3::ZERO, 4, 0.0).unwrap();
        assert_eq!(
            (lo, hi),
            (DVec3::new(0.25, 0.5, 4.0), DVec3::new(0.25, 0.5, 4.0))
        );
        // On face -x it is the other side's point: none.
        for f in [0, 1, 2, 3, 5] {
            let seen = face_box(p.into_iter(), DVec3::ZERO, f, 0.0);
            assert!(seen.is_none(), "face {f}: {seen:?}");
        }
    }

    /// A small random generator, the same numbers every run.
    fn numbers(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// The face a direction is on, and its coordinates there.
    fn on_face(d: DVec3) -> (usize, DVec3) {
        let a = (0..3)
            .max_by(|&i, &j| d[i].abs().total_cmp(&d[j].abs()))
            .unwrap();
        let f = 2 * a + usize::from(d[a] < 0.0);
        let (axis, b, c, side) = axes(f);
        let w = d[axis] * side;
        (f, DVec3::new(d[b] / w, d[c] / w, w))
    }

    /// A square seen from the light has four sides facing inwards, either
    /// way round; seen edge on, none.
    #[test]
    fn a_target_has_its_sides_facing_inwards_unless_edge_on() {
        let square = [
            DVec3::new(-1.0, -1.0, 4.0),
            DVec3::new(1.0, -1.0, 4.0),
            DVec3::new(1.0, 1.0, 4.0),
            DVec3::new(-1.0, 1.0, 4.0),
        ];
        let mut sides = Vec::new();
        for ring in [square.to_vec(), square.iter().rev().copied().collect()] {
            face_sides(&ring, DVec3::ZERO, 4, &mut sides);
            assert_eq!(sides.len(), 4);
            let inside = |u: f64, v: f64| {
                sides
                    .iter()
                    .all(|s| s.dot(DVec4::new(u, v, 0.0, 1.0)) >= 0.0)
            };
            assert!(inside(0.0, 0.0) && inside(0.24, -0.24));
            assert!(!inside(0.26, 0.0) && !inside(0.0, -0.3));
        }
        let edge_on = [
            DVec3::new(-1.0, 0.0, 4.0),
            DVec3::new(1.0, 0.0, 4.0),
            DVec3::new(1.0, 0.0, 6.0),
        ];
        face_sides(&edge_on, DVec3::ZERO, 4, &mut sides);
        assert!(sides.is_empty(), "{sides:?}");
    }

    /// Asserts that point `q` lies in the box that its face (seen from
    /// `light`) has among `boxes` for polygon `tri`.
    fn assert_in_its_box(q: DVec3, light: DVec3, boxes: &[(usize, FaceBox)], tri: &[DVec3]) {
        let (f, x) = on_face(q - light);
        let inside = boxes
            .iter()
            .any(|&(g, (lo, hi))| g == f && lo.cmple(x).all() && x.cmple(hi).all());
        assert!(inside, "{q} {x} on face {f} outside {boxes:?} of {tri:?}");
    }

    /// Every point within the tolerance of a polygon lies in the box its
    /// face has for the polygon: random triangles of all sizes, from
    /// small ones inside one face to large ones passing beside the light
    /// over several faces, and random points near them.
    #[test]
    fn every_nearby_point_is_in_the_box_of_its_face() {
        let mut next = numbers(0x9e37_79b9_7f4a_7c15);
        let light = DVec3::new(0.1, -0.2, 0.3);
        let tol = 1e-3;
        let mut clip = FaceClip::default();
        for k in 0..4000 {
            let size = [0.05, 0.5, 3.0, 20.0][k % 4];
            let centre = DVec3::new(next(), next(), next()) * 3.0;
            let tri: Vec<DVec3> = (0..3)
                .map(|_| centre + DVec3::new(next(), next(), next()) * size)
                .collect();
            let mut boxes = Vec::new();
            caster_boxes(&tri, light, tol, &mut clip, |f, b| boxes.push((f, b)));
            for _ in 0..8 {
                let (s, t) = (next().abs(), next().abs());
                let (s, t) = if s + t > 1.0 {
                    (1.0 - s, 1.0 - t)
                } else {
                    (s, t)
                };
                let on = tri[0] + (tri[1] - tri[0]) * s + (tri[2] - tri[0]) * t;
                let q = on + DVec3::new(next(), next(), next()).normalize() * tol * 0.99;
                if q.distance(light) < 1e3 * tol {
                    continue;
                }
                assert_in_its_box(q, light, &boxes, &tri);
            }
        }
    }

    /// A point on the edge between two faces, within the tolerance of a
    /// polygon that lies just over the edge, on the other face: the
    /// point's face still has a box for the polygon, holding the point.
    #[test]
    fn a_polygon_just_over_the_edge_of_a_face_is_on_it() {
        let mut next = numbers(0x5851_f42d_4c95_7f2d);
        let light = DVec3::new(-0.4, 0.2, 0.1);
        let tol = 1e-3;
        let mut clip = FaceClip::default();
        for _ in 0..4000 {
            // On the edge between the faces of two axes: |d[a]| = |d[b]|.
            let mut d = DVec3::new(next(), next(), next());
            let a = (next().abs() * 3.0) as usize % 3;
            let b = (a + 1 + usize::from(next() > 0.0)) % 3;
            let c = 3 - a - b;
            d[b] = d[a].abs() * d[b].signum();
            d[c] *= d[a].abs();
            let q = light + d * (1.0 + next().abs() * 4.0);
            let p = q + DVec3::new(next(), next(), next()).normalize() * tol * 0.99;
            let (e1, e2) = (
                DVec3::new(next(), next(), next()),
                DVec3::new(next(), next(), next()),
            );
            let tri = [p + e1, p + e2, p - e1 - e2];
            let mut boxes = Vec::new();
            caster_boxes(&tri, light, tol, &mut clip, |f, b| boxes.push((f, b)));
            assert_in_its_box(q, light, &boxes, &tri);
        }
    }

    /// No point over a face's box nearer `farthest` than the plane allows
    /// is cut off: every point on the light's side of a random plane, or
    /// within `beyond` behind it, has `w` at most `farthest`.
    #[test]
    fn farthest_keeps_every_point_in_front_of_the_plane() {
        let mut next = numbers(0x2545_f491_4f6c_dd1d);
        let light = DVec3::new(0.3, 0.1, -0.2);
        let beyond = 1e-2;
        let mut kept = 0;
        for _ in 0..20000 {
            let n = DVec3::new(next(), next(), next()).normalize();
            let plane = n.extend(-n.dot(light) + next().abs() * 4.0);
            let q = light + DVec3::new(next(), next(), next()) * 6.0;
            let value = plane.truncate().dot(q) + plane.w;
            // Half in front of the plane, half within `beyond` behind it.
            let q = if next() > 0.0 {
                q - n * (value + beyond * next().abs())
            } else {
                q
            };
            if plane.truncate().dot(q) + plane.w < -beyond {
                continue;
            }
            let (f, x) = on_face(q - light);
            let (lo, hi) = (
                x - DVec3::splat(next().abs() * 0.3),
                x + DVec3::splat(next().abs() * 0.3),
            );
            let far = farthest(plane, light, f, lo, hi, beyond);
            assert!(
                x.z <= far,
                "{q} (w {}) past {far} before plane {plane}",
                x.z
            );
            kept += 1;
        }
        assert!(kept > 5000, "only {kept} points tried");
    }
}

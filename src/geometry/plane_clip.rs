//! Clipping a polygon to an intersection of half-spaces without
//! allocating: [`face_splitter::clip_to_planes`] (Donovan 000 section 4)
//! for the common case where every plane cuts the polygon at most twice,
//! in reused buffers, with an early out as soon as nothing is left.
//!
//! Shadow casting (004 section 4.7) clips millions of caster polygons to
//! shadow volumes, and most of them come out empty; the general splitter
//! allocates a ring, its crossings and every piece for each of them.
//! Here a plane crossed exactly twice is handled in place and gives the
//! same single piece, bit for bit, as the splitter: the piece starts at
//! the crossing where the ring enters the front side, vertices within
//! `epsilon` of the plane are snapped onto it and counted behind, the
//! crossing points, the ordering check of the crossings along the line
//! of intersection and the removal of repeated points are the splitter's.
//! A plane crossed more often (a non-convex polygon) hands the rest of the
//! work to the splitter, so the result is always that of
//! [`face_splitter::clip_to_planes`].

use glam::{DVec3, DVec4};

use super::face_splitter::{self, NotSimple};
use super::polygon::newell_vector;

/// Reusable buffers for [`clip_to_planes`].
#[derive(Debug, Default, Clone)]
pub struct ClipScratch {
    current: Vec<DVec3>,
    next: Vec<DVec3>,
    distance: Vec<f64>,
}

/// What [`clip_to_planes`] left.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clipped {
    /// Nothing inside every half-space.
    Empty,
    /// One piece, in [`ClipScratch::piece`].
    One,
    /// Several pieces (a non-convex polygon), in `pieces`.
    Many,
}

impl ClipScratch {
    /// The piece after [`Clipped::One`].
    pub fn piece(&self) -> &[DVec3] {
        &self.current
    }
}

/// Whether `points` lie wholly beyond one of `planes` by more than
/// `epsilon`: [`clip_to_planes`] keeps nothing of them (its test of that
/// plane), so a caller can pass them over before any other work.
pub fn beyond_one(points: &[DVec3], planes: &[DVec4], epsilon: f64) -> bool {
    planes.iter().any(|pl| {
        let n = pl.truncate();
        points.iter().all(|p| n.dot(*p) + pl.w < -epsilon)
    })
}

/// Clips `points` to the front half-spaces of `planes` (front where
/// `A x + B y + C z + D > 0`) exactly as [`face_splitter::clip_to_planes`]
/// does. A single piece is left in `scratch` (no allocation once the
/// buffers have grown); several pieces go to `pieces` (cleared first).
pub fn clip_to_planes(
    points: &[DVec3],
    planes: &[DVec4],
    epsilon: f64,
    scratch: &mut ClipScratch,
    pieces: &mut Vec<Vec<DVec3>>,
) -> Result<Clipped, NotSimple> {
    pieces.clear();
    scratch.current.clear();
    scratch.current.extend_from_slice(points);
    for (k, &plane) in planes.iter().enumerate() {
        let n = plane.truncate();
        let (lo, hi) =
            scratch
                .current
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let d = n.dot(*p) + plane.w;
                    (lo.min(d), hi.max(d))
                });
        if lo >= -epsilon {
            continue;
        }
        if hi <= epsilon {
            return Ok(Clipped::Empty);
        }
        match cut_once(scratch, plane, epsilon)? {
            Some(true) => {}
            Some(false) => return Ok(Clipped::Empty),
            None => {
                // Crossed more than twice: the splitter does the rest.
                let rest = face_splitter::clip_to_planes(&scratch.current, &planes[k..], epsilon)?;
                return Ok(match rest.len() {
                    0 => Clipped::Empty,
                    1 => {
                        scratch.current.clear();
                        scratch.current.extend_from_slice(&rest[0]);
                        Clipped::One
                    }
                    _ => {
                        *pieces = rest;
                        Clipped::Many
                    }
                });
            }
        }
    }
    Ok(Clipped::One)
}

/// The splitter's ordering of two crossing keys.
fn key_cmp(a: (f64, f64), b: (f64, f64)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
}

/// Cuts `scratch.current` by `plane`, known to have vertices on both
/// sides beyond `epsilon`, keeping the front piece. `Some(true)`: one
/// piece left; `Some(false)`: the piece had no area; `None`: the ring
/// crosses the plane more than twice.
fn cut_once(
    scratch: &mut ClipScratch,
    plane: DVec4,
    epsilon: f64,
) -> Result<Option<bool>, NotSimple> {
    let points = &scratch.current;
    let m = points.len();
    let normal = plane.truncate();
    let distance = &mut scratch.distance;
    distance.clear();
    distance.extend(points.iter().map(|p| {
        let d = normal.dot(*p) + plane.w;
        if d.abs() <= epsilon { 0.0 } else { d }
    }));
    // The edges whose ends lie on different sides (snapped points behind).
    let mut entry = usize::MAX;
    let mut exit = usize::MAX;
    let mut crossings = 0;
    for i in 0..m {
        let (fa, fb) = (distance[i] > 0.0, distance[(i + 1) % m] > 0.0);
        if fa != fb {
            crossings += 1;
            if fb {
                entry = i;
            } else {
                exit = i;
            }
        }
    }
    if crossings != 2 {
        return Ok(None);
    }
    let poly_normal = newell_vector(points.iter().copied());
    let along = normal.cross(poly_normal);
    let crossing = |i: usize| {
        let j = (i + 1) % m;
        let (a, b) = (points[i], points[j]);
        let (da, db) = (distance[i], distance[j]);
        let t = da / (da - db);
        let point = if t <= 0.0 {
            a
        } else if t >= 1.0 {
            b
        } else {
            a + (b - a) * t
        };
        let slope = (b - a) / (db - da);
        (point, (along.dot(point), along.dot(slope)))
    };
    let (entry_point, entry_key) = crossing(entry);
    let (exit_point, exit_key) = crossing(exit);
    // The splitter sorts the two crossings (stably, in ring order) along
    // the line, for the front side and for the back side, and needs an
    // exit then an entry on each.
    let (first_key, second_key, first_is_entry) = if entry < exit {
        (entry_key, exit_key, true)
    } else {
        (exit_key, entry_key, false)
    };
    let neg = |k: (f64, f64)| (-k.0, -k.1);
    let front_swapped = key_cmp(second_key, first_key) == std::cmp::Ordering::Less;
    let front_first_is_entry = first_is_entry != front_swapped;
    let back_swapped = key_cmp(neg(second_key), neg(first_key)) == std::cmp::Ordering::Less;
    let back_first_is_entry = first_is_entry != back_swapped;
    // Front: first an exit of the front side (not an entry); back: first
    // an exit of the back side, which is an entry of the front side.
    if front_first_is_entry || !back_first_is_entry {
        return Err(NotSimple);
    }
    let next = &mut scratch.next;
    next.clear();
    next.push(entry_point);
    let mut i = (entry + 1) % m;
    loop {
        next.push(points[i]);
        if i == exit {
            break;
        }
        i = (i + 1) % m;
    }
    next.push(exit_point);
    next.dedup_by(|a, b| a == b);
    while next.len() > 1 && next.first() == next.last() {
        next.pop();
    }
    let keep = next.len() >= 3 && newell_vector(next.iter().copied()).length() > 0.0;
    std::mem::swap(&mut scratch.current, &mut scratch.next);
    Ok(Some(keep))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn general(points: &[DVec3], planes: &[DVec4], eps: f64) -> Result<Vec<Vec<DVec3>>, NotSimple> {
        face_splitter::clip_to_planes(points, planes, eps)
    }

    fn fast(points: &[DVec3], planes: &[DVec4], eps: f64) -> Result<Vec<Vec<DVec3>>, NotSimple> {
        let mut scratch = ClipScratch::default();
        let mut pieces = Vec::new();
        Ok(
            match clip_to_planes(points, planes, eps, &mut scratch, &mut pieces)? {
                Clipped::Empty => Vec::new(),
                Clipped::One => vec![scratch.piece().to_vec()],
                Clipped::Many => pieces,
            },
        )
    }

    /// A star-shaped polygon (convex when the radii are equal) in a
    /// tilted plane.
    fn star(radii: &[f64], tilt: f64) -> Vec<DVec3> {
        let n = radii.len();
        (0..n)
            .map(|i| {
                let a = -(i as f64) * std::f64::consts::TAU / n as f64;
                let (x, y) = (radii[i] * a.cos(), radii[i] * a.sin());
                DVec3::new(x, y * tilt.cos(), y * tilt.sin())
            })
            .collect()
    }

    #[test]
    fn square_clipped_by_a_slab_hand_worked() {
        // The unit square clipped to 0.25 <= x <= 0.5: the piece starts
        // where the ring enters the front of the last plane cut.
        let sq = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
        ];
        let planes = [
            DVec4::new(1.0, 0.0, 0.0, -0.25),
            DVec4::new(-1.0, 0.0, 0.0, 0.5),
        ];
        let got = fast(&sq, &planes, 1e-9).unwrap();
        assert_eq!(got, general(&sq, &planes, 1e-9).unwrap());
        assert_eq!(got.len(), 1);
        let mut xs: Vec<f64> = got[0].iter().map(|p| p.x).collect();
        xs.sort_by(f64::total_cmp);
        assert_eq!(xs, vec![0.25, 0.25, 0.5, 0.5]);
        // Wholly outside: empty at once.
        assert!(
            fast(&sq, &[DVec4::new(1.0, 0.0, 0.0, -2.0)], 1e-9)
                .unwrap()
                .is_empty()
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// Bit for bit the splitter's result, for convex and star-shaped
        /// (non-convex) polygons and planes through vertices.
        #[test]
        fn same_as_the_splitter(
            radii in prop::collection::vec(0.2f64..3.0, 3..12),
            convex in any::<bool>(),
            tilt in -1.2f64..1.2,
            planes in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, -1.5f64..1.5, 0usize..16), 1..7),
        ) {
            let radii: Vec<f64> = if convex { vec![1.5; radii.len()] } else { radii };
            let poly = star(&radii, tilt);
            let planes: Vec<DVec4> = planes
                .into_iter()
                .filter_map(|(x, y, z, d, snap)| {
                    let n = DVec3::new(x, y, z).try_normalize()?;
                    let d = if snap < poly.len() { -n.dot(poly[snap]) } else { d };
                    Some(n.extend(d))
                })
                .collect();
            let clipped = fast(&poly, &planes, 1e-9);
            if beyond_one(&poly, &planes, 1e-9) {
                prop_assert!(clipped.as_ref().is_ok_and(Vec::is_empty));
            }
            prop_assert_eq!(clipped, general(&poly, &planes, 1e-9));
        }
    }
}

//! Segments and points painted among the pieces of a paint order, as
//! list priority paints every primitive at its place in one order (004
//! section 4.4): a segment is cut only where an opaque polygon hides it
//! (translucent and unfilled ones hide nothing), and each visible part,
//! and each point (a marker's or a label's anchor, painted whole), is
//! painted just before the first patch that covers it on the screen and
//! lies in front of it. Everything behind it has then been painted, and
//! what is in front of it is painted over it. A segment is split where
//! that patch changes along it: at the screen outlines of the translucent
//! pieces and where it passes through their planes.

use glam::DVec3;

use super::segments::{Occluders, sub_segment};
use super::{PaintOrder, Projected, invalid};
use crate::error::Result;

/// What [`Projected::layered`] gives: the paint order, and where the
/// segments' visible parts and the points go in it.
///
/// ```
/// use plytrace::api::Projected;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// // A translucent square above a segment, seen from above: the segment
/// // is not hidden, and is painted before the square (patch 0).
/// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let seen = Projected::new(&[&square[..]], m)?;
/// let under = [[[1., -1., -1.], [1., 1., -1.]]];
/// let layered = seen.layered(None, &[false], &under, &[[1., 1., 1.], [1., 1., -1.]])?;
/// let before: Vec<usize> = layered.segments.iter().map(|s| s.before).collect();
/// assert_eq!(before, [1, 0], "outside the square: at the end; under it: before it");
/// assert_eq!(layered.points, [Some(1), Some(0)], "a point above, a point below");
/// // Opaque, the square hides the part under it.
/// assert_eq!(seen.layered(None, &[true], &under, &[])?.segments.len(), 1);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Layered {
    /// The polygons' pieces, as [`Projected::paint_order_by`] gives them.
    pub order: PaintOrder,
    /// The visible parts of the segments, in the order of the segments
    /// and along each from its first end.
    pub segments: Vec<PlacedSegment>,
    /// Per point: the patch it is painted before (`patches.len()`: after
    /// all of them); `None` when it is behind the eye.
    pub points: Vec<Option<usize>>,
}

/// A visible part of a segment given to [`Projected::layered`] and its
/// place in the paint order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedSegment {
    /// Index of the segment.
    pub segment: usize,
    /// Its ends, in the projected 2-D coordinates.
    pub points: [[f64; 2]; 2],
    /// The patch it is painted before (`patches.len()`: after all).
    pub before: usize,
}

impl Projected {
    /// The paint order of [`Projected::paint_order_by`] (with `keys`),
    /// and the places in it of `segments` and `points` (3-D). `opaque`:
    /// per polygon, whether it hides what is behind it; the others (a
    /// translucent fill, or none) are painted over what they cover.
    /// Segments keep their parts that no opaque polygon hides (as
    /// [`Projected::visible_segments`]); a point is placed whether hidden
    /// or not, and the polygons in front of it paint over it.
    pub fn layered(
        &self,
        keys: Option<&[u32]>,
        opaque: &[bool],
        segments: &[[[f64; 3]; 2]],
        points: &[[f64; 3]],
    ) -> Result<Layered> {
        if opaque.len() != self.sources.len() {
            return Err(invalid(&format!(
                "{} opaque flags for {} polygons",
                opaque.len(),
                self.sources.len()
            )));
        }
        check_finite("segment", segments.iter().map(|s| s.as_flattened()))?;
        check_finite("point", points.iter().map(|p| &p[..]))?;
        let sorted = self.sorted(keys)?;
        let end = sorted.groups.len();
        let mut patch_of = vec![0u32; sorted.pieces.len()];
        for (g, members) in sorted.groups.iter().enumerate() {
            for &k in members {
                patch_of[k] = g as u32;
            }
        }
        let pieces = &sorted.pieces;
        let tagged = |k: usize| (&pieces[k].points[..], patch_of[k]);
        let see_through = |k: &usize| !opaque[pieces[*k].source as usize];
        let mut placed = Vec::new();
        if !segments.is_empty() {
            let hiders = Occluders::new(
                self.faces
                    .iter()
                    .filter(|f| opaque[f.source as usize])
                    .map(|f| (&f.points[..], 0)),
            );
            let translucent = Occluders::new((0..pieces.len()).filter(see_through).map(tagged));
            let mut query = Query::new(&translucent);
            self.visible_parts(&hiders, segments, &mut |segment, a, b| {
                let covers = query.covers(a, b, self.eps);
                place(a, b, covers, end, &mut |p, q, before| {
                    placed.push(PlacedSegment {
                        segment,
                        points: [self.to_2d(p), self.to_2d(q)],
                        before,
                    })
                });
            })?;
            crate::cancel::check()?;
        }
        let all = Occluders::new((0..pieces.len()).filter(|_| !points.is_empty()).map(tagged));
        let mut query = Query::new(&all);
        let points = points
            .iter()
            .map(|p| {
                let p = self.normalized_point(*p)?;
                let first = query.covers(p, p, self.eps).iter().map(|c| c.2).min();
                Some(first.map_or(end, |g| g as usize))
            })
            .collect();
        Ok(Layered {
            order: self.order_of(&sorted),
            segments: placed,
            points,
        })
    }
}

/// Repeated questions to one set of occluders.
struct Query<'a> {
    occluders: &'a Occluders,
    stamp: Vec<u32>,
    epoch: u32,
    found: Vec<(f64, f64, u32)>,
}

impl<'a> Query<'a> {
    fn new(occluders: &'a Occluders) -> Query<'a> {
        Query {
            occluders,
            stamp: vec![0; occluders.faces.len()],
            epoch: 0,
            found: Vec::new(),
        }
    }

    /// The intervals of `a`-`b` that faces cover in front, with their tags.
    fn covers(&mut self, a: DVec3, b: DVec3, eps: f64) -> &[(f64, f64, u32)] {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        self.found.clear();
        let (epoch, found) = (self.epoch, &mut self.found);
        self.occluders
            .hiding(a, b, eps, epoch, &mut self.stamp, found);
        &self.found
    }
}

/// `a`-`b` in parts, each given to `out` with the least tag among the
/// `covers` over it (`end` where none is): cut where a cover begins or
/// ends, consecutive parts of one tag joined.
fn place(
    a: DVec3,
    b: DVec3,
    covers: &[(f64, f64, u32)],
    end: usize,
    out: &mut dyn FnMut(DVec3, DVec3, usize),
) {
    let first_over = |t: f64| {
        covers
            .iter()
            .filter(|c| c.0 <= t && t <= c.1)
            .map(|c| c.2 as usize)
            .min()
            .unwrap_or(end)
    };
    if a.truncate() == b.truncate() {
        out(a, b, first_over(0.5));
        return;
    }
    let mut cuts: Vec<f64> = covers
        .iter()
        .flat_map(|c| [c.0, c.1])
        .filter(|t| *t > 0.0 && *t < 1.0)
        .chain([0.0, 1.0])
        .collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut run: Option<(f64, usize)> = None;
    for w in cuts.windows(2) {
        let slot = first_over((w[0] + w[1]) / 2.0);
        match run {
            Some((_, k)) if k == slot => {}
            Some((start, k)) => {
                sub_segment(a, b, start, w[0], &mut |p, q| out(p, q, k));
                run = Some((w[0], slot));
            }
            None => run = Some((w[0], slot)),
        }
    }
    if let Some((start, k)) = run {
        sub_segment(a, b, start, 1.0, &mut |p, q| out(p, q, k));
    }
}

/// Refuses the first of `items` with a coordinate that is not finite.
fn check_finite<'a>(what: &str, items: impl Iterator<Item = &'a [f64]>) -> Result<()> {
    for (i, v) in items.enumerate() {
        if v.iter().any(|c| !c.is_finite()) {
            return Err(invalid(&format!("{what} {i} is not finite: {v:?}")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seen from above: x and y kept, depth -z.
    const TOP: [[f64; 4]; 4] = [
        [1., 0., 0., 0.],
        [0., 1., 0., 0.],
        [0., 0., -1., 0.],
        [0., 0., 0., 1.],
    ];

    fn square(z: f64, x0: f64) -> Vec<[f64; 3]> {
        vec![[x0, 0., z], [x0 + 2., 0., z], [x0 + 2., 2., z], [x0, 2., z]]
    }

    #[test]
    fn a_segment_through_a_translucent_plane_is_split_where_it_pierces_it() {
        let plane = square(0., 0.);
        let seen = Projected::new(&[&plane[..]], TOP).unwrap();
        // From below the plane to above it, along x at y = 1: x < 0 and
        // x > 2 are off the plane's outline; it pierces it at x = 1.
        let seg = [[[-1., 1., -1.], [3., 1., 1.]]];
        let l = seen.layered(None, &[false], &seg, &[]).unwrap();
        let parts: Vec<(f64, f64, usize)> = l
            .segments
            .iter()
            .map(|s| (s.points[0][0], s.points[1][0], s.before))
            .collect();
        assert_eq!(parts.len(), 3, "{parts:?}");
        let close = |a: f64, b: f64| (a - b).abs() < 1e-6;
        assert!(close(parts[0].0, -1.) && close(parts[0].1, 0.) && parts[0].2 == 1);
        assert!(close(parts[1].0, 0.) && close(parts[1].1, 1.) && parts[1].2 == 0);
        assert!(close(parts[2].0, 1.) && close(parts[2].1, 3.) && parts[2].2 == 1);
    }

    #[test]
    fn a_point_goes_before_the_first_patch_in_front_of_it() {
        // Three squares stacked, painted low (0) to high (2); a point
        // between the lower two is covered by patches 1 and 2: before 1.
        let (a, b, c) = (square(0., 0.), square(1., 0.), square(2., 0.));
        let seen = Projected::new(&[&c[..], &a[..], &b[..]], TOP).unwrap();
        let l = seen
            .layered(
                None,
                &[true, false, true],
                &[],
                &[[1., 1., 0.5], [5., 5., 0.]],
            )
            .unwrap();
        let sources: Vec<usize> = l.order.patches.iter().map(|p| p.source()).collect();
        assert_eq!(sources, [1, 2, 0]);
        assert_eq!(l.points, [Some(1), Some(3)]);
    }

    #[test]
    fn only_opaque_polygons_hide_segments() {
        let (low, high) = (square(0., 0.), square(1., 0.));
        let seen = Projected::new(&[&low[..], &high[..]], TOP).unwrap();
        let seg = [[[1., 1., -1.], [1., 1.5, -1.]]];
        for (opaque, parts) in [([true, true], 0), ([false, true], 0), ([false, false], 1)] {
            let l = seen.layered(None, &opaque, &seg, &[]).unwrap();
            assert_eq!(l.segments.len(), parts, "{opaque:?}");
        }
        let l = seen.layered(None, &[false, false], &seg, &[]).unwrap();
        assert_eq!(l.segments[0].before, 0, "under both: before the first");
        assert!(seen.layered(None, &[true], &seg, &[]).is_err());
        assert!(
            seen.layered(None, &[true, true], &[], &[[f64::NAN, 0., 0.]])
                .is_err()
        );
    }
}

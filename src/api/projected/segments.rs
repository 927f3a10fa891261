//! The visible pieces of segments among the projected polygons: each
//! segment cut where a polygon's face is nearer the eye, the faces found
//! by screen cell ([`Occluders`]).

use glam::{DVec3, DVec4};

use super::{Projected, invalid};
use crate::error::Result;

/// A visible piece of a segment given to [`Projected::visible_segments`].
///
/// ```
/// use plytrace::api::Projected;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let seen = Projected::new(&[&square[..]], m)?;
/// // Segment 1 passes above the square; segment 0 lies under it.
/// let pieces = seen.visible_segments(&[[[0.5, 1., -1.], [1.5, 1., -1.]], [[0.5, 1., 1.], [1.5, 1., 1.]]])?;
/// assert_eq!(pieces.len(), 1);
/// assert_eq!(pieces[0].segment, 1);
/// assert_eq!(pieces[0].points, [[0.5, 1.], [1.5, 1.]]);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentPiece {
    /// Index of the segment.
    pub segment: usize,
    /// Its ends, in the projected 2-D coordinates.
    pub points: [[f64; 2]; 2],
}
impl Projected {
    /// The visible pieces of `segments` (3-D ends): where no polygon is
    /// nearer the eye. A segment lying on a polygon (to the tolerance of
    /// the sort) stays visible; a segment of zero length is a point, kept
    /// whole or dropped. Pieces come in the order of the segments, along
    /// each from its first end.
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// let seen = Projected::new(&[&square[..]], m)?;
    /// // Under the square from x = -1 to x = 3: only the ends outside it show.
    /// let pieces = seen.visible_segments(&[[[-1., 1., -1.], [3., 1., -1.]]])?;
    /// assert_eq!(pieces.len(), 2);
    /// assert!((pieces[0].points[1][0] - 0.).abs() < 1e-6 && (pieces[1].points[0][0] - 2.).abs() < 1e-6);
    /// # Ok(())
    /// # }
    /// ```
    pub fn visible_segments(&self, segments: &[[[f64; 3]; 2]]) -> Result<Vec<SegmentPiece>> {
        if let Some(i) = segments
            .iter()
            .position(|s| s.iter().flatten().any(|c| !c.is_finite()))
        {
            return Err(invalid(&format!(
                "segment {i} is not finite: {:?}",
                segments[i]
            )));
        }
        let occluders = Occluders::new(self.faces.iter().map(|f| (&f.points[..], 0)));
        let mut out = Vec::new();
        self.visible_parts(&occluders, segments, &mut |segment, a, b| {
            out.push(SegmentPiece {
                segment,
                points: [self.to_2d(a), self.to_2d(b)],
            })
        })?;
        Ok(out)
    }

    /// The parts of `segments` that no face of `occluders` hides, as
    /// normalized ends given to `part` with the segment's index, in the
    /// order of the segments and along each from its first end.
    pub(super) fn visible_parts(
        &self,
        occluders: &Occluders,
        segments: &[[[f64; 3]; 2]],
        part: &mut dyn FnMut(usize, DVec3, DVec3),
    ) -> Result<()> {
        let mut stamp = vec![0u32; occluders.faces.len()];
        let mut hidden: Vec<(f64, f64, u32)> = Vec::new();
        for (i, seg) in segments.iter().enumerate() {
            if i % 4096 == 0 {
                crate::cancel::check()?;
            }
            let Some((a, b)) = self.normalized_segment(seg) else {
                continue;
            };
            hidden.clear();
            let epoch = (i as u32).wrapping_add(1);
            occluders.hiding(a, b, self.eps, epoch, &mut stamp, &mut hidden);
            if a.truncate() == b.truncate() {
                if hidden.is_empty() {
                    part(i, a, b);
                }
                continue;
            }
            hidden.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut t = 0.0;
            for &(h0, h1, _) in hidden.iter() {
                if h0 > t {
                    sub_segment(a, b, t, h0, &mut |p, q| part(i, p, q));
                }
                t = t.max(h1);
            }
            sub_segment(a, b, t, 1.0, &mut |p, q| part(i, p, q));
        }
        Ok(())
    }

    /// `p` through the matrix, normalized; `None` behind the eye.
    pub(super) fn normalized_point(&self, p: [f64; 3]) -> Option<DVec3> {
        let h = self.homogeneous(p);
        (h.w >= self.w_min).then(|| (h.truncate() / h.w - self.centre) * self.scale)
    }

    fn homogeneous(&self, p: [f64; 3]) -> DVec4 {
        let r = |k: usize| {
            self.matrix[k][0] * p[0]
                + self.matrix[k][1] * p[1]
                + self.matrix[k][2] * p[2]
                + self.matrix[k][3]
        };
        DVec4::new(r(0), r(1), r(2), r(3))
    }

    /// `seg` through the matrix, clipped to `W >= w_min`, normalized;
    /// `None` when it lies wholly behind the eye.
    fn normalized_segment(&self, seg: &[[f64; 3]; 2]) -> Option<(DVec3, DVec3)> {
        let (mut a, mut b) = (self.homogeneous(seg[0]), self.homogeneous(seg[1]));
        let (ina, inb) = (a.w >= self.w_min, b.w >= self.w_min);
        match (ina, inb) {
            (false, false) => return None,
            (true, false) => b = a + (b - a) * ((a.w - self.w_min) / (a.w - b.w)),
            (false, true) => a = b + (a - b) * ((b.w - self.w_min) / (b.w - a.w)),
            (true, true) => {}
        }
        let norm = |h: DVec4| (h.truncate() / h.w - self.centre) * self.scale;
        Some((norm(a), norm(b)))
    }
}

/// The part of `a`-`b` from `t0` to `t1` given to `part`, unless it is
/// shorter than rounding (a stroke's cap would show it as a dot). The
/// ends themselves at 0 and 1, so that the pieces of a polyline meet
/// exactly.
pub(super) fn sub_segment(
    a: DVec3,
    b: DVec3,
    t0: f64,
    t1: f64,
    part: &mut dyn FnMut(DVec3, DVec3),
) {
    let shortest = 1e-9 / (b - a).truncate().length().max(1e-300);
    if t1 - t0 <= shortest {
        return;
    }
    let at = |t: f64| match t {
        0.0 => a,
        1.0 => b,
        _ => a + (b - a) * t,
    };
    part(at(t0), at(t1));
}

/// The faces that may hide segments, by screen cell, each with a tag.
pub(super) struct Occluders {
    /// Screen outline (counter-clockwise), plane `z = a x + b y + c`.
    pub(super) faces: Vec<(Vec<glam::DVec2>, [f64; 3])>,
    pub(super) tags: Vec<u32>,
    pub(super) cells: Vec<Vec<u32>>,
    pub(super) n: usize,
}

impl Occluders {
    /// The faces (convex, normalized) with their tags; edge-on ones hide
    /// nothing and are left out.
    pub(super) fn new<'a>(faces: impl Iterator<Item = (&'a [DVec3], u32)>) -> Occluders {
        use glam::DVec2;
        let mut list = Vec::new();
        let mut tags = Vec::new();
        for (points, tag) in faces {
            let Some(unit) =
                crate::geometry::polygon::newell_vector(points.iter().copied()).try_normalize()
            else {
                continue;
            };
            if unit.z.abs() < 1e-9 {
                continue; // edge-on
            }
            let c = points[0];
            // unit . (p - c) = 0  =>  z = c.z - (ux (x - cx) + uy (y - cy)) / uz
            let (a, b) = (-unit.x / unit.z, -unit.y / unit.z);
            let plane = [a, b, c.z - a * c.x - b * c.y];
            let mut pts: Vec<DVec2> = points.iter().map(|p| p.truncate()).collect();
            if unit.z > 0.0 {
                // Newell z > 0: counter-clockwise already.
            } else {
                pts.reverse();
            }
            list.push((pts, plane));
            tags.push(tag);
        }
        let n = ((list.len() as f64 / 2.0).sqrt() as usize).clamp(1, 512);
        let mut cells = vec![Vec::new(); n * n];
        let cell = |v: f64| (((v + 1.0) / 2.0 * n as f64).floor().max(0.0) as usize).min(n - 1);
        for (k, (pts, _)) in list.iter().enumerate() {
            let (lo, hi) = pts
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                });
            for y in cell(lo.y)..=cell(hi.y) {
                for x in cell(lo.x)..=cell(hi.x) {
                    cells[y * n + x].push(k as u32);
                }
            }
        }
        Occluders {
            faces: list,
            tags,
            cells,
            n,
        }
    }

    /// Appends the parameter intervals of segment `a`-`b` (normalized)
    /// that faces hide, each with the face's tag: inside a face's
    /// outline and farther than its plane by more than `eps`.
    pub(super) fn hiding(
        &self,
        a: DVec3,
        b: DVec3,
        eps: f64,
        epoch: u32,
        stamp: &mut [u32],
        hidden: &mut Vec<(f64, f64, u32)>,
    ) {
        let n = self.n;
        let cell = |v: f64| (((v + 1.0) / 2.0 * n as f64).floor().max(0.0) as usize).min(n - 1);
        let (lo, hi) = (a.min(b), a.max(b));
        if hi.x < -1.0 || lo.x > 1.0 || hi.y < -1.0 || lo.y > 1.0 {
            return;
        }
        let d = b - a;
        for y in cell(lo.y)..=cell(hi.y) {
            for x in cell(lo.x)..=cell(hi.x) {
                // Only the cells the segment's line passes near.
                let (cx0, cy0) = (
                    x as f64 / n as f64 * 2.0 - 1.0,
                    y as f64 / n as f64 * 2.0 - 1.0,
                );
                let w = 2.0 / n as f64;
                let corners = [
                    (cx0, cy0),
                    (cx0 + w, cy0),
                    (cx0, cy0 + w),
                    (cx0 + w, cy0 + w),
                ];
                let side = |(px, py): (f64, f64)| d.x * (py - a.y) - d.y * (px - a.x);
                let s: Vec<f64> = corners.iter().map(|c| side(*c)).collect();
                if s.iter().all(|v| *v > 0.0) || s.iter().all(|v| *v < 0.0) {
                    continue;
                }
                for &k in &self.cells[y * n + x] {
                    let k = k as usize;
                    if stamp[k] == epoch {
                        continue;
                    }
                    stamp[k] = epoch;
                    let (pts, [pa, pb, pc]) = &self.faces[k];
                    // Inside the outline, or on it to rounding (so that
                    // adjacent faces leave no gap between them).
                    let (mut t0, mut t1) = (0.0f64, 1.0f64);
                    let m = pts.len();
                    let mut empty = false;
                    for i in 0..m {
                        let (e0, e1) = (pts[i], pts[(i + 1) % m]);
                        let e = e1 - e0;
                        let tol = 1e-9 * e.length();
                        let f0 = e.perp_dot(a.truncate() - e0) + tol;
                        let f1 = e.perp_dot(b.truncate() - e0) + tol;
                        if !clip_interval(f0, f1, &mut t0, &mut t1) {
                            empty = true;
                            break;
                        }
                    }
                    if empty {
                        continue;
                    }
                    // Behind the plane by more than eps.
                    let g = |p: DVec3| p.z - (pa * p.x + pb * p.y + pc) - eps;
                    if !clip_interval(g(a), g(b), &mut t0, &mut t1) {
                        continue;
                    }
                    if a.truncate() == b.truncate() || t1 > t0 {
                        hidden.push((t0, t1, self.tags[k]));
                    }
                }
            }
        }
    }
}

/// Narrows `[t0, t1]` to where `f0 + t (f1 - f0) > 0`; false if nothing
/// is left.
pub(super) fn clip_interval(f0: f64, f1: f64, t0: &mut f64, t1: &mut f64) -> bool {
    if f0 <= 0.0 && f1 <= 0.0 {
        return false;
    }
    if f0 > 0.0 && f1 > 0.0 {
        return *t0 <= *t1;
    }
    let t = f0 / (f0 - f1);
    if f0 > 0.0 {
        *t1 = t1.min(t);
    } else {
        *t0 = t0.max(t);
    }
    *t0 <= *t1
}

pub(super) fn distance_to_segment(x: DVec3, p: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((x - p).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x - (p + d * t)).length()
}

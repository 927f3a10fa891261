//! Hidden-line drawings (Brown 1978, 003: "painting the edges of faces
//! black and their interiors white"): the visible parts of the edges of
//! the faces seen directly, as strokes.
//!
//! Brown gets the drawing by painting; a vector drawing needs the visible
//! pieces themselves. The level-1 pieces come back to front from NNS with
//! splitting (004 section 4.4), so a point of an edge is hidden exactly
//! when a piece painted later covers it strictly inside (a neighbour that
//! merely shares the edge does not hide it). Each edge is cut where such
//! pieces start and stop covering it; the parts left are drawn. Only the
//! edges that lie on an edge of the original polygon are drawn: none made
//! by NNS splitting or by clipping to the viewport
//! ([`super::VectorInput::original_edges`]). Shadows, reflections and
//! refractions are not drawn: mirrors and glass are plain faces.
//!
//! [`rasterize`] draws the segments into a white frame buffer for PNG
//! output, 1 pixel wide: anti-aliased by the exact box-filtered coverage
//! of a 1-pixel-wide line, or as one pixel per column (row) without.

use super::{Pt, VectorInput};
use crate::raster::frame_buffer::FrameBuffer;

/// How far inside a face a point must be to be hidden (user units).
const INSIDE: f64 = 1e-3;
/// Shortest part drawn (user units).
const SHORTEST: f64 = 0.05;
/// Pieces sharing one vertex from which they are indexed together, by
/// angle around it, instead of one by one in the grid (a fan).
const FAN: usize = 8;
/// Most cells per side of the lookup grid.
const MAX_GRID: usize = 1024;
/// Grid entries allowed per piece (and a floor) when choosing the grid.
const ENTRIES_PER_PIECE: usize = 16;
/// Pieces looked at between two looks at [`crate::cancel`].
const CANCEL_EVERY: usize = 256;

/// A level-1 piece in painting order.
struct Piece {
    pts: Vec<Pt>,
    min: Pt,
    max: Pt,
}

/// The visible edge segments of the faces seen directly.
pub fn visible_edges(input: &VectorInput) -> Vec<[Pt; 2]> {
    try_visible_edges(input).unwrap_or_default()
}

/// [`visible_edges`], stopping with [`crate::error::Error::Cancelled`]
/// within a fraction of a second of a stop being requested.
pub fn try_visible_edges(input: &VectorInput) -> crate::error::Result<Vec<[Pt; 2]>> {
    let (w, h) = (input.width as f64, input.height as f64);
    let mut faces = Vec::new();
    for (k, r) in input.stream.records.iter().enumerate() {
        if !input.direct[k] || r.points.len() < 3 {
            continue;
        }
        let pts: Vec<Pt> = r
            .points
            .iter()
            .map(|p| [p[0] as f64 * w, (1.0 - p[1] as f64) * h])
            .collect();
        faces.push((pts, input.original_edges[k].clone()));
    }
    segments_of(&faces, w, h)
}

/// The visible parts of the flagged edges of `faces` (user units, in
/// painting order, each with one flag per edge: drawn or not), in a `w` x
/// `h` picture: what [`visible_edges`] draws.
///
/// A point of an edge is hidden when a later face covers it strictly
/// inside. The work is kept near linear in the usual cases:
///
/// - an edge that later drawn edges on the same line cover wholly is
///   skipped: its visible part is within theirs (the faces that hide
///   them come after it too), so identical faces cost one edge each;
/// - the later faces are found by a grid over their boxes, and the faces
///   that share a vertex with [`FAN`] or more others are indexed by their
///   angle around it (as seen from the vertex, a convex face lies within
///   the angle of its two edges there): the faces of a fan that merely
///   touch an edge at its end are not looked at;
/// - the faces are tried nearest first and the search stops once the edge
///   is hidden wholly.
#[doc(hidden)]
pub fn segments_of(
    faces: &[(Vec<Pt>, Vec<bool>)],
    w: f64,
    h: f64,
) -> crate::error::Result<Vec<[Pt; 2]>> {
    let pieces: Vec<Piece> = faces
        .iter()
        .map(|(pts, _)| {
            let (min, max) = bounds(pts);
            Piece {
                pts: pts.clone(),
                min,
                max,
            }
        })
        .collect();
    let skip = covered_by_later_edges(faces)?;
    let index = Index::new(&pieces, w, h);
    let mut out = Vec::new();
    let mut scratch = Scratch {
        seen: vec![0; pieces.len()],
        stamp: 0,
        found: Vec::new(),
    };
    for (i, (pts, flags)) in faces.iter().enumerate() {
        if i % CANCEL_EVERY == 0 {
            crate::cancel::check()?;
        }
        let m = pts.len();
        for e in 0..m {
            if !flags.get(e).copied().unwrap_or(false) || skip[i].get(e).copied().unwrap_or(false) {
                continue;
            }
            let (a, b) = (pts[e], pts[(e + 1) % m]);
            index.later(&pieces, i, a, b, &mut scratch);
            let mut hidden: Vec<(f64, f64)> = Vec::new();
            for &j in &scratch.found {
                covered(&pieces[j], a, b, &mut hidden);
                if hidden_wholly(&mut hidden) {
                    break;
                }
            }
            push_visible(a, b, hidden, &mut out);
        }
    }
    Ok(out)
}

/// The brute-force [`segments_of`]: every edge against every later face.
/// For tests.
#[doc(hidden)]
pub fn segments_brute_force(faces: &[(Vec<Pt>, Vec<bool>)]) -> Vec<[Pt; 2]> {
    let pieces: Vec<Piece> = faces
        .iter()
        .map(|(pts, _)| {
            let (min, max) = bounds(pts);
            Piece {
                pts: pts.clone(),
                min,
                max,
            }
        })
        .collect();
    let mut out = Vec::new();
    for (i, (pts, flags)) in faces.iter().enumerate() {
        let m = pts.len();
        for e in 0..m {
            if !flags.get(e).copied().unwrap_or(false) {
                continue;
            }
            let (a, b) = (pts[e], pts[(e + 1) % m]);
            let mut hidden = Vec::new();
            for p in &pieces[i + 1..] {
                covered(p, a, b, &mut hidden);
            }
            push_visible(a, b, hidden, &mut out);
        }
    }
    out
}

fn push_visible(a: Pt, b: Pt, hidden: Vec<(f64, f64)>, out: &mut Vec<[Pt; 2]>) {
    let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    for (t0, t1) in complement(hidden) {
        if (t1 - t0) * len >= SHORTEST {
            out.push([lerp(a, b, t0), lerp(a, b, t1)]);
        }
    }
}

/// Whether `hidden` covers `[0, 1]`; merges it when it is long.
fn hidden_wholly(hidden: &mut Vec<(f64, f64)>) -> bool {
    if hidden.is_empty() {
        return false;
    }
    let merged = merge(std::mem::take(hidden), 0.0);
    let whole = merged.len() == 1 && merged[0].0 <= 0.0 && merged[0].1 >= 1.0;
    *hidden = merged;
    whole
}

/// Sorted, disjoint union of `v`, joining intervals closer than `slack`.
fn merge(mut v: Vec<(f64, f64)>, slack: f64) -> Vec<(f64, f64)> {
    v.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(v.len());
    for (s, e) in v {
        match out.last_mut() {
            Some(last) if s <= last.1 + slack => last.1 = last.1.max(e),
            _ => out.push((s, e)),
        }
    }
    out
}

/// Per face and edge: whether drawn edges of later faces on the same line
/// cover it wholly (lines are matched exactly, to 1e-9 of a radian and
/// 1e-6 of a unit: edges made from the same points).
fn covered_by_later_edges(faces: &[(Vec<Pt>, Vec<bool>)]) -> crate::error::Result<Vec<Vec<bool>>> {
    use std::collections::HashMap;
    let mut lines: HashMap<(i64, i64), Vec<(f64, f64)>> = HashMap::new();
    let mut skip: Vec<Vec<bool>> = faces.iter().map(|(p, _)| vec![false; p.len()]).collect();
    for (i, (pts, flags)) in faces.iter().enumerate().rev() {
        if i % CANCEL_EVERY == 0 {
            crate::cancel::check()?;
        }
        let m = pts.len();
        for e in 0..m {
            if !flags.get(e).copied().unwrap_or(false) {
                continue;
            }
            let (a, b) = (pts[e], pts[(e + 1) % m]);
            let mut d = [b[0] - a[0], b[1] - a[1]];
            let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
            if !len.is_finite() || len <= 0.0 {
                continue;
            }
            if d[0] < 0.0 || (d[0] == 0.0 && d[1] < 0.0) {
                d = [-d[0], -d[1]];
            }
            let (ux, uy) = (d[0] / len, d[1] / len);
            let angle = uy.atan2(ux);
            let offset = -uy * a[0] + ux * a[1];
            let key = ((angle * 1e9).round() as i64, (offset * 1e6).round() as i64);
            let (ta, tb) = (ux * a[0] + uy * a[1], ux * b[0] + uy * b[1]);
            let (t0, t1) = (ta.min(tb), ta.max(tb));
            let set = lines.entry(key).or_default();
            // `set` is sorted and disjoint: the interval that starts at or
            // before `t0` is the only one that can cover it.
            let k = set.partition_point(|iv| iv.0 <= t0 + 1e-9);
            if k > 0 && set[k - 1].1 >= t1 - 1e-9 {
                skip[i][e] = true;
                continue;
            }
            // Insert and merge the neighbours it touches.
            let lo = set.partition_point(|iv| iv.1 < t0);
            let hi = set.partition_point(|iv| iv.0 <= t1);
            let (mut s, mut t) = (t0, t1);
            if lo < hi {
                s = s.min(set[lo].0);
                t = t.max(set[hi - 1].1);
            }
            set.splice(lo..hi, [(s, t)]);
        }
    }
    Ok(skip)
}

/// The faces of a fan: pieces sharing vertex `at`, by the angle their
/// edges make there.
struct Fan {
    at: Pt,
    /// (start angle in `[0, 2pi)`, width, piece), by start angle.
    wedges: Vec<(f64, f64, usize)>,
    widest: f64,
}

const TAU: f64 = std::f64::consts::TAU;
/// Slack of the angle comparisons (radians).
const ANGLE_SLACK: f64 = 1e-6;

impl Fan {
    /// The pieces whose angle can meet the directions of the points of
    /// `a b` as seen from the fan's vertex.
    fn visit(&self, a: Pt, b: Pt, mut f: impl FnMut(usize)) {
        let v = self.at;
        let da = [a[0] - v[0], a[1] - v[1]];
        let db = [b[0] - v[0], b[1] - v[1]];
        let na = da[0].hypot(da[1]);
        let nb = db[0].hypot(db[1]);
        let tiny = 1e-9;
        let (start, width) = if na <= tiny && nb <= tiny {
            return;
        } else if na <= tiny {
            (db[1].atan2(db[0]), 0.0)
        } else if nb <= tiny {
            (da[1].atan2(da[0]), 0.0)
        } else {
            let cross = da[0] * db[1] - da[1] * db[0];
            let dot = da[0] * db[0] + da[1] * db[1];
            if cross.abs() <= 1e-12 * na * nb && dot < 0.0 {
                // The segment passes through the vertex: every direction.
                for &(_, _, k) in &self.wedges {
                    f(k);
                }
                return;
            }
            let (ta, tb) = (da[1].atan2(da[0]), db[1].atan2(db[0]));
            let span = cross.atan2(dot).abs();
            if cross >= 0.0 { (ta, span) } else { (tb, span) }
        };
        // Wedges [s, s + w] meeting [start, start + width]: s within
        // [start - widest, start + width], around the circle.
        let lo = (start - self.widest - ANGLE_SLACK).rem_euclid(TAU);
        let len = width + self.widest + 2.0 * ANGLE_SLACK;
        let q0 = (start - ANGLE_SLACK).rem_euclid(TAU);
        let qw = width + 2.0 * ANGLE_SLACK;
        let mut take = |from: f64, to: f64| {
            let i0 = self.wedges.partition_point(|x| x.0 < from);
            let i1 = self.wedges.partition_point(|x| x.0 <= to);
            for &(s, w, k) in &self.wedges[i0..i1] {
                // Circular overlap of [s, s + w] and [q0, q0 + qw].
                let d = (q0 - s).rem_euclid(TAU);
                if d <= w || TAU - d <= qw {
                    f(k);
                }
            }
        };
        if len >= TAU {
            take(0.0, TAU);
        } else if lo + len <= TAU {
            take(lo, lo + len);
        } else {
            take(lo, TAU);
            take(0.0, lo + len - TAU);
        }
    }
}

/// What the grid holds: a piece, or a fan.
#[derive(Clone, Copy)]
enum Entry {
    Piece(u32),
    Fan(u32),
}

/// Later pieces by screen cell; fans by their vertex.
struct Index {
    cells: Vec<Vec<Entry>>,
    fans: Vec<Fan>,
    n: usize,
    sx: f64,
    sy: f64,
}

struct Scratch {
    seen: Vec<u32>,
    stamp: u32,
    found: Vec<usize>,
}

/// The pieces grouped into fans about their busiest vertex (one met by at
/// least `FAN` pieces), and the pieces in no fan.
fn fans(pieces: &[Piece]) -> (Vec<Fan>, Vec<usize>) {
    use std::collections::HashMap;
    // Vertices by their exact coordinates, and how many pieces each.
    let key = |p: Pt| (p[0].to_bits(), p[1].to_bits());
    let mut degree: HashMap<(u64, u64), usize> = HashMap::new();
    for p in pieces {
        for &v in &p.pts {
            *degree.entry(key(v)).or_default() += 1;
        }
    }
    let mut fan_of: HashMap<(u64, u64), usize> = HashMap::new();
    let mut fans: Vec<Fan> = Vec::new();
    let mut single: Vec<usize> = Vec::new();
    for (k, p) in pieces.iter().enumerate() {
        let best = (0..p.pts.len())
            .filter(|&i| degree[&key(p.pts[i])] >= FAN)
            .max_by_key(|&i| degree[&key(p.pts[i])]);
        match best
            .filter(|_| convex(&p.pts))
            .and_then(|i| wedge(&p.pts, i))
        {
            Some((v, s, w)) => {
                let f = *fan_of.entry(key(v)).or_insert_with(|| {
                    fans.push(Fan {
                        at: v,
                        wedges: Vec::new(),
                        widest: 0.0,
                    });
                    fans.len() - 1
                });
                fans[f].wedges.push((s, w, k));
                fans[f].widest = fans[f].widest.max(w);
            }
            None => single.push(k),
        }
    }
    (fans, single)
}

/// The wedge of a convex piece at its vertex `i`: the vertex, the angle
/// where the wedge starts (in `[0, TAU)`) and its width; `None` at a
/// repeated vertex.
fn wedge(pts: &[Pt], i: usize) -> Option<(Pt, f64, f64)> {
    let m = pts.len();
    let v = pts[i];
    let (pv, nx) = (pts[(i + m - 1) % m], pts[(i + 1) % m]);
    let (d1, d2) = ([pv[0] - v[0], pv[1] - v[1]], [nx[0] - v[0], nx[1] - v[1]]);
    if d1 == [0.0, 0.0] || d2 == [0.0, 0.0] {
        return None;
    }
    let (a1, a2) = (d1[1].atan2(d1[0]), d2[1].atan2(d2[0]));
    let diff = (a2 - a1).rem_euclid(TAU);
    let (s, w) = if diff <= std::f64::consts::PI {
        (a1, diff)
    } else {
        (a2, TAU - diff)
    };
    Some((v, s.rem_euclid(TAU), w))
}

/// The cells a side of the grid for `entries` in a `w x h` picture: about
/// two entries per cell, no finer than a pixel, and within a total of
/// grid entries proportional to the pieces.
fn grid_size(entries: &[(Entry, (Pt, Pt))], w: f64, h: f64) -> usize {
    let finest = w.max(h).ceil().max(1.0) as usize;
    let mut n = ((entries.len() as f64 / 2.0).sqrt() as usize).clamp(1, MAX_GRID.min(finest));
    let cap = (entries.len().saturating_mul(ENTRIES_PER_PIECE)).max(1 << 20);
    loop {
        let (sx, sy) = (n as f64 / w.max(1.0), n as f64 / h.max(1.0));
        let total: usize = entries
            .iter()
            .map(|(_, b)| {
                let (c0, c1, r0, r1) = range(n, sx, sy, *b);
                (c1 - c0 + 1) * (r1 - r0 + 1)
            })
            .sum();
        if total <= cap || n == 1 {
            return n;
        }
        n /= 2;
    }
}

impl Index {
    fn new(pieces: &[Piece], w: f64, h: f64) -> Index {
        let (mut fans, single) = fans(pieces);
        let mut fan_box: Vec<(Pt, Pt)> = vec![([f64::MAX; 2], [f64::MIN; 2]); fans.len()];
        for (f, fan) in fans.iter_mut().enumerate() {
            fan.wedges.sort_by(|x, y| x.0.total_cmp(&y.0));
            for &(_, _, k) in &fan.wedges {
                for c in 0..2 {
                    fan_box[f].0[c] = fan_box[f].0[c].min(pieces[k].min[c]);
                    fan_box[f].1[c] = fan_box[f].1[c].max(pieces[k].max[c]);
                }
            }
        }
        let entries: Vec<(Entry, (Pt, Pt))> = single
            .iter()
            .map(|&k| (Entry::Piece(k as u32), (pieces[k].min, pieces[k].max)))
            .chain(
                fan_box
                    .iter()
                    .enumerate()
                    .map(|(f, b)| (Entry::Fan(f as u32), *b)),
            )
            .collect();
        let n = grid_size(&entries, w, h);
        let mut index = Index {
            cells: vec![Vec::new(); n * n],
            fans,
            n,
            sx: n as f64 / w.max(1.0),
            sy: n as f64 / h.max(1.0),
        };
        for (e, b) in entries {
            let (c0, c1, r0, r1) = range(n, index.sx, index.sy, b);
            for r in r0..=r1 {
                for c in c0..=c1 {
                    index.cells[r * n + c].push(e);
                }
            }
        }
        index
    }

    /// The pieces after `i` that may cover part of `a b`, nearest (last
    /// painted) first, in `scratch.found`.
    fn later(&self, pieces: &[Piece], i: usize, a: Pt, b: Pt, scratch: &mut Scratch) {
        scratch.found.clear();
        scratch.stamp = scratch.stamp.wrapping_add(1);
        if scratch.stamp == 0 {
            scratch.seen.iter_mut().for_each(|s| *s = 0);
            scratch.stamp = 1;
        }
        let stamp = scratch.stamp;
        let (min, max) = bounds(&[a, b]);
        let mut fans_seen: Vec<u32> = Vec::new();
        let found = &mut scratch.found;
        let seen = &mut scratch.seen;
        let mut take = |k: usize| {
            if k > i && seen[k] != stamp {
                seen[k] = stamp;
                let p = &pieces[k];
                if !(max[0] < p.min[0]
                    || min[0] > p.max[0]
                    || max[1] < p.min[1]
                    || min[1] > p.max[1])
                {
                    found.push(k);
                }
            }
        };
        // The cells the segment crosses, row by row.
        let n = self.n;
        let (_, _, r0, r1) = range(n, self.sx, self.sy, (min, max));
        for r in r0..=r1 {
            let (y0, y1) = (r as f64 / self.sy, (r + 1) as f64 / self.sy);
            let (lo, hi) = if r0 == r1 || a[1] == b[1] {
                (min[0], max[0])
            } else {
                let x_at = |y: f64| a[0] + (b[0] - a[0]) * ((y - a[1]) / (b[1] - a[1]));
                let (ya, yb) = (y0.max(min[1]), y1.min(max[1]));
                let (xa, xb) = (x_at(ya), x_at(yb));
                (xa.min(xb), xa.max(xb))
            };
            let (c0, c1, _, _) = range(n, self.sx, self.sy, ([lo, y0], [hi, y0]));
            for c in c0..=c1 {
                for &e in &self.cells[r * n + c] {
                    match e {
                        Entry::Piece(k) => take(k as usize),
                        Entry::Fan(f) => {
                            if !fans_seen.contains(&f) {
                                fans_seen.push(f);
                                self.fans[f as usize].visit(a, b, &mut take);
                            }
                        }
                    }
                }
            }
        }
        found.sort_unstable_by(|x, y| y.cmp(x));
    }
}

/// Whether the polygon is convex (either orientation, collinear points
/// allowed).
fn convex(pts: &[Pt]) -> bool {
    let m = pts.len();
    let mut sign = 0.0;
    for k in 0..m {
        let (p, q, r) = (pts[k], pts[(k + 1) % m], pts[(k + 2) % m]);
        let c = (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]);
        if c != 0.0 {
            if sign != 0.0 && c.signum() != sign {
                return false;
            }
            sign = c.signum();
        }
    }
    // The turns add up to one full turn (not a star).
    let mut turn = 0.0;
    for k in 0..m {
        let (p, q, r) = (pts[k], pts[(k + 1) % m], pts[(k + 2) % m]);
        let (d1, d2) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
        turn += (d1[0] * d2[1] - d1[1] * d2[0]).atan2(d1[0] * d2[0] + d1[1] * d2[1]);
    }
    sign != 0.0 && (turn.abs() - TAU).abs() < 1e-6
}

/// The cells of the box `(min, max)` in an `n` x `n` grid of scale `sx`,
/// `sy`: first and last column, first and last row.
fn range(n: usize, sx: f64, sy: f64, (min, max): (Pt, Pt)) -> (usize, usize, usize, usize) {
    let cell = |v: f64, s: f64| {
        let c = (v * s).floor();
        if c.is_nan() || c < 0.0 {
            0
        } else {
            (c as usize).min(n - 1)
        }
    };
    (
        cell(min[0], sx),
        cell(max[0], sx),
        cell(min[1], sy),
        cell(max[1], sy),
    )
}

fn lerp(a: Pt, b: Pt, t: f64) -> Pt {
    [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
}

fn bounds(pts: &[Pt]) -> (Pt, Pt) {
    let mut min = [f64::MAX; 2];
    let mut max = [f64::MIN; 2];
    for p in pts {
        for c in 0..2 {
            min[c] = min[c].min(p[c]);
            max[c] = max[c].max(p[c]);
        }
    }
    (min, max)
}

/// The parameter intervals of segment `a b` strictly inside `piece`.
fn covered(piece: &Piece, a: Pt, b: Pt, hidden: &mut Vec<(f64, f64)>) {
    let (min, max) = bounds(&[a, b]);
    if max[0] < piece.min[0]
        || min[0] > piece.max[0]
        || max[1] < piece.min[1]
        || min[1] > piece.max[1]
    {
        return;
    }
    let d = [b[0] - a[0], b[1] - a[1]];
    let mut ts = vec![0.0, 1.0];
    let n = piece.pts.len();
    for k in 0..n {
        let (p, q) = (piece.pts[k], piece.pts[(k + 1) % n]);
        let e = [q[0] - p[0], q[1] - p[1]];
        let den = d[0] * e[1] - d[1] * e[0];
        if den.abs() < 1e-12 {
            continue;
        }
        let ap = [p[0] - a[0], p[1] - a[1]];
        let t = (ap[0] * e[1] - ap[1] * e[0]) / den;
        let u = (ap[0] * d[1] - ap[1] * d[0]) / den;
        if (0.0..=1.0).contains(&t) && (-1e-9..=1.0 + 1e-9).contains(&u) {
            ts.push(t);
        }
    }
    ts.sort_by(f64::total_cmp);
    for pair in ts.windows(2) {
        let (t0, t1) = (pair[0], pair[1]);
        if t1 - t0 < 1e-9 {
            continue;
        }
        if strictly_inside(&piece.pts, lerp(a, b, (t0 + t1) / 2.0)) {
            hidden.push((t0, t1));
        }
    }
}

/// Inside the polygon (even-odd) and farther than [`INSIDE`] from its
/// boundary.
fn strictly_inside(pts: &[Pt], x: Pt) -> bool {
    let n = pts.len();
    let mut inside = false;
    for k in 0..n {
        let (p, q) = (pts[k], pts[(k + 1) % n]);
        if distance(x, p, q) <= INSIDE {
            return false;
        }
        if (p[1] > x[1]) != (q[1] > x[1]) {
            let xi = p[0] + (x[1] - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
            if xi > x[0] {
                inside = !inside;
            }
        }
    }
    inside
}

fn distance(x: Pt, p: Pt, q: Pt) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((x[0] - p[0] - d[0] * t).powi(2) + (x[1] - p[1] - d[1] * t).powi(2)).sqrt()
}

/// `[0, 1]` minus the union of `hidden`.
fn complement(mut hidden: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    hidden.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out = Vec::new();
    let mut at = 0.0;
    for (t0, t1) in hidden {
        if t0 > at {
            out.push((at, t0));
        }
        at = f64::max(at, t1);
    }
    if at < 1.0 {
        out.push((at, 1.0));
    }
    out
}

/// The segments drawn black, 1 pixel wide, on white.
pub fn rasterize(segments: &[[Pt; 2]], width: u32, height: u32, aa: bool) -> FrameBuffer {
    let mut fb = FrameBuffer::new(width, height, [1.0; 3]);
    let (w, h) = (width as i64, height as i64);
    let mut darken = |x: i64, y: i64, cov: f64| {
        if x >= 0 && y >= 0 && x < w && y < h && cov > 0.0 {
            let px = &mut fb.color[(y * w + x) as usize];
            let v = (1.0 - cov.min(1.0)) as f32;
            for c in px.iter_mut() {
                *c = c.min(v);
            }
        }
    };
    for (k, s) in segments.iter().enumerate() {
        // A stop request ends the drawing; the caller reports it.
        if k % 4096 == 0 && crate::cancel::requested() {
            break;
        }
        let (a, b) = (s[0], s[1]);
        if aa {
            let y0 = (a[1].min(b[1]) - 1.5).floor() as i64;
            let y1 = (a[1].max(b[1]) + 1.5).ceil() as i64;
            for y in y0.max(0)..=y1.min(h - 1) {
                // Only the pixels within 1 of the points of the segment
                // less than 1 away in y can be darkened.
                let yc = y as f64 + 0.5;
                let (xa, xb) = if a[1] == b[1] {
                    (a[0].min(b[0]), a[0].max(b[0]))
                } else {
                    let t = |v: f64| ((v - a[1]) / (b[1] - a[1])).clamp(0.0, 1.0);
                    let (ta, tb) = (t(yc - 1.0), t(yc + 1.0));
                    let (pa, pb) = (lerp(a, b, ta)[0], lerp(a, b, tb)[0]);
                    (pa.min(pb), pa.max(pb))
                };
                let x0 = (xa - 1.5).floor() as i64;
                let x1 = (xb + 1.5).ceil() as i64;
                for x in x0.max(0)..=x1.min(w - 1) {
                    let d = distance([x as f64 + 0.5, yc], a, b);
                    darken(x, y, 1.0 - d);
                }
            }
        } else {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let steps = dx.abs().max(dy.abs()).ceil().max(1.0) as i64;
            for k in 0..=steps {
                let p = lerp(a, b, k as f64 / steps as f64);
                darken(p[0].floor() as i64, p[1].floor() as i64, 1.0);
            }
        }
    }
    fb
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complement_of_overlapping_intervals() {
        let v = complement(vec![(0.5, 0.7), (0.1, 0.2), (0.15, 0.3)]);
        assert_eq!(v, vec![(0.0, 0.1), (0.3, 0.5), (0.7, 1.0)]);
    }

    #[test]
    fn a_square_hides_the_middle_of_a_segment() {
        let sq = Piece {
            pts: vec![[1.0, -1.0], [2.0, -1.0], [2.0, 1.0], [1.0, 1.0]],
            min: [1.0, -1.0],
            max: [2.0, 1.0],
        };
        let mut hidden = Vec::new();
        covered(&sq, [0.0, 0.0], [4.0, 0.0], &mut hidden);
        assert_eq!(hidden, vec![(0.25, 0.5)]);
        // An edge on the square's boundary is not hidden by it.
        let mut none = Vec::new();
        covered(&sq, [1.0, -1.0], [1.0, 1.0], &mut none);
        assert!(none.is_empty());
    }
}

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

/// Cells per side of the lookup grid.
const GRID: usize = 64;
/// How far inside a face a point must be to be hidden (user units).
const INSIDE: f64 = 1e-3;
/// Shortest part drawn (user units).
const SHORTEST: f64 = 0.05;

/// A level-1 piece in painting order.
struct Piece {
    pts: Vec<Pt>,
    min: Pt,
    max: Pt,
}

/// The visible edge segments of the faces seen directly.
pub fn visible_edges(input: &VectorInput) -> Vec<[Pt; 2]> {
    let (w, h) = (input.width as f64, input.height as f64);
    let mut pieces = Vec::new();
    let mut flags = Vec::new();
    for (k, r) in input.stream.records.iter().enumerate() {
        if !input.direct[k] || r.points.len() < 3 {
            continue;
        }
        let pts: Vec<Pt> = r
            .points
            .iter()
            .map(|p| [p[0] as f64 * w, (1.0 - p[1] as f64) * h])
            .collect();
        let (min, max) = bounds(&pts);
        pieces.push(Piece { pts, min, max });
        flags.push(&input.original_edges[k]);
    }
    let grid = Grid::new(&pieces, w, h);
    let mut seen = vec![usize::MAX; pieces.len()];
    let mut out = Vec::new();
    let mut stamp = 0;
    for (i, p) in pieces.iter().enumerate() {
        let m = p.pts.len();
        for e in 0..m {
            if !flags[i].get(e).copied().unwrap_or(false) {
                continue;
            }
            let (a, b) = (p.pts[e], p.pts[(e + 1) % m]);
            stamp += 1;
            let mut hidden: Vec<(f64, f64)> = Vec::new();
            grid.visit(bounds(&[a, b]), |j| {
                if j > i && seen[j] != stamp {
                    seen[j] = stamp;
                    covered(&pieces[j], a, b, &mut hidden);
                }
            });
            for (t0, t1) in complement(hidden) {
                let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
                if (t1 - t0) * len >= SHORTEST {
                    out.push([lerp(a, b, t0), lerp(a, b, t1)]);
                }
            }
        }
    }
    out
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

/// Pieces by screen cell.
struct Grid {
    cells: Vec<Vec<usize>>,
    sx: f64,
    sy: f64,
}

impl Grid {
    fn new(pieces: &[Piece], w: f64, h: f64) -> Grid {
        let mut g = Grid {
            cells: vec![Vec::new(); GRID * GRID],
            sx: GRID as f64 / w.max(1.0),
            sy: GRID as f64 / h.max(1.0),
        };
        for (k, p) in pieces.iter().enumerate() {
            let (c0, c1, r0, r1) = g.range((p.min, p.max));
            for r in r0..=r1 {
                for c in c0..=c1 {
                    g.cells[r * GRID + c].push(k);
                }
            }
        }
        g
    }

    fn range(&self, (min, max): (Pt, Pt)) -> (usize, usize, usize, usize) {
        let cell = |v: f64, s: f64| ((v * s).floor().max(0.0) as usize).min(GRID - 1);
        (
            cell(min[0], self.sx),
            cell(max[0], self.sx),
            cell(min[1], self.sy),
            cell(max[1], self.sy),
        )
    }

    fn visit(&self, b: (Pt, Pt), mut f: impl FnMut(usize)) {
        let (c0, c1, r0, r1) = self.range(b);
        for r in r0..=r1 {
            for c in c0..=c1 {
                for &k in &self.cells[r * GRID + c] {
                    f(k);
                }
            }
        }
    }
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
    for s in segments {
        let (a, b) = (s[0], s[1]);
        if aa {
            let x0 = (a[0].min(b[0]) - 1.5).floor() as i64;
            let x1 = (a[0].max(b[0]) + 1.5).ceil() as i64;
            let y0 = (a[1].min(b[1]) - 1.5).floor() as i64;
            let y1 = (a[1].max(b[1]) + 1.5).ceil() as i64;
            for y in y0.max(0)..=y1.min(h - 1) {
                for x in x0.max(0)..=x1.min(w - 1) {
                    let d = distance([x as f64 + 0.5, y as f64 + 0.5], a, b);
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

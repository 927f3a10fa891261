//! The anti-aliasing polygon tiler of 004 section 5.5, generalized to any
//! simple polygon (convex or not). Edges are kept in an active edge list
//! walked from row to row (figure 5.3's edge structures), each clipped to
//! the row strip `j <= y <= j + 1` with its fractional top and bottom
//! heights, so edges shorter than a scan line still count; the strip's
//! slice of the polygon is thus divided at every vertex (figures 5.4, 5.5).
//!
//! For each row the tiler yields
//! - runs `[i0, i1)` of pixels whose square lies wholly inside the polygon
//!   (found without any per-pixel geometry), and
//! - the partial pixels, each with (a) the exact area of polygon ∩ pixel
//!   square (method 1's segment pre-processor, done as signed trapezoid
//!   areas accumulated along the row, exact for simple polygons), (b) the
//!   `n x n` sample mask (method 2's pixel mask for `n = 4`, the centre
//!   sample for `n = 1`, Donovan's blocks otherwise) and (c) whether the
//!   pixel centre is covered.
//!
//! Samples follow the point sampler's half-open convention (see
//! `raster::tiler`): a sample line at `y` crosses the edges with
//! `y0 <= y < y1` in canonical endpoint order, and a span covers samples
//! with `xl <= x < xr`, so polygons sharing an edge own each sample once.
//!
//! Precondition: a simple polygon (no self-intersection), any orientation.
//! For a self-intersecting one the masks follow the even-odd rule while
//! the areas are signed winding sums clamped to 0..1.

use glam::DVec2;

use super::edge::Edge;
use super::mask::SampleMask;
use super::shade::Prepared;

/// A partly covered pixel of a row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Partial {
    /// Pixel column.
    pub col: u32,
    /// Exact area of the polygon inside the pixel square, 0 to 1.
    pub area: f64,
    /// The `n x n` sample mask, bit `n * row + column`, row 0 on top.
    pub mask: SampleMask,
    /// Whether the pixel centre sample is covered.
    pub centre: bool,
}

/// The tiler's results for one row.
#[derive(Debug)]
pub(crate) struct RowCover<'a> {
    /// Screen row, from the bottom.
    pub j: u32,
    /// Fully covered runs.
    pub runs: &'a [(u32, u32)],
    /// Partly covered pixels, left to right.
    pub partials: &'a [Partial],
    /// The active edges of the row (none horizontal).
    pub edges: &'a [Edge],
}

/// Coverage this close to 0 or 1 is empty or full (the running sums of
/// edge contributions are exact up to rounding).
const COVER_EPS: f64 = 1e-9;

const TOUCHED: u8 = 1;
const DIRTY: u8 = 2;

/// A reusable tiler for images `width` pixels wide with `n x n` samples.
#[derive(Debug)]
pub(crate) struct Tiler {
    width: u32,
    n: u32,
    centre: bool,
    edges: Vec<Edge>,
    /// The next of `edges` to become active.
    next: usize,
    active: Vec<Edge>,
    acc: Vec<f64>,
    flags: Vec<u8>,
    touched: Vec<u32>,
    /// The active edges' segments in the row strip: ends' x and signed
    /// height.
    segments: Vec<(f64, f64, f64)>,
    runs: Vec<(u32, u32)>,
    partials: Vec<Partial>,
    xs: Vec<f64>,
    /// Per column, the index of its partial pixel in the row being
    /// masked, or `NO_SLOT`.
    slot: Vec<u32>,
    /// Per partial pixel (and one past the last), the sub-rows of
    /// samples that edges crossing left of it toggle from it on.
    carry: Vec<SampleMask>,
    /// The same for the centre sample.
    carry_centre: Vec<bool>,
    /// `right[(n + 1) r + k]`: samples `k..n` of sub-row `r`.
    right: Vec<SampleMask>,
}

/// A column without a partial pixel in [`Tiler::slot`].
const NO_SLOT: u32 = u32::MAX;

/// Where a sample line's crossing at sample `s` toggles coverage: all
/// samples at or after `s` (the point sampler's rule; even-odd over the
/// crossings, as pairs of sorted crossings fill).
#[derive(Debug, Clone, Copy)]
enum Toggle {
    /// Every partial pixel from this index on, wholly.
    From(usize),
    /// Samples `k..` of partial pixel `i`, and every partial after it.
    Within(usize, u32),
}

impl Tiler {
    /// A tiler with `n x n` samples per pixel (`1 <= n <= 16`); with
    /// `centre` the centre sample is found even when `n` is even.
    pub fn new(width: u32, n: u32, centre: bool) -> Tiler {
        let w = width as usize + 2;
        Tiler {
            width,
            n,
            centre,
            edges: Vec::new(),
            next: 0,
            active: Vec::new(),
            acc: vec![0.0; w],
            flags: vec![0; w],
            touched: Vec::new(),
            segments: Vec::new(),
            runs: Vec::new(),
            partials: Vec::new(),
            xs: Vec::new(),
            slot: vec![NO_SLOT; width as usize + 1],
            carry: Vec::new(),
            carry_centre: Vec::new(),
            right: (0..n * (n + 1))
                .map(|rk| {
                    let (r, k) = (rk / (n + 1), rk % (n + 1));
                    let mut m = SampleMask::EMPTY;
                    m.set_range(n * r + k, n * r + n);
                    m
                })
                .collect(),
        }
    }

    /// Tiles `poly` over screen rows `rows` (from the bottom), calling
    /// `visit` for each row it touches, bottom row first: the walk of
    /// [`Self::rows`], [`Self::enter`] and [`Self::cover`] with no row
    /// passed over.
    #[cfg(test)]
    pub fn tile(
        &mut self,
        poly: &Prepared,
        rows: std::ops::Range<u32>,
        mut visit: impl FnMut(&RowCover<'_>),
    ) {
        for j in self.rows(poly, rows) {
            if self.enter(j).is_some()
                && let Some(row) = self.cover(j)
            {
                visit(&row);
            }
        }
    }

    /// Starts the walk over `poly`'s rows: the rows within `rows` (from
    /// the bottom) that it may touch, to be entered bottom row first.
    pub fn rows(&mut self, poly: &Prepared, rows: std::ops::Range<u32>) -> std::ops::Range<u32> {
        let pts = &poly.points;
        self.active.clear();
        self.next = 0;
        if pts.len() < 3 {
            self.edges.clear();
            return 0..0;
        }
        let first = (poly.ymin.floor().max(rows.start as f64)) as u32;
        let end = (poly.ymax.ceil().min(rows.end as f64)).max(first as f64) as u32;
        if first >= end {
            self.edges.clear();
            return 0..0;
        }
        self.build_edges(pts);
        first..end
    }

    /// Enters row `j`, the next of the walk: the active edges brought up
    /// to it. `None` when no edge crosses its strip, else the columns its
    /// coverage can reach, so that a row whose pixels would all stay as
    /// they are can be passed over before any coverage is found.
    pub fn enter(&mut self, j: u32) -> Option<std::ops::Range<u32>> {
        let (y0, y1) = (j as f64, j as f64 + 1.0);
        while self.next < self.edges.len() && self.edges[self.next].lo.y < y1 {
            self.active.push(self.edges[self.next]);
            self.next += 1;
        }
        self.active.retain(|e| e.hi.y > y0);
        if self.active.is_empty() {
            return None;
        }
        Some(self.segments(j))
    }

    /// The coverage of row `j`, the row entered last; `None` when it
    /// covers nothing.
    pub fn cover(&mut self, j: u32) -> Option<RowCover<'_>> {
        self.areas();
        if !self.partials.is_empty() {
            self.masks(j);
        }
        (!self.runs.is_empty() || !self.partials.is_empty()).then_some(RowCover {
            j,
            runs: &self.runs,
            partials: &self.partials,
            edges: &self.active,
        })
    }

    /// Non-horizontal edges, sorted by their lower end, oriented so that
    /// the polygon's inside accumulates to +1.
    fn build_edges(&mut self, pts: &[DVec2]) {
        let n = pts.len();
        let twice_area: f64 = (0..n).map(|k| pts[k].perp_dot(pts[(k + 1) % n])).sum();
        let orient = if twice_area < 0.0 { 1.0 } else { -1.0 };
        self.edges.clear();
        for k in 0..n {
            let (ka, kb) = (k as u32, ((k + 1) % n) as u32);
            let (a, b) = (pts[ka as usize], pts[kb as usize]);
            if a.y == b.y {
                continue;
            }
            let up = (a.y, a.x) <= (b.y, b.x);
            let (lo, hi, lo_vertex, hi_vertex) = if up { (a, b, ka, kb) } else { (b, a, kb, ka) };
            let dir = if up { orient } else { -orient };
            self.edges.push(Edge {
                lo,
                hi,
                dir,
                lo_vertex,
                hi_vertex,
                slope: (hi.x - lo.x) / (hi.y - lo.y),
            });
        }
        self.edges.sort_by(|a, b| a.lo.y.total_cmp(&b.lo.y));
    }

    /// The active edges' segments in the strip of row `j`, and the
    /// columns their coverage can reach: from the leftmost end's to the
    /// one right of the rightmost end's, within the image.
    fn segments(&mut self, j: u32) -> std::ops::Range<u32> {
        let (y0, y1) = (j as f64, j as f64 + 1.0);
        self.segments.clear();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for e in &self.active {
            let (ya, yb) = (e.lo.y.max(y0), e.hi.y.min(y1));
            if yb > ya {
                let xa = e.x_at(ya);
                let xb = if yb == e.hi.y { e.hi.x } else { e.x_at(yb) };
                self.segments.push((xa, xb, (yb - ya) * e.dir));
                lo = lo.min(xa.min(xb));
                hi = hi.max(xa.max(xb));
            }
        }
        let w = self.width as f64;
        if self.segments.is_empty() {
            return 0..0;
        }
        if lo.is_nan() || hi.is_nan() {
            return 0..self.width;
        }
        let first = lo.clamp(0.0, w) as u32;
        let end = (ceil_index(hi.clamp(0.0, w)) as u32 + 1).min(self.width);
        first..end.max(first)
    }

    /// Whether row `j`, the row entered last, covers some of a pixel:
    /// area, a sample or the centre. Found from the areas alone unless
    /// only slivers of no area are partly covered.
    pub fn covers(&mut self, j: u32) -> bool {
        self.areas();
        if !self.runs.is_empty() || self.partials.iter().any(|p| p.area > 0.0) {
            return true;
        }
        if self.partials.is_empty() {
            return false;
        }
        self.masks(j);
        self.partials.iter().any(|p| !p.mask.is_empty() || p.centre)
    }

    /// The runs and partial pixels, with their areas, of the row whose
    /// [`Self::segments`] were found last.
    fn areas(&mut self) {
        for k in 0..self.segments.len() {
            let (xa, xb, d) = self.segments[k];
            self.clip_x(xa, xb, d);
        }
        self.sweep();
    }

    /// Splits a strip segment from `x0` to `x1` (signed height `d`) at the
    /// image's sides; parts outside become vertical at the side.
    fn clip_x(&mut self, x0: f64, x1: f64, d: f64) {
        let w = self.width as f64;
        if (0.0..=w).contains(&x0) && (0.0..=w).contains(&x1) {
            // No cut: the general path's one part, the same arithmetic.
            let xb = x0 + (x1 - x0);
            self.accumulate(x0, xb.clamp(0.0, w), d, true);
            return;
        }
        let mut cuts = [0.0; 4];
        let mut m = 1;
        for side in [0.0, w] {
            if (x0 - side) * (x1 - side) < 0.0 {
                cuts[m] = (side - x0) / (x1 - x0);
                m += 1;
            }
        }
        cuts[1..m].sort_by(f64::total_cmp);
        cuts[m] = 1.0;
        for k in 0..m {
            let (ta, tb) = (cuts[k], cuts[k + 1]);
            if tb <= ta {
                continue;
            }
            let (xa, xb) = (x0 + ta * (x1 - x0), x0 + tb * (x1 - x0));
            let mid = 0.5 * (xa + xb);
            let inside = (0.0..=w).contains(&mid);
            self.accumulate(xa.clamp(0.0, w), xb.clamp(0.0, w), d * (tb - ta), inside);
        }
    }

    fn add(&mut self, c: usize, v: f64) {
        if self.flags[c] & TOUCHED == 0 {
            self.flags[c] |= TOUCHED;
            self.touched.push(c as u32);
        }
        self.acc[c] += v;
    }

    /// Adds the signed area right of a segment inside the strip to the
    /// columns it crosses (a running sum then gives the coverage).
    fn accumulate(&mut self, x0: f64, x1: f64, d: f64, dirty: bool) {
        let (xl, xr) = if x0 < x1 { (x0, x1) } else { (x1, x0) };
        // `xl`, `xr` are clamped to the image (0..=width): truncation is
        // `floor` there.
        let c0 = xl as u32 as usize;
        let c1 = ceil_index(xr).max(c0 + 1);
        if c1 == c0 + 1 {
            let xmf = 0.5 * (x0 + x1) - c0 as f64;
            self.add(c0, d * (1.0 - xmf));
            self.add(c0 + 1, d * xmf);
        } else {
            let s = 1.0 / (xr - xl);
            let x0f = xl - c0 as f64;
            let a0 = 0.5 * s * (1.0 - x0f) * (1.0 - x0f);
            let x1f = xr - c1 as f64 + 1.0;
            let am = 0.5 * s * x1f * x1f;
            self.add(c0, d * a0);
            if c1 == c0 + 2 {
                self.add(c0 + 1, d * (1.0 - a0 - am));
            } else {
                let a1 = s * (1.5 - x0f);
                self.add(c0 + 1, d * (a1 - a0));
                for c in c0 + 2..c1 - 1 {
                    self.add(c, d * s);
                }
                let a2 = a1 + (c1 - c0 - 3) as f64 * s;
                self.add(c1 - 1, d * (1.0 - a2 - am));
            }
            self.add(c1, d * am);
        }
        if dirty {
            let w = self.width as usize;
            for c in c0.min(w)..c1.min(w) {
                self.flags[c] |= DIRTY;
            }
        }
    }

    /// Running sums over the touched columns: partial pixels where an
    /// edge passes, constant runs in between.
    fn sweep(&mut self) {
        self.touched.sort_unstable();
        self.runs.clear();
        self.partials.clear();
        let w = self.width;
        let mut sum = 0.0;
        for k in 0..self.touched.len() {
            let c = self.touched[k];
            let cu = c as usize;
            sum += self.acc[cu];
            let dirty = self.flags[cu] & DIRTY != 0;
            self.acc[cu] = 0.0;
            self.flags[cu] = 0;
            if c >= w {
                continue;
            }
            let start = if dirty {
                self.partials.push(Partial {
                    col: c,
                    area: sum.clamp(0.0, 1.0),
                    mask: SampleMask::EMPTY,
                    centre: false,
                });
                c + 1
            } else {
                c
            };
            let end = self.touched.get(k + 1).map_or(w, |&n| n.min(w));
            if start >= end || sum <= COVER_EPS {
                continue;
            }
            if sum >= 1.0 - COVER_EPS {
                match self.runs.last_mut() {
                    Some(r) if r.1 == start => r.1 = end,
                    _ => self.runs.push((start, end)),
                }
            } else {
                // No edge passes through these pixels, yet they are only
                // partly covered: a horizontal edge crosses the row strip.
                self.partials.extend((start..end).map(|col| Partial {
                    col,
                    area: sum,
                    mask: SampleMask::EMPTY,
                    centre: false,
                }));
            }
        }
        self.touched.clear();
    }

    /// Sample masks (and centre samples) of the partial pixels of row `j`,
    /// edge by edge (the A-buffer's way): each crossing of a sample line
    /// toggles the samples at and right of it, within its pixel from a
    /// table of sub-row masks and in every later partial pixel through a
    /// running carry, so a row costs a few operations per crossing and
    /// one per partial pixel, with no sort and no search per sample line.
    /// The same samples as filling between pairs of sorted crossings
    /// ([`Self::sample_masks`], which a row with a crossing that is not a
    /// number, or an odd count of them, falls back to).
    fn masks(&mut self, j: u32) {
        if !self.edge_masks(j) {
            for p in &mut self.partials {
                p.mask = SampleMask::EMPTY;
                p.centre = false;
            }
            self.sample_masks(j);
        }
    }

    /// [`Self::masks`] by toggles; `false` (masks half made) when the row
    /// must be masked line by line instead.
    fn edge_masks(&mut self, j: u32) -> bool {
        let n = self.n;
        let count = self.partials.len();
        for (k, p) in self.partials.iter().enumerate() {
            self.slot[p.col as usize] = k as u32;
        }
        self.carry.clear();
        self.carry.resize(count + 1, SampleMask::EMPTY);
        let mut ok = true;
        for r in 0..n {
            let y = j as f64 + 1.0 - (r as f64 + 0.5) / n as f64;
            ok = self.toggle_line(y, n, |t, toggle| {
                let row = &t.right[((n + 1) * r) as usize..];
                match toggle {
                    Toggle::From(i) => t.carry[i] = t.carry[i].xor(row[0]),
                    Toggle::Within(i, k) => {
                        let p = &mut t.partials[i];
                        p.mask = p.mask.xor(row[k as usize]);
                        t.carry[i + 1] = t.carry[i + 1].xor(row[0]);
                    }
                }
            });
            if !ok {
                break;
            }
        }
        if ok && n != 1 && self.centre {
            self.carry_centre.clear();
            self.carry_centre.resize(count + 1, false);
            ok = self.toggle_line(j as f64 + 0.5, 1, |t, toggle| match toggle {
                Toggle::From(i) => t.carry_centre[i] ^= true,
                // One sample per pixel: a crossing is never within one.
                Toggle::Within(i, _) => t.carry_centre[i + 1] ^= true,
            });
        }
        for p in &self.partials {
            self.slot[p.col as usize] = NO_SLOT;
        }
        if !ok {
            return false;
        }
        let (mut carry, mut centre) = (SampleMask::EMPTY, false);
        for (k, p) in self.partials.iter_mut().enumerate() {
            carry = carry.xor(self.carry[k]);
            p.mask = p.mask.xor(carry);
            if n == 1 {
                p.centre = !p.mask.is_empty();
            } else if self.centre {
                centre ^= self.carry_centre[k];
                p.centre = centre;
            }
        }
        true
    }

    /// Calls `apply` with where each crossing of the sample line `y`
    /// (`m` samples per pixel) toggles; `false` for a crossing that is
    /// not a number or an odd count of crossings.
    fn toggle_line(&mut self, y: f64, m: u32, mut apply: impl FnMut(&mut Self, Toggle)) -> bool {
        let total = (self.width * m) as f64;
        let mut crossings = 0usize;
        for e in 0..self.active.len() {
            let Some(x) = self.active[e].cross(y) else {
                continue;
            };
            if x.is_nan() {
                return false;
            }
            crossings += 1;
            let s = sample_at_or_after(x * m as f64 - 0.5, total);
            if let Some(t) = self.locate(s, m) {
                apply(self, t);
            }
        }
        crossings.is_multiple_of(2)
    }

    /// Where toggling the samples from sample `s` on (`m` per pixel) acts
    /// on the partial pixels; `None` when on none.
    #[inline]
    fn locate(&self, s: u32, m: u32) -> Option<Toggle> {
        let (c, k) = if m.is_power_of_two() {
            (s >> m.trailing_zeros(), s & (m - 1))
        } else {
            (s / m, s % m)
        };
        if c >= self.width {
            return None;
        }
        let slot = self.slot[c as usize];
        if slot != NO_SLOT {
            let i = slot as usize;
            return Some(if k == 0 {
                Toggle::From(i)
            } else {
                Toggle::Within(i, k)
            });
        }
        // The column is no partial pixel (a run or empty): every partial
        // right of it.
        Some(Toggle::From(self.partials.partition_point(|p| p.col < c)))
    }

    /// Sample masks (and centre samples) of the partial pixels of row `j`,
    /// sample line by sample line: the crossings sorted, samples filled
    /// between pairs.
    fn sample_masks(&mut self, j: u32) {
        let n = self.n;
        for r in 0..n {
            let y = j as f64 + 1.0 - (r as f64 + 0.5) / n as f64;
            self.sample_line(y, n, |p, lo, hi| p.mask.set_range(n * r + lo, n * r + hi));
        }
        if n == 1 {
            for p in &mut self.partials {
                p.centre = !p.mask.is_empty();
            }
        } else if self.centre {
            self.sample_line(j as f64 + 0.5, 1, |p, _, _| p.centre = true);
        }
    }

    /// Crossings of the sample line `y` with `m` samples per pixel: calls
    /// `set(partial, lo, hi)` with the covered sample columns of each
    /// partial pixel.
    fn sample_line(&mut self, y: f64, m: u32, mut set: impl FnMut(&mut Partial, u32, u32)) {
        self.xs.clear();
        self.xs
            .extend(self.active.iter().filter_map(|e| e.cross(y)));
        self.xs.sort_by(f64::total_cmp);
        let total = (self.width * m) as f64;
        for pair in self.xs.chunks_exact(2) {
            let s0 = sample_at_or_after(pair[0] * m as f64 - 0.5, total);
            let s1 = sample_at_or_after(pair[1] * m as f64 - 0.5, total);
            if s1 <= s0 {
                continue;
            }
            let (p0, p1) = if m.is_power_of_two() {
                let shift = m.trailing_zeros();
                (s0 >> shift, (s1 - 1) >> shift)
            } else {
                (s0 / m, (s1 - 1) / m)
            };
            let from = self.partials.partition_point(|p| p.col < p0);
            for p in self.partials[from..].iter_mut().take_while(|p| p.col <= p1) {
                let base = p.col * m;
                set(p, s0.max(base) - base, s1.min(base + m) - base);
            }
        }
    }
}

/// `x.ceil() as usize` for `0 <= x < 2^32` (a column or sample index).
/// The row loops round several times per edge and pixel: `f64::ceil` is a
/// call into libm on the baseline x86-64 target (no SSE4.1 rounding), and
/// conversions between `f64` and 64-bit unsigned integers take a dozen
/// instructions there, where `u32` takes one or two.
#[inline]
fn ceil_index(x: f64) -> usize {
    let t = x as u32;
    (if f64::from(t) < x { t + 1 } else { t }) as usize
}

/// `x.ceil().clamp(0.0, total) as u32` without libm: the first sample at
/// or after sample coordinate `x`, within `0..=total` (`NaN` gives 0).
#[inline]
fn sample_at_or_after(x: f64, total: f64) -> u32 {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    if x >= total {
        return total as u32;
    }
    ceil_index(x) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::scan::shade::Shading;
    use proptest::prelude::*;

    /// The rounding without libm equals `ceil` and `clamp`, at integers,
    /// halves, signed zeros, tiny steps either side, the ends and NaN.
    #[test]
    fn rounding_equals_ceil() {
        let total = 2048.0;
        let mut xs = vec![
            f64::NAN,
            -0.0,
            0.0,
            -1.5,
            -1e-300,
            1e-300,
            total,
            total + 0.5,
            1e30,
        ];
        for k in 0..=64 {
            let x = k as f64 * 0.5;
            xs.extend([x, x.next_up(), x.next_down()]);
        }
        for x in xs {
            let want = x.ceil().clamp(0.0, total) as u32;
            assert_eq!(sample_at_or_after(x, total), want, "x = {x:e}");
            if x >= 0.0 && x <= total {
                assert_eq!(ceil_index(x), x.ceil() as usize, "x = {x:e}");
            }
        }
    }

    fn poly(points: Vec<DVec2>) -> Prepared {
        let (ymin, ymax) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.y), hi.max(p.y))
            });
        Prepared {
            points,
            shading: Shading::Special,
            level: 1,
            ymin,
            ymax,
        }
    }

    /// Per-pixel areas of `p` on a `w x h` image, row-major from the bottom.
    fn areas(p: &Prepared, w: u32, h: u32) -> Vec<f64> {
        let mut a = vec![0.0; (w * h) as usize];
        let mut t = Tiler::new(w, 4, true);
        t.tile(p, 0..h, |row| {
            let base = (row.j * w) as usize;
            for &(i0, i1) in row.runs {
                for i in i0..i1 {
                    a[base + i as usize] += 1.0;
                }
            }
            for q in row.partials {
                a[base + q.col as usize] += q.area;
            }
        });
        a
    }

    fn shoelace(p: &[DVec2]) -> f64 {
        let n = p.len();
        0.5 * (0..n)
            .map(|k| p[k].perp_dot(p[(k + 1) % n]))
            .sum::<f64>()
            .abs()
    }

    /// A polygon star-shaped around `c` (so simple): vertex `k` at angle
    /// `(k + jitter_k) 2 pi / n`, jitters in 0..0.9 so that every angular
    /// gap is below pi; equal radii make it convex.
    pub(crate) fn star(c: (f64, f64), jitter: &[f64], radii: &[f64]) -> Vec<DVec2> {
        let n = jitter.len() as f64;
        jitter
            .iter()
            .zip(radii.iter().cycle())
            .enumerate()
            .map(|(k, (j, r))| {
                let t = (k as f64 + j) * std::f64::consts::TAU / n;
                DVec2::new(c.0 + r * t.cos(), c.1 + r * t.sin())
            })
            .collect()
    }

    proptest! {
        #[test]
        fn areas_sum_to_the_polygon_area(
            cx in 8.0f64..24.0, cy in 8.0f64..24.0,
            jitter in prop::collection::vec(0.0f64..0.9, 4..12),
            radii in prop::collection::vec(0.05f64..7.5, 1..12),
            convex in any::<bool>(),
        ) {
            let radii = if convex { vec![radii[0]] } else { radii };
            let pts = star((cx, cy), &jitter, &radii);
            let exact = shoelace(&pts);
            let total: f64 = areas(&poly(pts), 32, 32).iter().sum();
            prop_assert!((total - exact).abs() <= 1e-9 * exact.max(1e-3), "{total} {exact}");
        }
    }

    proptest! {
        /// Every pixel a row's coverage reaches lies in the columns the
        /// row is entered with (the scan converter skips a row by them),
        /// and `covers` tells whether the coverage has area, a sample or a
        /// centre. Polygons reach past the image's sides, and with `snap`
        /// their corners lie on half pixels.
        #[test]
        fn rows_reach_only_the_columns_they_are_entered_with(
            cx in -6.0f64..38.0, cy in 4.0f64..28.0,
            jitter in prop::collection::vec(0.0f64..0.9, 3..12),
            radii in prop::collection::vec(0.05f64..12.0, 1..12),
            snap in any::<bool>(),
        ) {
            let mut pts = star((cx, cy), &jitter, &radii);
            if snap {
                pts.iter_mut().for_each(|p| *p = (*p * 2.0).round() / 2.0);
            }
            let p = poly(pts);
            let (mut t, mut u) = (Tiler::new(32, 4, true), Tiler::new(32, 4, true));
            let walk = t.rows(&p, 0..32);
            prop_assert_eq!(walk.clone(), u.rows(&p, 0..32));
            for j in walk {
                let (a, b) = (t.enter(j), u.enter(j));
                prop_assert_eq!(&a, &b);
                let Some(columns) = a else { continue };
                let covers = u.covers(j);
                let Some(row) = t.cover(j) else {
                    prop_assert!(!covers);
                    continue;
                };
                for &(i0, i1) in row.runs {
                    prop_assert!(columns.start <= i0 && i1 <= columns.end, "{i0}..{i1} {columns:?}");
                }
                for q in row.partials {
                    prop_assert!(columns.contains(&q.col), "{} {columns:?}", q.col);
                }
                let some = !row.runs.is_empty()
                    || row.partials.iter().any(|q| q.area > 0.0 || !q.mask.is_empty() || q.centre);
                prop_assert_eq!(covers, some);
            }
        }
    }

    /// The masks of row `j`, just covered, found line by line instead.
    fn masks_by_lines(t: &mut Tiler, j: u32) -> Vec<(u32, SampleMask, bool)> {
        let kept = t.partials.clone();
        for p in &mut t.partials {
            p.mask = SampleMask::EMPTY;
            p.centre = false;
        }
        t.sample_masks(j);
        let got = t
            .partials
            .iter()
            .map(|p| (p.col, p.mask, p.centre))
            .collect();
        t.partials = kept;
        got
    }

    proptest! {
        /// Masks by edge toggles equal masks by filling between sorted
        /// crossings, sample line by sample line: any grid side, with and
        /// without the centre, polygons convex or not, past the image's
        /// sides, with corners on sample positions (1/8 pixel for 4 x 4)
        /// when `snap`.
        #[test]
        fn edge_masks_equal_sample_line_masks(
            cx in -6.0f64..22.0, cy in 2.0f64..14.0,
            jitter in prop::collection::vec(0.0f64..0.9, 3..12),
            radii in prop::collection::vec(0.05f64..9.0, 1..12),
            n in prop::sample::select(vec![1u32, 2, 3, 4, 5, 8, 16]),
            centre in any::<bool>(),
            snap in any::<bool>(),
        ) {
            let mut pts = star((cx, cy), &jitter, &radii);
            if snap {
                let g = 2.0 * n as f64;
                pts.iter_mut().for_each(|p| *p = (*p * g).round() / g);
            }
            let p = poly(pts);
            let mut t = Tiler::new(16, n, centre);
            for j in t.rows(&p, 0..16) {
                if t.enter(j).is_none() {
                    continue;
                }
                let want = {
                    let Some(_) = t.cover(j) else { continue };
                    masks_by_lines(&mut t, j)
                };
                let got: Vec<_> = t.partials.iter().map(|q| (q.col, q.mask, q.centre)).collect();
                prop_assert_eq!(got, want, "row {}", j);
            }
        }
    }

    #[test]
    fn clipped_to_the_image_and_exact_on_pixel_edges() {
        // A square sticking out on all sides covers the image exactly once.
        let big = [(-3.5, -2.25), (-3.5, 9.5), (11.0, 9.5), (11.0, -2.25)];
        let a = areas(&poly(big.map(|(x, y)| DVec2::new(x, y)).to_vec()), 5, 4);
        assert!(a.iter().all(|&v| (v - 1.0).abs() < 1e-12), "{a:?}");
        // Pixel-aligned square: exactly its four pixels, full.
        let sq = [(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)];
        let a = areas(&poly(sq.map(|(x, y)| DVec2::new(x, y)).to_vec()), 4, 4);
        let full: Vec<usize> = (0..16).filter(|&k| a[k] == 1.0).collect();
        assert_eq!(full, vec![5, 6, 9, 10]);
        assert_eq!(a.iter().sum::<f64>(), 4.0);
    }

    #[test]
    fn thin_slivers_count() {
        // A triangle much thinner than a scan line and narrower than a pixel.
        let t = [(2.1, 3.3), (2.9, 3.35), (2.2, 3.31)].map(|(x, y)| DVec2::new(x, y));
        let exact = shoelace(&t);
        let a = areas(&poly(t.to_vec()), 6, 6);
        assert!((a[3 * 6 + 2] - exact).abs() < 1e-15, "{}", a[3 * 6 + 2]);
    }

    #[test]
    fn a_mesh_tiles_every_pixel_exactly_once() {
        let (w, h, g) = (17u32, 13u32, 5usize);
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let v: Vec<Vec<DVec2>> = (0..=g)
            .map(|r| {
                (0..=g)
                    .map(|c| {
                        let inner = |k: usize| k > 0 && k < g;
                        let (dx, dy) = if inner(r) && inner(c) {
                            (rnd() - 0.5, rnd() - 0.5)
                        } else {
                            (0.0, 0.0)
                        };
                        DVec2::new(
                            (c as f64 + 0.7 * dx) * w as f64 / g as f64,
                            (r as f64 + 0.7 * dy) * h as f64 / g as f64,
                        )
                    })
                    .collect()
            })
            .collect();
        let mut sum = vec![0.0; (w * h) as usize];
        for r in 0..g {
            for c in 0..g {
                let (a, b, cc, d) = (v[r][c], v[r][c + 1], v[r + 1][c + 1], v[r + 1][c]);
                for tri in [vec![a, b, cc], vec![a, cc, d]] {
                    for (s, x) in sum.iter_mut().zip(areas(&poly(tri), w, h)) {
                        *s += x;
                    }
                }
            }
        }
        assert!(sum.iter().all(|&s| (s - 1.0).abs() < 1e-9), "{sum:?}");
    }
}

//! Hidden fragments of a priority order. A list-priority renderer paints
//! (or, front to back, masks) its polygons in order, so a polygon none of
//! whose samples escapes the opaque polygons later in the painting order
//! leaves no trace in an image made from those samples: not its colour,
//! not its shadows (004 section 4.7), not its reflections. The tree
//! builder drops such polygons before it casts their shadows or traces
//! their branches: the sort's order already holds what a visible-surface
//! test would find.
//!
//! [`CoverMask`] is one bit per sample of the `n x n` grid the sampling
//! scan converters use (the pixel mask of 004 section 5.7 for `n = 4`,
//! the centre for `n = 1`, Donovan's supersampling otherwise): sample
//! `(X, Y)` at `((X + 1/2) / n, (Y + 1/2) / n)`, rows from the bottom. Both
//! questions are conservative: a sample is covered only when it is inside
//! a convex polygon by a margin, and a polygon is hidden only when every
//! sample within that margin of it is covered. The exact-area methods
//! (004 sections 5.6 and 5.8) see slivers between samples, so they get no
//! mask.
//!
//! Both questions look at each row of samples alone, so [`hidden`] asks
//! them of bands of rows on all threads: a polygon is hidden when it is
//! hidden in every band, which is what one mask of the whole image finds.

use glam::DVec2;
use rayon::prelude::*;

/// Screen distance (pixels) by which covering shrinks and touching
/// grows: far above the rounding of the record stream's coordinates.
const MARGIN: f64 = 1e-4;

/// Which samples of a `width x height` image with `n x n` samples per
/// pixel are covered.
#[derive(Debug, Clone)]
pub struct CoverMask {
    n: f64,
    columns: u32,
    /// The sample rows held: a band of the image's rows.
    rows: std::ops::Range<u32>,
    words: usize,
    bits: Vec<u64>,
}

/// The largest mask made ([`CoverMask::bytes`]): 16384 x 16384 pixels
/// with 4 x 4 samples would take 512 MiB, more than the whole render.
pub const MAX_BYTES: u64 = 64 << 20;

impl CoverMask {
    /// The bytes of a mask for `width x height` pixels of `n x n`
    /// samples.
    pub fn bytes(width: u32, height: u32, n: u32) -> u64 {
        Self::words(width, n) * 8 * u64::from(height) * u64::from(n)
    }

    /// The 64-bit words of a row of samples.
    fn words(width: u32, n: u32) -> u64 {
        (u64::from(width) * u64::from(n)).div_ceil(64)
    }

    /// An image with nothing covered (of at most [`Self::bytes`], which
    /// the caller has checked).
    pub fn new(width: u32, height: u32, n: u32) -> CoverMask {
        Self::band(width, n, 0..height * n)
    }

    /// The sample rows `rows` of an image `width` pixels wide with
    /// nothing covered: what lies outside them is neither covered nor
    /// asked about.
    fn band(width: u32, n: u32, rows: std::ops::Range<u32>) -> CoverMask {
        let words = Self::words(width, n) as usize;
        CoverMask {
            n: n as f64,
            columns: width * n,
            bits: vec![0; words * rows.len()],
            rows,
            words,
        }
    }

    /// Marks the samples inside `pts` (screen coordinates in pixels, y
    /// up). Only convex polygons cover; any other marks nothing.
    pub fn cover(&mut self, pts: &[DVec2]) {
        if can_cover(pts) {
            self.fill(pts);
        }
    }

    /// Marks the samples inside `pts`, a polygon that [`can_cover`].
    fn fill(&mut self, pts: &[DVec2]) {
        for row in self.sample_rows(pts, -MARGIN) {
            let y = self.at(row);
            if let Some((xl, xr)) = crossing(pts, y)
                && let Some((c0, c1)) = self.sample_columns(xl + MARGIN, xr - MARGIN)
            {
                let line = self.line(row);
                crate::math::for_bit_words(c0, c1, |w, m| line[w] |= m);
            }
        }
    }

    /// The bits of sample row `row`.
    fn line(&mut self, row: u32) -> &mut [u64] {
        let at = (row - self.rows.start) as usize * self.words;
        &mut self.bits[at..][..self.words]
    }

    /// Whether every sample within the margin of `pts` (any simple
    /// polygon) is covered. Samples outside the image do not count.
    pub fn hides(&self, pts: &[DVec2]) -> bool {
        if pts.len() < 3 || pts.iter().any(|p| !p.is_finite()) {
            return false;
        }
        self.sample_rows(pts, MARGIN).all(|row| {
            let y = self.at(row);
            let (xl, xr) = x_extent(pts, y - MARGIN, y + MARGIN);
            let Some((c0, c1)) = self.sample_columns(xl - MARGIN, xr + MARGIN) else {
                return true;
            };
            let at = (row - self.rows.start) as usize * self.words;
            let line = &self.bits[at..][..self.words];
            let mut all = true;
            crate::math::for_bit_words(c0, c1, |w, m| all &= line[w] & m == m);
            all
        })
    }

    /// Coordinate of sample row or column `k`.
    fn at(&self, k: u32) -> f64 {
        (k as f64 + 0.5) / self.n
    }

    /// The sample rows whose line lies within `pts`'s y range widened by
    /// `margin`.
    fn sample_rows(&self, pts: &[DVec2], margin: f64) -> std::ops::Range<u32> {
        rows_near(self.n, pts, margin, self.rows.clone())
    }

    /// The sample columns `[c0, c1)` at `xl <= x <= xr`, in the image.
    fn sample_columns(&self, xl: f64, xr: f64) -> Option<(u32, u32)> {
        self.sample_columns_in(xl, xr, self.columns)
    }

    /// The samples `[k0, k1)` of `0..count` whose coordinate is in
    /// `lo..=hi`.
    fn sample_columns_in(&self, lo: f64, hi: f64, count: u32) -> Option<(u32, u32)> {
        samples_in(self.n, lo, hi, count)
    }
}

/// The samples `[k0, k1)` of `0..count`, `n` a pixel, whose coordinate
/// is in `lo..=hi`.
fn samples_in(n: f64, lo: f64, hi: f64, count: u32) -> Option<(u32, u32)> {
    let k0 = (lo * n - 0.5).ceil().max(0.0);
    let k1 = ((hi * n - 0.5).floor() + 1.0).min(count as f64);
    (k1 > k0).then_some((k0 as u32, k1 as u32))
}

/// The sample rows of `rows` (`n` a pixel) whose line lies within
/// `pts`'s y range widened by `margin`.
fn rows_near(
    n: f64,
    pts: &[DVec2],
    margin: f64,
    rows: std::ops::Range<u32>,
) -> std::ops::Range<u32> {
    let (ymin, ymax) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.y), b.max(p.y))
        });
    match samples_in(n, ymin - margin, ymax + margin, rows.end) {
        Some((r0, r1)) => r0.max(rows.start)..r1,
        None => 0..0,
    }
}

/// A polygon on the screen, in painting order: its points (pixels, y
/// up), and whether it hides what is behind it (opaque).
#[derive(Debug, Clone)]
pub struct Outline {
    /// The corners, in pixels (y up).
    pub points: Vec<DVec2>,
    /// Whether it hides what is behind it.
    pub opaque: bool,
}

/// Which of `outlines` (back to front) are hidden at every sample of a
/// `width x height` image with `n x n` samples per pixel (a mask within
/// [`MAX_BYTES`], which the caller has checked) by the opaque convex
/// ones later in the order; a hidden polygon hides nothing more.
pub fn hidden(width: u32, height: u32, n: u32, outlines: &[Outline]) -> Vec<bool> {
    let rows = height * n;
    // The rows each outline is asked about (any it covers are among
    // them; every band asks one that is never hidden), and whether it
    // covers.
    let asked: Vec<(Option<std::ops::Range<u32>>, bool)> = outlines
        .par_iter()
        .map(|o| {
            let kept = o.points.len() < 3 || o.points.iter().any(|p| !p.is_finite());
            let near = (!kept).then(|| rows_near(n as f64, &o.points, MARGIN, 0..rows));
            (near, o.opaque && can_cover(&o.points))
        })
        .collect();
    // Only the rows some outline is asked about (a mirror's level lies in
    // a small part of the picture), in many bands a thread: the polygons
    // crowd some rows more than others.
    let span = asked
        .iter()
        .filter_map(|(near, _)| near.clone().filter(|r| !r.is_empty()))
        .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end))
        .unwrap_or(0..0);
    let (first, len) = (span.start, span.len() as u32);
    let count = (rayon::current_num_threads() as u32 * 16).clamp(1, len.max(1));
    let bands: Vec<std::ops::Range<u32>> = (0..count)
        .map(|b| first + len * b / count..first + len * (b + 1) / count)
        .collect();
    let seen = |band: &std::ops::Range<u32>| {
        let mut mask = CoverMask::band(width, n, band.clone());
        let mut seen = vec![false; outlines.len()];
        for (k, o) in outlines.iter().enumerate().rev() {
            let (near, covers) = &asked[k];
            if let Some(r) = near
                && (r.end <= band.start || r.start >= band.end)
            {
                continue;
            }
            if !mask.hides(&o.points) {
                seen[k] = true;
                if *covers {
                    mask.fill(&o.points);
                }
            }
        }
        seen
    };
    // A band a task: the bands of the crowded rows take longest, and an
    // idle thread can then take any band left, not only half of a run.
    let seen = bands.par_iter().with_max_len(1).map(seen).reduce(
        || vec![false; outlines.len()],
        |mut a, b| {
            a.iter_mut().zip(b).for_each(|(a, b)| *a |= b);
            a
        },
    );
    seen.into_iter().map(|s| !s).collect()
}

/// Whether `pts` may cover samples: a convex polygon.
fn can_cover(pts: &[DVec2]) -> bool {
    pts.len() >= 3 && is_convex(pts)
}

/// The x interval where the horizontal line `y` crosses a convex polygon,
/// `None` when it misses it.
fn crossing(pts: &[DVec2], y: f64) -> Option<(f64, f64)> {
    let mut span: Option<(f64, f64)> = None;
    let mut take = |x: f64| {
        span = Some(span.map_or((x, x), |(a, b)| (a.min(x), b.max(x))));
    };
    for (k, &a) in pts.iter().enumerate() {
        let b = pts[(k + 1) % pts.len()];
        if a.y == y {
            take(a.x);
        }
        if (a.y < y) != (b.y < y) && a.y != y && b.y != y {
            take(a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y));
        }
    }
    span
}

/// The x extent of the part of polygon `pts` between lines `y0 < y1`,
/// for any simple polygon: its vertices in the strip and its edges'
/// crossings of the two lines.
fn x_extent(pts: &[DVec2], y0: f64, y1: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut take = |x: f64| {
        lo = lo.min(x);
        hi = hi.max(x);
    };
    for (k, &a) in pts.iter().enumerate() {
        let b = pts[(k + 1) % pts.len()];
        if (y0..=y1).contains(&a.y) {
            take(a.x);
        }
        for y in [y0, y1] {
            if (a.y < y) != (b.y < y) {
                take(a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y));
            }
        }
    }
    (lo, hi)
}

/// Whether `pts` is a convex polygon (either orientation; collinear
/// points allowed) that turns around once.
fn is_convex(pts: &[DVec2]) -> bool {
    let n = pts.len();
    let (mut pos, mut neg) = (false, false);
    let mut turned = 0.0;
    for k in 0..n {
        let (a, b, c) = (pts[k], pts[(k + 1) % n], pts[(k + 2) % n]);
        let cross = (b - a).perp_dot(c - b);
        pos |= cross > 0.0;
        neg |= cross < 0.0;
        let (u, v) = (b - a, c - b);
        turned += u.perp_dot(v).atan2(u.dot(v));
    }
    !(pos && neg) && (turned.abs() - std::f64::consts::TAU).abs() < 1e-6
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<DVec2> {
        vec![
            DVec2::new(x0, y0),
            DVec2::new(x1, y0),
            DVec2::new(x1, y1),
            DVec2::new(x0, y1),
        ]
    }

    /// Two triangles sharing a diagonal cover what neither covers alone:
    /// the samples near the seam are inside one or the other. A seam
    /// through samples leaves them uncovered (within the margin of both).
    #[test]
    fn a_seam_between_two_covering_polygons_hides() {
        let behind = square(3.0, 3.0, 13.0, 13.0);
        for (top, hidden) in [(14.3, true), (15.0, false)] {
            let mut mask = CoverMask::new(16, 16, 4);
            let (a, b, c, d) = (
                DVec2::new(1.0, 1.0),
                DVec2::new(15.0, 1.0),
                DVec2::new(15.0, top),
                DVec2::new(1.0, top),
            );
            mask.cover(&[a, b, c]);
            assert!(
                !mask.hides(&behind),
                "half a square hides nothing behind it"
            );
            mask.cover(&[a, c, d]);
            assert_eq!(mask.hides(&behind), hidden, "seam to {top}");
            assert!(!mask.hides(&square(3.0, 3.0, 15.5, 13.0)), "it juts out");
            assert!(!mask.hides(&square(-5.0, 3.0, 13.0, 13.0)));
            assert!(!mask.hides(&square(3.0, 3.0, 13.0, 50.0)));
        }
    }

    #[test]
    fn the_mask_of_a_big_picture_is_too_big() {
        assert_eq!(CoverMask::bytes(512, 512, 4), 512 * 512 * 2);
        assert_eq!(CoverMask::bytes(65, 1, 1), 16);
        assert!(CoverMask::bytes(4096, 4096, 4) <= MAX_BYTES);
        assert!(CoverMask::bytes(16384, 16384, 4) > MAX_BYTES);
        assert!(CoverMask::bytes(u32::MAX, u32::MAX, 16) > MAX_BYTES);
    }

    /// A sample line the polygon only touches within the margin counts
    /// as touched; samples between the lines do not.
    #[test]
    fn the_margin_touches_and_the_samples_decide() {
        let mut mask = CoverMask::new(8, 8, 1);
        // Samples at x, y = k + 0.5: this covers columns 1..=4 of row 2.
        mask.cover(&square(1.2, 2.2, 4.8, 2.8));
        assert!(mask.hides(&square(1.4, 2.3, 4.6, 2.7)));
        // Between the sample lines 2.5 and 3.5: no sample, hidden.
        assert!(mask.hides(&square(1.0, 2.6, 7.0, 3.4)));
        // Reaches the sample (5.5, 2.5), not covered.
        assert!(!mask.hides(&square(1.4, 2.3, 5.5, 2.7)));
        assert!(!mask.hides(&square(1.4, 2.3, 5.5 - MARGIN / 2.0, 2.7)));
    }

    /// A concave polygon covers nothing; degenerate or non-finite ones
    /// are never hidden.
    #[test]
    fn concave_covers_nothing_and_bad_points_are_kept() {
        let mut mask = CoverMask::new(8, 8, 4);
        let arrow = [
            DVec2::new(0.0, 0.0),
            DVec2::new(8.0, 4.0),
            DVec2::new(0.0, 8.0),
            DVec2::new(2.0, 4.0),
        ];
        mask.cover(&arrow);
        assert!(!mask.hides(&square(4.0, 3.5, 5.0, 4.5)));
        mask.cover(&square(0.0, 0.0, 8.0, 8.0));
        assert!(mask.hides(&square(4.0, 3.5, 5.0, 4.5)));
        assert!(!mask.hides(&[DVec2::new(1.0, 1.0), DVec2::new(2.0, f64::NAN), DVec2::ZERO]));
        assert!(!mask.hides(&[DVec2::new(1.0, 1.0), DVec2::new(2.0, 2.0)]));
    }

    fn inside_convex(pts: &[DVec2], p: DVec2) -> bool {
        let n = pts.len();
        let side = |k: usize| (pts[(k + 1) % n] - pts[k]).perp_dot(p - pts[k]);
        (0..n).all(|k| side(k) > 0.0) || (0..n).all(|k| side(k) < 0.0)
    }

    fn triangle() -> impl Strategy<Value = Vec<DVec2>> {
        prop::collection::vec((-2.0..10.0f64, -2.0..10.0f64), 3)
            .prop_map(|v| v.into_iter().map(|(x, y)| DVec2::new(x, y)).collect())
    }

    /// The serial question [`hidden`] answers by bands: one mask of the
    /// whole image, front to back.
    fn hidden_serially(width: u32, height: u32, n: u32, outlines: &[Outline]) -> Vec<bool> {
        let mut mask = CoverMask::new(width, height, n);
        let mut hidden = vec![false; outlines.len()];
        for (k, o) in outlines.iter().enumerate().rev() {
            hidden[k] = mask.hides(&o.points);
            if !hidden[k] && o.opaque {
                mask.cover(&o.points);
            }
        }
        hidden
    }

    fn outline() -> impl Strategy<Value = Outline> {
        let point = (-4.0..40.0f64, -4.0..40.0f64).prop_map(|(x, y)| DVec2::new(x, y));
        (prop::collection::vec(point, 2..6), any::<bool>(), 0..20u32).prop_map(
            |(mut points, opaque, bad)| {
                if bad == 0 {
                    points[0].y = f64::NAN;
                }
                Outline { points, opaque }
            },
        )
    }

    proptest! {
        /// Bands on all threads hide what one mask hides, whatever the
        /// polygons (concave, degenerate, non-finite, transparent) and the
        /// bands (a picture of 1 to 40 rows of 1 to 4 samples).
        #[test]
        fn the_bands_hide_what_one_mask_hides(
            outlines in prop::collection::vec(outline(), 0..80),
            height in 1u32..40,
            n in 1u32..5,
        ) {
            let banded = hidden(36, height, n, &outlines);
            prop_assert_eq!(banded, hidden_serially(36, height, n, &outlines));
        }

        /// Against brute force: a polygon said to be hidden has every
        /// image sample strictly inside it also strictly inside an
        /// occluder, and a fan of occluders that covers the whole image
        /// hides anything.
        #[test]
        fn hidden_means_every_sample_is_covered(
            occluders in prop::collection::vec(triangle(), 1..12),
            target in triangle(),
            n in 1u32..5,
        ) {
            let mut mask = CoverMask::new(8, 8, n);
            for o in &occluders {
                mask.cover(o);
            }
            if mask.hides(&target) {
                for y in 0..8 * n {
                    for x in 0..8 * n {
                        let s = DVec2::new((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
                        if inside_convex(&target, s) {
                            prop_assert!(occluders.iter().any(|o| inside_convex(o, s)), "{s}");
                        }
                    }
                }
            }
            mask.cover(&square(-1.0, -1.0, 9.0, 9.0));
            prop_assert!(mask.hides(&target));
        }
    }
}

//! The face sampler of Donovan 1973 (000 section 5): a polygon is cut by
//! the horizontal lines through the sample points, the crossings on each
//! line sorted and paired into segments.
//!
//! Sampling convention (000 section 5, figure 15f): an edge spanning
//! `y0 <= y < y1` is crossed by the sample rows in that half-open range
//! ("the last scan line an edge appears on is ceil(YMAX - 1)"), and a
//! segment from `xl` to `xr` covers the samples with `xl <= x < xr` (the
//! same rule "applied to the left edge of segments"). So two polygons that
//! share an edge never both cover, nor both miss, a sample on it: no seams,
//! no pixel painted twice. Sample points are pixel centres: pixel `(i, j)`
//! is sampled at `(i + 0.5, j + 0.5)` in screen coordinates (y up).
//!
//! Preconditions: finite coordinates. Polygons may be non-convex or
//! self-intersecting; the even-odd rule decides.

use glam::DVec2;

/// [`for_each_span`] with `stride` attributes per vertex (`attrs[k *
/// stride..]` for vertex `k`: Gouraud's vertex shades, Phong's highlight
/// vectors), interpolated along the edges to the span's ends. `span` gets
/// the row, the pixel run, and the ends' x and attributes; inside the span
/// attributes are linear in x (see [`lerp_at`]).
pub fn for_each_attr_span(
    points: &[DVec2],
    attrs: &[f32],
    stride: usize,
    rows: std::ops::Range<u32>,
    width: u32,
    mut span: impl FnMut(u32, u32, u32, (f64, &[f32]), (f64, &[f32])),
) {
    let n = points.len();
    if n < 3 || attrs.len() != n * stride {
        return;
    }
    let (ymin, ymax) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    let first = ((ymin - 0.5).ceil().max(rows.start as f64)) as u32;
    let last_excl = ((ymax - 0.5).ceil().min(rows.end as f64)).max(first as f64) as u32;
    let mut xs: Vec<(f64, usize)> = Vec::with_capacity(8);
    let mut values: Vec<f32> = Vec::with_capacity(8 * stride);
    for j in first..last_excl {
        let yc = j as f64 + 0.5;
        xs.clear();
        values.clear();
        for k in 0..n {
            let (a, b) = (k, (k + 1) % n);
            let (p, q) = if (points[a].y, points[a].x) <= (points[b].y, points[b].x) {
                (a, b)
            } else {
                (b, a)
            };
            let (pp, qq) = (points[p], points[q]);
            if pp.y <= yc && yc < qq.y {
                let t = (yc - pp.y) / (qq.y - pp.y);
                xs.push((pp.x + t * (qq.x - pp.x), values.len()));
                for i in 0..stride {
                    let (va, vb) = (attrs[p * stride + i], attrs[q * stride + i]);
                    values.push(va + (vb - va) * t as f32);
                }
            }
        }
        xs.sort_by(|a, b| a.0.total_cmp(&b.0));
        for pair in xs.chunks_exact(2) {
            let i0 = (pair[0].0 - 0.5).ceil().clamp(0.0, width as f64) as u32;
            let i1 = (pair[1].0 - 0.5).ceil().clamp(0.0, width as f64) as u32;
            if i1 > i0 {
                let left = &values[pair[0].1..pair[0].1 + stride];
                let right = &values[pair[1].1..pair[1].1 + stride];
                span(j, i0, i1, (pair[0].0, left), (pair[1].0, right));
            }
        }
    }
}

/// The attributes at pixel column `i` of a span from `(x0, a0)` to
/// `(x1, a1)`, written to `out`.
pub fn lerp_at(i: u32, (x0, a0): (f64, &[f32]), (x1, a1): (f64, &[f32]), out: &mut [f32]) {
    let t = if x1 > x0 {
        (((i as f64 + 0.5) - x0) / (x1 - x0)).clamp(0.0, 1.0)
    } else {
        0.0
    } as f32;
    for k in 0..out.len() {
        out[k] = a0[k] + (a1[k] - a0[k]) * t;
    }
}

/// Calls `span(j, i0, i1)` for each row `j` (counted from the bottom) in
/// `rows` and each run of covered pixels `i0..i1` on it, left to right.
pub fn for_each_span(
    points: &[DVec2],
    rows: std::ops::Range<u32>,
    width: u32,
    mut span: impl FnMut(u32, u32, u32),
) {
    let n = points.len();
    if n < 3 {
        return;
    }
    let (ymin, ymax) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    // Rows whose centre y = j + 0.5 lies in [ymin, ymax).
    let first = ((ymin - 0.5).ceil().max(rows.start as f64)) as u32;
    let last_excl = ((ymax - 0.5).ceil().min(rows.end as f64)).max(first as f64) as u32;
    let mut xs: Vec<f64> = Vec::with_capacity(8);
    for j in first..last_excl {
        let yc = j as f64 + 0.5;
        xs.clear();
        for k in 0..n {
            let (a, b) = (points[k], points[(k + 1) % n]);
            // Canonical order so shared edges give identical crossings.
            let (p, q) = if (a.y, a.x) <= (b.y, b.x) {
                (a, b)
            } else {
                (b, a)
            };
            if p.y <= yc && yc < q.y {
                xs.push(p.x + (yc - p.y) * (q.x - p.x) / (q.y - p.y));
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            // Pixels whose centre i + 0.5 lies in [xl, xr).
            let i0 = (pair[0] - 0.5).ceil().clamp(0.0, width as f64) as u32;
            let i1 = (pair[1] - 0.5).ceil().clamp(0.0, width as f64) as u32;
            if i1 > i0 {
                span(j, i0, i1);
            }
        }
    }
}

/// An upper bound on the work of tiling the outline `points` in a
/// `width` x `height` image, counted in pixel samples: the samples it can
/// cover, plus a visit per vertex on each row it spans (the crossings
/// [`for_each_span`] computes there). The samples are bounded twice, by
/// the rows times the columns of its bounding box within the image and
/// by its fan triangles from the first point (they cover every point the
/// even-odd rule fills), a triangle sampling at most its area, its width
/// and two pixels per row (a unimodal section sampled at unit steps).
pub fn work(points: &[DVec2], width: u32, height: u32) -> f64 {
    let (w, h) = (f64::from(width), f64::from(height));
    let bounds = |pts: &mut dyn Iterator<Item = DVec2>| {
        pts.fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        )
    };
    let (lo, hi) = bounds(&mut points.iter().copied());
    let extent = |a: f64, b: f64, end: f64| b.min(end) - a.max(0.0);
    let (cols, rows) = (extent(lo.x, hi.x, w), extent(lo.y, hi.y, h));
    if points.len() < 3 || cols.is_nan() || rows.is_nan() || cols < 0.0 || rows < 0.0 {
        return 0.0;
    }
    let (cols, rows) = (cols.floor() + 1.0, rows.floor() + 1.0);
    let fan: f64 = points[1..]
        .windows(2)
        .map(|e| {
            let (a, b, c) = (points[0], e[0], e[1]);
            let (tlo, thi) = bounds(&mut [a, b, c].into_iter());
            let area = (b - a).perp_dot(c - a).abs() / 2.0;
            area + (thi.x - tlo.x) + 2.0 * (thi.y - tlo.y + 1.0)
        })
        .sum();
    rows * points.len() as f64 + (rows * cols).min(fan)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coverage(points: &[DVec2], w: u32, h: u32) -> Vec<u32> {
        let mut c = vec![0; (w * h) as usize];
        for_each_span(points, 0..h, w, |j, i0, i1| {
            for i in i0..i1 {
                c[(j * w + i) as usize] += 1;
            }
        });
        c
    }

    fn pt(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn square_on_pixel_boundaries_covers_exactly_its_pixels() {
        let c = coverage(
            &[pt(1.0, 1.0), pt(1.0, 3.0), pt(3.0, 3.0), pt(3.0, 1.0)],
            4,
            4,
        );
        let covered: Vec<usize> = (0..16).filter(|&k| c[k] == 1).collect();
        assert_eq!(covered, vec![5, 6, 9, 10]);
    }

    #[test]
    fn triangles_sharing_a_diagonal_tile_exactly_once() {
        // Two triangles splitting a 7 x 5 rectangle with odd corners along
        // a diagonal: every pixel of the rectangle painted exactly once.
        let a = [pt(0.3, 0.2), pt(7.3, 5.2), pt(7.3, 0.2)];
        let b = [pt(0.3, 0.2), pt(0.3, 5.2), pt(7.3, 5.2)];
        let (w, h) = (9, 7);
        let ca = coverage(&a, w, h);
        let cb = coverage(&b, w, h);
        let rect = coverage(
            &[pt(0.3, 0.2), pt(0.3, 5.2), pt(7.3, 5.2), pt(7.3, 0.2)],
            w,
            h,
        );
        for k in 0..(w * h) as usize {
            assert_eq!(ca[k] + cb[k], rect[k], "pixel {k}");
        }
        assert_eq!(rect.iter().sum::<u32>(), 7 * 5);
    }

    #[test]
    fn non_convex_polygon_even_odd() {
        // A U shape: the notch in the middle stays empty.
        let u = [
            pt(0.0, 0.0),
            pt(0.0, 3.0),
            pt(1.0, 3.0),
            pt(1.0, 1.0),
            pt(2.0, 1.0),
            pt(2.0, 3.0),
            pt(3.0, 3.0),
            pt(3.0, 0.0),
        ];
        let c = coverage(&u, 3, 3);
        assert_eq!(c, vec![1, 1, 1, 1, 0, 1, 1, 0, 1]);
    }

    #[test]
    fn gouraud_interpolates_vertex_values() {
        // A right triangle with value x + y at its corners (a linear
        // function): every pixel gets its centre's x + y.
        let pts = [pt(0.0, 0.0), pt(0.0, 8.0), pt(8.0, 0.0)];
        let attrs = [0.0, 8.0, 8.0];
        let mut count = 0;
        let mut v = [0.0f32];
        for_each_attr_span(&pts, &attrs, 1, 0..8, 8, |j, i0, i1, l, r| {
            for i in i0..i1 {
                lerp_at(i, l, r, &mut v);
                assert!(
                    (v[0] - (i as f32 + 0.5 + j as f32 + 0.5)).abs() < 1e-4,
                    "{i} {j} {v:?}"
                );
                count += 1;
            }
        });
        // Same coverage as the plain sampler.
        let plain = coverage(&pts, 8, 8).iter().sum::<u32>();
        assert_eq!(count, plain);
    }

    #[test]
    fn clamps_to_the_image() {
        let c = coverage(
            &[pt(-5.0, -5.0), pt(-5.0, 9.0), pt(9.0, 9.0), pt(9.0, -5.0)],
            3,
            2,
        );
        assert_eq!(c, vec![1; 6]);
    }

    #[test]
    fn work_bounds_the_samples_covered() {
        // Hand-worked: a 4 x 2 rectangle on pixel boundaries covers 8
        // samples; its 2 fan triangles give 4 + 4 + 2 * (2 + 1) each,
        // its box 3 rows of 5 columns (15, the smaller); 4 vertices on 3
        // rows add 12.
        let rect = [pt(1.0, 1.0), pt(1.0, 3.0), pt(5.0, 3.0), pt(5.0, 1.0)];
        assert_eq!(work(&rect, 8, 8), 12.0 + 15.0);
        assert_eq!(coverage(&rect, 8, 8).iter().sum::<u32>(), 8);
        // A sliver on a sample row: no area, yet it covers the row; the
        // bound still holds. Outside the image: nothing.
        let sliver = [pt(0.0, 2.5), pt(64.0, 2.5 + 1e-9), pt(64.0, 2.5 - 1e-9)];
        let covered = coverage(&sliver, 64, 8).iter().sum::<u32>();
        assert!(covered >= 60 && work(&sliver, 64, 8) >= f64::from(covered));
        let away = [pt(-9.0, -9.0), pt(-9.0, -5.0), pt(-5.0, -5.0)];
        assert_eq!(work(&away, 8, 8), 0.0);
        // Random triangles and a self-crossing outline: never fewer than
        // the samples the tiler takes.
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 40.0 - 4.0
        };
        for _ in 0..200 {
            let n = 3 + (next().abs() as usize % 4);
            let poly: Vec<DVec2> = (0..n).map(|_| pt(next(), next())).collect();
            let covered = coverage(&poly, 32, 32).iter().sum::<u32>();
            assert!(work(&poly, 32, 32) >= f64::from(covered), "{poly:?}");
        }
    }
}

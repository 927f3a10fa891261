//! Warnock's area subdivision (Firebaugh, 001, the textbook hidden-surface
//! algorithms): a window is resolved at once when it is simple enough,
//! and otherwise divided in four. Against a window each polygon is
//! *surrounding* (it covers the whole window), *intersecting* (it crosses
//! the window's boundary), *contained* (wholly inside) or *disjoint*. A
//! window is simple when:
//!
//! 1. every polygon is disjoint: it keeps the background;
//! 2. exactly one polygon is intersecting or contained and none surrounds:
//!    that polygon is scan converted inside the window;
//! 3. one polygon surrounds and no other touches the window: it fills it;
//! 4. a surrounding polygon is nearer than every other polygon's plane at
//!    the window's four corners: it fills the window.
//!
//! A window of one pixel takes the polygon nearest at the pixel centre.
//! Windows are whole pixels; a polygon "covers" the pixels whose centres it
//! samples under the tiler's convention ([`crate::raster::tiler`]).
//!
//! Preconditions: planar, convex polygons in screen coordinates (convexity
//! makes "surrounding" a test of the window's corners); polygons seen
//! edge-on are skipped.

use std::sync::atomic::AtomicBool;
use std::sync::atomic::Ordering::Relaxed;

use glam::DVec2;

use super::z_buffer::{DepthItem, depth_plane};
use crate::budget::Meter;
use crate::error::Result;
use crate::raster::frame_buffer::{Band, FrameBuffer};
use crate::raster::tiler;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Class {
    Surrounding,
    Intersecting,
    Contained,
    Disjoint,
}

struct Poly {
    points: Vec<DVec2>,
    plane: (f64, f64, f64),
    lo: DVec2,
    hi: DVec2,
    /// +1 or -1: the orientation of `points` (signed area).
    orient: f64,
    /// `|a| W + |b| H + |c|` of the plane `a x + b y + c` over the
    /// `W` x `H` image: the size of its depths there, for rounding.
    scale: f64,
}

impl Poly {
    /// The polygon of `item` in a `width` x `height` image, or `None`
    /// when it is seen edge-on or has no area.
    fn new(item: &DepthItem, width: u32, height: u32) -> Option<Poly> {
        let plane = depth_plane(&item.points)?;
        let points: Vec<DVec2> = item.points.iter().map(|p| DVec2::new(p.x, p.y)).collect();
        let area: f64 = (0..points.len())
            .map(|i| points[i].perp_dot(points[(i + 1) % points.len()]))
            .sum();
        let (lo, hi) = points.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let scale =
            plane.0.abs() * f64::from(width) + plane.1.abs() * f64::from(height) + plane.2.abs();
        (area != 0.0).then_some(Poly {
            points,
            plane,
            lo,
            hi,
            orient: area.signum(),
            scale,
        })
    }

    fn depth(&self, x: f64, y: f64) -> f64 {
        self.plane.0 * x + self.plane.1 * y + self.plane.2
    }

    /// Whether point `p` is inside or on the boundary.
    fn contains(&self, p: DVec2) -> bool {
        let n = self.points.len();
        (0..n).all(|i| {
            let (a, b) = (self.points[i], self.points[(i + 1) % n]);
            self.orient * (b - a).perp_dot(p - a) >= 0.0
        })
    }

    /// Classifies the polygon against the window spanning the pixel centres
    /// of columns `x0..x1`, rows `y0..y1` (the box through those centres).
    fn classify(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> Class {
        let (wl, wr) = (x0 as f64 + 0.5, x1 as f64 - 0.5);
        let (wb, wt) = (y0 as f64 + 0.5, y1 as f64 - 0.5);
        if self.hi.x < wl || self.lo.x > wr || self.hi.y < wb || self.lo.y > wt {
            return Class::Disjoint;
        }
        let corners = [
            DVec2::new(wl, wb),
            DVec2::new(wl, wt),
            DVec2::new(wr, wt),
            DVec2::new(wr, wb),
        ];
        if corners.iter().all(|c| self.contains(*c)) {
            return Class::Surrounding;
        }
        if self.lo.x >= wl && self.hi.x <= wr && self.lo.y >= wb && self.hi.y <= wt {
            return Class::Contained;
        }
        // A separating edge of the polygon puts the window wholly outside.
        let n = self.points.len();
        for i in 0..n {
            let (a, b) = (self.points[i], self.points[(i + 1) % n]);
            if corners
                .iter()
                .all(|c| self.orient * (b - a).perp_dot(*c - a) < 0.0)
            {
                return Class::Disjoint;
            }
        }
        Class::Intersecting
    }
}

/// Paints `items` by area subdivision, within `budget` polygon-window
/// tests (`--max-window-tests`). Returns how many polygons covered at
/// least one pixel; [`Error::Cancelled`] on a stop request (looked at per
/// window), the budget's error past it.
///
/// [`Error::Cancelled`]: crate::error::Error::Cancelled
pub fn paint(frame: &mut FrameBuffer, items: &[DepthItem], budget: u64) -> Result<usize> {
    let meter = Meter::new(
        "polygon-window tests of Warnock's area subdivision",
        budget,
        "--max-window-tests",
    );
    let seen = paint_with(frame, items, &meter, true);
    meter.result()?;
    Ok(seen)
}

/// [`paint`], counting on `meter`, with or without the hidden polygons'
/// removal (the same image either way).
fn paint_with(frame: &mut FrameBuffer, items: &[DepthItem], meter: &Meter, prune: bool) -> usize {
    let (w, h) = (frame.width, frame.height);
    let polys: Vec<Option<Poly>> = items.iter().map(|it| Poly::new(it, w, h)).collect();
    let all: Vec<u32> = (0..items.len() as u32)
        .filter(|&k| polys[k as usize].is_some())
        .collect();
    // Removal needs depths that are finite everywhere in the image.
    let prune = prune && polys.iter().flatten().all(|p| p.scale < 1e300);
    let painter = Painter {
        items,
        polys: &polys,
        seen: items.iter().map(|_| AtomicBool::new(false)).collect(),
        meter,
        prune,
    };
    let mut out = Out {
        rows: Band {
            lo: 0,
            hi: h,
            width: w,
            colors: &mut frame.color,
            ids: &mut frame.ids,
        },
        pending: 0,
    };
    painter.window(&mut out, (0, 0, w, h), &all);
    meter.add(out.pending);
    painter.seen.iter().filter(|s| s.load(Relaxed)).count()
}

/// Windows of at least this many pixels hand their halves (the two lower
/// quarters, the two upper ones) to two threads.
const PARALLEL_PIXELS: u32 = 1 << 14;

struct Painter<'a> {
    items: &'a [DepthItem],
    polys: &'a [Option<Poly>],
    /// Which polygons were painted somewhere, by any thread.
    seen: Vec<AtomicBool>,
    meter: &'a Meter,
    /// Whether polygons hidden behind a surrounding one leave the list.
    prune: bool,
}

/// Where one thread paints: the rows that hold its windows, and the tests
/// it counted that the meter has not been told of yet.
struct Out<'f> {
    rows: Band<'f>,
    pending: u64,
}

impl Out<'_> {
    /// The rows below screen row `at` and those from it up, each with
    /// nothing pending.
    fn halves(&mut self, at: u32) -> (Out<'_>, Out<'_>) {
        let Band {
            lo,
            hi,
            width,
            ref mut colors,
            ref mut ids,
        } = self.rows;
        let split = (hi - at) as usize * width as usize;
        let (top_colors, bottom_colors) = colors.split_at_mut(split);
        let (top_ids, bottom_ids) = ids.split_at_mut(split);
        let half = |lo, hi, colors, ids| Out {
            rows: Band {
                lo,
                hi,
                width,
                colors,
                ids,
            },
            pending: 0,
        };
        (
            half(lo, at, bottom_colors, bottom_ids),
            half(at, hi, top_colors, top_ids),
        )
    }
}

/// A window: columns `x0..x1` and rows `y0..y1` (rows from the bottom).
type Window = (u32, u32, u32, u32);

/// A window's corners, as the box through its pixel centres.
type Corners = [(f64, f64); 4];

impl Painter<'_> {
    fn poly(&self, k: u32) -> &Poly {
        self.polys[k as usize]
            .as_ref()
            .expect("listed polygons are planar")
    }

    fn put(&self, out: &mut Out<'_>, x: u32, y: u32, k: u32) {
        let px = out.rows.index(y, x);
        out.rows.colors[px] = self.items[k as usize].color;
        out.rows.ids[px] = self.items[k as usize].id;
        self.seen[k as usize].store(true, Relaxed);
    }

    /// Resolves `window`, given the polygons not disjoint from its parent.
    fn window(&self, out: &mut Out<'_>, window: Window, parent: &[u32]) {
        let (x0, y0, x1, y1) = window;
        if x0 >= x1
            || y0 >= y1
            || !self
                .meter
                .add_batched(&mut out.pending, parent.len() as u64)
        {
            return;
        }
        let mut surrounding = Vec::new();
        let mut others = Vec::new();
        for &k in parent {
            match self.poly(k).classify(x0, y0, x1, y1) {
                Class::Disjoint => {}
                Class::Surrounding => surrounding.push(k),
                Class::Intersecting | Class::Contained => others.push(k),
            }
        }
        // Case 1: nothing here.
        if surrounding.is_empty() && others.is_empty() {
            return;
        }
        // Case 2: one polygon inside or crossing, none surrounding.
        if surrounding.is_empty() && others.len() == 1 {
            self.scan_convert(out, window, others[0]);
            return;
        }
        let corners = [
            (x0 as f64 + 0.5, y0 as f64 + 0.5),
            (x0 as f64 + 0.5, y1 as f64 - 0.5),
            (x1 as f64 - 0.5, y0 as f64 + 0.5),
            (x1 as f64 - 0.5, y1 as f64 - 0.5),
        ];
        if self.prune {
            self.remove_hidden(&corners, &mut surrounding, &mut others);
        }
        // Cases 3 and 4: a surrounding polygon in front of all others at
        // the window's corners.
        if let Some(s) = self.front(&corners, &surrounding, &others) {
            for y in y0..y1 {
                for x in x0..x1 {
                    self.put(out, x, y, s);
                }
            }
            return;
        }
        // A single pixel: the nearest polygon at its centre.
        if x1 - x0 == 1 && y1 - y0 == 1 {
            self.nearest(out, x0, y0, &surrounding, &others);
            return;
        }
        // Otherwise divide in four.
        let list: Vec<u32> = surrounding.into_iter().chain(others).collect();
        self.divide(out, window, &list);
    }

    /// The four quarters of `window`, each given `list`; a large window's
    /// lower and upper halves on two threads (they hold different rows,
    /// and no window paints outside itself, so the image is the same).
    fn divide(&self, out: &mut Out<'_>, (x0, y0, x1, y1): Window, list: &[u32]) {
        let (xm, ym) = ((x0 + x1).div_ceil(2), (y0 + y1).div_ceil(2));
        let lower = [(x0, y0, xm, ym), (xm, y0, x1, ym)];
        let upper = [(x0, ym, xm, y1), (xm, ym, x1, y1)];
        if (x1 - x0) * (y1 - y0) < PARALLEL_PIXELS || ym == y1 {
            for w in lower.into_iter().chain(upper) {
                self.window(out, w, list);
            }
            return;
        }
        let (mut below, mut above) = out.halves(ym);
        let paint = |out: &mut Out<'_>, windows: [Window; 2]| {
            for w in windows {
                self.window(out, w, list);
            }
            self.meter.add(std::mem::take(&mut out.pending));
        };
        rayon::join(|| paint(&mut below, lower), || paint(&mut above, upper));
    }

    /// Case 2: polygon `k` scan converted inside the window.
    fn scan_convert(&self, out: &mut Out<'_>, (x0, y0, x1, y1): Window, k: u32) {
        let pts = self.poly(k).points.clone();
        let mut spans = Vec::new();
        tiler::for_each_span(&pts, y0..y1, x1, |j, i0, i1| {
            spans.push((j, i0.max(x0), i1))
        });
        for (j, i0, i1) in spans {
            for i in i0..i1 {
                self.put(out, i, j, k);
            }
        }
    }

    /// The first surrounding polygon (in list order) whose depth at each
    /// corner is at most every other polygon's: at each corner it is the
    /// least, and no depth there is NaN (which compares false).
    fn front(&self, corners: &Corners, surrounding: &[u32], others: &[u32]) -> Option<u32> {
        if surrounding.len() + others.len() == 1 {
            return surrounding.first().copied();
        }
        let mut least = [f64::INFINITY; 4];
        let mut nan = false;
        for &k in surrounding.iter().chain(others) {
            let p = self.poly(k);
            for (m, &(x, y)) in least.iter_mut().zip(corners) {
                let d = p.depth(x, y);
                nan |= d.is_nan();
                if d < *m {
                    *m = d;
                }
            }
        }
        if nan {
            return None;
        }
        surrounding.iter().copied().find(|&s| {
            let p = self.poly(s);
            least
                .iter()
                .zip(corners)
                .all(|(m, &(x, y))| p.depth(x, y) <= *m)
        })
    }

    /// Removes from the lists the polygons whose planes lie behind a
    /// surrounding polygon's at every corner of the window, by more than
    /// rounding: that polygon hides them in the whole window and its
    /// subwindows, so they can decide nothing there (no window's front
    /// polygon and no pixel's nearest changes). The candidates that hide
    /// are the surrounding polygons nearest at a corner.
    fn remove_hidden(&self, corners: &Corners, surrounding: &mut Vec<u32>, others: &mut Vec<u32>) {
        if surrounding.is_empty() || surrounding.len() + others.len() < 2 {
            return;
        }
        let mut hiders: Vec<u32> = corners
            .iter()
            .filter_map(|&(x, y)| {
                surrounding.iter().copied().min_by(|&a, &b| {
                    self.poly(a)
                        .depth(x, y)
                        .total_cmp(&self.poly(b).depth(x, y))
                })
            })
            .collect();
        hiders.sort_unstable();
        hiders.dedup();
        let hidden = |k: u32| {
            let p = self.poly(k);
            hiders.iter().any(|&s| {
                let q = self.poly(s);
                let margin = 1e-9 * (p.scale + q.scale);
                s != k
                    && corners
                        .iter()
                        .all(|&(x, y)| p.depth(x, y) - q.depth(x, y) > margin)
            })
        };
        surrounding.retain(|&k| !hidden(k));
        others.retain(|&k| !hidden(k));
    }

    /// A single pixel no polygon is in front at: the nearest at its
    /// centre among those the tiler samples there.
    fn nearest(&self, out: &mut Out<'_>, x0: u32, y0: u32, surrounding: &[u32], others: &[u32]) {
        let c = DVec2::new(x0 as f64 + 0.5, y0 as f64 + 0.5);
        let nearest = surrounding
            .iter()
            .chain(others)
            .copied()
            .filter(|&k| sampled(&self.poly(k).points, x0, y0))
            .min_by(|&a, &b| {
                self.poly(a)
                    .depth(c.x, c.y)
                    .total_cmp(&self.poly(b).depth(c.x, c.y))
                    .then(a.cmp(&b))
            });
        if let Some(k) = nearest {
            self.put(out, x0, y0, k);
        }
    }
}

/// Whether the tiler samples pixel `(x, y)` for this outline.
fn sampled(points: &[DVec2], x: u32, y: u32) -> bool {
    let mut hit = false;
    tiler::for_each_span(points, y..y + 1, x + 1, |_, i0, i1| {
        hit |= i0 <= x && x < i1
    });
    hit
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    #[test]
    fn classes_of_a_square() {
        let sq = Poly {
            points: vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(0.0, 10.0),
                DVec2::new(10.0, 10.0),
                DVec2::new(10.0, 0.0),
            ],
            plane: (0.0, 0.0, 0.0),
            lo: DVec2::ZERO,
            hi: DVec2::splat(10.0),
            orient: -1.0,
            scale: 0.0,
        };
        assert_eq!(sq.classify(2, 2, 4, 4), Class::Surrounding);
        assert_eq!(sq.classify(8, 8, 14, 14), Class::Intersecting);
        // The window box runs through the pixel centres: 0.5 to 19.5.
        assert_eq!(sq.classify(0, 0, 20, 20), Class::Intersecting);
        let small = Poly {
            points: sq
                .points
                .iter()
                .map(|p| *p * 0.5 + DVec2::splat(2.0))
                .collect(),
            lo: DVec2::splat(2.0),
            hi: DVec2::splat(7.0),
            ..sq
        };
        assert_eq!(small.classify(0, 0, 20, 20), Class::Contained);
        assert_eq!(sq.classify(12, 0, 20, 20), Class::Disjoint);
        assert!(sq.contains(DVec2::new(3.5, 3.5)));
    }

    /// A small random generator (no dependency for a unit test).
    struct Lcg(u64);

    impl Lcg {
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
        }
    }

    fn item(points: [DVec3; 3], id: u32) -> DepthItem {
        DepthItem {
            points: points.to_vec(),
            color: [id as f32; 3],
            id,
        }
    }

    /// Random interpenetrating triangles over a `w` x `h` image, with
    /// copies (the same plane exactly) and a coplanar strip of triangles
    /// sharing edges: what could tell a removal that is not exact.
    fn soup(seed: u64, count: usize, w: f64, h: f64) -> Vec<DepthItem> {
        let mut rng = Lcg(seed);
        let mut items = Vec::new();
        for _ in 0..count {
            let mut p = || DVec3::new(rng.range(-0.2, 1.2) * w, rng.range(-0.2, 1.2) * h, 0.0);
            let mut t = [p(), p(), p()];
            for v in &mut t {
                v.z = rng.range(-1.0, 1.0);
            }
            items.push(item(t, items.len() as u32 + 1));
            if items.len() % 5 == 0 {
                items.push(item(t, items.len() as u32 + 1));
            }
        }
        for k in 0..6 {
            let (x0, x1) = (k as f64 * w / 6.0, (k + 1) as f64 * w / 6.0);
            let z = |x: f64| 0.1 * x / w - 0.05;
            let (a, b) = (DVec3::new(x0, 0.0, z(x0)), DVec3::new(x1, 0.0, z(x1)));
            let (c, d) = (DVec3::new(x1, h, z(x1)), DVec3::new(x0, h, z(x0)));
            items.push(item([a, b, c], items.len() as u32 + 1));
            items.push(item([a, c, d], items.len() as u32 + 1));
        }
        items
    }

    /// The ids painted and the polygons seen, and the tests made.
    fn painted(items: &[DepthItem], w: u32, h: u32, prune: bool) -> (Vec<u32>, usize, u64) {
        let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
        let meter = Meter::new("tests", u64::MAX, "--flag");
        let seen = paint_with(&mut frame, items, &meter, prune);
        (frame.ids, seen, meter.spent())
    }

    #[test]
    fn removing_hidden_polygons_changes_no_pixel_and_saves_tests() {
        let (mut with, mut without) = (0, 0);
        for seed in 1..=8 {
            let (w, h) = (40 + 3 * seed as u32, 64 - 2 * seed as u32);
            let items = soup(seed, 60, f64::from(w), f64::from(h));
            let pruned = painted(&items, w, h, true);
            let plain = painted(&items, w, h, false);
            assert_eq!(pruned.0, plain.0, "seed {seed}: the ids differ");
            assert_eq!(pruned.1, plain.1, "seed {seed}: the polygons seen");
            (with, without) = (with + pruned.2, without + plain.2);
        }
        // 60 triangles deep: most windows' lists are mostly hidden.
        assert!(
            with * 2 < without,
            "{with} tests with removal, {without} without"
        );
    }

    #[test]
    fn a_budget_of_window_tests_stops_the_subdivision() {
        let items = soup(3, 60, 48.0, 48.0);
        let needed = painted(&items, 48, 48, true).2;
        let mut frame = FrameBuffer::new(48, 48, [0.0; 3]);
        assert!(paint(&mut frame, &items, needed).is_ok());
        let e = paint(&mut frame, &items, needed - 1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("Warnock") && e.contains(&format!("budget of {}", needed - 1)),
            "{e}"
        );
        assert!(e.contains("`--max-window-tests N` raises it"), "{e}");
        // It stops soon after the count passes (each thread hands in its
        // count by blocks): far fewer tests than a large image needs.
        let items = soup(4, 200, 400.0, 400.0);
        let needed = painted(&items, 400, 400, false).2;
        assert!(needed > 20 * Meter::BLOCK, "{needed} tests");
        let mut frame = FrameBuffer::new(400, 400, [0.0; 3]);
        let meter = Meter::new("tests", needed / 10, "--flag");
        paint_with(&mut frame, &items, &meter, false);
        let most = needed / 10 + 4 * Meter::BLOCK;
        assert!(meter.spent() < most, "{} of {needed}", meter.spent());
    }

    #[test]
    fn the_front_polygon_is_the_first_nearest_at_every_corner() {
        // Against the definition, all pairs compared: random windows of
        // a soup with copies (ties), and a NaN depth (no front).
        let mut items = soup(5, 40, 32.0, 32.0);
        let mut polys: Vec<Option<Poly>> = items.iter().map(|it| Poly::new(it, 32, 32)).collect();
        let all = item(
            [
                DVec3::new(-99.0, -99.0, 2.0),
                DVec3::new(-99.0, 199.0, 2.0),
                DVec3::new(199.0, -99.0, 2.0),
            ],
            999,
        );
        polys.push(Some(Poly {
            plane: (f64::NAN, 0.0, 0.0),
            ..Poly::new(&all, 32, 32).expect("planar")
        }));
        items.push(all);
        let meter = Meter::new("tests", u64::MAX, "--flag");
        let painter = Painter {
            items: &items,
            polys: &polys,
            seen: Vec::new(),
            meter: &meter,
            prune: false,
        };
        let mut rng = Lcg(9);
        let mut fronts = 0;
        for round in 0..400 {
            let (x0, y0) = (rng.range(0.0, 28.0) as u32, rng.range(0.0, 28.0) as u32);
            let (x1, y1) = (
                x0 + 1 + rng.range(0.0, 4.0) as u32,
                y0 + 1 + rng.range(0.0, 4.0) as u32,
            );
            let last = if round % 7 == 0 {
                polys.len()
            } else {
                polys.len() - 1
            };
            let (mut surrounding, mut others) = (Vec::new(), Vec::new());
            for k in 0..last as u32 {
                match polys[k as usize]
                    .as_ref()
                    .map(|p| p.classify(x0, y0, x1, y1))
                {
                    Some(Class::Surrounding) => surrounding.push(k),
                    Some(Class::Intersecting | Class::Contained) => others.push(k),
                    _ => {}
                }
            }
            let corners = [
                (x0 as f64 + 0.5, y0 as f64 + 0.5),
                (x0 as f64 + 0.5, y1 as f64 - 0.5),
                (x1 as f64 - 0.5, y0 as f64 + 0.5),
                (x1 as f64 - 0.5, y1 as f64 - 0.5),
            ];
            let brute = surrounding.iter().copied().find(|&s| {
                let ps = painter.poly(s);
                surrounding
                    .iter()
                    .chain(&others)
                    .filter(|&&k| k != s)
                    .all(|&k| {
                        corners
                            .iter()
                            .all(|&(x, y)| ps.depth(x, y) <= painter.poly(k).depth(x, y))
                    })
            });
            assert_eq!(
                painter.front(&corners, &surrounding, &others),
                brute,
                "round {round}"
            );
            fronts += usize::from(brute.is_some());
        }
        assert!(fronts > 50, "{fronts} windows with a front");
    }
}

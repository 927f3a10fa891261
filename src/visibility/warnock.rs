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

use glam::DVec2;

use super::z_buffer::{DepthItem, depth_plane};
use crate::raster::frame_buffer::FrameBuffer;
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
}

impl Poly {
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

/// Paints `items` by area subdivision. Returns how many polygons covered at
/// least one pixel.
pub fn paint(frame: &mut FrameBuffer, items: &[DepthItem]) -> usize {
    let polys: Vec<Option<Poly>> = items
        .iter()
        .map(|it| {
            let plane = depth_plane(&it.points)?;
            let points: Vec<DVec2> = it.points.iter().map(|p| DVec2::new(p.x, p.y)).collect();
            let area: f64 = (0..points.len())
                .map(|i| points[i].perp_dot(points[(i + 1) % points.len()]))
                .sum();
            let (lo, hi) = points.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            (area != 0.0).then_some(Poly {
                points,
                plane,
                lo,
                hi,
                orient: area.signum(),
            })
        })
        .collect();
    let all: Vec<u32> = (0..items.len() as u32)
        .filter(|&k| polys[k as usize].is_some())
        .collect();
    let mut painter = Painter {
        frame,
        items,
        polys: &polys,
        seen: vec![false; items.len()],
    };
    let (w, h) = (painter.frame.width, painter.frame.height);
    painter.window(0, 0, w, h, &all);
    painter.seen.iter().filter(|&&s| s).count()
}

struct Painter<'a> {
    frame: &'a mut FrameBuffer,
    items: &'a [DepthItem],
    polys: &'a [Option<Poly>],
    seen: Vec<bool>,
}

impl Painter<'_> {
    fn poly(&self, k: u32) -> &Poly {
        self.polys[k as usize]
            .as_ref()
            .expect("listed polygons are planar")
    }

    fn put(&mut self, x: u32, y: u32, k: u32) {
        let px = ((self.frame.height - 1 - y) * self.frame.width + x) as usize;
        self.frame.color[px] = self.items[k as usize].color;
        self.frame.ids[px] = self.items[k as usize].id;
        self.seen[k as usize] = true;
    }

    /// Resolves the window of columns `x0..x1` and rows `y0..y1` (rows from
    /// the bottom), given the polygons not disjoint from its parent.
    fn window(&mut self, x0: u32, y0: u32, x1: u32, y1: u32, parent: &[u32]) {
        if x0 >= x1 || y0 >= y1 {
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
            let k = others[0];
            let pts = self.poly(k).points.clone();
            let mut spans = Vec::new();
            tiler::for_each_span(&pts, y0..y1, x1, |j, i0, i1| {
                spans.push((j, i0.max(x0), i1))
            });
            for (j, i0, i1) in spans {
                for i in i0..i1 {
                    self.put(i, j, k);
                }
            }
            return;
        }
        // Cases 3 and 4: a surrounding polygon in front of all others at
        // the window's corners.
        let corners = [
            (x0 as f64 + 0.5, y0 as f64 + 0.5),
            (x0 as f64 + 0.5, y1 as f64 - 0.5),
            (x1 as f64 - 0.5, y0 as f64 + 0.5),
            (x1 as f64 - 0.5, y1 as f64 - 0.5),
        ];
        let front = surrounding.iter().copied().find(|&s| {
            let ps = self.poly(s);
            surrounding
                .iter()
                .chain(&others)
                .filter(|&&k| k != s)
                .all(|&k| {
                    corners
                        .iter()
                        .all(|&(x, y)| ps.depth(x, y) <= self.poly(k).depth(x, y))
                })
        });
        if let Some(s) = front {
            for y in y0..y1 {
                for x in x0..x1 {
                    self.put(x, y, s);
                }
            }
            return;
        }
        // A single pixel: the nearest polygon at its centre.
        if x1 - x0 == 1 && y1 - y0 == 1 {
            let c = DVec2::new(x0 as f64 + 0.5, y0 as f64 + 0.5);
            let nearest = surrounding
                .iter()
                .chain(&others)
                .copied()
                .filter(|&k| sampled(&self.poly(k).points, x0, y0))
                .min_by(|&a, &b| {
                    self.poly(a)
                        .depth(c.x, c.y)
                        .total_cmp(&self.poly(b).depth(c.x, c.y))
                        .then(a.cmp(&b))
                });
            if let Some(k) = nearest {
                self.put(x0, y0, k);
            }
            return;
        }
        // Otherwise divide in four.
        let list: Vec<u32> = surrounding.into_iter().chain(others).collect();
        let (xm, ym) = ((x0 + x1).div_ceil(2), (y0 + y1).div_ceil(2));
        self.window(x0, y0, xm, ym, &list);
        self.window(xm, y0, x1, ym, &list);
        self.window(x0, ym, xm, y1, &list);
        self.window(xm, ym, x1, y1, &list);
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
}

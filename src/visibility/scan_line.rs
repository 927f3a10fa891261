//! The scan-line algorithm (Firebaugh, 001, the textbook hidden-surface
//! algorithms; Watkins' method): an edge table bucketed by first scan line,
//! an active edge list carried from line to line, the spans of each active
//! polygon on the line, and depth comparisons only where spans overlap.
//!
//! Sampling follows [`crate::raster::tiler`] exactly (edges cover rows
//! `y0 <= y < y1`, spans the samples `xl <= x < xr`), so a lone polygon
//! covers the same pixels as under the painter. Where spans overlap, each
//! pixel takes the polygon nearest at its centre (depth from the polygon's
//! plane in screen coordinates, exact for interpenetrating polygons); ties
//! go to the polygon listed first. Lines are processed in parallel.
//!
//! Preconditions: planar polygons in screen coordinates; polygons seen
//! edge-on are skipped (they cover no area).

use glam::DVec3;

use super::z_buffer::{DepthItem, depth_plane};
use crate::raster::frame_buffer::{Band, FrameBuffer};

/// An edge in the edge table, filed under the first row it covers; it
/// covers rows up to `last` (exclusive).
#[derive(Debug, Clone, Copy)]
struct Edge {
    polygon: u32,
    last: u32,
    /// Lower endpoint (by y, then x) and the inverse slope.
    x0: f64,
    y0: f64,
    dxdy: f64,
}

/// Paints `items` scan line by scan line. Returns how many polygons
/// covered at least one pixel. Stops early, between lines, when a stop
/// is requested ([`crate::cancel`]): the caller looks at the request and
/// discards the frame.
pub fn paint(frame: &mut FrameBuffer, items: &[DepthItem]) -> usize {
    let (w, h) = (frame.width, frame.height);
    let planes: Vec<Option<(f64, f64, f64)>> =
        items.iter().map(|it| depth_plane(&it.points)).collect();
    // The edge table: edges bucketed by the first row they cross.
    let mut table: Vec<Vec<Edge>> = vec![Vec::new(); h as usize];
    for (k, item) in items.iter().enumerate() {
        if planes[k].is_none() {
            continue;
        }
        let pts: &[DVec3] = &item.points;
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            let (p, q) = if (a.y, a.x) <= (b.y, b.x) {
                (a, b)
            } else {
                (b, a)
            };
            if p.y == q.y {
                continue;
            }
            let first = (p.y - 0.5).ceil().max(0.0);
            let last = (q.y - 0.5).ceil().min(h as f64);
            if last <= first {
                continue;
            }
            table[first as usize].push(Edge {
                polygon: k as u32,
                last: last as u32,
                x0: p.x,
                y0: p.y,
                dxdy: (q.x - p.x) / (q.y - p.y),
            });
        }
    }
    // Rows are independent once the active edge list of a row is known; it
    // is rebuilt per band from the table and then carried line to line.
    frame.par_bands(|band| {
        let Band {
            lo,
            hi,
            colors,
            ids,
            ..
        } = band;
        // Active edges entering before this band and still active.
        let mut active: Vec<Edge> = table[..lo as usize]
            .iter()
            .flatten()
            .filter(|e| e.last > lo)
            .copied()
            .collect();
        let mut spans: Vec<(u32, u32, u32)> = Vec::new();
        let mut crossings: Vec<(u32, f64)> = Vec::new();
        let mut sweep = Sweep::new(items.len());
        for j in lo..hi {
            // A stop request ends the band; the caller reports it.
            if crate::cancel::requested() {
                break;
            }
            active.retain(|e| e.last > j);
            active.extend(table[j as usize].iter().copied());
            let yc = j as f64 + 0.5;
            crossings.clear();
            crossings.extend(
                active
                    .iter()
                    .map(|e| (e.polygon, e.x0 + (yc - e.y0) * e.dxdy)),
            );
            crossings.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            spans.clear();
            for pair in crossings.chunk_by(|a, b| a.0 == b.0) {
                for two in pair.chunks_exact(2) {
                    let i0 = (two[0].1 - 0.5).ceil().clamp(0.0, w as f64) as u32;
                    let i1 = (two[1].1 - 0.5).ceil().clamp(0.0, w as f64) as u32;
                    if i1 > i0 {
                        spans.push((i0, i1, two[0].0));
                    }
                }
            }
            let row = (hi - 1 - j) as usize * w as usize;
            sweep.resolve_line(&spans, yc, &planes, |i, k| {
                colors[row + i as usize] = items[k as usize].color;
                ids[row + i as usize] = items[k as usize].id;
            });
        }
    });
    frame.distinct_ids()
}

/// The sweep of one line's spans, with its buffers kept from line to
/// line: the span ends in order, and the polygons covering the stretch
/// between two consecutive ends (each polygon's place in that list, so
/// that one enters and leaves in constant time).
struct Sweep {
    ends: Vec<(u32, bool, u32)>,
    covering: Vec<u32>,
    /// The depth planes of `covering`, in its order.
    planes: Vec<(f64, f64, f64)>,
    place: Vec<u32>,
}

impl Sweep {
    fn new(polygons: usize) -> Sweep {
        Sweep {
            ends: Vec::new(),
            covering: Vec::new(),
            planes: Vec::new(),
            place: vec![u32::MAX; polygons],
        }
    }

    /// Sweeps the spans of one line left to right; between consecutive
    /// span ends the set of covering polygons is fixed: one polygon fills
    /// its pixels outright, several are compared by depth at each pixel
    /// (ties to the polygon listed first).
    fn resolve_line(
        &mut self,
        spans: &[(u32, u32, u32)],
        yc: f64,
        planes: &[Option<(f64, f64, f64)>],
        mut put: impl FnMut(u32, u32),
    ) {
        // (x, enters, polygon): at one x the spans ending leave first.
        self.ends.clear();
        self.ends.extend(
            spans
                .iter()
                .flat_map(|s| [(s.0, true, s.2), (s.1, false, s.2)]),
        );
        self.ends.sort_unstable();
        let mut next = 0;
        while next < self.ends.len() {
            let a = self.ends[next].0;
            while next < self.ends.len() && self.ends[next].0 == a {
                let (_, enters, k) = self.ends[next];
                if enters {
                    let plane = planes[k as usize].expect("only planar polygons have edges");
                    self.enter(k, plane);
                } else {
                    self.leave(k);
                }
                next += 1;
            }
            let Some(&(b, _, _)) = self.ends.get(next) else {
                break;
            };
            match self.covering[..] {
                [] => {}
                [k] => (a..b).for_each(|i| put(i, k)),
                _ => {
                    for i in a..b {
                        put(i, self.nearest(i as f64 + 0.5, yc));
                    }
                }
            }
        }
        debug_assert!(self.covering.is_empty(), "every span entered has left");
    }

    /// The covering polygon nearest at `(xc, yc)`, the first listed of
    /// equally near ones.
    fn nearest(&self, xc: f64, yc: f64) -> u32 {
        let depth = |(a, b, c): (f64, f64, f64)| a * xc + b * yc + c;
        let mut best = (depth(self.planes[0]), self.covering[0]);
        for (&k, &plane) in self.covering.iter().zip(&self.planes).skip(1) {
            let d = depth(plane);
            if d.total_cmp(&best.0).then(k.cmp(&best.1)).is_lt() {
                best = (d, k);
            }
        }
        best.1
    }

    fn enter(&mut self, k: u32, plane: (f64, f64, f64)) {
        self.place[k as usize] = self.covering.len() as u32;
        self.covering.push(k);
        self.planes.push(plane);
    }

    fn leave(&mut self, k: u32) {
        let at = std::mem::replace(&mut self.place[k as usize], u32::MAX) as usize;
        self.covering.swap_remove(at);
        self.planes.swap_remove(at);
        if let Some(&moved) = self.covering.get(at) {
            self.place[moved as usize] = at as u32;
        }
    }
}

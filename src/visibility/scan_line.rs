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
/// covered at least one pixel.
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
        for j in lo..hi {
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
            resolve_line(&spans, yc, &planes, |i, k| {
                colors[row + i as usize] = items[k as usize].color;
                ids[row + i as usize] = items[k as usize].id;
            });
        }
    });
    frame.distinct_ids()
}

/// Sweeps the spans of one line left to right; between consecutive span
/// ends the set of covering polygons is fixed: one polygon fills its pixels
/// outright, several are compared by depth at each pixel.
fn resolve_line(
    spans: &[(u32, u32, u32)],
    yc: f64,
    planes: &[Option<(f64, f64, f64)>],
    mut put: impl FnMut(u32, u32),
) {
    let mut cuts: Vec<u32> = spans.iter().flat_map(|s| [s.0, s.1]).collect();
    cuts.sort_unstable();
    cuts.dedup();
    let mut covering: Vec<u32> = Vec::new();
    for seg in cuts.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        covering.clear();
        covering.extend(spans.iter().filter(|s| s.0 <= a && b <= s.1).map(|s| s.2));
        match covering.len() {
            0 => {}
            1 => (a..b).for_each(|i| put(i, covering[0])),
            _ => {
                covering.sort_unstable();
                for i in a..b {
                    let xc = i as f64 + 0.5;
                    let depth = |k: u32| {
                        let (pa, pb, pc) =
                            planes[k as usize].expect("only planar polygons have edges");
                        pa * xc + pb * yc + pc
                    };
                    let nearest = covering
                        .iter()
                        .copied()
                        .min_by(|&p, &q| depth(p).total_cmp(&depth(q)).then(p.cmp(&q)))
                        .expect("not empty");
                    put(i, nearest);
                }
            }
        }
    }
}

//! The z-buffer (Firebaugh, 001, the textbook hidden-surface algorithms):
//! every polygon is sampled with the tiler of [`crate::raster::tiler`];
//! at each sample the polygon's depth, from its plane in screen
//! coordinates, replaces the stored one if it is nearer.
//!
//! Screen coordinates (x, y in pixels, z the normalized depth) are a
//! projective image of world space, so polygons stay planar in them and
//! depth is exact at every sample. Ties keep the polygon drawn first, so the
//! image is deterministic. Rows are processed in parallel bands.
//!
//! Preconditions: planar polygons in screen coordinates; polygons seen
//! edge-on (no depth gradient defined) are skipped, as they cover no area.

use glam::{DVec2, DVec3};

use crate::raster::frame_buffer::{Band, FrameBuffer};
use crate::raster::tiler;

/// A polygon for the z-buffer: screen points, colour, id (never 0).
#[derive(Debug, Clone, PartialEq)]
pub struct DepthItem {
    /// Screen x, y in pixels (y up) and depth z.
    pub points: Vec<DVec3>,
    /// Colour.
    pub color: [f32; 3],
    /// Id written to the frame buffer.
    pub id: u32,
}

/// `z = a x + b y + c` for a polygon's plane, or `None` if edge-on.
pub fn depth_plane(points: &[DVec3]) -> Option<(f64, f64, f64)> {
    let n = crate::geometry::polygon::newell_vector(points.iter().copied());
    let scale = n.length();
    if scale.is_nan() || scale <= 0.0 || n.z.abs() <= 1e-12 * scale {
        return None;
    }
    let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let a = -n.x / n.z;
    let b = -n.y / n.z;
    Some((a, b, centre.z - a * centre.x - b * centre.y))
}

/// Screen outline, depth plane, and y range of an item.
type Prepared = (Vec<DVec2>, (f64, f64, f64), f64, f64);

/// Paints `items` by depth. Returns how many covered at least one pixel.
/// Stops early, between polygons, when a stop is requested
/// ([`crate::cancel`]): the caller looks at the request and discards the
/// frame.
pub fn paint(frame: &mut FrameBuffer, items: &[DepthItem]) -> usize {
    let w = frame.width;
    let prepared: Vec<Option<Prepared>> = items
        .iter()
        .map(|it| {
            let plane = depth_plane(&it.points)?;
            let pts: Vec<DVec2> = it.points.iter().map(|p| DVec2::new(p.x, p.y)).collect();
            let (lo, hi) = pts
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.y), hi.max(p.y))
                });
            Some((pts, plane, lo, hi))
        })
        .collect();
    frame.par_bands(|band| {
        let Band {
            lo,
            hi,
            colors,
            ids,
            ..
        } = band;
        let mut depth = vec![f64::INFINITY; colors.len()];
        for (k, prep) in prepared.iter().enumerate() {
            let Some((pts, (a, bb, c), ymin, ymax)) = prep else {
                continue;
            };
            // A stop request ends the band; the caller reports it.
            if crate::cancel::requested() {
                break;
            }
            if *ymax < lo as f64 || *ymin > hi as f64 + 1.0 {
                continue;
            }
            tiler::for_each_span(pts, lo..hi, w, |j, i0, i1| {
                let row = (hi - 1 - j) as usize;
                let yc = j as f64 + 0.5;
                for i in i0..i1 {
                    let px = row * w as usize + i as usize;
                    let z = a * (i as f64 + 0.5) + bb * yc + c;
                    if z < depth[px] {
                        depth[px] = z;
                        colors[px] = items[k].color;
                        ids[px] = items[k].id;
                    }
                }
            });
        }
    });
    frame.distinct_ids()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(x0: f64, x1: f64, z0: f64, z1: f64, id: u32) -> DepthItem {
        // z varies along x from z0 to z1.
        DepthItem {
            points: vec![
                DVec3::new(x0, 0.0, z0),
                DVec3::new(x0, 8.0, z0),
                DVec3::new(x1, 8.0, z1),
                DVec3::new(x1, 0.0, z1),
            ],
            color: [id as f32; 3],
            id,
        }
    }

    #[test]
    fn interpenetrating_quads_cross_where_depths_meet() {
        // Two quads over the same 8 x 8 pixels, depths crossing at x = 4.
        let items = [quad(0.0, 8.0, 0.0, 1.0, 1), quad(0.0, 8.0, 1.0, 0.0, 2)];
        let mut fb = FrameBuffer::new(8, 8, [0.0; 3]);
        assert_eq!(paint(&mut fb, &items), 2);
        for x in 0..8 {
            let want = if x < 4 { 1 } else { 2 };
            assert_eq!(fb.id(x, 3), want, "column {x}");
        }
    }

    #[test]
    fn plane_of_a_tilted_triangle() {
        let (a, b, c) = depth_plane(&[
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 3.0),
            DVec3::new(0.0, 1.0, 0.0),
        ])
        .unwrap();
        assert!((a - 2.0).abs() < 1e-12 && (b + 1.0).abs() < 1e-12 && (c - 1.0).abs() < 1e-12);
        assert!(depth_plane(&[DVec3::ZERO, DVec3::X, DVec3::Z]).is_none());
    }
}

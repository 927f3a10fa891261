//! The frame buffer and the painter's loop: polygons are sampled in list
//! order and either overwrite what is there (back to front, the
//! "overwriting principle" of 004 appendix) or fill only pixels still empty
//! (front to back). Rows are painted in parallel bands; every band sees the
//! polygons in the same order, so the image does not depend on the number
//! of threads.

use glam::DVec2;
use rayon::prelude::*;

use super::tiler;

/// How a polygon treats pixels already painted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PaintMode {
    /// Later polygons hide earlier ones (back-to-front list).
    Overwrite,
    /// Earlier polygons hide later ones (front-to-back list).
    FirstWins,
}

/// A polygon to paint: screen points (pixels, y up), a colour, an id.
#[derive(Debug, Clone, PartialEq)]
pub struct PaintItem {
    /// Screen coordinates in pixels, y up.
    pub points: Vec<DVec2>,
    /// Colour, components 0..1.
    pub color: [f32; 3],
    /// Identifier written to the id buffer (never 0, which is background).
    pub id: u32,
    /// Transparency `k_t` (0 opaque): back to front, painting over a pixel
    /// gives `I_new = I_old k_t + I_cur` (004 section 4.9); front to back,
    /// what lies behind is seen through it with weight `k_t`.
    pub transparency: f32,
    /// Gouraud vertex shades (one per point), else the single `color`.
    pub vertex_colors: Option<Vec<[f32; 3]>>,
    /// With vertex shades: a transparency per point, interpolated like a
    /// colour component (004 section 4.9), else `transparency` throughout.
    pub vertex_transparency: Option<Vec<f32>>,
    /// Phong highlight vectors (004 section 4.8), overriding the others.
    pub phong: Option<crate::shading::PhongVertices>,
}

/// An RGB frame buffer with an id per pixel. Row 0 is the top of the image.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameBuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Colours, row-major from the top.
    pub color: Vec<[f32; 3]>,
    /// Id of the polygon painted last at each pixel, 0 for background.
    pub ids: Vec<u32>,
}

/// Rows per parallel band.
pub const BAND: u32 = 16;

/// A band of rows of a frame buffer, painted by one thread: screen rows
/// `lo..hi`, counted from the bottom of the image.
pub struct Band<'a> {
    /// First screen row (from the bottom).
    pub lo: u32,
    /// One past the last screen row.
    pub hi: u32,
    /// Image width.
    pub width: u32,
    /// The band's colours, rows from the top.
    pub colors: &'a mut [[f32; 3]],
    /// The band's ids.
    pub ids: &'a mut [u32],
}

impl Band<'_> {
    /// Index in `colors`/`ids` of pixel column `i` of screen row `j`.
    pub fn index(&self, j: u32, i: u32) -> usize {
        (self.hi - 1 - j) as usize * self.width as usize + i as usize
    }
}

impl FrameBuffer {
    /// Runs `f` on bands of rows in parallel and collects the results in
    /// band order. Each band must see the same inputs in the same order, so
    /// that the image does not depend on the number of threads.
    pub fn par_bands<R: Send>(&mut self, f: impl Fn(Band<'_>) -> R + Sync + Send) -> Vec<R> {
        let (w, h) = (self.width, self.height);
        let band_len = (BAND * w) as usize;
        self.color
            .par_chunks_mut(band_len)
            .zip(self.ids.par_chunks_mut(band_len))
            .enumerate()
            .map(|(b, (colors, ids))| {
                let top_row = b as u32 * BAND;
                let rows_here = (colors.len() / w as usize) as u32;
                f(Band {
                    lo: h - (top_row + rows_here),
                    hi: h - top_row,
                    width: w,
                    colors,
                    ids,
                })
            })
            .collect()
    }

    /// A buffer cleared to `background`.
    pub fn new(width: u32, height: u32, background: [f32; 3]) -> FrameBuffer {
        let n = width as usize * height as usize;
        FrameBuffer {
            width,
            height,
            color: vec![background; n],
            ids: vec![0; n],
        }
    }

    /// Colour at pixel column `x`, row `y` from the top.
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        self.color[(y * self.width + x) as usize]
    }

    /// How many different polygons (non-zero ids) the image shows.
    pub fn distinct_ids(&self) -> usize {
        let mut ids: Vec<u32> = self.ids.iter().copied().filter(|&i| i != 0).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }

    /// Id at pixel column `x`, row `y` from the top.
    pub fn id(&self, x: u32, y: u32) -> u32 {
        self.ids[(y * self.width + x) as usize]
    }

    /// Paints `items` in order. Returns how many covered at least one pixel.
    /// Stops early, between polygons, when a stop is requested
    /// ([`crate::cancel`]): the caller looks at the request and discards
    /// the frame.
    pub fn paint(&mut self, items: &[PaintItem], mode: PaintMode) -> usize {
        let w = self.width;
        let bounds: Vec<(f64, f64)> = items
            .iter()
            .map(|it| {
                it.points
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p.y), hi.max(p.y))
                    })
            })
            .collect();
        let touched: Vec<Vec<bool>> = self.par_bands(|band| {
            let Band {
                lo,
                hi,
                colors,
                ids,
                ..
            } = band;
            let mut touched = vec![false; items.len()];
            // Front to back: what is in front is accumulated, with the
            // fraction of light still passing (`I = sum T_k I_k`,
            // `T_k = prod of the k_t in front`); what was in the buffer
            // is behind everything and is added at the end.
            let first_wins = mode == PaintMode::FirstWins;
            let n = if first_wins { colors.len() } else { 0 };
            let mut front = vec![[0.0f32; 3]; n];
            let mut passing = vec![1.0f32; n];
            for (k, item) in items.iter().enumerate() {
                let (ymin, ymax) = bounds[k];
                if ymax < lo as f64 || ymin > hi as f64 + 1.0 {
                    continue;
                }
                // A stop request ends the band; the caller reports it.
                if crate::cancel::requested() {
                    break;
                }
                let mut put = |j: u32, i: u32, color: [f32; 3], kt: f32| {
                    let px = (hi - 1 - j) as usize * w as usize + i as usize;
                    if first_wins {
                        if passing[px] <= 0.0 {
                            return;
                        }
                        for c in 0..3 {
                            front[px][c] += passing[px] * color[c];
                        }
                        passing[px] *= kt.max(0.0);
                        if ids[px] == 0 {
                            ids[px] = item.id;
                        }
                        touched[k] = true;
                        return;
                    }
                    colors[px] = if kt > 0.0 {
                        let old = colors[px];
                        std::array::from_fn(|c| old[c] * kt + color[c])
                    } else {
                        color
                    };
                    ids[px] = item.id;
                    touched[k] = true;
                };
                item_spans(item, lo..hi, w, &mut put);
            }
            for px in 0..n {
                colors[px] = std::array::from_fn(|c| front[px][c] + passing[px] * colors[px][c]);
            }
            touched
        });
        (0..items.len())
            .filter(|&k| touched.iter().any(|t| t[k]))
            .count()
    }
}

/// Calls `put(j, i, colour, transparency)` for every pixel `item` covers
/// in rows `rows` (from the band's bottom), with the colour of its shading:
/// Phong's attributes, vertex colours, or one colour.
fn item_spans(
    item: &PaintItem,
    rows: std::ops::Range<u32>,
    w: u32,
    put: &mut impl FnMut(u32, u32, [f32; 3], f32),
) {
    match (&item.phong, &item.vertex_colors) {
        (Some(ph), _) => {
            let mut v = vec![0.0f32; ph.stride()];
            tiler::for_each_attr_span(
                &item.points,
                &ph.attrs,
                ph.stride(),
                rows.clone(),
                w,
                |j, i0, i1, l, r| {
                    for i in i0..i1 {
                        tiler::lerp_at(i, l, r, &mut v);
                        put(j, i, ph.shade(&v), item.transparency);
                    }
                },
            )
        }
        (None, Some(vc)) => {
            // r, g, b and the vertex transparency.
            let kts = item.vertex_transparency.as_deref();
            let flat: Vec<f32> = vc
                .iter()
                .enumerate()
                .flat_map(|(q, c)| [c[0], c[1], c[2], kts.map_or(item.transparency, |t| t[q])])
                .collect();
            let mut v = [0.0f32; 4];
            tiler::for_each_attr_span(
                &item.points,
                &flat,
                4,
                rows.clone(),
                w,
                |j, i0, i1, l, r| {
                    for i in i0..i1 {
                        tiler::lerp_at(i, l, r, &mut v);
                        put(j, i, [v[0], v[1], v[2]], v[3]);
                    }
                },
            )
        }
        (None, None) => tiler::for_each_span(&item.points, rows.clone(), w, |j, i0, i1| {
            for i in i0..i1 {
                put(j, i, item.color, item.transparency);
            }
        }),
    }
}

/// A frame buffer fills from scan-converted rows (of its width).
impl crate::raster::scan::RowSink for FrameBuffer {
    fn row(&mut self, row: &crate::raster::scan::Row<'_>) -> crate::error::Result<()> {
        let w = self.width as usize;
        let at = row.y as usize * w;
        self.color[at..at + w].copy_from_slice(row.rgb);
        if let Some(ids) = row.ids {
            self.ids[at..at + w].copy_from_slice(ids);
        }
        Ok(())
    }

    fn wants_pixel_structs(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, x1: f64, y1: f64, id: u32) -> PaintItem {
        PaintItem {
            points: vec![
                DVec2::new(x0, y0),
                DVec2::new(x0, y1),
                DVec2::new(x1, y1),
                DVec2::new(x1, y0),
            ],
            color: [id as f32 / 10.0; 3],
            id,
            transparency: 0.0,
            vertex_colors: None,
            vertex_transparency: None,
            phong: None,
        }
    }

    #[test]
    fn overwrite_and_first_wins() {
        let items = [
            square(0.0, 0.0, 20.0, 40.0, 1),
            square(10.0, 0.0, 30.0, 40.0, 2),
        ];
        let mut fb = FrameBuffer::new(30, 40, [0.0; 3]);
        assert_eq!(fb.paint(&items, PaintMode::Overwrite), 2);
        assert_eq!((fb.id(5, 0), fb.id(15, 39), fb.id(25, 20)), (1, 2, 2));
        let mut fb = FrameBuffer::new(30, 40, [0.0; 3]);
        fb.paint(&items, PaintMode::FirstWins);
        assert_eq!((fb.id(5, 0), fb.id(15, 39), fb.id(25, 20)), (1, 1, 2));
    }

    #[test]
    fn transparency_blends_over_what_is_behind() {
        let mut front = square(0.0, 0.0, 4.0, 4.0, 2);
        front.transparency = 0.5;
        let mut fb = FrameBuffer::new(4, 4, [0.8, 0.4, 0.0]);
        fb.paint(&[front], PaintMode::Overwrite);
        // 0.8 * 0.5 + 0.2, 0.4 * 0.5 + 0.2, 0 + 0.2
        let c = fb.pixel(1, 1);
        assert!(
            (c[0] - 0.6).abs() < 1e-6 && (c[1] - 0.4).abs() < 1e-6 && (c[2] - 0.2).abs() < 1e-6
        );
    }

    #[test]
    fn transparency_is_the_same_in_both_orders() {
        // A transparent square over an opaque one over the background:
        // back to front and front to back give the same colours.
        let mut glass = square(0.0, 0.0, 4.0, 4.0, 2);
        glass.transparency = 0.5;
        let wall = square(2.0, 0.0, 6.0, 4.0, 1);
        let mut a = FrameBuffer::new(8, 4, [0.8, 0.4, 0.0]);
        a.paint(&[wall.clone(), glass.clone()], PaintMode::Overwrite);
        let mut b = FrameBuffer::new(8, 4, [0.8, 0.4, 0.0]);
        b.paint(&[glass, wall], PaintMode::FirstWins);
        for (p, q) in a.color.iter().zip(&b.color) {
            for c in 0..3 {
                assert!((p[c] - q[c]).abs() < 1e-6, "{p:?} {q:?}");
            }
        }
        assert_eq!(a.ids, b.ids);
    }

    #[test]
    fn rows_are_stored_from_the_top() {
        // A square in the bottom-left screen corner is at the last rows.
        let mut fb = FrameBuffer::new(4, 40, [0.0; 3]);
        fb.paint(&[square(0.0, 0.0, 1.0, 1.0, 7)], PaintMode::Overwrite);
        assert_eq!(fb.id(0, 39), 7);
        assert_eq!(fb.ids.iter().filter(|&&i| i == 7).count(), 1);
    }
}

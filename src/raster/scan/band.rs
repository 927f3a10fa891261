//! The virtual frame buffer of 004 section 5.10, in modern form: the image
//! is processed in bands of `act_lines` rows. Records are bucketed once by
//! the bands their y-range meets; each band runs through its bucket in
//! stream order, so every pixel sees the same records in the same order as
//! with a full frame and the result is identical. A finished band's rows
//! go to the sink top row first and its memory is reused for a later band.
//!
//! Bands replace Garcia's paging: his frame buffer was kept on disk and
//! scan lines paged in and out because polygons visit the image in any
//! order. Here every band sees all of its polygons before it is finished,
//! so a finished band never needs to come back and nothing is paged to
//! disk. Bands run in parallel (at most `threads` at once), rows are still
//! delivered in order, and the output does not depend on the thread count:
//! memory is (bands in flight) x `act_lines` x width pixels plus the
//! records.

use rayon::prelude::*;

use super::mask::SampleMask;
use super::shade::{Prepared, RowShader, Shade, Shading};
use super::tiler::Tiler;
use super::{PixelStruct, Row, RowSink, ScanStats};
use crate::error::{Error, Result};

/// What one record leaves at one pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Fragment {
    /// The pixel square lies wholly inside the polygon.
    pub full: bool,
    /// Exact area inside the pixel, 0 to 1.
    pub area: f64,
    /// Covered samples.
    pub mask: SampleMask,
    /// Whether the centre sample is covered.
    pub centre: bool,
}

/// A band's finished pixels, rows from the top.
#[derive(Debug, Default)]
pub(crate) struct BandOut {
    pub rgb: Vec<[f32; 3]>,
    pub coverage: Vec<u8>,
    pub mask: Vec<u16>,
    pub pixels: Vec<PixelStruct>,
    pub ids: Vec<u32>,
}

/// A pixel integrator: the hidden-surface and blending logic of a method.
pub(crate) trait Integrator: Send {
    /// Clears the state for a band of `pixels` pixels.
    fn reset(&mut self, pixels: usize);
    /// Blends a fragment at tree depth `level`; `shade` gives its colour.
    /// Returns whether any of it was visible.
    fn pixel(
        &mut self,
        px: usize,
        frag: &Fragment,
        level: u16,
        shade: impl FnOnce() -> Shade,
    ) -> bool;
    /// A special record at `level` covers the pixel.
    fn restore(&mut self, _px: usize, _level: u16) {}
    /// The final background pass.
    fn background(&mut self, px: usize, bg: [f32; 3]);
    /// Writes the band's colours and method outputs.
    fn output(&mut self, out: &mut BandOut);
    /// Peak and total pixel-fragments of the last band.
    fn fragments(&self) -> (usize, u64) {
        (0, 0)
    }
}

/// The shared, read-only description of a scan conversion.
#[derive(Debug)]
pub(crate) struct Plan<'a> {
    pub width: u32,
    pub height: u32,
    pub act_lines: u32,
    pub records: &'a [Prepared],
    /// Samples per pixel side.
    pub side: u32,
    pub ids: bool,
    /// Ids: the last record seen wins (back to front).
    pub last_wins: bool,
    pub background: Option<[f32; 3]>,
    pub coverage: bool,
    pub mask: bool,
    pub pixels: bool,
}

impl Plan<'_> {
    fn bands(&self) -> usize {
        self.height.div_ceil(self.act_lines) as usize
    }

    /// Screen rows (from the bottom) of band `b`.
    fn rows(&self, b: usize) -> std::ops::Range<u32> {
        let top = b as u32 * self.act_lines;
        let n = self.act_lines.min(self.height - top);
        self.height - top - n..self.height - top
    }

    /// Record indices per band, in stream order.
    fn buckets(&self) -> Vec<Vec<u32>> {
        let (h, l) = (self.height as f64, self.act_lines);
        let mut buckets = vec![Vec::new(); self.bands()];
        for (k, r) in self.records.iter().enumerate() {
            let first = r.ymin.floor().max(0.0);
            let end = r.ymax.ceil().min(h);
            if r.points.len() < 3 || first >= end {
                continue;
            }
            let top_row = |j: f64| (h - 1.0 - j) as u32 / l;
            for b in top_row(end - 1.0)..=top_row(first) {
                buckets[b as usize].push(k as u32);
            }
        }
        buckets
    }
}

/// One band's worth of state, reused from band to band.
struct Worker<I> {
    tiler: Tiler,
    shader: RowShader,
    integ: I,
    full: Fragment,
    out: BandOut,
    rows: u32,
    covered: Vec<u32>,
    written: u64,
}

impl<I: Integrator> Worker<I> {
    fn new(plan: &Plan<'_>, integ: I) -> Self {
        let n = plan.side;
        Worker {
            tiler: Tiler::new(plan.width, n, plan.ids && n != 1),
            shader: RowShader::default(),
            integ,
            full: Fragment {
                full: true,
                area: 1.0,
                mask: SampleMask::full(n * n),
                centre: true,
            },
            out: BandOut::default(),
            rows: 0,
            covered: Vec::new(),
            written: 0,
        }
    }

    fn run(&mut self, plan: &Plan<'_>, band: usize, bucket: &[u32]) {
        let rows = plan.rows(band);
        let w = plan.width as usize;
        let pixels = rows.len() * w;
        self.rows = rows.len() as u32;
        self.integ.reset(pixels);
        self.out.ids.clear();
        self.out.ids.resize(if plan.ids { pixels } else { 0 }, 0);
        self.covered.clear();
        self.written = 0;
        for &r in bucket {
            if self.record(plan, r as usize, rows.clone()) {
                self.covered.push(r);
            }
        }
        if let Some(bg) = plan.background {
            for px in 0..pixels {
                self.integ.background(px, bg);
            }
        }
        self.integ.output(&mut self.out);
    }

    /// Tiles record `r` into the band; returns whether it covered a pixel.
    fn record(&mut self, plan: &Plan<'_>, r: usize, rows: std::ops::Range<u32>) -> bool {
        let poly = &plan.records[r];
        let special = matches!(poly.shading, Shading::Special);
        let (w, hi, id) = (plan.width as usize, rows.end, r as u32 + 1);
        let Worker {
            tiler,
            shader,
            integ,
            full,
            out,
            written,
            ..
        } = self;
        let mut any = false;
        tiler.tile(poly, rows, |row| {
            shader.setup(poly, row.j, row.edges);
            let base = (hi - 1 - row.j) as usize * w;
            let mut put = |i: u32, frag: &Fragment| {
                let px = base + i as usize;
                if special {
                    integ.restore(px, poly.level);
                    return;
                }
                if integ.pixel(px, frag, poly.level, || shader.shade(poly, i)) {
                    *written += 1;
                    if plan.ids && frag.centre && (plan.last_wins || out.ids[px] == 0) {
                        out.ids[px] = id;
                    }
                }
            };
            for &(i0, i1) in row.runs {
                any = true;
                for i in i0..i1 {
                    put(i, full);
                }
            }
            for p in row.partials {
                if p.area > 0.0 || !p.mask.is_empty() || p.centre {
                    any = true;
                    let frag = Fragment {
                        full: false,
                        area: p.area,
                        mask: p.mask,
                        centre: p.centre,
                    };
                    put(p.col, &frag);
                }
            }
        });
        any
    }

    fn deliver(&self, plan: &Plan<'_>, band: usize, sink: &mut dyn RowSink) -> Result<()> {
        let w = plan.width as usize;
        let top = band as u32 * plan.act_lines;
        for r in 0..self.rows as usize {
            let s = r * w..(r + 1) * w;
            let out = &self.out;
            sink.row(&Row {
                y: top + r as u32,
                rgb: &out.rgb[s.clone()],
                coverage: plan.coverage.then(|| &out.coverage[s.clone()]),
                mask: plan.mask.then(|| &out.mask[s.clone()]),
                pixels: plan.pixels.then(|| &out.pixels[s.clone()]),
                ids: plan.ids.then(|| &out.ids[s.clone()]),
            })?;
        }
        Ok(())
    }
}

/// Runs the bands of `plan` with integrators from `make`, at most
/// `threads` bands at once (0: all cores), and hands the rows to `sink`.
pub(crate) fn convert<I: Integrator>(
    plan: &Plan<'_>,
    threads: usize,
    make: impl Fn() -> I,
    sink: &mut dyn RowSink,
) -> Result<ScanStats> {
    let pool = if threads > 0 {
        let p = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Invalid(format!("cannot start {threads} threads: {e}")))?;
        Some(p)
    } else {
        None
    };
    let in_flight = if threads > 0 {
        threads
    } else {
        rayon::current_num_threads()
    };
    let buckets = plan.buckets();
    let nb = buckets.len();
    let k = in_flight.clamp(1, nb.max(1));
    let mut workers: Vec<Worker<I>> = (0..k).map(|_| Worker::new(plan, make())).collect();
    let mut stats = ScanStats::default();
    let mut hit = vec![false; plan.records.len()];
    for start in (0..nb).step_by(k) {
        let count = k.min(nb - start);
        let job = |ws: &mut [Worker<I>]| {
            ws.par_iter_mut().enumerate().for_each(|(o, w)| {
                let b = start + o;
                w.run(plan, b, &buckets[b]);
            })
        };
        match &pool {
            Some(p) => p.install(|| job(&mut workers[..count])),
            None => job(&mut workers[..count]),
        }
        for (o, w) in workers[..count].iter().enumerate() {
            w.deliver(plan, start + o, sink)?;
            for &r in &w.covered {
                hit[r as usize] = true;
            }
            stats.pixels_written += w.written;
            let (peak, total) = w.integ.fragments();
            stats.peak_fragments = stats.peak_fragments.max(peak);
            stats.total_fragments += total;
        }
    }
    stats.polygons_tiled = hit.iter().filter(|&&h| h).count();
    Ok(stats)
}

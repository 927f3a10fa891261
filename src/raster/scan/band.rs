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
//! disk. Bands run in parallel on `threads` workers, each taking the next
//! band as it finishes one, while the calling thread hands the finished
//! bands to the sink in order (PNG encoding overlaps the scanning). The
//! workers are tasks of rayon's pool, whose threads are already running,
//! and never wait in it: one that finds 2 x `threads` bands waiting for
//! delivery returns, and the calling thread starts it again. A caller
//! that is itself in the pool gets threads of its own instead. The output
//! does not depend on the thread count; memory is at most 2 x `threads` +
//! 1 bands of `act_lines` x width pixels plus the records.

use std::sync::{Condvar, Mutex, MutexGuard};

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
    /// The pixels `base + i`, `i` in `cols`, that a record at `level`
    /// covers wholly (`full`), in order: the same as [`Self::pixel`] with
    /// `full` at each; `shade(i)` gives the colour at column `i` and
    /// `seen(i)` is called for each pixel of which some was visible.
    #[inline]
    fn span(
        &mut self,
        base: usize,
        cols: std::ops::Range<u32>,
        full: &Fragment,
        level: u16,
        mut shade: impl FnMut(u32) -> Shade,
        mut seen: impl FnMut(u32),
    ) {
        for i in cols {
            if self.pixel(base + i as usize, full, level, || shade(i)) {
                seen(i);
            }
        }
    }
    /// A special record at `level` covers the pixel.
    fn restore(&mut self, _px: usize, _level: u16) {}
    /// Whether a fragment at tree depth `level` would be hidden in every
    /// pixel of `pixels` and change none of them: those pixels need not
    /// be tiled.
    fn hidden(&self, _pixels: std::ops::Range<usize>, _level: u16) -> bool {
        false
    }
    /// The final background pass at one pixel.
    fn background(&mut self, px: usize, bg: [f32; 3]);
    /// The final background pass over the band's first `pixels` pixels.
    fn background_all(&mut self, pixels: usize, bg: [f32; 3]) {
        for px in 0..pixels {
            self.background(px, bg);
        }
    }
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
    /// The rows, from the top, handed to the sink: a part of the image.
    /// Only the bands that meet them are scan converted; each band is
    /// converted from its own bucket alone, so its rows are the same
    /// whatever other bands are converted.
    pub part: std::ops::Range<u32>,
}

impl Plan<'_> {
    /// The bands that meet [`Plan::part`], in order.
    fn wanted(&self) -> std::ops::Range<usize> {
        if self.part.is_empty() {
            return 0..0;
        }
        let first = (self.part.start / self.act_lines) as usize;
        let end = self.part.end.min(self.height).div_ceil(self.act_lines) as usize;
        first..end.max(first)
    }

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

/// A finished band, waiting to be delivered in order; its buffers are
/// reused for a later band.
#[derive(Default)]
struct Finished {
    band: usize,
    rows: u32,
    out: BandOut,
    /// Records that covered a pixel of the band.
    covered: Vec<u32>,
    written: u64,
    /// Peak and total pixel-fragments.
    fragments: (usize, u64),
}

/// One thread's scan conversion state, reused from band to band.
struct Worker<I> {
    tiler: Tiler,
    shader: RowShader,
    integ: I,
    full: Fragment,
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
        }
    }

    /// Scan converts band `band` (its records `bucket`) into `done`.
    /// Returns `false`, leaving the band unfinished, when a stop was
    /// requested ([`crate::cancel`]): it is looked at before every record
    /// and every row of one, so that a band of many records, or of one
    /// record over many rows, stops within a second.
    fn run(&mut self, plan: &Plan<'_>, band: usize, bucket: &[u32], done: &mut Finished) -> bool {
        let rows = plan.rows(band);
        let w = plan.width as usize;
        let pixels = rows.len() * w;
        done.band = band;
        done.rows = rows.len() as u32;
        self.integ.reset(pixels);
        done.out.ids.clear();
        done.out.ids.resize(if plan.ids { pixels } else { 0 }, 0);
        done.covered.clear();
        done.written = 0;
        for &r in bucket {
            if crate::cancel::requested() {
                return false;
            }
            if self.record(plan, r as usize, rows.clone(), done) {
                done.covered.push(r);
            }
        }
        if crate::cancel::requested() {
            return false;
        }
        if let Some(bg) = plan.background {
            self.integ.background_all(pixels, bg);
        }
        self.integ.output(&mut done.out);
        done.fragments = self.integ.fragments();
        true
    }

    /// Tiles record `r` into the band; returns whether it covered a pixel.
    fn record(
        &mut self,
        plan: &Plan<'_>,
        r: usize,
        rows: std::ops::Range<u32>,
        done: &mut Finished,
    ) -> bool {
        let poly = &plan.records[r];
        let special = matches!(poly.shading, Shading::Special);
        let (w, hi, id) = (plan.width as usize, rows.end, r as u32 + 1);
        let Worker {
            tiler,
            shader,
            integ,
            full,
        } = self;
        let (ids, written) = (&mut done.out.ids, &mut done.written);
        let mut any = false;
        for j in tiler.rows(poly, rows) {
            let Some(columns) = tiler.enter(j) else {
                continue;
            };
            // Stopping: the rows left are not painted.
            if crate::cancel::requested() {
                break;
            }
            let base = (hi - 1 - j) as usize * w;
            // A row that would change no pixel is skipped, once the
            // figures know whether the record covers a pixel of the band.
            let pixels = base + columns.start as usize..base + columns.end as usize;
            if !special && integ.hidden(pixels, poly.level) {
                any = any || tiler.covers(j);
                continue;
            }
            let Some(row) = tiler.cover(j) else {
                continue;
            };
            shader.setup(poly, row.j, row.edges);
            let mut seen = |i: u32, frag: &Fragment| {
                let px = base + i as usize;
                *written += 1;
                if plan.ids && frag.centre && (plan.last_wins || ids[px] == 0) {
                    ids[px] = id;
                }
            };
            for &(i0, i1) in row.runs {
                any = true;
                if special {
                    (i0..i1).for_each(|i| integ.restore(base + i as usize, poly.level));
                    continue;
                }
                let shade = |i: u32| shader.shade(poly, i);
                integ.span(base, i0..i1, full, poly.level, shade, |i| seen(i, full));
            }
            let mut put = |i: u32, frag: &Fragment| {
                let px = base + i as usize;
                if special {
                    integ.restore(px, poly.level);
                    return;
                }
                if integ.pixel(px, frag, poly.level, || shader.shade(poly, i)) {
                    seen(i, frag);
                }
            };
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
        }
        any
    }
}

/// Hands a finished band's rows to `sink`, top row first.
fn deliver(plan: &Plan<'_>, done: &Finished, sink: &mut dyn RowSink) -> Result<()> {
    let w = plan.width as usize;
    let top = done.band as u32 * plan.act_lines;
    let out = &done.out;
    for r in 0..done.rows as usize {
        let y = top + r as u32;
        if !plan.part.contains(&y) {
            continue;
        }
        let s = r * w..(r + 1) * w;
        sink.row(&Row {
            y,
            rgb: &out.rgb[s.clone()],
            coverage: plan.coverage.then(|| &out.coverage[s.clone()]),
            mask: plan.mask.then(|| &out.mask[s.clone()]),
            pixels: plan.pixels.then(|| &out.pixels[s.clone()]),
            ids: plan.ids.then(|| &out.ids[s.clone()]),
        })?;
    }
    Ok(())
}

/// The bands' progress, shared by the workers and the delivering thread.
#[derive(Default)]
struct Schedule {
    /// The next band to start (an index into the wanted bands).
    next: usize,
    /// Bands delivered so far (in order, counted like `next`).
    delivered: usize,
    /// Finished bands not yet delivered.
    done: std::collections::BTreeMap<usize, Finished>,
    /// Buffers of delivered bands, for reuse.
    spare: Vec<Finished>,
    /// Set when delivery failed, a worker panicked or a stop was
    /// requested ([`crate::cancel`]): everyone stops.
    stop: bool,
    /// Workers running as tasks of rayon's pool (not as threads).
    active: usize,
}

impl Schedule {
    /// Whether bands of the `n` are left to start, and no stop came.
    fn has_more(&self, n: usize) -> bool {
        !self.stop && self.next < n
    }

    /// Whether a worker may start the next of `n` bands: fewer than
    /// `window` wait for delivery.
    fn can_start(&self, n: usize, window: usize) -> bool {
        self.has_more(n) && self.next < self.delivered + window
    }
}

/// The schedule and its condition variable.
struct Shared {
    state: Mutex<Schedule>,
    changed: Condvar,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, Schedule> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn wait<'g>(&self, g: MutexGuard<'g, Schedule>) -> MutexGuard<'g, Schedule> {
        self.changed.wait(g).unwrap_or_else(|e| e.into_inner())
    }

    fn stop(&self) {
        self.lock().stop = true;
        self.changed.notify_all();
    }
}

/// Stops everyone if its thread unwinds: a worker's, so that the
/// delivering thread does not wait for a band that will never come, or
/// the delivering thread's, so that no worker waits for a delivery.
struct StopOnPanic<'a>(&'a Shared);

impl Drop for StopOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.stop();
        }
    }
}

/// A worker: takes the next band while fewer than `window` bands wait for
/// delivery, converts it and hands it back. When the window is full a
/// thread of its own (`wait`) waits; a task of rayon's pool returns, and
/// the delivering thread starts it again once a band is delivered, since
/// a pool thread must not block: the sink may use the pool itself.
fn work<I: Integrator>(worker: &mut Worker<I>, crew: &Crew<'_, '_>, wait: bool) {
    let Crew {
        plan,
        buckets,
        shared,
        window,
    } = *crew;
    let _guard = StopOnPanic(shared);
    let wanted = plan.wanted();
    let n = wanted.len();
    let mut g = shared.lock();
    loop {
        while wait && g.has_more(n) && !g.can_start(n, window) {
            g = shared.wait(g);
        }
        if !g.can_start(n, window) {
            return;
        }
        let band = wanted.start + g.next;
        g.next += 1;
        let mut done = g.spare.pop().unwrap_or_default();
        drop(g);
        let finished = worker.run(plan, band, &buckets[band], &mut done);
        g = shared.lock();
        if !finished {
            // Cancelled: the delivering thread reports it.
            g.stop = true;
            shared.changed.notify_all();
            return;
        }
        g.done.insert(band, done);
        shared.changed.notify_all();
    }
}

/// A worker as a task of rayon's pool: an idle worker's state runs
/// [`work`] until no band can start, then is put back.
fn task<I: Integrator>(idle: &Mutex<Vec<Worker<I>>>, crew: &Crew<'_, '_>) {
    let taken = idle.lock().unwrap_or_else(|e| e.into_inner()).pop();
    if let Some(mut worker) = taken {
        work(&mut worker, crew, false);
        idle.lock().unwrap_or_else(|e| e.into_inner()).push(worker);
    }
    crew.shared.lock().active -= 1;
    crew.shared.changed.notify_all();
}

/// Runs the bands of `plan` with integrators from `make` on `threads`
/// threads (0: as many as cores), while this thread hands the rows, in
/// order, to `sink`. At most twice as many bands as threads are in flight
/// or waiting, so memory stays bounded whatever the image height.
pub(crate) fn convert<I: Integrator>(
    plan: &Plan<'_>,
    threads: usize,
    make: impl Fn() -> I,
    sink: &mut dyn RowSink,
) -> Result<ScanStats> {
    let buckets = plan.buckets();
    let nb = plan.wanted().len();
    let threads = if threads > 0 {
        threads
    } else {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    };
    let k = threads.clamp(1, nb.max(1));
    let window = 2 * k;
    let mut workers: Vec<Worker<I>> = (0..k).map(|_| Worker::new(plan, make())).collect();
    let shared = Shared {
        state: Mutex::new(Schedule::default()),
        changed: Condvar::new(),
    };
    let mut stats = ScanStats::default();
    let mut hit = vec![false; plan.records.len()];
    let deliver = |start: &mut dyn FnMut(&mut Schedule)| {
        // A sink that panics stops the workers too, or threads waiting
        // for the window would never be joined.
        let _stop = StopOnPanic(&shared);
        let delivered = deliver_all(plan, nb, &shared, sink, &mut stats, &mut hit, start);
        shared.stop();
        delivered
    };
    let crew = Crew {
        plan,
        buckets: &buckets,
        shared: &shared,
        window,
    };
    if rayon::current_thread_index().is_none() {
        crew.as_tasks(workers, deliver)?;
    } else {
        crew.on_threads(&mut workers, deliver)?;
    }
    stats.polygons_tiled = hit.iter().filter(|&&h| h).count();
    Ok(stats)
}

/// What every worker shares: the plan, its buckets, the schedule and the
/// window of bands that may wait for delivery.
#[derive(Clone, Copy)]
struct Crew<'a, 'p> {
    plan: &'a Plan<'p>,
    buckets: &'a [Vec<u32>],
    shared: &'a Shared,
    window: usize,
}

impl Crew<'_, '_> {
    /// The workers as tasks of rayon's pool, whose threads are already
    /// running (a new thread could start milliseconds late on cores busy
    /// with the pool's last work); `deliver` starts them as bands may
    /// start.
    fn as_tasks<I: Integrator>(
        &self,
        workers: Vec<Worker<I>>,
        deliver: impl FnOnce(&mut dyn FnMut(&mut Schedule)) -> Result<()>,
    ) -> Result<()> {
        let (k, n) = (workers.len(), self.plan.wanted().len());
        let idle = Mutex::new(workers);
        let idle = &idle;
        rayon::in_place_scope(|scope| {
            deliver(&mut |g: &mut Schedule| {
                while g.active < k && g.can_start(n, self.window) {
                    g.active += 1;
                    let crew = *self;
                    scope.spawn(move |_| task(idle, &crew));
                }
            })
        })
    }

    /// The workers on threads of their own, for a caller within rayon's
    /// pool (its own parallel work): no worker then waits for a pool
    /// thread that is waiting for it.
    fn on_threads<I: Integrator>(
        &self,
        workers: &mut [Worker<I>],
        deliver: impl FnOnce(&mut dyn FnMut(&mut Schedule)) -> Result<()>,
    ) -> Result<()> {
        let crew = *self;
        std::thread::scope(|scope| {
            for w in workers {
                let started = std::thread::Builder::new()
                    .name("scan band".into())
                    .spawn_scoped(scope, move || work(w, &crew, true));
                if let Err(e) = started {
                    crew.shared.stop();
                    return Err(Error::Invalid(format!("cannot start a scan thread: {e}")));
                }
            }
            deliver(&mut |_: &mut Schedule| {})
        })
    }
}

/// Delivers the `nb` bands in order as the workers finish them; `start`
/// starts workers that are not running, before each wait and after each
/// delivery.
fn deliver_all(
    plan: &Plan<'_>,
    nb: usize,
    shared: &Shared,
    sink: &mut dyn RowSink,
    stats: &mut ScanStats,
    hit: &mut [bool],
    start: &mut dyn FnMut(&mut Schedule),
) -> Result<()> {
    for band in plan.wanted().take(nb) {
        crate::cancel::check()?;
        let done = {
            let mut g = shared.lock();
            loop {
                if let Some(d) = g.done.remove(&band) {
                    break d;
                }
                if g.stop {
                    crate::cancel::check()?;
                    return Err(Error::Invalid("a scan thread failed".into()));
                }
                start(&mut g);
                g = shared.wait(g);
            }
        };
        deliver(plan, &done, sink)?;
        for &r in &done.covered {
            hit[r as usize] = true;
        }
        stats.pixels_written += done.written;
        stats.peak_fragments = stats.peak_fragments.max(done.fragments.0);
        stats.total_fragments += done.fragments.1;
        let mut g = shared.lock();
        g.spare.push(done);
        g.delivered += 1;
        start(&mut g);
        shared.changed.notify_all();
    }
    Ok(())
}

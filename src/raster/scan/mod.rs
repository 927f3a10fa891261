//! The scan conversion processors of Garcia 1986 (004 chapter 5): a
//! [`RecordStream`] in, rows of pixels out, top row first.
//!
//! The types below are the fixed interface between the record stream, the
//! scan converters and the outputs (PNG, separations, pixel-struct files).
//! Inside: the tiler of section 5.5 (`tiler`), the integrators of
//! sections 5.6-5.9 (`single`, `multilevel`, `painter`) and the
//! virtual frame buffer of section 5.10 (`band`).
//!
//! Which stream each method accepts, and which hidden-surface logic runs:
//!
//! | method | back to front | ftb, pre-blended | ftb, post-blended |
//! |---|---|---|---|
//! | `Point` | painter | single-level, 1 sample | multi-level, 1 sample |
//! | `Area`, `Mask`, `Hybrid` | error | single-level | error |
//! | `Multilevel` | error | error | multi-level, 16 samples |
//! | `Supersample(n)` | error | single-level, n² samples | multi-level, n² samples |
//!
//! With [`TransparencyRule::Donovan`] (Donovan 000 section 6, rule (3))
//! the table is different: the rule needs the colour behind a transparent
//! surface before the surface is blended, which a front-to-back stream
//! never has, so every method takes a back-to-front (pre-blended) stream
//! and paints it with the painter, `Point` at the pixel centre,
//! `Supersample(n)` at n² samples and `Area`, `Mask`, `Hybrid`,
//! `Multilevel` at the 16 samples of the 4 x 4 pixel mask; a
//! front-to-back stream is an error.
//!
//! Any other combination, `Supersample(n)` with `n` outside 1..=16, a
//! multi-level run with a record level outside 1..=31, an empty image and
//! [`TransparencyRule::Coverage`] (section 5.6) with anything but the
//! single-level logic are [`Error::Invalid`].
//!
//! Ids ([`ScanOptions::ids`]): front to back, the first record (in stream
//! order) that covers the pixel centre and leaves a visible share in the
//! pixel; back to front, the last record painted at the centre. Special
//! records never become ids. With 16 or `N x N` samples "visible" is
//! judged on the pixel's samples, not on the centre alone.
//!
//! # Design notes
//!
//! - `tiler`: section 5.5 for any simple polygon. An active edge list is
//!   walked row by row; each edge is clipped to the row strip with its
//!   fractional heights and adds signed trapezoid areas to the columns it
//!   crosses, so a running sum along the row gives every pixel's exact area;
//!   pixels no edge passes through form constant runs (full, empty, or
//!   partly covered when a horizontal edge crosses the strip). Masks come
//!   from `n x n` subpixel centres with the point sampler's half-open rule,
//!   so abutting polygons own every sample once. Shades follow Garcia's two
//!   steps (along edges, then across), at the pixel centre. The band walks
//!   a polygon's rows itself (`rows`, `enter`, `cover`): entering a row
//!   gives the columns its coverage can reach, and a row whose pixels the
//!   hidden-surface logic says would all stay as they are (`hidden`:
//!   method 4's case 2) is passed over before its masks are found.
//! - Hidden-surface logic, one module each: `single` (methods 1-3 and the
//!   pre-blended point/supersample paths), `multilevel` (method 4's six
//!   cases, fragment pool, restore records, final background pass; also
//!   point sampling and Donovan's N x N on post-blended streams), `painter`
//!   (back to front, overwriting, at the pixel centre or at the N x N or
//!   4 x 4 samples of every method: the only logic Donovan's transparency
//!   rule (3) can run under, since it needs the colour behind first). Which one runs follows from the method and
//!   the stream (`scan/mod.rs` has the table); a wrong pairing is an error
//!   naming the setting to change.
//! - `band`: the virtual frame buffer. Records are bucketed by band once;
//!   workers each take the next band of `act_lines` rows as they finish
//!   one, and the calling thread hands finished bands, top first and in
//!   order, to a `RowSink` (frame buffer, streamed PNG, separations,
//!   pixel-struct file) while the others scan; at most 2 x threads bands
//!   wait. The workers are tasks of rayon's pool, already running when the
//!   tree is done (threads spawned then started milliseconds late on busy
//!   cores); a task that finds the window full returns rather than wait in
//!   the pool, where a sink's own parallel work may need it, and the
//!   calling thread starts it again after a delivery. A caller inside the
//!   pool gets threads of its own. The output is bit-identical for any
//!   thread count and band height.
//! - Transparency follows 004 section 4.9 (`I = I_front + k_t I_behind`) in
//!   plytrace's own picture, whatever the method, so every method agrees
//!   with the painter inside polygons; rftb2 and rftb4, to which the manual
//!   gives no transparency, keep it too. rftb1 and rftb3 follow their manual
//!   page and section 5.6 (`TransparencyRule::Coverage`: a transparent
//!   fragment covers `A (1 - T)` and adds that share of its intensity).
//!   Blending is linear in the written values (no gamma), as the thesis's
//!   arithmetic.

mod band;
mod edge;
mod mask;
mod multilevel;
mod painter;
mod shade;
mod single;
mod tiler;

use crate::error::{Error, Result};
use crate::tree::RecordStream;
use band::{Plan, convert};
use glam::DVec2;
use multilevel::MultiLevel;
use painter::Painter;
use shade::Prepared;
use single::{Measure, SingleLevel};

/// How coverage is found and blended (004 sections 5.6-5.9; Donovan 000
/// section 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// One sample at the pixel centre (the preview, `--aa none`).
    Point,
    /// Method 1 (rftb1): exact area coverage, one coverage byte.
    Area,
    /// Method 2 (rftb2): 4x4 pixel masks.
    Mask,
    /// Method 3 (rftb3): 4x4 masks and exact area.
    Hybrid,
    /// Method 4 (rftb4): multi-level pixel masks (pixel-structs).
    Multilevel,
    /// Donovan's N x N supersampling, N from 1 to 16.
    Supersample(u32),
}

/// How a transparent polygon blends with what is behind it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TransparencyRule {
    /// 004 section 4.9: `I = I_cur + k_t I_behind`.
    #[default]
    Garcia,
    /// Donovan 000 rule (3): `I = I_a` if `I_a > I_b`, else
    /// `(1 - w) I_a + w I_b`.
    Donovan,
    /// 004 section 5.6, the pixel-coverage rule of rftb1 and rftb3: a
    /// transparent fragment covers `Ā = A (1 - T)`, adds `A_cov I_cur`
    /// with `A_cov = min(Ā, 1 - A_old)`, and the coverage becomes
    /// `min(A_old + Ā, 1)`. Front-to-back pre-blended streams only (the
    /// single-level methods).
    Coverage,
}

/// Options of one scan conversion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The method.
    pub method: Method,
    /// Rows of the frame buffer kept in memory at once per band (the
    /// manual's `act-lines`, at least 1).
    pub act_lines: u32,
    /// Paint the background polygon after everything (`-B`; always for
    /// plytrace's own picture).
    pub paint_background: bool,
    /// The transparency rule.
    pub transparency: TransparencyRule,
    /// Worker threads; 0 means all cores. The output does not depend on it.
    pub threads: usize,
    /// Also produce, per pixel, the 1-based index of the record seen at
    /// the pixel centre (0 for none).
    pub ids: bool,
    /// Refuse, before tiling, records whose bounding boxes within the
    /// image add up to more than this many times its pixels
    /// ([`crate::budget::Budgets::overdraw`]).
    pub max_overdraw: u64,
}

impl ScanOptions {
    /// The `n x n` grid of samples per pixel that alone decides what is
    /// seen (the pixel mask, the centre, supersampling; with Donovan's
    /// rule every method paints at samples), or `None` for the methods
    /// that also weigh exact areas (1 and 3), where a sliver between
    /// samples counts.
    pub fn sample_grid(&self) -> Option<u32> {
        match (self.method, self.transparency) {
            (Method::Supersample(n), _) => Some(n),
            (Method::Point, _) => Some(1),
            (_, TransparencyRule::Donovan) => Some(4),
            (Method::Mask | Method::Multilevel, _) => Some(4),
            (Method::Area | Method::Hybrid, _) => None,
        }
    }
}

/// Figures of one scan conversion.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ScanStats {
    /// Records that covered at least one pixel.
    pub polygons_tiled: usize,
    /// Pixel writes.
    pub pixels_written: u64,
    /// Method 4: the most pixel-fragments alive at once in one band of
    /// `act_lines` rows (so it does not depend on the thread count).
    pub peak_fragments: usize,
    /// Method 4: pixel-fragments allocated in all.
    pub total_fragments: u64,
}

/// A pixel-fragment left at a complex pixel (004 figure 5.16), as saved in
/// a pixel-struct file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SavedFragment {
    /// The 4x4 pixel mask, bit `4 * row + column`, row 0 at the top.
    pub pmask: u16,
    /// The saved pixel status (figure 5.17).
    pub pstat: u8,
    /// The pixel coverage, 0 to 255.
    pub pcover: u8,
}

/// A pixel-struct (004 figure 5.15) of method 4.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PixelStruct {
    /// Accumulated colour.
    pub rgb: [u8; 3],
    /// Pixel status (figure 5.17): bits 0-4 the tree depth, bit 5
    /// covered, bit 6 complex.
    pub pixstat: u8,
    /// The fragment list, head (deepest level) first; empty for simple
    /// pixels.
    pub fragments: Vec<SavedFragment>,
}

/// One finished row of the frame buffer.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    /// Row index from the top.
    pub y: u32,
    /// Colours, 0 to 1, the written intensities (no gamma).
    pub rgb: &'a [[f32; 3]],
    /// Methods 1 and 3: coverage bytes (the `.a` separation).
    pub coverage: Option<&'a [u8]>,
    /// Methods 2 and 3: pixel masks (the `.m` separation).
    pub mask: Option<&'a [u16]>,
    /// Method 4: pixel-structs.
    pub pixels: Option<&'a [PixelStruct]>,
    /// With [`ScanOptions::ids`]: record ids.
    pub ids: Option<&'a [u32]>,
}

impl<'a> Row<'a> {
    /// A row of colours alone (no coverage, masks, pixel-structs or ids).
    pub fn colors(y: u32, rgb: &'a [[f32; 3]]) -> Row<'a> {
        Row {
            y,
            rgb,
            coverage: None,
            mask: None,
            pixels: None,
            ids: None,
        }
    }
}

/// Receives the rows of a scan conversion, top row first, each once.
pub trait RowSink {
    /// Takes one row.
    fn row(&mut self, row: &Row<'_>) -> Result<()>;

    /// Whether the rows must carry method 4's pixel-structs
    /// ([`Row::pixels`]). Making them costs a few percent of the scan
    /// conversion; a sink that only looks at colours says `false`.
    fn wants_pixel_structs(&self) -> bool {
        true
    }
}

/// The work of a row for [`part_rows`], in pixels' worth: the row's
/// pixels count 1 each, a record's bounding box crossing it `.0` per
/// pixel of its width, and each record crossing it `.1`. A pixel costs
/// far more than a span pixel of a record: each is integrated, output and
/// encoded whatever covers it. Fitted by least squares to the measured
/// time of each band of office1, office2, gallery and mirror at
/// 8192 x 8192 and 16384 x 16384, methods 1 and 4 (a record pixel 0.12
/// to 0.30, a record row 7 to 35 pixels' worth); with these weights the
/// longest of 16 parts takes 1.1 to 1.5 times the mean, against 1.4 to
/// 2.0 when a record's pixel counted as much as a row's.
const ROW_WORK: (f64, f64) = (0.2, 8.0);

/// Scan converts `stream` and hands its rows, top first, to `sink`.
pub fn scan_convert(
    stream: &RecordStream,
    options: &ScanOptions,
    sink: &mut dyn RowSink,
) -> Result<ScanStats> {
    scan_convert_rows(stream, options, 0..options.height, sink)
}

/// The rows (from the top) of part `index` of `count` of `stream`'s
/// image, chosen so that the parts have about equal work (see
/// `ROW_WORK`), and part boundaries fall on band boundaries (of
/// `options.act_lines` rows), so no band is converted by two parts. The
/// parts cover every row once, in order; every process given the same
/// stream and options finds the same rows. A part may have no rows.
pub fn part_rows(
    stream: &RecordStream,
    options: &ScanOptions,
    index: u32,
    count: u32,
) -> std::ops::Range<u32> {
    let (w, h) = (options.width, options.height);
    let count = count.max(1);
    let index = index.min(count - 1);
    if h == 0 {
        return 0..0;
    }
    let act_lines = options.act_lines.clamp(1, h);
    let bands = h.div_ceil(act_lines) as usize;
    // Work a band (ROW_WORK): over its rows, the pixels, the records'
    // widths and the records (difference arrays over rows from the top).
    let mut delta = vec![[0.0f64; 2]; h as usize + 1];
    let (wf, hf) = (f64::from(w), f64::from(h));
    for r in &stream.records {
        if r.points.len() < 3 {
            continue;
        }
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in &r.points {
            let q = DVec2::new(p[0] as f64 * wf, p[1] as f64 * hf);
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let width = hi.x.min(wf) - lo.x.max(0.0);
        let (bottom, top) = (lo.y.max(0.0).floor(), hi.y.min(hf).ceil());
        let meets = width > 0.0 && top > bottom;
        if !meets {
            continue;
        }
        // Rows from the top: h - top .. h - bottom.
        let (first, end) = ((hf - top) as usize, (hf - bottom) as usize);
        delta[first][0] += width;
        delta[first][1] += 1.0;
        delta[end.min(h as usize)][0] -= width;
        delta[end.min(h as usize)][1] -= 1.0;
    }
    let mut band_work = vec![0.0f64; bands];
    let mut running = [0.0; 2];
    let (per_width, per_record) = ROW_WORK;
    for (y, d) in delta.iter().take(h as usize).enumerate() {
        running = [running[0] + d[0], running[1] + d[1]];
        band_work[y / act_lines as usize] +=
            wf + per_width * running[0].max(0.0) + per_record * running[1].max(0.0);
    }
    let total: f64 = band_work.iter().sum();
    // Part k starts at the first band where the work before it reaches
    // k / count of the total.
    let start_of = |k: u32| -> u32 {
        if k == 0 {
            return 0;
        }
        if k >= count {
            return h;
        }
        let goal = total * f64::from(k) / f64::from(count);
        let mut before = 0.0;
        for (b, work) in band_work.iter().enumerate() {
            if before + work / 2.0 >= goal {
                return (b as u32 * act_lines).min(h);
            }
            before += work;
        }
        h
    };
    let (a, b) = (start_of(index), start_of(index + 1));
    a..b.max(a)
}

/// Scan converts the part of `stream`'s image made of `rows` (from the
/// top) and hands those rows, top first, to `sink`: each row is exactly
/// the row [`scan_convert`] gives, since the bands the rows lie in are
/// converted as they would be for the whole image, and the other bands
/// are not converted at all. The statistics count the part's bands.
pub fn scan_convert_rows(
    stream: &RecordStream,
    options: &ScanOptions,
    rows: std::ops::Range<u32>,
    sink: &mut dyn RowSink,
) -> Result<ScanStats> {
    if rows.end > options.height || rows.start > rows.end {
        return Err(Error::Invalid(format!(
            "rows {}..{} are not rows of a {}-row image",
            rows.start, rows.end, options.height
        )));
    }
    let logic = choose(stream, options)?;
    let (w, h) = (options.width, options.height);
    let act_lines = options.act_lines.clamp(1, h);
    let (records, area) = prepare_records(stream, options, &rows)?;
    crate::cancel::check()?;
    check_overdraw_area(area, records.len(), w, h, options.max_overdraw)?;
    if let Logic::Multi(_) = logic {
        check_levels(&records)?;
    }
    let m = options.method;
    let side = match (m, logic) {
        (Method::Supersample(n), _) => n,
        (Method::Point, _) => 1,
        _ => 4,
    };
    let bg = stream
        .background
        .unwrap_or([0; 3])
        .map(|c| c as f32 / 255.0);
    let plan = Plan {
        width: w,
        height: h,
        act_lines,
        records: &records,
        side,
        ids: options.ids,
        last_wins: logic == Logic::Painter,
        background: (options.paint_background && logic != Logic::Painter).then_some(bg),
        // The painter leaves no coverage, masks or pixel-structs.
        coverage: logic != Logic::Painter && matches!(m, Method::Area | Method::Hybrid),
        mask: logic != Logic::Painter && matches!(m, Method::Mask | Method::Hybrid),
        pixels: logic != Logic::Painter && m == Method::Multilevel && sink.wants_pixel_structs(),
        part: rows,
    };
    let t = options.threads;
    match logic {
        Logic::Painter => {
            let initial = if options.paint_background {
                bg
            } else {
                [0.0; 3]
            };
            convert(
                &plan,
                t,
                || Painter::new(options.transparency, initial, side * side),
                sink,
            )
        }
        Logic::Single(measure) => convert(
            &plan,
            t,
            || SingleLevel::new(measure, side * side, options.transparency),
            sink,
        ),
        Logic::Multi(n) => convert(&plan, t, || MultiLevel::new(n, plan.pixels), sink),
    }
}

/// The records of `stream` prepared for tiling, in order (in parallel, in
/// a pool of `options.threads` when given), with the pixels their
/// bounding boxes cover in all. For a part (`rows` not the whole image),
/// records outside its bands are checked, not prepared (their bucket would
/// be skipped anyway).
fn prepare_records(
    stream: &RecordStream,
    options: &ScanOptions,
    rows: &std::ops::Range<u32>,
) -> Result<(Vec<Prepared>, f64)> {
    let (w, h) = (options.width, options.height);
    let act_lines = options.act_lines.clamp(1, h);
    let whole = *rows == (0..h);
    let wanted = rows.start / act_lines..rows.end.div_ceil(act_lines);
    let needed = |r: &crate::tree::Record| {
        if whole {
            return true;
        }
        let (ymin, ymax) = shade::y_range(r, h);
        let (hf, first, end) = (h as f64, ymin.floor().max(0.0), ymax.ceil().min(h as f64));
        if first >= end {
            return false;
        }
        let top_row = |j: f64| (hf - 1.0 - j) as u32 / act_lines;
        top_row(end - 1.0) < wanted.end && top_row(first) >= wanted.start
    };
    let one = |r: &crate::tree::Record| -> (Prepared, f64) {
        if needed(r) {
            let p = shade::prepare(r, w, h);
            let area = tiled_area_of(p.points.iter().copied(), w, h);
            return (p, area);
        }
        let points = r
            .points
            .iter()
            .map(|p| DVec2::new(p[0] as f64 * w as f64, p[1] as f64 * h as f64));
        let skipped = Prepared {
            points: Vec::new(),
            shading: shade::Shading::Special,
            level: r.level,
            ymin: 0.0,
            ymax: 0.0,
        };
        (skipped, tiled_area_of(points, w, h))
    };
    // Every record checked first (the first bad one, whatever the
    // threads), then prepared into lists made at their size.
    let prepare = || -> Result<(Vec<Prepared>, Vec<f64>)> {
        use rayon::prelude::*;
        let records = &stream.records;
        let bad = records
            .par_iter()
            .enumerate()
            .find_map_first(|(k, r)| shade::validate(r, k, w, h).err());
        match bad {
            Some(e) => Err(e),
            None => Ok(records.par_iter().map(one).unzip()),
        }
    };
    let (prepared, areas) = crate::threads::Pool::new(options.threads)?.install(prepare)?;
    Ok((prepared, areas.iter().sum()))
}

/// Method 4 keeps a record's level in a pixel-struct's five bits: a
/// level outside 1..31 is refused, naming the record.
fn check_levels(records: &[Prepared]) -> Result<()> {
    match records
        .iter()
        .enumerate()
        .find(|(_, r)| !(1..=31).contains(&r.level))
    {
        Some((k, r)) => Err(Error::Invalid(format!(
            "record {}: level {} is outside 1..31, the depths a pixel-struct can hold",
            k + 1,
            r.level
        ))),
        None => Ok(()),
    }
}

/// Pixels of a record's bounding box within a `width` x `height` image.
fn tiled_area_of(points: impl Iterator<Item = DVec2>, width: u32, height: u32) -> f64 {
    let (w, h) = (width as f64, height as f64);
    let (lo, hi) = points.fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let x = hi.x.min(w) - lo.x.max(0.0);
    let y = hi.y.min(h) - lo.y.max(0.0);
    if x > 0.0 && y > 0.0 { x * y } else { 0.0 }
}

/// Pixels of the records' bounding boxes within a `width` x `height`
/// image: an upper bound on the pixel visits of tiling them.
#[cfg(test)]
fn tiled_area(records: &[Prepared], width: u32, height: u32) -> f64 {
    records
        .iter()
        .map(|r| tiled_area_of(r.points.iter().copied(), width, height))
        .sum()
}

/// Refuses records that would tile more than `limit` times the image.
#[cfg(test)]
fn check_overdraw(records: &[Prepared], width: u32, height: u32, limit: u64) -> Result<()> {
    let area = tiled_area(records, width, height);
    check_overdraw_area(area, records.len(), width, height, limit)
}

/// Refuses `count` records whose bounding boxes cover `area` pixels of
/// the image when that is more than `limit` times the image.
fn check_overdraw_area(area: f64, count: usize, width: u32, height: u32, limit: u64) -> Result<()> {
    let pixels = f64::from(width) * f64::from(height);
    let overdraw = area / pixels.max(1.0);
    if overdraw <= limit as f64 {
        return Ok(());
    }
    Err(Error::budget(
        &format!(
            "scan converting {count} records that cover the {width} x {height} image {overdraw:.1} times over (their bounding boxes)"
        ),
        format!("{limit} times"),
        "--max-overdraw",
    ))
}

/// The hidden-surface logic a run uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Logic {
    /// Back to front, overwrite.
    Painter,
    /// Front to back, pre-blended.
    Single(Measure),
    /// Front to back, post-blended, with this many samples.
    Multi(u32),
}

fn name(m: Method) -> String {
    match m {
        Method::Point => "point sampling (--aa none)".into(),
        Method::Area => "rftb1 (area coverage)".into(),
        Method::Mask => "rftb2 (pixel masks)".into(),
        Method::Hybrid => "rftb3 (hybrid area/mask)".into(),
        Method::Multilevel => "rftb4 (multilevel)".into(),
        Method::Supersample(n) => format!("supersampling {n} x {n}"),
    }
}

/// Checks the options against the stream and picks the logic.
fn choose(stream: &RecordStream, o: &ScanOptions) -> Result<Logic> {
    let m = o.method;
    if o.width == 0 || o.height == 0 {
        return Err(Error::Invalid(format!(
            "cannot scan convert a {} x {} image",
            o.width, o.height
        )));
    }
    if let Method::Supersample(n) = m
        && !(1..=16).contains(&n)
    {
        return Err(Error::Invalid(format!(
            "supersampling takes 1 to 16 samples per pixel side, not {n}"
        )));
    }
    let got = match (stream.front_to_back, stream.blended) {
        (false, _) => "back to front",
        (true, true) => "pre-blended",
        (true, false) => "post-blended",
    };
    let wants_pre = "wants a front-to-back tree with pre-blended shades (setmode b on)";
    let wants_post = "wants a front-to-back tree with post-blended shades (setmode b off)";
    let donovan = o.transparency == TransparencyRule::Donovan;
    let logic = match (m, stream.front_to_back, stream.blended) {
        (Method::Point, false, _) => Logic::Painter,
        // Donovan's rule needs the surface behind first: every method
        // paints a back-to-front stream, sample by sample.
        (_, false, _) if donovan => Logic::Painter,
        (Method::Area, true, true) => Logic::Single(Measure::Area),
        (Method::Mask, true, true) => Logic::Single(Measure::Mask),
        (Method::Hybrid, true, true) => Logic::Single(Measure::Hybrid),
        (Method::Point | Method::Supersample(_), true, true) => Logic::Single(Measure::Mask),
        (Method::Multilevel, true, false) => Logic::Multi(16),
        (Method::Point, true, false) => Logic::Multi(1),
        (Method::Supersample(n), true, false) => Logic::Multi(n * n),
        (Method::Area | Method::Mask | Method::Hybrid, ..) => {
            return Err(Error::Invalid(format!(
                "{} {wants_pre}; this one is {got}",
                name(m)
            )));
        }
        (Method::Multilevel, ..) => {
            return Err(Error::Invalid(format!(
                "{} {wants_post}; this one is {got}",
                name(m)
            )));
        }
        (Method::Supersample(_), false, _) => {
            return Err(Error::Invalid(format!(
                "{} wants a front-to-back tree; this one is back to front",
                name(m)
            )));
        }
    };
    if logic != Logic::Painter && donovan {
        return Err(Error::Invalid(format!(
            "{}: Donovan's transparency rule needs the surface behind first, so it is \
             painted from a back-to-front tree (sort btf); this one is front to back",
            name(m)
        )));
    }
    if !matches!(logic, Logic::Single(_)) && o.transparency == TransparencyRule::Coverage {
        return Err(Error::Invalid(format!(
            "{}: the pixel-coverage transparency of section 5.6 is for the single-level \
             methods, which want a front-to-back pre-blended tree; this one is {got}",
            name(m)
        )));
    }
    Ok(logic)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(points: &[[f64; 2]]) -> Prepared {
        let points: Vec<DVec2> = points.iter().map(|p| DVec2::from(*p)).collect();
        let (ymin, ymax) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.y), b.max(p.y))
            });
        Prepared {
            points,
            shading: shade::Shading::Special,
            level: 1,
            ymin,
            ymax,
        }
    }

    /// Bounding boxes clipped to a 16 x 8 image, worked by hand.
    #[test]
    fn tiled_area_counts_bounding_boxes_within_the_image() {
        let inside = record(&[[1.0, 1.0], [3.0, 1.0], [2.0, 4.0]]); // 2 x 3
        let overhanging = record(&[[-10.0, -10.0], [20.0, 5.0], [5.0, 30.0]]); // 16 x 8
        let corner = record(&[[14.0, 6.0], [30.0, 6.0], [30.0, 30.0]]); // 2 x 2
        let outside = record(&[[-5.0, 1.0], [-1.0, 1.0], [-3.0, 4.0]]);
        let records = [inside, overhanging, corner, outside];
        assert_eq!(tiled_area(&records, 16, 8), 6.0 + 128.0 + 4.0);
        assert!(check_overdraw(&records, 16, 8, 2).is_ok()); // 138 / 128
        let e = check_overdraw(&records, 16, 8, 1).unwrap_err().to_string();
        assert!(
            e.contains("1.1 times over") && e.contains("--max-overdraw"),
            "{e}"
        );
    }
}

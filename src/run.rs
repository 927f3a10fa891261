//! One `run` of the scene language with its files (004 appendix B,
//! `run`: "the image is generated and written"): the outputs are created
//! before anything is rendered, the picture is made by the path its
//! settings choose (vector drawing, the virtual image tree scan converted
//! in streamed bands or into a whole frame, the ray tracer, a part of the
//! image), and every file of the run is committed together or not at all
//! ([`crate::output::commit_all`]).
//!
//! The program only talks to the user: it says what [`RunSpec`] asks for
//! and prints the [`RunReport`]; a [`RunObserver`] sees the rows go by
//! and the warnings as they happen.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::display::LiveDisplay;
use crate::error::{Error, Result};
use crate::output::{self, AtomicFile, Staged};
use crate::part::{PartInfo, PartSink, PartSpec};
use crate::raster::frame_buffer::FrameBuffer;
use crate::raster::scan::{Row, RowSink, part_rows};
use crate::render::{self, Plan, Prepared, RenderOptions, RenderStats, Rendered, Reuse};
use crate::scene::Scene;
use crate::vector::Format as VectorFormat;

/// What a run writes and how it renders.
#[derive(Clone, Debug)]
pub struct RunSpec {
    /// The image (PNG, PPM, a vector format by its extension).
    pub image: PathBuf,
    /// `--id-image`: the polygon ids of every pixel.
    pub id_image: Option<PathBuf>,
    /// `setmode o`: the virtual image tree goes to STEM.out and STEM.txt.
    pub tree_stem: Option<String>,
    /// The renderer's settings.
    pub options: RenderOptions,
    /// `--hidden-line`: a vector drawing of the visible edges.
    pub hidden_line: bool,
    /// `--raytrace`: the ray tracer paints the image (N x N rays a pixel
    /// with [`Method::Supersample`](crate::raster::scan::Method)).
    pub raytrace: bool,
    /// `--part I/N`: only this part's rows, into [`RunSpec::image`], a
    /// part file.
    pub part: Option<PartRun>,
}

/// A part of the image: which, and what its file says of the whole.
#[derive(Clone, Debug)]
pub struct PartRun {
    /// Which part, of how many.
    pub spec: PartSpec,
    /// The whole image the parts merge into.
    pub whole: PathBuf,
    /// The settings that decide the pixels, as text (the fingerprint that
    /// `merge` compares across parts).
    pub flags: String,
}

/// What a run made.
pub struct RunReport {
    /// The render: its frame (empty when streamed) and figures.
    pub rendered: Rendered,
    /// The image's size.
    pub size: (u32, u32),
    /// The files committed, in order.
    pub written: Vec<PathBuf>,
    /// `setmode o`: the tree's records and its two files.
    pub tree: Option<(usize, PathBuf, PathBuf)>,
    /// With a part: the rows it holds.
    pub rows: Option<Range<u32>>,
}

/// Sees a run as it goes: the rows of its scan conversion, its warnings.
/// Every method does nothing by default.
pub trait RunObserver {
    /// The outputs are checked and created; the render begins.
    fn started(&mut self) {}
    /// The scan conversion starts on `rows` rows.
    fn rows_start(&mut self, _rows: u32) {}
    /// One more row is finished.
    fn row_done(&mut self) {}
    /// The scan conversion is over (or failed).
    fn rows_end(&mut self) {}
    /// A warning to show the user.
    fn warning(&mut self, _message: &str) {}
}

/// An observer that sees nothing.
pub struct Unobserved;

impl RunObserver for Unobserved {}

/// Renders `scene` as `spec` says, showing it in `live` when a display
/// was asked for, and commits its files together.
pub fn run(
    scene: &Scene,
    spec: &RunSpec,
    reuse: &Reuse,
    live: &mut LiveDisplay,
    observer: &mut dyn RunObserver,
) -> Result<RunReport> {
    if let Some(part) = &spec.part {
        return run_part(scene, spec, part, reuse, observer);
    }
    let mut out = Outputs::create(spec)?;
    observer.started();
    let mut staged = Vec::new();
    let (rendered, size) = picture(scene, spec, reuse, live, &mut out, &mut staged, observer)?;
    let tree = stage_tree(rendered.tree.as_ref(), out.tree, &mut staged)?;
    if let Some(file) = out.id {
        staged.push(output::stage_id_png(
            file,
            &rendered.frame,
            &rendered.polygons,
        )?);
    }
    let written = staged.iter().map(|s| s.path().to_path_buf()).collect();
    output::commit_all(staged)?;
    Ok(RunReport {
        rendered,
        size,
        written,
        tree,
        rows: None,
    })
}

/// The files of a run, created (each a temporary file beside its place)
/// before anything is rendered.
struct Outputs {
    /// The image, until the picture takes it.
    image: Option<AtomicFile>,
    id: Option<AtomicFile>,
    tree: Option<(AtomicFile, AtomicFile)>,
}

impl Outputs {
    fn create(spec: &RunSpec) -> Result<Outputs> {
        let image = Some(AtomicFile::create(&spec.image)?);
        let id = spec
            .id_image
            .as_deref()
            .map(AtomicFile::create)
            .transpose()?;
        let tree = match &spec.tree_stem {
            Some(stem) => Some((
                AtomicFile::create(Path::new(&format!("{stem}.out")))?,
                AtomicFile::create(Path::new(&format!("{stem}.txt")))?,
            )),
            None => None,
        };
        Ok(Outputs { image, id, tree })
    }
}

/// Renders the picture into the run's image file (staged, not yet
/// committed): vector output, PNG bands streamed as they are finished, or
/// a whole frame. Returns the render and the image's size.
fn picture(
    scene: &Scene,
    spec: &RunSpec,
    reuse: &Reuse,
    live: &mut LiveDisplay,
    out: &mut Outputs,
    staged: &mut Vec<Staged>,
    observer: &mut dyn RunObserver,
) -> Result<(Rendered, (u32, u32))> {
    let options = &spec.options;
    let (w, h) = options
        .size
        .unwrap_or((scene.viewport.width(), scene.viewport.height()));
    if VectorFormat::from_path(&spec.image).is_some() || spec.hidden_line {
        let run = render::vector::render_run(out.image.take(), scene, options, spec.hidden_line)?;
        staged.extend(run.0);
        let rendered = Rendered {
            tree: run.2,
            ..Rendered::empty(run.1)
        };
        return Ok((rendered, (w, h)));
    }
    let streamed = !live.wanted()
        && spec.id_image.is_none()
        && spec
            .image
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !streamed {
        // The whole frame is kept; the image-space algorithms check their
        // larger need themselves.
        options
            .budgets
            .check_frame(w, h, render::FRAME_BYTES_PER_PIXEL)
            .map_err(Error::Invalid)?;
    }
    let plan = if spec.raytrace {
        Plan::Painted(Box::new(ray_traced(scene, options)?))
    } else {
        render::plan_with(scene, options, reuse)?
    };
    let file = out.image.take().expect("created before the render");
    match plan {
        Plan::Tree(prepared) if streamed => {
            let size = (prepared.scan.width, prepared.scan.height);
            let (rendered, png) = streamed_png(*prepared, file, scene, observer)?;
            staged.push(png);
            Ok((rendered, size))
        }
        plan => {
            let rendered = whole_frame(plan, (w, h), live, observer)?;
            staged.push(output::stage_image(file, &rendered.frame, scene.outmode)?);
            let size = (rendered.frame.width, rendered.frame.height);
            Ok((rendered, size))
        }
    }
}

/// The `--raytrace` render: N x N rays per pixel with supersampling.
fn ray_traced(scene: &Scene, options: &RenderOptions) -> Result<Rendered> {
    let samples = match options.aa {
        Some(crate::raster::scan::Method::Supersample(n)) => n,
        _ => 1,
    };
    let rt = crate::raytrace::RayTraceOptions {
        size: options.size,
        samples,
        shadows: options.shadows,
        shading: options.shading,
        threads: options.threads,
        max_rays: options.budgets.rays,
    };
    let (frame, rays) = crate::raytrace::render(scene, &rt)?;
    Ok(Rendered {
        frame,
        stats: RenderStats {
            max_depth: scene.modes.max_level,
            paint_time: rays.trace_time,
            raytrace: Some(rays),
            ..RenderStats::default()
        },
        ..Rendered::empty(RenderStats::default())
    })
}

/// The virtual frame buffer: bands of rows go to the PNG as they are
/// finished; the whole image is never in memory.
fn streamed_png(
    mut prepared: Prepared,
    file: AtomicFile,
    scene: &Scene,
    observer: &mut dyn RunObserver,
) -> Result<(Rendered, Staged)> {
    prepared.scan.ids = false;
    let (w, h) = (prepared.scan.width, prepared.scan.height);
    let mut sink = output::PngSink::from_file(file, w, h, scene.outmode.into())?;
    let rendered = observed(prepared, None, &mut sink, observer)?;
    let (file, note) = sink.finish()?;
    if let Some(note) = note {
        observer.warning(&note);
    }
    Ok((rendered, file))
}

/// A render kept whole in memory, shown level by level in the live
/// display when `disp on` opened one.
fn whole_frame(
    plan: Plan,
    (w, h): (u32, u32),
    live: &mut LiveDisplay,
    observer: &mut dyn RunObserver,
) -> Result<Rendered> {
    let window = live.observer(w, h).unwrap_or_else(|message| {
        observer.warning(&message);
        None
    });
    Ok(match (plan, window) {
        (Plan::Tree(prepared), Some(window)) => crate::display::scan_levels(*prepared, window)?,
        (Plan::Painted(r), Some(window)) => {
            crate::display::show_painted(&r, window);
            *r
        }
        (Plan::Tree(prepared), None) => {
            let (w, h) = (prepared.scan.width, prepared.scan.height);
            let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
            let mut rendered = observed(*prepared, None, &mut frame, observer)?;
            rendered.frame = frame;
            rendered
        }
        (Plan::Painted(r), None) => *r,
    })
}

/// Scan converts `prepared` (only `rows` of it, for a part) into `sink`,
/// telling `observer` of each row.
fn observed(
    prepared: Prepared,
    rows: Option<Range<u32>>,
    sink: &mut dyn RowSink,
    observer: &mut dyn RunObserver,
) -> Result<Rendered> {
    let count = rows
        .as_ref()
        .map_or(prepared.scan.height, |r| r.len() as u32);
    observer.rows_start(count);
    let mut seen = Observed { sink, observer };
    let rendered = match rows {
        None => render::scan_into(prepared, &mut seen),
        Some(rows) => render::scan_rows_into(prepared, rows, &mut seen),
    };
    seen.observer.rows_end();
    rendered
}

/// Passes rows on to `sink` and tells `observer` of each.
struct Observed<'a> {
    sink: &'a mut dyn RowSink,
    observer: &'a mut dyn RunObserver,
}

impl RowSink for Observed<'_> {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        crate::cancel::check()?;
        self.sink.row(row)?;
        self.observer.row_done();
        Ok(())
    }

    fn wants_pixel_structs(&self) -> bool {
        self.sink.wants_pixel_structs()
    }
}

/// Stages the tree files (`setmode o`).
fn stage_tree(
    tree: Option<&crate::tree::RecordStream>,
    files: Option<(AtomicFile, AtomicFile)>,
    staged: &mut Vec<Staged>,
) -> Result<Option<(usize, PathBuf, PathBuf)>> {
    let (Some(tree), Some((mut bin, mut txt))) = (tree, files) else {
        return Ok(None);
    };
    bin.write_all(&tree.to_bytes())?;
    txt.write_all(tree.to_text().as_bytes())?;
    let told = (
        tree.records.len(),
        bin.path().to_path_buf(),
        txt.path().to_path_buf(),
    );
    staged.push(bin.finish()?);
    staged.push(txt.finish()?);
    Ok(Some(told))
}

/// One `run` with `--part I/N`: only the part's rows of the image are
/// scan converted, into the part file [`RunSpec::image`].
fn run_part(
    scene: &Scene,
    spec: &RunSpec,
    part: &PartRun,
    reuse: &Reuse,
    observer: &mut dyn RunObserver,
) -> Result<RunReport> {
    output::check_target(&spec.image)?;
    observer.started();
    let plan = render::plan_with(scene, &spec.options, reuse)?;
    let Plan::Tree(prepared) = plan else {
        return Err(Error::Invalid(format!(
            "--part {}: the {} algorithm paints the image itself; parts are scan \
             conversions of the virtual image tree (--visibility depth-sort or nns)",
            part.spec,
            render::chosen_algorithm(scene, &spec.options)
        )));
    };
    let mut prepared = *prepared;
    prepared.scan.ids = false;
    let (w, h) = (prepared.scan.width, prepared.scan.height);
    let rows = part_rows(
        &prepared.picture,
        &prepared.scan,
        part.spec.index,
        part.spec.count,
    );
    let info = PartInfo {
        part: part.spec,
        image: (w, h),
        first: rows.start,
        rows: rows.len() as u32,
        output: part.whole.display().to_string(),
        fingerprint: crate::part::fingerprint("plytrace", &part.flags),
    };
    let mut sink = PartSink::create(&spec.image, info, scene.outmode.into())?;
    let rendered = observed(prepared, Some(rows.clone()), &mut sink, observer)?;
    output::commit_all(vec![sink.finish()?])?;
    Ok(RunReport {
        rendered,
        size: (w, h),
        written: vec![spec.image.clone()],
        tree: None,
        rows: Some(rows),
    })
}

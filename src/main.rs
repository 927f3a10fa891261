//! The `plytrace` program: the command interpreter and immediate mode of
//! Garcia 1986 (004 appendix, plytrace manual page), and the `mkdet`,
//! `mkpcl`, `mkvcl` converters. A thin layer over the library: argument
//! parsing, terminal input, messages and exit codes.
//!
//! The arguments are parsed by hand because the manual's flags are unusual
//! for an argument library: every `setmode` letter is a flag taking its
//! value as the next word (`-n on`, `-l 3`), and the debugging level is a
//! bare digit (`-3`).

use std::io::{BufRead, IsTerminal, Write};
use std::path::{Component, Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use plytrace::budget::Budgets;
use plytrace::error::{Error, Result, printable};
use plytrace::output::{self, AtomicFile};
use plytrace::raster::frame_buffer::FrameBuffer;
use plytrace::raster::scan::{Row, RowSink};
use plytrace::render::{self, RenderOptions};
use plytrace::scene::commands::COMMANDS;
use plytrace::scene::object_file::{self, ConvertKind};
use plytrace::scene::{Flow, Host, Interpreter, Scene};
use plytrace::visibility::Algorithm;

/// jemalloc: the tree and the records are hundreds of thousands of small
/// blocks made and freed by several threads, where glibc's allocator spent
/// 15-25 % of the cycles (consolidating its fast bins on every large free).
#[global_allocator]
static ALLOCATOR: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

/// jemalloc's options (its `malloc_conf`; `_RJEM_MALLOC_CONF` in the
/// environment still overrides them), chosen for peak memory (issue 10's
/// 64 MiB for office2), measured on office2 at 512x512:
/// - `dirty_decay_ms:10,muzzy_decay_ms:0`: pages freed for 10 ms go back
///   to the system. With the default 10 s, what the tree builder frees
///   stays resident to the end: 72 MB peak, against 58 MB.
/// - `thp:never`: huge pages cut the page faults (and a tenth of the
///   time) but hold 2 MB wherever any of it is used: 74-86 MB.
/// - `percpu_arena:percpu`: one arena per CPU rather than four.
#[unsafe(export_name = "_rjem_malloc_conf")]
static MALLOC_CONF: MallocConf =
    MallocConf(c"thp:never,dirty_decay_ms:10,muzzy_decay_ms:0,percpu_arena:percpu".as_ptr());

/// A C string pointer jemalloc reads once at start-up.
#[repr(transparent)]
struct MallocConf(*const std::ffi::c_char);

// SAFETY: the pointer is to a string literal, never written.
unsafe impl Sync for MallocConf {}

mod repl;

const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The longest line printed from input, in characters; the rest is cut
/// (see [`printable`]).
const MAX_LINE: usize = 1000;

/// Set when stdout is a closed pipe: nothing more is printed there, and the
/// program goes on (the image is still written) and ends with status 0.
static STDOUT_GONE: AtomicBool = AtomicBool::new(false);

/// Set while a run renders: Ctrl-C then cancels the render (the session
/// goes on); at any other time, or pressed twice, it ends the program.
static RENDERING: AtomicBool = AtomicBool::new(false);

/// The SIGINT handler (it runs on its own thread, so it may print).
fn on_interrupt() {
    if !RENDERING.load(Ordering::SeqCst) || plytrace::cancel::request() {
        std::process::exit(130);
    }
    err("^C: cancelling the render (press Ctrl-C again to quit)");
}

/// Writes `text` to stdout, each line escaped ([`printable`]), with a
/// final newline when `newline`. A closed pipe (EPIPE) ends printing
/// quietly rather than panicking as `println!` would.
fn out_text(text: &str, newline: bool) {
    if STDOUT_GONE.load(Ordering::Relaxed) {
        return;
    }
    let mut o = std::io::stdout().lock();
    let body = text.strip_suffix('\n').unwrap_or(text);
    let ends_line = newline || body.len() < text.len();
    let mut lines = body.split('\n').peekable();
    let mut result = Ok(());
    while let Some(line) = lines.next() {
        let last = lines.peek().is_none();
        let line = printable(line, MAX_LINE);
        result = if !last || ends_line {
            writeln!(o, "{line}")
        } else {
            write!(o, "{line}").and_then(|()| o.flush())
        };
        if result.is_err() {
            break;
        }
    }
    if result.is_err() {
        // EPIPE or another failure of stdout: stop printing there.
        STDOUT_GONE.store(true, Ordering::Relaxed);
    }
}

/// Prints a line (or lines) on stdout; see [`out_text`].
fn out(text: &str) {
    out_text(text, true);
}

/// Prints `text` on stderr, each line escaped and cut to [`MAX_LINE`]; a
/// closed stderr is ignored.
fn err(text: &str) {
    let mut e = std::io::stderr().lock();
    for line in text.strip_suffix('\n').unwrap_or(text).split('\n') {
        if writeln!(e, "{}", printable(line, MAX_LINE)).is_err() {
            return;
        }
    }
}

#[derive(Debug, Default)]
struct Options {
    immediate: bool,
    scene: Option<PathBuf>,
    modes: Vec<(char, String)>,
    output: Option<PathBuf>,
    size: Option<(u32, u32)>,
    id_image: Option<PathBuf>,
    visibility: Option<Algorithm>,
    profile: bool,
    refraction: plytrace::image_tree::Refraction,
    aa: Option<plytrace::raster::scan::Method>,
    threads: usize,
    shading: plytrace::shading::ShadingModel,
    quiet: bool,
    allow_outside: bool,
    budgets: Budgets,
    hidden_line: bool,
    /// `--raytrace`: render with the Whitted ray tracer.
    raytrace: bool,
}

fn usage() -> String {
    let mut s = format!(
        "plytrace {VERSION} - image rendering processor for 3-D polygonal environments

USAGE:
    plytrace                      interactive command interpreter (prompt `Command:`)
    plytrace -i -f SCENE.des      immediate mode: read the scene, render it, exit
    plytrace SCENE.des [-o OUT.png]
                                  the same (a lone scene file means immediate mode)
    plytrace mkdet|mkpcl|mkvcl IN OUT
                                  convert an ASCII object file to binary form
    plytrace tessellation FILE    check Brown's Angle and Edge Conditions of a
                                  triangulated surface about its origin
    plytrace continuity FILE [bezier|hermite]
                                  C0/C1 continuity between adjacent bicubic
                                  patches of a .bpt (Bezier) or .hpt (Hermite) file

FLAGS (the setmode letters of the manual, each taking its value as the next word):
    -i                 immediate mode
    -f FILE            scene descriptor file
    -b on|off          pre-blend parent and child intensities
    -d SIZE            minimum screen detail (default 0.0002)
    -e EPS             clipping epsilon (default 1e-7)
    -h on|off          explicit shadow shades
    -l 1-14            maximum reflection/refraction level
    -n on|off          Newell-Newell-Sancha sorting
    -o on|off          write the virtual image tree
    -p on|off          bounding boxes only
    -s on|off          Phong highlight vectors
    -v on|off          vertex shades
    -x on|off          expand all objects into one list before sorting
    -0 .. -9           debugging level
Flags override the same setmode in the scene file.

MODERN CONVENIENCES:
    -o FILE.png|.ppm|.svg|.pdf|.tex
                       output image (any value of -o other than on/off): PNG, binary
                       PPM, or vector graphics chosen by the extension (SVG, one-page
                       PDF, TikZ), painted back to front from NNS with splitting
    --hidden-line      Brown's hidden-line drawing: white faces, black visible edges
                       (PNG lines 1 px; strokes in vector output)
    --output FILE      output image (default FNAME.png in the working directory)
    --size WxH         image size overriding the scene's resolution/viewport (a
                       different aspect ratio stretches the picture: warned)
    --id-image FILE.png
                       also write the polygon seen at every pixel as a false-colour PNG
                       (one colour per object and polygon, the same for every algorithm)
    --visibility ALG   visible-surface algorithm: depth-sort (default), nns (also
                       `setmode n on` / -n on), z-buffer, scan-line, warnock, brown
                       (well-tesselated surfaces), ray-cast (the oracle)
    --quiet            print only errors and warnings
    --profile          print the run-time profile in the categories of 004 table 6.2
    --refraction M     refraction matrix: linearized (exact for the ray through the
                       polygon's centre), orthographic (M_to), paraxial (M_tp), or exact
                       (the refracted branch ray traced per pixel); default: linearized,
                       or exact when a linear map is off by more than a pixel
    --aa METHOD        scan conversion (004 chapter 5): none (point sampled preview),
                       area (1), mask (2), hybrid (3), multilevel (4); default: the
                       best for the scene (multilevel: every tree level blended)
    --supersample N    Donovan's N x N samples per pixel instead (N from 1 to 16); with
                       --raytrace, N x N rays per pixel
    --raytrace         render with the Whitted ray tracer (same scene and illumination
                       model; exact reflection and refraction, shadow rays with `run y`)
    --shading MODEL    illumination: garcia (004 section 4.8, default) or donovan (000
                       section 6: I0 cos^a, I1 cos^b(theta - theta1), transparency rule 3)
    --threads N        worker threads (default: all cores); the image does not depend on it
    --allow-outside    let the scene's `fname` name files outside the working directory
                       (`..` or an absolute path); refused otherwise
    --help, --version

BUDGETS (a run that would exceed one stops with a message naming its flag):
    --max-polygons N   polygons in the scene, read and generated
    --max-call-depth N nesting of `call`
    --max-tree-nodes N fragments of the virtual image tree
    --max-splits N     face splits of one NNS sort
    --max-pixels N     pixels of one image (checked before rendering)
    --max-overdraw N   records per pixel on average that scan conversion tiles, each
                       counted by its bounding box (default 4096; checked before tiling)
    --max-frame-memory MiB  a whole frame held in memory (image-space
                       algorithms, PPM, --id-image, clear; default 1024)

OUTPUTS: every output of a `run` (image, --id-image, FNAME.out and FNAME.txt)
is checked before the render (directory present; no link, FIFO or device) and
written under a temporary name, all renamed into place together at the end.

FILES:
    FNAME.png          the image (FNAME from `fname`, else the scene file's name)
    FNAME.out, FNAME.txt
                       the virtual image tree, with `setmode o on` / -o on
    plytrace.log       one line per run appended in the working directory: UTC
                       date, scene, image, size, polygons tiled, max depth, seconds

COMMANDS of the scene descriptor language (shortest unique prefix accepted):
"
    );
    s.push_str(&command_help(None));
    s.push_str(
        "\nNot yet acted on (parsed, checked and kept): clear (every run starts from the\n\
         background).\n",
    );
    s
}

enum Parsed {
    Run(Options),
    Tessellation(PathBuf),
    /// `plytrace continuity FILE [bezier|hermite]`.
    Continuity(PathBuf, Option<String>),
    Convert(ConvertKind, Vec<String>),
    Help,
    Version,
}

fn parse_args(args: &[String]) -> std::result::Result<Parsed, String> {
    if let Some(first) = args.first() {
        let kind = match first.as_str() {
            "mkdet" => Some(ConvertKind::Det),
            "mkpcl" => Some(ConvertKind::Pcl),
            "mkvcl" => Some(ConvertKind::Vcl),
            _ => None,
        };
        if first == "tessellation" {
            return match args {
                [_, file] => Ok(Parsed::Tessellation(file.into())),
                _ => Err("usage: plytrace tessellation <object file>".into()),
            };
        }
        if first == "continuity" {
            return match args {
                [_, file] => Ok(Parsed::Continuity(file.into(), None)),
                [_, file, form] => Ok(Parsed::Continuity(file.into(), Some(form.clone()))),
                _ => Err("usage: plytrace continuity <patch file> [bezier|hermite]".into()),
            };
        }
        if let Some(kind) = kind {
            return Ok(Parsed::Convert(kind, args[1..].to_vec()));
        }
    }
    let mut o = Options::default();
    let mut positional: Option<PathBuf> = None;
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let mut value = |what: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| format!("`{arg}` needs {what}"))
        };
        let mut count = |flag: &str| -> std::result::Result<u64, String> {
            let v = value("a number")?;
            v.parse::<u64>().ok().filter(|n| *n >= 1).ok_or_else(|| {
                format!("{flag}: expected a whole number of at least 1, found `{v}`")
            })
        };
        match arg.as_str() {
            "--help" | "-help" => return Ok(Parsed::Help),
            "--version" | "-V" => return Ok(Parsed::Version),
            "-i" => o.immediate = true,
            "-f" => o.scene = Some(value("a scene file")?.into()),
            "--output" => o.output = Some(image_path(value("a file name")?)?),
            "--id-image" => {
                let v = PathBuf::from(value("a file name")?);
                if !v.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
                    return Err(format!(
                        "--id-image: {}: the id image is written as PNG only; name it .png",
                        v.display()
                    ));
                }
                o.id_image = Some(v);
            }
            "--allow-outside" => o.allow_outside = true,
            "--hidden-line" => o.hidden_line = true,
            "--max-polygons" => o.budgets.polygons = to_usize(count(arg)?),
            "--max-call-depth" => o.budgets.call_depth = to_usize(count(arg)?),
            "--max-tree-nodes" => o.budgets.tree_nodes = to_usize(count(arg)?),
            "--max-splits" => o.budgets.splits = to_usize(count(arg)?),
            "--max-pixels" => o.budgets.pixels = count(arg)?,
            "--max-overdraw" => o.budgets.overdraw = count(arg)?,
            "--max-frame-memory" => {
                o.budgets.frame_memory = count(arg)?.saturating_mul(1 << 20);
            }
            "--quiet" | "-q" => o.quiet = true,
            "--profile" => o.profile = true,
            "--raytrace" => o.raytrace = true,
            "--aa" => {
                let v = value("none, area, mask, hybrid or multilevel (or 1 to 4)")?;
                o.aa = Some(parse_aa(&v)?);
            }
            "--supersample" => {
                let v = value("N from 1 to 16")?;
                match v.parse::<u32>() {
                    Ok(n @ 1..=16) => o.aa = Some(plytrace::raster::scan::Method::Supersample(n)),
                    _ => {
                        return Err(format!(
                            "--supersample: expected N from 1 to 16, found `{v}`"
                        ));
                    }
                }
            }
            "--shading" => {
                o.shading = match value("garcia or donovan")?.to_ascii_lowercase().as_str() {
                    "garcia" => plytrace::shading::ShadingModel::Garcia,
                    "donovan" => plytrace::shading::ShadingModel::Donovan,
                    v => {
                        return Err(format!(
                            "--shading: expected garcia or donovan, found `{v}`"
                        ));
                    }
                };
            }
            "--threads" => {
                let v = value("a thread count")?;
                o.threads = match v.parse::<usize>() {
                    Ok(n @ 1..=1024) => n,
                    _ => return Err(format!("--threads: expected 1 to 1024, found `{v}`")),
                };
            }
            "--refraction" => {
                let v = value("linearized, orthographic, paraxial or exact")?;
                o.refraction = v.parse().map_err(|e| format!("--refraction: {e}"))?;
            }
            "--visibility" => {
                let v = value("an algorithm name")?;
                o.visibility = Some(
                    v.parse::<Algorithm>()
                        .map_err(|e| format!("--visibility: {e}"))?,
                );
            }
            "--size" => {
                let v = value("a size WxH")?;
                o.size = Some(parse_size(&v).ok_or_else(|| {
                    format!("--size: expected WxH with 1 <= W, H <= 65536, found `{v}`")
                })?);
            }
            "-o" => {
                let v = value("`on`, `off` or an output file")?;
                if matches!(v.to_ascii_lowercase().as_str(), "on" | "off") {
                    o.modes.push(('o', v));
                } else {
                    o.output = Some(image_path(v)?);
                }
            }
            a if a.len() == 2 && a.starts_with('-') => {
                let letter = a.chars().nth(1).expect("two characters");
                if letter.is_ascii_digit() {
                    o.modes.push((letter, String::new()));
                } else if "bdehlnpsvx".contains(letter) {
                    o.modes.push((letter, value("a value")?));
                } else {
                    return Err(format!(
                        "unknown flag `{a}`; `plytrace --help` lists the flags"
                    ));
                }
            }
            a if !a.starts_with('-')
                && positional.is_none()
                && Path::new(a)
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("des")) =>
            {
                positional = Some(a.into());
            }
            a => {
                return Err(format!(
                    "unexpected argument `{a}`; `plytrace --help` lists the flags"
                ));
            }
        }
    }
    if let Some(p) = positional {
        if o.scene.is_some() {
            return Err(format!(
                "two scene files: `{}` and -f `{}`; give one",
                p.display(),
                o.scene.as_deref().unwrap_or(Path::new("")).display()
            ));
        }
        o.scene = Some(p);
        o.immediate = true;
    }
    if let Some((w, h)) = o.size
        && u64::from(w) * u64::from(h) > o.budgets.pixels
    {
        return Err(pixels_exceeded(w, h, o.budgets.pixels));
    }
    let vector = o
        .output
        .as_deref()
        .and_then(plytrace::vector::Format::from_path)
        .is_some();
    if o.id_image.is_some() && (vector || o.hidden_line) {
        return Err(
            "--id-image is made from the shaded PNG; it cannot go with vector output or --hidden-line"
                .into(),
        );
    }
    if o.output.is_some() && o.output == o.id_image {
        return Err("the image and --id-image name the same file".into());
    }
    if o.immediate && o.scene.is_none() {
        return Err("immediate mode (-i) needs a scene file: plytrace -i -f scene.des".into());
    }
    Ok(Parsed::Run(o))
}

fn method_name(m: plytrace::raster::scan::Method) -> String {
    use plytrace::raster::scan::Method;
    match m {
        Method::Point => "point sampled (--aa none)".into(),
        Method::Area => "method 1, area coverage".into(),
        Method::Mask => "method 2, 4x4 pixel masks".into(),
        Method::Hybrid => "method 3, hybrid area/mask".into(),
        Method::Multilevel => "method 4, multi-level pixel masks".into(),
        Method::Supersample(n) => format!("Donovan's {n} x {n} supersampling"),
    }
}

fn parse_aa(v: &str) -> std::result::Result<plytrace::raster::scan::Method, String> {
    use plytrace::raster::scan::Method;
    Ok(match v.to_ascii_lowercase().as_str() {
        "none" | "point" | "0" => Method::Point,
        "area" | "1" => Method::Area,
        "mask" | "2" => Method::Mask,
        "hybrid" | "3" => Method::Hybrid,
        "multilevel" | "4" => Method::Multilevel,
        _ => {
            return Err(format!(
                "--aa: expected none, area, mask, hybrid, multilevel or 1 to 4, found `{v}`"
            ));
        }
    })
}

/// An output image name from the command line: its format must be one
/// that is written.
fn image_path(v: String) -> std::result::Result<PathBuf, String> {
    let p = PathBuf::from(v);
    if plytrace::vector::Format::from_path(&p).is_some() {
        return Ok(p);
    }
    output::check_image_extension(&p)
        .map_err(|e| format!("{e}, and the vector formats .svg, .pdf and .tex"))?;
    Ok(p)
}

fn to_usize(n: u64) -> usize {
    usize::try_from(n).unwrap_or(usize::MAX)
}

fn pixels_exceeded(w: u32, h: u32, limit: u64) -> String {
    Budgets::exceeded(
        &format!(
            "the image of {w} x {h} = {} pixels",
            u64::from(w) * u64::from(h)
        ),
        limit,
        "--max-pixels",
    )
}

fn parse_size(s: &str) -> Option<(u32, u32)> {
    let (w, h) = s.split_once(['x', 'X'])?;
    let (w, h): (u32, u32) = (w.trim().parse().ok()?, h.trim().parse().ok()?);
    let ok = |v: u32| (1..=65536).contains(&v);
    (ok(w) && ok(h) && (w as u64 * h as u64) <= 1 << 28).then_some((w, h))
}

fn hms(d: Duration) -> String {
    let s = d.as_secs();
    format!(
        "Time (HR:MIN:SEC) = {:02}:{:02}:{:02} ({:.3} s)",
        s / 3600,
        s / 60 % 60,
        s % 60,
        d.as_secs_f64()
    )
}

/// Renders on `run` and writes the image.
struct CliHost {
    output: Option<PathBuf>,
    size: Option<(u32, u32)>,
    id_image: Option<PathBuf>,
    visibility: Option<Algorithm>,
    profile: bool,
    refraction: plytrace::image_tree::Refraction,
    aa: Option<plytrace::raster::scan::Method>,
    threads: usize,
    shading: plytrace::shading::ShadingModel,
    scene_stem: Option<String>,
    /// The scene file last read, for the log.
    scene_file: Option<PathBuf>,
    quiet: bool,
    interactive: bool,
    /// `--allow-outside`: the scene's `fname` may leave the working
    /// directory.
    allow_outside: bool,
    /// The limits of the session: the interpreter has its own copy
    /// (polygons, call depth); `run` checks pixels and hands the rest to
    /// the renderer.
    budgets: Budgets,
    /// A progress bar on stderr during the scan conversion.
    progress: bool,
    /// The aspect-ratio warning was given (once per session).
    aspect_warned: bool,
    /// Every file written by the runs so far, in order.
    written: Vec<PathBuf>,
    /// `run`s rendered so far.
    runs: usize,
    /// `--hidden-line`.
    hidden_line: bool,
    /// Brown's priority orders of the previous frame (003 sections 2-3).
    orders: plytrace::visibility::brown::PriorityCache,
    /// `--raytrace`.
    raytrace: bool,
    /// The live display (`disp on`).
    live: plytrace::display::LiveDisplay,
}

/// The name and place of a scene-chosen output, `fname`, checked: no `..`
/// and no absolute path, unless `--allow-outside`.
fn confine(name: &str) -> Result<()> {
    let p = Path::new(name);
    let outside = p.is_absolute()
        || p.components().any(|c| {
            matches!(
                c,
                Component::ParentDir | Component::RootDir | Component::Prefix(_)
            )
        });
    if outside {
        return Err(Error::Invalid(format!(
            "fname `{}`: names from a scene file must stay inside the working directory \
             (no `..`, no absolute path); `--allow-outside` permits it",
            printable(name, 200)
        )));
    }
    if name.is_empty() {
        return Err(Error::Invalid("fname: an empty output name".into()));
    }
    // A directory on the way that is a link out of the working directory
    // escapes as surely as `..`.
    if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty())
        && let (Ok(real), Ok(cwd)) = (
            dir.canonicalize(),
            std::env::current_dir().and_then(|c| c.canonicalize()),
        )
        && !real.starts_with(&cwd)
    {
        return Err(Error::Invalid(format!(
            "fname `{}`: its directory leads outside the working directory (through a link); \
             names from a scene file must stay inside it; `--allow-outside` permits it",
            printable(name, 200)
        )));
    }
    Ok(())
}

/// Passes rows on to `inner` and advances a progress bar, one step a row
/// (a band of rows at a time, as the scan converter finishes them).
struct ProgressSink<'a> {
    inner: &'a mut dyn RowSink,
    bar: Option<indicatif::ProgressBar>,
}

impl<'a> ProgressSink<'a> {
    fn new(inner: &'a mut dyn RowSink, rows: u32, show: bool) -> Self {
        let bar = show.then(|| {
            let bar = indicatif::ProgressBar::new(u64::from(rows));
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "Scan conversion [{bar:30}] {pos}/{len} rows (eta {eta})",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.tick();
            bar
        });
        ProgressSink { inner, bar }
    }

    fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}

impl RowSink for ProgressSink<'_> {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        plytrace::cancel::check()?;
        self.inner.row(row)?;
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
        Ok(())
    }
}

/// The date and time now, UTC, as the logs of every program write it.
fn utc_now() -> String {
    plytrace::rftb::utc_timestamp(std::time::SystemTime::now())
}

/// Appends `line` to `plytrace.log` in the working directory (the manual's
/// FILES). A log that is a link or special file is left alone; a failure
/// is a warning, never an error of the run.
fn append_log(line: &str) {
    let path = Path::new("plytrace.log");
    if let Ok(m) = std::fs::symlink_metadata(path)
        && !m.file_type().is_file()
    {
        err("warning: plytrace.log is not a regular file; the run is not logged");
        return;
    }
    let written = std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .and_then(|mut f| f.write_all(format!("{line}\n").as_bytes()));
    if let Err(e) = written {
        err(&format!(
            "warning: plytrace.log: {e}; the run is not logged"
        ));
    }
}

impl CliHost {
    fn say(&self, s: &str) {
        if !self.quiet {
            out(s);
        }
    }

    /// The stem of the outputs: the scene's `fname` (checked by
    /// [`confine`]), else the scene file's name, else `plytrace`.
    fn stem(&self, scene: &Scene) -> Result<String> {
        if let Some(f) = &scene.fname {
            if !self.allow_outside {
                confine(f)?;
            }
            return Ok(f.clone());
        }
        Ok(self.scene_stem.clone().unwrap_or_else(|| "plytrace".into()))
    }

    /// The image a run writes: `-o`, else the stem with `.png`.
    fn image_path(&self, scene: &Scene) -> Result<PathBuf> {
        match &self.output {
            Some(p) => Ok(p.clone()),
            None => Ok(PathBuf::from(format!("{}.png", self.stem(scene)?))),
        }
    }

    /// Warns once when `--size` stretches the scene's image.
    fn warn_aspect(&mut self, scene: &Scene) {
        let Some((w, h)) = self.size else { return };
        let (sw, sh) = (scene.viewport.width(), scene.viewport.height());
        let (a, b) = (f64::from(w) / f64::from(h), f64::from(sw) / f64::from(sh));
        if !self.aspect_warned && ((a - b) / b).abs() > 0.01 {
            self.aspect_warned = true;
            err(&format!(
                "warning: --size {w}x{h} changes the aspect ratio of the scene's {sw} x {sh} image \
                 ({b:.3} to {a:.3}); the picture is stretched"
            ));
        }
    }
}

impl CliHost {
    /// The `--raytrace` render: N x N rays per pixel with `--supersample N`.
    fn ray_traced(&self, scene: &Scene, shadows: bool) -> Result<render::Rendered> {
        let samples = match self.aa {
            Some(plytrace::raster::scan::Method::Supersample(n)) => n,
            _ => 1,
        };
        let options = plytrace::raytrace::RayTraceOptions {
            size: self.size,
            samples,
            shadows,
            shading: self.shading,
            threads: self.threads,
        };
        let (frame, rays) = plytrace::raytrace::render(scene, &options)?;
        Ok(render::Rendered {
            frame,
            polygons: Vec::new(),
            shadows: Vec::new(),
            tree: None,
            profile: None,
            stats: render::RenderStats {
                max_depth: scene.modes.max_level,
                paint_time: rays.trace_time,
                raytrace: Some(rays),
                ..render::RenderStats::default()
            },
        })
    }

    /// Creates every output of a run (each a temporary file beside its
    /// place) before anything is rendered; `fname` is checked only where
    /// it names a file. `disp` is the live display (the manual's
    /// "attached device"): the image file is written either way.
    fn create_outputs(&self, scene: &Scene) -> Result<RunOutputs> {
        let named = self.output.is_none() || scene.modes.output_tree;
        let stem = if named {
            self.stem(scene)?
        } else {
            String::new()
        };
        let path = match &self.output {
            Some(p) => p.clone(),
            None => PathBuf::from(format!("{stem}.png")),
        };
        let image = Some(AtomicFile::create(&path)?);
        let id = match &self.id_image {
            Some(p) => Some(AtomicFile::create(p)?),
            None => None,
        };
        let tree = if scene.modes.output_tree {
            Some((
                AtomicFile::create(Path::new(&format!("{stem}.out")))?,
                AtomicFile::create(Path::new(&format!("{stem}.txt")))?,
            ))
        } else {
            None
        };
        Ok(RunOutputs {
            path,
            image,
            id,
            tree,
        })
    }

    fn render_options(&self, shadows: bool) -> RenderOptions {
        RenderOptions {
            size: self.size,
            shadows,
            visibility: self.visibility,
            profile: self.profile,
            refraction: self.refraction,
            aa: self.aa,
            threads: self.threads,
            shading: self.shading,
            budgets: self.budgets,
        }
    }

    /// Renders the picture into the run's image file (staged, not yet
    /// committed): vector output, PNG bands streamed as they are finished,
    /// or a whole frame. Returns the render and the image's size.
    fn picture(
        &mut self,
        scene: &Scene,
        shadows: bool,
        out: &mut RunOutputs,
        staged: &mut Vec<output::Staged>,
    ) -> Result<(render::Rendered, (u32, u32))> {
        let options = self.render_options(shadows);
        let (w, h) = self
            .size
            .unwrap_or((scene.viewport.width(), scene.viewport.height()));
        if plytrace::vector::Format::from_path(&out.path).is_some() || self.hidden_line {
            let run =
                plytrace::vector::render_run(out.image.take(), scene, &options, self.hidden_line)?;
            staged.extend(run.0);
            let rendered = render::Rendered {
                tree: run.2,
                ..render::Rendered::empty(run.1)
            };
            return Ok((rendered, (w, h)));
        }
        let streamed = !self.live.wanted()
            && self.id_image.is_none()
            && out
                .path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !streamed {
            // The whole frame is kept; the image-space algorithms check
            // their larger need themselves.
            self.budgets
                .check_frame(w, h, render::FRAME_BYTES_PER_PIXEL)
                .map_err(Error::Invalid)?;
        }
        let plan = if self.raytrace {
            render::Plan::Painted(Box::new(self.ray_traced(scene, shadows)?))
        } else {
            render::plan_with(scene, &options, &self.orders)?
        };
        let file = out.image.take().expect("created before the render");
        match plan {
            render::Plan::Tree(prepared) if streamed => {
                let (w, h) = (prepared.scan.width, prepared.scan.height);
                let rendered = self.streamed(*prepared, file, scene, staged)?;
                Ok((rendered, (w, h)))
            }
            plan => {
                let rendered = self.whole_frame(plan, w, h)?;
                staged.push(output::stage_image(file, &rendered.frame, scene.outmode)?);
                let size = (rendered.frame.width, rendered.frame.height);
                Ok((rendered, size))
            }
        }
    }

    /// The virtual frame buffer: bands of rows go to the PNG as they are
    /// finished; the whole image is never in memory.
    fn streamed(
        &self,
        mut prepared: render::Prepared,
        file: AtomicFile,
        scene: &Scene,
        staged: &mut Vec<output::Staged>,
    ) -> Result<render::Rendered> {
        prepared.scan.ids = false;
        let (w, h) = (prepared.scan.width, prepared.scan.height);
        let mut sink = output::PngSink::from_file(file, w, h, scene.outmode.into())?;
        let mut progress = ProgressSink::new(&mut sink, h, self.progress);
        let rendered = render::scan_into(prepared, &mut progress);
        progress.finish();
        let rendered = rendered?;
        let (file, note) = sink.finish()?;
        if let Some(note) = note {
            err(&format!("warning: {note}"));
        }
        staged.push(file);
        Ok(rendered)
    }

    /// A render kept whole in memory, shown level by level in the live
    /// display when `disp on` opened one.
    fn whole_frame(&mut self, plan: render::Plan, w: u32, h: u32) -> Result<render::Rendered> {
        let progress = self.progress;
        let live = match self.live.observer(w, h) {
            Ok(o) => o,
            Err(message) => {
                err(&format!("warning: {message}"));
                None
            }
        };
        Ok(match (plan, live) {
            (render::Plan::Tree(prepared), Some(window)) => {
                plytrace::display::scan_levels(*prepared, window)?
            }
            (render::Plan::Painted(r), Some(window)) => {
                plytrace::display::show_painted(&r, window);
                *r
            }
            (render::Plan::Tree(prepared), None) => {
                let (w, h) = (prepared.scan.width, prepared.scan.height);
                let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
                let mut sink = render::FrameSink { frame: &mut frame };
                let mut bar = ProgressSink::new(&mut sink, h, progress);
                let rendered = render::scan_into(*prepared, &mut bar);
                bar.finish();
                let mut rendered = rendered?;
                rendered.frame = frame;
                rendered
            }
            (render::Plan::Painted(r), None) => *r,
        })
    }

    /// Stages the tree files (`setmode o`); the message to print once
    /// they are committed.
    fn stage_tree(
        tree: Option<&plytrace::tree::RecordStream>,
        files: Option<(AtomicFile, AtomicFile)>,
        staged: &mut Vec<output::Staged>,
    ) -> Result<Option<String>> {
        let (Some(tree), Some((mut bin, mut txt))) = (tree, files) else {
            return Ok(None);
        };
        bin.write_all(&tree.to_bytes())?;
        txt.write_all(tree.to_text().as_bytes())?;
        let message = format!(
            "Wrote the virtual image tree ({} polygons) to {} and {}",
            tree.records.len(),
            bin.path().display(),
            txt.path().display()
        );
        staged.push(bin.finish()?);
        staged.push(txt.finish()?);
        Ok(Some(message))
    }

    /// One `run`: checks and creates the outputs, renders, commits them
    /// all together (or none), then reports.
    fn render(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        self.runs += 1;
        let start = Instant::now();
        let (w, h) = self
            .size
            .unwrap_or((scene.viewport.width(), scene.viewport.height()));
        if u64::from(w) * u64::from(h) > self.budgets.pixels {
            return Err(Error::Invalid(pixels_exceeded(w, h, self.budgets.pixels)));
        }
        let mut out = self.create_outputs(scene)?;
        self.warn_aspect(scene);
        self.say("Building image.");
        if scene.objects.is_empty() {
            err("warning: the scene has no objects; the image is the background only");
        }
        let mut staged = Vec::new();
        let (rendered, (w, h)) = self.picture(scene, shadows, &mut out, &mut staged)?;
        let tree_message = Self::stage_tree(rendered.tree.as_ref(), out.tree, &mut staged)?;
        if let Some(file) = out.id {
            staged.push(output::stage_id_png(
                file,
                &rendered.frame,
                &rendered.polygons,
            )?);
        }
        let paths: Vec<PathBuf> = staged.iter().map(|s| s.path().to_path_buf()).collect();
        output::commit_all(staged)?;
        self.written.extend(paths);
        self.say(&format!("Wrote {} ({w} x {h})", out.path.display()));
        if let Some(m) = tree_message {
            self.say(&m);
        }
        if let Some(p) = &self.id_image {
            self.say(&format!("Wrote the id image {}", p.display()));
        }
        self.report_stats(scene, &rendered);
        let elapsed = start.elapsed();
        self.say(&hms(elapsed));
        let field = |p: &Path| printable(&p.display().to_string(), 300).replace(' ', "\\x20");
        let s = &rendered.stats;
        append_log(&format!(
            "{} scene={} image={} size={w}x{h} polygons_tiled={} max_depth={} seconds={:.3}",
            utc_now(),
            self.scene_file
                .as_deref()
                .map_or_else(|| "<stdin>".into(), field),
            field(&out.path),
            s.polygons_tiled,
            s.max_depth,
            elapsed.as_secs_f64()
        ));
        Ok(())
    }

    /// The manual's statistics of a run, and this program's own figures.
    fn report_stats(&self, scene: &Scene, rendered: &render::Rendered) {
        let s = &rendered.stats;
        self.say(&format!(
            "{} Polygons tiled, Max depth = {}",
            s.polygons_tiled, s.max_depth
        ));
        for w in &s.warnings {
            err(&format!("warning: {w}"));
        }
        if let Some(r) = &s.raytrace {
            self.say(&format!(
                "Ray tracing: {} primary rays, {} rays in all, {} shadow rays, {:.0} rays per second \
                 (hierarchy {:.3} s, tracing {:.3} s)",
                r.primary,
                r.rays,
                r.shadow_rays,
                r.rays_per_second(),
                r.build_time.as_secs_f64(),
                r.trace_time.as_secs_f64()
            ));
        }
        if let Some(m) = &s.refraction {
            self.say(&format!("Refraction: {m}"));
        }
        if let Some(m) = s.method {
            let fragments = if s.scan.total_fragments > 0 {
                format!(
                    ", {} pixel-fragments at most at once, {} in all",
                    s.scan.peak_fragments, s.scan.total_fragments
                )
            } else {
                String::new()
            };
            self.say(&format!("Scan conversion: {}{fragments}", method_name(m)));
        }
        if let Some(p) = &rendered.profile {
            out(&p.to_string());
        } else if self.profile {
            out(
                "(no profile: the virtual image tree was not built; it is for the depth-sort and nns algorithms)",
            );
        }
        if let Some(n) = &s.nns {
            self.say(&nns_line(n));
        }
        if let Some(b) = &s.brown {
            self.say(&format!("Brown: {b}"));
        }
        if scene.modes.debug > 0 {
            self.say(&debug_timings(s));
        }
    }
}

/// The NNS statistics line.
fn nns_line(n: &plytrace::visibility::nns::NnsStats) -> String {
    format!(
        "NNS: {} faces in, {} out, {} splits ({} cycles of two, {} longer){}",
        n.faces_in,
        n.faces_out,
        n.splits,
        n.cycles_of_two,
        n.longer_cycles,
        if n.unresolved > 0 {
            format!(", {} unresolved", n.unresolved)
        } else {
            String::new()
        }
    )
}

/// The files of one run, created before it renders.
struct RunOutputs {
    /// The image's name.
    path: PathBuf,
    /// The image, until the picture takes it.
    image: Option<AtomicFile>,
    /// `--id-image`.
    id: Option<AtomicFile>,
    /// `setmode o`: FNAME.out and FNAME.txt.
    tree: Option<(AtomicFile, AtomicFile)>,
}

impl Host for CliHost {
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        plytrace::cancel::reset();
        RENDERING.store(true, Ordering::SeqCst);
        let result = self.render(scene, shadows);
        RENDERING.store(false, Ordering::SeqCst);
        plytrace::cancel::reset();
        result
    }
    /// The manual's `clear` empties the display to the background; here
    /// the display is the image file, so it is written (atomically) in the
    /// background colour, at the size the next `run` would write.
    fn clear(&mut self, scene: &Scene) -> Result<()> {
        let path = self.image_path(scene)?;
        let (w, h) = self
            .size
            .unwrap_or((scene.viewport.width(), scene.viewport.height()));
        if u64::from(w) * u64::from(h) > self.budgets.pixels {
            return Err(Error::Invalid(pixels_exceeded(w, h, self.budgets.pixels)));
        }
        self.budgets
            .check_frame(w, h, render::FRAME_BYTES_PER_PIXEL)
            .map_err(Error::Invalid)?;
        let file = AtomicFile::create(&path)?;
        let bg = scene.background;
        let frame = FrameBuffer::new(w, h, [bg.x as f32, bg.y as f32, bg.z as f32]);
        output::commit_all(vec![output::stage_image(file, &frame, scene.outmode)?])?;
        if let Ok(Some(window)) = self.live.observer(w, h) {
            let cleared = render::Rendered {
                frame,
                ..render::Rendered::empty(render::RenderStats::default())
            };
            plytrace::display::show_painted(&cleared, window);
        }
        self.say(&format!(
            "Cleared {} to the background ({w} x {h})",
            path.display()
        ));
        Ok(())
    }

    fn scanning(&mut self, file: &Path) {
        self.say(&format!("Scanning descriptor file {}", file.display()));
        self.scene_stem = file.file_stem().map(|s| s.to_string_lossy().into_owned());
        self.scene_file = Some(file.to_path_buf());
    }

    fn scanned(&mut self, _file: &Path, scene: &Scene, elapsed: Duration) {
        self.say(&format!(
            "{} objects, {} points, {} polygons",
            scene.objects.len(),
            scene.point_count(),
            scene.polygon_count()
        ));
        self.say(&hms(elapsed));
    }

    fn display(&mut self, on: bool) {
        if let Some(message) = self.live.request(on) {
            err(&format!("warning: {message}"));
        }
    }

    fn wait(&mut self) {
        if self.live.wait() {
            return;
        }
        if self.interactive && std::io::stdin().is_terminal() {
            out_text("Press return to continue.", false);
            let mut line = String::new();
            let _ = std::io::stdin().lock().read_line(&mut line);
        }
    }
}

fn report(e: &Error) {
    err(&format!("error: {e}"));
}

/// After an error in a scene that had already run: which files the earlier
/// runs wrote (complete; nothing of the failed part was written).
fn report_written(host: &CliHost) {
    if !host.written.is_empty() {
        let names: Vec<String> = host
            .written
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        err(&format!(
            "note: the runs before the error wrote {} (complete); nothing else was written",
            names.join(", ")
        ));
    }
}

/// The `setmode d` timing line: the stages the run measured, by name.
/// The tree path builds geometry, order and shadows in one pass (the
/// virtual image tree), then its records and the scan conversion; the
/// vector painter builds its tree, then paints; the image-space
/// algorithms have their own stages. Stages a path does not have are left
/// out rather than shown as zero.
fn debug_timings(s: &render::RenderStats) -> String {
    let names = if s.method.is_some() {
        [
            "geometry",
            "virtual image tree (geometry, sort, shadows)",
            "records (shading)",
            "scan conversion",
        ]
    } else {
        ["geometry", "sort", "shading", "paint"]
    };
    let times = [s.geometry_time, s.sort_time, s.shading_time, s.paint_time];
    let stages: Vec<String> = names
        .iter()
        .zip(times)
        .filter(|(_, t)| !t.is_zero())
        .map(|(n, t)| format!("{n} {t:?}"))
        .collect();
    format!("  {}; {:?}", stages.join(", "), s.geometry)
}

/// Reports the error that ended a batch run; status 130 for Ctrl-C (as a
/// shell reports SIGINT), 1 otherwise.
fn failed(e: &Error, host: &CliHost) -> ExitCode {
    report(e);
    report_written(host);
    if matches!(e, Error::Cancelled) {
        ExitCode::from(130)
    } else {
        ExitCode::FAILURE
    }
}

fn print_warnings(interp: &mut Interpreter) {
    for w in interp.take_warnings() {
        err(&w.to_string());
    }
}

fn load_scene(interp: &mut Interpreter, host: &mut CliHost, path: &Path) -> Result<Flow> {
    let start = Instant::now();
    host.scanning(path);
    let flow = interp.execute_file(path, true, host);
    print_warnings(interp);
    let flow = flow?;
    host.scanned(path, interp.current(), start.elapsed());
    Ok(flow)
}

/// The command table's lines, all of them or those of the commands whose
/// name starts with `topic` (the interpreter's shortest-prefix rule):
/// `--help` and the REPL's `help [CMD]` print from the same table.
fn command_help(topic: Option<&str>) -> String {
    let topic = topic.map(str::to_ascii_lowercase);
    let lines: Vec<String> = COMMANDS
        .iter()
        .filter(|c| {
            topic
                .as_ref()
                .is_none_or(|t| c.name.starts_with(t.as_str()))
        })
        .map(|c| format!("    {:<13} {:<38} {}\n", c.name, c.usage, c.help))
        .collect();
    match (lines.is_empty(), topic) {
        (true, Some(t)) => format!(
            "no command `{}`; `help` lists them all\n",
            plytrace::error::printable(&t, 40)
        ),
        _ => lines.concat(),
    }
}

/// `help` or `help CMD` typed at the prompt, answered; `None` for any
/// other line.
fn help_request(line: &str) -> Option<String> {
    let mut words = line.split_whitespace();
    let first = words.next()?;
    if !first.eq_ignore_ascii_case("help") {
        return None;
    }
    Some(command_help(words.next()))
}

/// Keeps the session's lines in `path` (its directory is made if need be);
/// a failure is a warning, never an error.
fn save_history(
    editor: &mut rustyline::Editor<repl::CommandCompleter, rustyline::history::FileHistory>,
    path: &Path,
) {
    let saved = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => std::fs::create_dir_all(dir)
            .map_err(rustyline::error::ReadlineError::Io)
            .and_then(|()| editor.save_history(path)),
        _ => editor.save_history(path),
    };
    if let Err(e) = saved {
        err(&format!(
            "warning: the command history was not kept in {}: {e}",
            path.display()
        ));
    }
}

fn interactive(interp: &mut Interpreter, host: &mut CliHost) -> ExitCode {
    let on_terminal = std::io::stdin().is_terminal();
    let stdin_label = Path::new("<stdin>");
    let mut line_no = 0usize;
    let mut failed = false;
    // Runs one line; errors are reported and remembered, the session goes on.
    let mut execute =
        |interp: &mut Interpreter, host: &mut CliHost, line: &str, line_no: usize| -> Flow {
            if let Some(text) = help_request(line) {
                host.say(text.trim_end());
                return Flow::Continue;
            }
            let result = interp.execute_source(line, stdin_label, Path::new("."), host);
            print_warnings(interp);
            match result {
                Ok(f) => f,
                Err(Error::Input(mut d)) => {
                    for loc in std::iter::once(&mut d.location).chain(d.included_from.iter_mut()) {
                        if loc.file == stdin_label {
                            loc.line = line_no;
                        }
                    }
                    report(&Error::Input(d));
                    failed = true;
                    Flow::Continue
                }
                Err(e) => {
                    report(&e);
                    failed = true;
                    Flow::Continue
                }
            }
        };
    if on_terminal {
        host.say(&format!("plytrace - version {VERSION}"));
        let Ok(mut editor) = rustyline::Editor::<repl::CommandCompleter, _>::with_history(
            rustyline::Config::builder()
                .max_history_size(repl::HISTORY_LINES)
                .map_or_else(|_| rustyline::Config::default(), |b| b.build()),
            rustyline::history::FileHistory::new(),
        ) else {
            err("error: cannot open the terminal for line editing");
            return ExitCode::FAILURE;
        };
        editor.set_helper(Some(repl::CommandCompleter::new()));
        let history = repl::history_path();
        if let Some(p) = &history {
            // A first session has no history yet.
            let _ = editor.load_history(p);
        }
        let mut interrupted = false;
        loop {
            match editor.readline("Command: ") {
                Ok(line) => {
                    interrupted = false;
                    line_no += 1;
                    let _ = editor.add_history_entry(line.as_str());
                    if execute(interp, host, &line, line_no) == Flow::Quit {
                        break;
                    }
                }
                // Ctrl-C at the prompt drops the line; twice in a row quits.
                Err(rustyline::error::ReadlineError::Interrupted) if !interrupted => {
                    interrupted = true;
                    err("(press Ctrl-C again, or type quit, to leave)");
                }
                Err(_) => break,
            }
        }
        if let Some(p) = &history {
            save_history(&mut editor, p);
        }
    } else {
        for line in std::io::stdin().lock().lines() {
            let Ok(line) = line else {
                err("error: standard input is not text");
                return ExitCode::FAILURE;
            };
            line_no += 1;
            if execute(interp, host, &line, line_no) == Flow::Quit {
                break;
            }
        }
    }
    if failed && !on_terminal {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// `plytrace tessellation FILE`: Brown's Angle and Edge Conditions for a
/// triangulated surface about its origin.
fn check_tessellation(path: &Path) -> ExitCode {
    let is_det = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("det"));
    let mesh = if is_det {
        object_file::read_det(path)
    } else {
        plytrace::scene::mesh_import::read_mesh(path)
    };
    let mesh = match mesh {
        Ok(m) => m,
        Err(e) => {
            report(&e);
            return ExitCode::FAILURE;
        }
    };
    match plytrace::modeling::geodesic::check_tessellation(&mesh, glam::DVec3::ZERO) {
        Ok(r) => {
            let yes = |b: bool| if b { "met" } else { "NOT met" };
            out(&format!(
                "{}: {} vertices, {} faces",
                path.display(),
                mesh.vertices.len(),
                mesh.polygons.len()
            ));
            out(&format!(
                "Angle Condition {}: adjacent patch edges at most {:.2} deg (limit 90), nonadjacent at least {:.2} deg (limit 90), degree up to {}",
                yes(r.angle_condition),
                r.max_adjacent_angle.to_degrees(),
                r.min_nonadjacent_angle.to_degrees(),
                r.max_degree
            ));
            out(&format!(
                "Edge Condition {}: longest patch edge {:.4} rad (limit 1), edge ratio up to {:.4} (limit 1.27)",
                yes(r.edge_condition),
                r.max_edge,
                r.max_edge_ratio
            ));
            ExitCode::SUCCESS
        }
        Err(e) => {
            err(&format!("error: {}: {e}", path.display()));
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let options = match parse_args(&args) {
        Ok(Parsed::Help) => {
            out(&usage());
            return ExitCode::SUCCESS;
        }
        Ok(Parsed::Version) => {
            out(&format!("plytrace {VERSION}"));
            return ExitCode::SUCCESS;
        }
        Ok(Parsed::Convert(kind, args)) => return plytrace::convert::main(kind, &args),
        Ok(Parsed::Tessellation(path)) => return check_tessellation(&path),
        Ok(Parsed::Continuity(path, form)) => {
            return match plytrace::modeling::patch::continuity_report(&path, form.as_deref()) {
                Ok(text) => {
                    out(&text);
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    report(&e);
                    ExitCode::FAILURE
                }
            };
        }
        Ok(Parsed::Run(o)) => o,
        Err(msg) => {
            err(&format!("error: {msg}"));
            return ExitCode::from(2);
        }
    };

    // The command line's outputs are checked at once, before the scene is
    // read (and again when each run creates them).
    for p in options.output.iter().chain(&options.id_image) {
        if let Err(e) = output::check_target(p) {
            report(&e);
            return ExitCode::FAILURE;
        }
    }
    if let Err(e) = ctrlc::set_handler(on_interrupt) {
        err(&format!("warning: Ctrl-C cannot cancel a render: {e}"));
    }
    let mut interp = Interpreter::new();
    interp.set_budgets(options.budgets);
    for (letter, value) in &options.modes {
        if let Err(e) = interp.force_mode(*letter, value) {
            let msg = match e.diagnostic() {
                Some(d) => d.message.clone(),
                None => e.to_string(),
            };
            err(&format!("error: flag -{letter}: {msg}"));
            return ExitCode::from(2);
        }
    }
    let mut host = CliHost {
        output: options.output.clone(),
        size: options.size,
        id_image: options.id_image.clone(),
        visibility: options.visibility,
        profile: options.profile,
        refraction: options.refraction,
        aa: options.aa,
        threads: options.threads,
        shading: options.shading,
        scene_stem: options
            .scene
            .as_ref()
            .and_then(|p| p.file_stem())
            .map(|s| s.to_string_lossy().into_owned()),
        scene_file: options.scene.clone(),
        quiet: options.quiet,
        interactive: !options.immediate,
        allow_outside: options.allow_outside,
        budgets: options.budgets,
        progress: !options.quiet && std::io::stderr().is_terminal(),
        aspect_warned: false,
        written: Vec::new(),
        runs: 0,
        hidden_line: options.hidden_line,
        orders: Default::default(),
        raytrace: options.raytrace,
        live: Default::default(),
    };

    if let Some(scene) = &options.scene {
        match load_scene(&mut interp, &mut host, scene) {
            Ok(Flow::Quit) => return ExitCode::SUCCESS,
            Ok(Flow::Continue) => {}
            Err(e) => {
                return failed(&e, &host);
            }
        }
        // Immediate mode is `get` then `run y`; a scene that says `run`
        // itself (an animation) is rendered as it says, each `run` once.
        if options.immediate && host.runs > 0 {
            return ExitCode::SUCCESS;
        }
        if options.immediate {
            return match host.run(interp.current(), true) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => failed(&e, &host),
            };
        }
    }
    interactive(&mut interp, &mut host)
}

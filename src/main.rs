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

const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The longest line printed from input, in characters; the rest is cut
/// (see [`printable`]).
const MAX_LINE: usize = 1000;

/// Set when stdout is a closed pipe: nothing more is printed there, and the
/// program goes on (the image is still written) and ends with status 0.
static STDOUT_GONE: AtomicBool = AtomicBool::new(false);

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
    -o FILE.png|.ppm   output image (any value of -o other than on/off); PNG and
                       binary PPM are the formats written
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
    --refraction M     refraction matrix: linearized (default; exact for the ray through
                       the polygon's centre), orthographic (M_to), paraxial (M_tp)
    --aa METHOD        scan conversion (004 chapter 5): none (point sampled preview),
                       area (1), mask (2), hybrid (3), multilevel (4); default: the
                       best for the scene (multilevel: every tree level blended)
    --supersample N    Donovan's N x N samples per pixel instead (N from 1 to 16)
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
            "--max-polygons" => o.budgets.polygons = to_usize(count(arg)?),
            "--max-call-depth" => o.budgets.call_depth = to_usize(count(arg)?),
            "--max-tree-nodes" => o.budgets.tree_nodes = to_usize(count(arg)?),
            "--max-splits" => o.budgets.splits = to_usize(count(arg)?),
            "--max-pixels" => o.budgets.pixels = count(arg)?,
            "--quiet" | "-q" => o.quiet = true,
            "--profile" => o.profile = true,
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
                let v = value("linearized, orthographic or paraxial")?;
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
    output::check_image_extension(&p)?;
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

impl Host for CliHost {
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        self.runs += 1;
        let start = Instant::now();
        // Everything that can be checked is checked before the render:
        // the size against the budget, the names, and every output (its
        // temporary file is created now, beside it).
        let (mut w, mut h) = self
            .size
            .unwrap_or((scene.viewport.width(), scene.viewport.height()));
        if u64::from(w) * u64::from(h) > self.budgets.pixels {
            return Err(Error::Invalid(pixels_exceeded(w, h, self.budgets.pixels)));
        }
        // `fname` is checked only where it names a file.
        let named = (scene.display && self.output.is_none()) || scene.modes.output_tree;
        let stem = if named {
            self.stem(scene)?
        } else {
            String::new()
        };
        let path = self
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("{stem}.png")));
        let mut image_file = if scene.display {
            Some(AtomicFile::create(&path)?)
        } else {
            None
        };
        let id_file = match &self.id_image {
            Some(p) => Some(AtomicFile::create(p)?),
            None => None,
        };
        let tree_files = if scene.modes.output_tree {
            Some((
                AtomicFile::create(Path::new(&format!("{stem}.out")))?,
                AtomicFile::create(Path::new(&format!("{stem}.txt")))?,
            ))
        } else {
            None
        };
        self.warn_aspect(scene);
        self.say("Building image.");
        if scene.objects.is_empty() {
            err("warning: the scene has no objects; the image is the background only");
        }
        let options = RenderOptions {
            size: self.size,
            shadows,
            visibility: self.visibility,
            profile: self.profile,
            refraction: self.refraction,
            aa: self.aa,
            threads: self.threads,
            shading: self.shading,
            budgets: self.budgets,
        };
        let streamed = scene.display
            && self.id_image.is_none()
            && path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let mut staged = Vec::new();
        let rendered = match render::plan(scene, &options)? {
            render::Plan::Tree(mut prepared) if streamed => {
                // The virtual frame buffer: bands of rows go to the PNG as
                // they are finished; the whole image is never in memory.
                prepared.scan.ids = false;
                (w, h) = (prepared.scan.width, prepared.scan.height);
                let file = image_file.take().expect("created for a displayed image");
                let mut sink = output::PngSink::from_file(file, w, h, scene.outmode.into())?;
                let mut progress = ProgressSink::new(&mut sink, h, self.progress);
                let rendered = render::scan_into(*prepared, &mut progress);
                progress.finish();
                let rendered = rendered?;
                let (file, note) = sink.finish()?;
                if let Some(note) = note {
                    err(&format!("warning: {note}"));
                }
                staged.push(file);
                rendered
            }
            plan => {
                let rendered = match plan {
                    render::Plan::Tree(prepared) => {
                        let (w, h) = (prepared.scan.width, prepared.scan.height);
                        let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
                        let mut sink = render::FrameSink { frame: &mut frame };
                        let mut progress = ProgressSink::new(&mut sink, h, self.progress);
                        let rendered = render::scan_into(*prepared, &mut progress);
                        progress.finish();
                        let mut rendered = rendered?;
                        rendered.frame = frame;
                        rendered
                    }
                    render::Plan::Painted(r) => *r,
                };
                if let Some(file) = image_file.take() {
                    staged.push(output::stage_image(file, &rendered.frame, scene.outmode)?);
                }
                rendered
            }
        };
        if rendered.frame.width > 0 {
            (w, h) = (rendered.frame.width, rendered.frame.height);
        }
        let mut tree_message = None;
        if let (Some(tree), Some((mut bin, mut txt))) = (&rendered.tree, tree_files) {
            bin.write_all(&tree.to_bytes())?;
            txt.write_all(tree.to_text().as_bytes())?;
            tree_message = Some(format!(
                "Wrote the virtual image tree ({} polygons) to {} and {}",
                tree.records.len(),
                bin.path().display(),
                txt.path().display()
            ));
            staged.push(bin.finish()?);
            staged.push(txt.finish()?);
        }
        if let Some(file) = id_file {
            staged.push(output::stage_id_png(
                file,
                &rendered.frame,
                &rendered.polygons,
            )?);
        }
        // All the outputs of the run appear together, or none of them.
        let paths: Vec<PathBuf> = staged.iter().map(|s| s.path().to_path_buf()).collect();
        output::commit_all(staged)?;
        self.written.extend(paths.iter().cloned());
        if scene.display {
            self.say(&format!("Wrote {} ({w} x {h})", path.display()));
        }
        if let Some(m) = tree_message {
            self.say(&m);
        }
        if let Some(p) = &self.id_image {
            self.say(&format!("Wrote the id image {}", p.display()));
        }
        let s = &rendered.stats;
        self.say(&format!(
            "{} Polygons tiled, Max depth = {}",
            s.polygons_tiled, s.max_depth
        ));
        for w in &s.warnings {
            err(&format!("warning: {w}"));
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
            self.say(&format!(
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
            ));
        }
        if scene.modes.debug > 0 {
            self.say(&format!(
                "  geometry {:?}, sort {:?}, shading {:?}, paint {:?}; {:?}",
                s.geometry_time, s.sort_time, s.shading_time, s.paint_time, s.geometry
            ));
        }
        let elapsed = start.elapsed();
        self.say(&hms(elapsed));
        let field = |p: &Path| printable(&p.display().to_string(), 300).replace(' ', "\\x20");
        append_log(&format!(
            "{} scene={} image={} size={w}x{h} polygons_tiled={} max_depth={} seconds={:.3}",
            utc_now(),
            self.scene_file
                .as_deref()
                .map_or_else(|| "<stdin>".into(), field),
            if scene.display {
                field(&path)
            } else {
                "-".into()
            },
            s.polygons_tiled,
            s.max_depth,
            elapsed.as_secs_f64()
        ));
        Ok(())
    }
    fn clear(&mut self, _scene: &Scene) {}

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

    fn wait(&mut self) {
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
    host.scanned(path, &interp.scene(), start.elapsed());
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
        let Ok(mut editor) = rustyline::DefaultEditor::new() else {
            err("error: cannot open the terminal for line editing");
            return ExitCode::FAILURE;
        };
        loop {
            match editor.readline("Command: ") {
                Ok(line) => {
                    line_no += 1;
                    let _ = editor.add_history_entry(line.as_str());
                    if execute(interp, host, &line, line_no) == Flow::Quit {
                        break;
                    }
                }
                Err(rustyline::error::ReadlineError::Interrupted) => continue,
                Err(_) => break,
            }
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
    };

    if let Some(scene) = &options.scene {
        match load_scene(&mut interp, &mut host, scene) {
            Ok(Flow::Quit) => return ExitCode::SUCCESS,
            Ok(Flow::Continue) => {}
            Err(e) => {
                report(&e);
                report_written(&host);
                return ExitCode::FAILURE;
            }
        }
        // Immediate mode is `get` then `run y`; a scene that says `run`
        // itself (an animation) is rendered as it says, each `run` once.
        if options.immediate && host.runs > 0 {
            return ExitCode::SUCCESS;
        }
        if options.immediate {
            let scene = interp.scene();
            return match host.run(&scene, true) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    report(&e);
                    report_written(&host);
                    ExitCode::FAILURE
                }
            };
        }
    }
    interactive(&mut interp, &mut host)
}

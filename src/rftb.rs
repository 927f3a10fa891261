//! The anti-aliasing polygon tilers rftb1-4 and getrgb as programs (Garcia
//! 1986, 004 appendix: the rftb and getrgb manual pages; chapter 5 for the
//! methods). Each binary in `src/bin` is a few lines over this module.
//!
//! ```text
//! rftbN <input> [output] [hres] [vres] [act-lines] [-flags]
//! getrgb NAME [hres vres] [-p | --png FILE]
//! ```
//!
//! Both take plytrace's budgets `--max-pixels N` and `--max-frame-memory
//! MiB`, with its defaults ([`Budgets::default`]): the resolution, the
//! bands of `act-lines` rows and the input files are checked against them
//! before anything is allocated or written, and an output that would pass
//! the file size limit (`ulimit -f`) is refused before it is started.
//! Inputs are read only from regular files, and no output may be an
//! input, another output or the program's log. SIGINT, SIGTERM and SIGHUP
//! stop a run within a second, remove its temporary files and end the
//! program with status 130, 143 or 129.
//!
//! rftbN reads `<input>.out` (a virtual image tree file, [`crate::tree`];
//! an input given as `X.out` is taken as `X`),
//! refuses a tree made for another method (back to front, or, with a
//! record below level 1, the other blending mode; both read from its
//! background record, see [`check_tree`]), blends transparency by
//! [`Program::transparency`] (section 5.6 for rftb1 and rftb3), and
//! writes, under the output seed (default: the input name):
//!
//! - rftb1 (method 1, area coverage): `OUTPUT.r .g .b .a`;
//! - rftb2 (method 2, pixel masks): `OUTPUT.r .g .b .m` (the manual's
//!   FILES section; its example says `.a`, but a mask tiler has masks);
//! - rftb3 (method 3, both): `OUTPUT.r .g .b .a .m`;
//! - rftb4 (method 4, pixel-structs): the pixel-struct file `OUTPUT`,
//!   exactly `hres x vres` 8-byte structs as getrgb's manual page says,
//!   and beside it `OUTPUT.frag`, the resolution and the fragment lists
//!   that the structs' `flist` fields point into.
//!
//! getrgb, like the manual's (`getrgb [fname]`), needs no resolution: it
//! writes the colours of the linear list of structs to `NAME.r .g .b`.
//! The PNG (`-p`, `--png`), an extension, needs the width: from the
//! optional `hres vres`, or else from `NAME.frag`.
//!
//! Layouts are in [`crate::output`]. With a display flag (`-a BITS`, `-r`,
//! `-g`, `-b`, `-y`, `-c`) the image is also written as `OUTPUT.png` in
//! that mode; there is no graphics screen, so `-Y` is accepted and
//! explained. All outputs appear together when the run succeeds and none
//! when it fails. Each run appends a line of statistics to `rftbN.log`
//! (`getrgb.log`) in the working directory.

use std::ffi::OsString;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Instant, SystemTime};

use crate::budget::Budgets;
use crate::error::{Error, Result};
use crate::output::{
    DisplayMode, PixelStructSink, Planes, PngSink, SeparationSink, Staged, commit_all, with_suffix,
};
use crate::raster::scan::{Method, Row, RowSink, ScanOptions, ScanStats, TransparencyRule};
use crate::tree::RecordStream;

/// One of the four tilers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Program {
    /// Pixel coverage (method 1).
    Rftb1,
    /// Pixel masks (method 2).
    Rftb2,
    /// Coverage and masks (method 3).
    Rftb3,
    /// Pixel-structs (method 4).
    Rftb4,
}

impl Program {
    /// The program's name.
    pub fn name(self) -> &'static str {
        match self {
            Program::Rftb1 => "rftb1",
            Program::Rftb2 => "rftb2",
            Program::Rftb3 => "rftb3",
            Program::Rftb4 => "rftb4",
        }
    }

    /// Its scan conversion method.
    pub fn method(self) -> Method {
        match self {
            Program::Rftb1 => Method::Area,
            Program::Rftb2 => Method::Mask,
            Program::Rftb3 => Method::Hybrid,
            Program::Rftb4 => Method::Multilevel,
        }
    }

    /// The separation planes besides `.r .g .b`; `None` for rftb4's
    /// pixel-struct file.
    pub fn planes(self) -> Option<Planes> {
        let (coverage, mask) = match self {
            Program::Rftb1 => (true, false),
            Program::Rftb2 => (false, true),
            Program::Rftb3 => (true, true),
            Program::Rftb4 => return None,
        };
        Some(Planes { coverage, mask })
    }

    /// Whether it wants pre-blended shades (`setmode b on`): rftb1-3 do,
    /// rftb4 blends itself.
    pub fn wants_preblended(self) -> bool {
        self != Program::Rftb4
    }

    /// How it blends transparent surfaces: rftb1 "simulates linear and
    /// non-linear transparency using a pixel-coverage byte" and rftb3
    /// "combines the features of rftb1 and rftb2" (the rftb manual page),
    /// by section 5.6 (`Ā = A (1 - T)`, section 5.8 for rftb3). The manual
    /// gives rftb2 and rftb4 no transparency; they keep plytrace's
    /// section 4.9 rule (`I = I_cur + k_t I_behind`).
    pub fn transparency(self) -> TransparencyRule {
        match self {
            Program::Rftb1 | Program::Rftb3 => TransparencyRule::Coverage,
            Program::Rftb2 | Program::Rftb4 => TransparencyRule::Garcia,
        }
    }

    /// The usage line.
    pub fn usage(self) -> String {
        format!(
            "usage: {} <input> [output] [hres] [vres] [act-lines] [-0..-9] [-B] \
             [-a BITS | -r | -g | -b | -y | -c] [-Y] [--part I/N -o PART.png] {BUDGET_FLAGS}",
            self.name()
        )
    }
}

/// The parsed command line of rftbN.
#[derive(Debug, Clone, PartialEq)]
pub struct Args {
    /// The tree file, `<input>.out`.
    pub input: PathBuf,
    /// The output seed.
    pub output: PathBuf,
    /// Width.
    pub hres: u32,
    /// Height.
    pub vres: u32,
    /// Frame buffer lines kept in memory.
    pub act_lines: u32,
    /// Debug level 0-9.
    pub debug: u8,
    /// `-B`: paint the background record after everything.
    pub background: bool,
    /// A display flag: also write `OUTPUT.png` in this mode.
    pub display: Option<DisplayMode>,
    /// `-Y` was given.
    pub screen: bool,
    /// `--max-pixels`, `--max-frame-memory`; the rest are unused.
    pub budgets: Budgets,
    /// `--part I/N`: only this part of the image, into the part file
    /// [`Args::part_file`] (see [`crate::part`]), and nothing else.
    pub part: Option<crate::part::PartSpec>,
    /// `-o FILE`: the part file of `--part`.
    pub part_file: Option<PathBuf>,
}

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Command<T> {
    /// Run with these arguments.
    Run(T),
    /// `-h` / `--help`.
    Help,
}

/// A command line that cannot be used (exit status 2).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsageError(pub String);

fn usage_err<T>(msg: impl Into<String>) -> std::result::Result<T, UsageError> {
    Err(UsageError(msg.into()))
}

/// The budget flags both programs take, as in plytrace.
const BUDGET_FLAGS: &str = "[--max-pixels N] [--max-frame-memory MiB]";

/// Parses a budget flag (`--max-pixels N`, `--max-frame-memory MiB`, or
/// with `=`) into `budgets`; false when `arg` is not one.
fn budget_flag(
    arg: &str,
    rest: &mut dyn Iterator<Item = OsString>,
    budgets: &mut Budgets,
) -> std::result::Result<bool, UsageError> {
    let (flag, inline) = match arg.split_once('=') {
        Some((f, v)) => (f, Some(v.to_string())),
        None => (arg, None),
    };
    if flag != "--max-pixels" && flag != "--max-frame-memory" {
        return Ok(false);
    }
    let value = match inline {
        Some(v) => v,
        None => rest
            .next()
            .ok_or_else(|| UsageError(format!("{flag} needs a number")))?
            .to_string_lossy()
            .into_owned(),
    };
    let n = match value.parse::<u64>() {
        Ok(n) if n > 0 => n,
        _ => {
            return usage_err(format!(
                "{flag}: expected a whole number of at least 1, got `{}`",
                crate::error::printable(&value, 40)
            ));
        }
    };
    if flag == "--max-pixels" {
        budgets.pixels = n;
    } else {
        budgets.frame_memory = n.saturating_mul(1 << 20);
    }
    Ok(true)
}

fn number(arg: &OsString, what: &str, min: u32) -> std::result::Result<u32, UsageError> {
    match arg.to_str().and_then(|s| s.parse::<u32>().ok()) {
        Some(n) if n >= min => Ok(n),
        _ => usage_err(format!(
            "{what}: expected a whole number of at least {min}, got `{}`",
            arg.to_string_lossy()
        )),
    }
}

/// Parses `-a BITS`' number.
fn bits(s: &str) -> std::result::Result<u8, UsageError> {
    match s.parse::<u8>() {
        Ok(b @ 1..=8) => Ok(b),
        _ => usage_err(format!("-a: bits per colour run from 1 to 8, got `{s}`")),
    }
}

fn set_display(args: &mut Args, mode: DisplayMode) -> std::result::Result<(), UsageError> {
    if args.display.is_some_and(|m| m != mode) {
        return usage_err("give at most one display mode (-a, -r, -g, -b, -y, -c)");
    }
    args.display = Some(mode);
    Ok(())
}

/// Parses one flag group such as `-B3`; `rest` gives `-a`'s argument when
/// the group does not hold it.
fn flag_group(
    group: &str,
    args: &mut Args,
    rest: &mut dyn Iterator<Item = OsString>,
) -> std::result::Result<(), UsageError> {
    for (i, c) in group.char_indices() {
        match c {
            '0'..='9' => args.debug = c as u8 - b'0',
            'B' => args.background = true,
            'Y' => args.screen = true,
            'r' => set_display(args, DisplayMode::Channel(0))?,
            'g' => set_display(args, DisplayMode::Channel(1))?,
            'b' => set_display(args, DisplayMode::Channel(2))?,
            'y' => set_display(args, DisplayMode::Luminance)?,
            'c' => set_display(args, DisplayMode::Rgb332)?,
            'a' => {
                let tail = &group[i + 1..];
                let n = if tail.is_empty() {
                    let next = rest
                        .next()
                        .ok_or(UsageError("-a needs BITS (1-8)".into()))?;
                    bits(&next.to_string_lossy())?
                } else {
                    bits(tail)?
                };
                return set_display(args, DisplayMode::Adaptive(n));
            }
            _ => return usage_err(format!("unknown flag `-{c}`")),
        }
    }
    Ok(())
}

/// Parses rftbN's arguments (without the program name).
pub fn parse_args(
    argv: impl IntoIterator<Item = OsString>,
) -> std::result::Result<Command<Args>, UsageError> {
    let mut args = Args {
        input: PathBuf::new(),
        output: PathBuf::new(),
        hres: 256,
        vres: 256,
        act_lines: 4,
        debug: 0,
        background: false,
        display: None,
        screen: false,
        budgets: Budgets::default(),
        part: None,
        part_file: None,
    };
    let mut positional: Vec<OsString> = Vec::new();
    let mut it = argv.into_iter();
    while let Some(arg) = it.next() {
        let s = arg.to_string_lossy();
        if s == "-h" || s == "--help" {
            return Ok(Command::Help);
        }
        if budget_flag(&s, &mut it, &mut args.budgets)? {
            continue;
        }
        if s == "--part" || s.starts_with("--part=") || s == "-o" {
            let value = match s.split_once('=') {
                Some((_, v)) => v.to_string(),
                None => it
                    .next()
                    .ok_or_else(|| UsageError(format!("{s} needs a value")))?
                    .to_string_lossy()
                    .into_owned(),
            };
            if s == "-o" {
                args.part_file = Some(PathBuf::from(value));
            } else {
                args.part = Some(
                    value
                        .parse()
                        .map_err(|e| UsageError(format!("--part: {e}")))?,
                );
            }
            continue;
        }
        if s.starts_with("--") {
            return usage_err(format!(
                "unknown flag `{}`",
                crate::error::printable(&s, 40)
            ));
        }
        match s.strip_prefix('-') {
            Some(group) if !group.is_empty() => flag_group(group, &mut args, &mut it)?,
            _ => positional.push(arg),
        }
    }
    let (input, output) = match positional.as_slice() {
        [] => return usage_err("no input given"),
        [_, _, _, _, _, extra, ..] => {
            return usage_err(format!(
                "too many arguments from `{}`",
                extra.to_string_lossy()
            ));
        }
        [input, rest @ ..] => (input, rest),
    };
    let seed = PathBuf::from(input);
    let seed = match seed.to_str().and_then(|s| s.strip_suffix(".out")) {
        Some(stem) => PathBuf::from(stem),
        None => seed,
    };
    args.input = with_suffix(&seed, "out");
    args.output = output.first().map_or(seed, PathBuf::from);
    if let Some(h) = output.get(1) {
        args.hres = number(h, "hres", 1)?;
    }
    if let Some(v) = output.get(2) {
        args.vres = number(v, "vres", 1)?;
    }
    if let Some(a) = output.get(3) {
        args.act_lines = number(a, "act-lines", 1)?;
    }
    match (&args.part, &args.part_file) {
        (Some(p), None) => {
            return usage_err(format!(
                "--part {p} writes a part file: name it with -o, such as -o parts/{}.png",
                p.index
            ));
        }
        (None, Some(_)) => return usage_err("-o names the part file of --part I/N"),
        (Some(_), Some(f)) if !f.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) => {
            return usage_err(format!(
                "-o {}: a part file is a PNG; name it .png",
                f.display()
            ));
        }
        _ => {}
    }
    Ok(Command::Run(args))
}

/// Checks that `stream` suits `program`: front to back, and pre-blended
/// for rftb1-3, post-blended for rftb4, unless the tree has only level-1
/// records. Pre-blending (`setmode b on`) blends "higher tree level parent
/// polygon intensities ... with each lower level children polygon" (004
/// appendix, SETMODE COMMANDS, `b`): with no record below level 1 there
/// is nothing to blend and both modes write the same shades, so either is
/// accepted (the manual's default, `setmode b off`, then works with every
/// tiler).
pub fn check_tree(program: Program, stream: &RecordStream, input: &Path) -> Result<()> {
    let mut wrong = Vec::new();
    if !stream.front_to_back {
        wrong.push("its polygons are back to front; write it with `sort ftb`".to_string());
    }
    let children = stream.records.iter().filter(|r| r.level > 1).count();
    let sub_level = |n: usize| {
        format!(
            "{n} of its records lie below level 1 (reflections or refractions), so the \
             blending mode matters"
        )
    };
    match (program.wants_preblended(), stream.blended) {
        (true, false) if children > 0 => wrong.push(format!(
            "its shades are post-blended and {}; {} blends nothing, so children would not \
             get their parents' shades: write it with `setmode b on` (or use rftb4)",
            sub_level(children),
            program.name()
        )),
        (false, true) if children > 0 => wrong.push(format!(
            "its shades are pre-blended and {}; rftb4 blends children with parents itself, \
             so parents would count twice: write it with `setmode b off`",
            sub_level(children)
        )),
        _ => {}
    }
    if wrong.is_empty() {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "{}: this tree is not for {}: {}",
        input.display(),
        program.name(),
        wrong.join("; ")
    )))
}

// ---------------------------------------------------------------------------
// Refusals before the work

/// Bytes a pixel of a band of `act-lines` rows takes in memory while it is
/// scan converted and delivered (the integrator's state and the band's
/// output), generously: methods 1-3 hold about 45, method 4 about 70 plus
/// its fragments.
pub fn band_bytes_per_pixel(program: Program) -> u64 {
    match program {
        Program::Rftb4 => 128,
        _ => 64,
    }
}

/// Scan threads of a run: the cores, as the scan converter takes them.
/// Looked up once: on Linux it reads the cgroup files, which took a
/// quarter of the time of the `rftb_args` fuzz target's checks.
fn scan_threads() -> u64 {
    static THREADS: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get() as u64))
}

/// Refuses a `hres x vres` image beyond the pixel budget.
pub fn check_pixels(hres: u32, vres: u32, budgets: &Budgets) -> Result<()> {
    let pixels = u64::from(hres) * u64::from(vres);
    if pixels <= budgets.pixels {
        return Ok(());
    }
    Err(Error::Budget {
        flag: "--max-pixels",
        message: format!(
            "{} (hres x vres)",
            Budgets::exceeded(
                &format!("a {hres} x {vres} image ({pixels} pixels)"),
                format!("{} pixels", budgets.pixels),
                "--max-pixels"
            )
        ),
    })
}

/// What the bands of `args` hold in memory at once, in bytes, and the
/// number of bands: up to 2 x threads + 1 of `act-lines` rows (see
/// `crate::raster::scan`).
pub fn band_memory(program: Program, args: &Args) -> (u64, u64) {
    let rows = u64::from(args.act_lines.min(args.vres));
    let bands = u64::from(args.vres).div_ceil(rows.max(1));
    let in_flight = (2 * scan_threads() + 1).min(bands.max(1));
    let need = rows
        .saturating_mul(u64::from(args.hres))
        .saturating_mul(band_bytes_per_pixel(program))
        .saturating_mul(in_flight);
    (need, in_flight)
}

/// Bytes of memory per byte of a tree file, read and prepared for scan
/// conversion. Measured (peak resident size over file size, rftb1-4 at
/// 64x64): tiny faceted triangles 9, tiny Gouraud triangles 25, tiny
/// Phong triangles 23, Gouraud polygons of 1000 vertices 22. With the
/// default frame memory budget a tree file may have about 32 MiB.
pub const TREE_MEMORY_PER_BYTE: u64 = 32;

/// Refuses what `args` would take beyond its budgets, before anything is
/// read, allocated or written: the pixels, and the bands in memory.
pub fn check_budgets(program: Program, args: &Args) -> Result<()> {
    check_pixels(args.hres, args.vres, &args.budgets)?;
    let (need, bands) = band_memory(program, args);
    if need > args.budgets.frame_memory {
        return Err(Error::Budget {
            flag: "--max-frame-memory",
            message: format!(
                "{}; lower act-lines (the fifth argument) or the width",
                Budgets::exceeded(
                    &format!(
                        "act-lines {} of {} pixels: {bands} bands in memory at once ({} MiB)",
                        args.act_lines.min(args.vres),
                        args.hres,
                        need.div_ceil(1 << 20)
                    ),
                    format!("{} MiB", args.budgets.frame_memory >> 20),
                    "--max-frame-memory"
                )
            ),
        });
    }
    Ok(())
}

/// The file size limit of this process (`ulimit -f`), in bytes, when
/// there is one.
pub fn file_size_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max file size"))?;
    let soft = line["Max file size".len()..].split_whitespace().next()?;
    soft.parse().ok()
}

/// Refuses an output of `bytes` bytes that the file size limit would cut
/// short (the system would end the program with SIGXFSZ, or fail the
/// write, half way).
pub fn check_output_size(path: &Path, bytes: u64) -> Result<()> {
    match file_size_limit() {
        Some(limit) if bytes > limit => Err(Error::Invalid(format!(
            "{}: this output would have {bytes} bytes, more than the file size limit of \
             {limit} bytes (`ulimit -f`); lower hres or vres, or raise the limit",
            crate::error::printable(&path.display().to_string(), 200)
        ))),
        _ => Ok(()),
    }
}

/// A name for comparing file names that may not exist yet: the canonical
/// directory and the file name (`./a` and `a` are the same name).
fn name_key(path: &Path) -> PathBuf {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    match path.file_name() {
        Some(name) => dir.join(name),
        None => path.to_path_buf(),
    }
}

fn shown(p: &Path) -> String {
    crate::error::printable(&p.display().to_string(), 200)
}

/// Refuses, before any work, a set of outputs in which one output is an
/// input, another output or the program's log `log` (each compared as a
/// name and, when it exists, as a file: a link or another spelling is
/// caught too). The message names both.
pub fn check_names(inputs: &[PathBuf], outputs: &[PathBuf], log: &Path) -> Result<()> {
    let same = |a: &Path, b: &Path| {
        if name_key(a) == name_key(b) {
            return true;
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
                return (x.dev(), x.ino()) == (y.dev(), y.ino());
            }
        }
        false
    };
    for (i, out) in outputs.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|p| same(out, p)) {
            return Err(Error::Invalid(format!(
                "{}: this output is the input {}; it is not written over (name another \
                 output)",
                shown(out),
                shown(input)
            )));
        }
        if let Some(other) = outputs[..i].iter().find(|p| same(out, p)) {
            return Err(Error::Invalid(format!(
                "{}: this output is also the output {} of this run; name another output",
                shown(out),
                shown(other)
            )));
        }
        if same(out, log) {
            return Err(Error::Invalid(format!(
                "{}: this output is {}, the log this program appends to; name another output",
                shown(out),
                shown(log)
            )));
        }
    }
    Ok(())
}

/// Reads the input `path` (a regular file only, noted so that no output
/// writes over it) when its size is within `limit` bytes; `budget` says
/// what the limit is, for the message (a `--max-frame-memory` budget).
fn read_input(path: &Path, limit: u64, budget: impl FnOnce(u64) -> String) -> Result<Vec<u8>> {
    if let Ok(meta) = std::fs::metadata(path)
        && meta.is_file()
        && meta.len() > limit
    {
        return Err(Error::Budget {
            flag: "--max-frame-memory",
            message: format!("{}: {}", shown(path), budget(meta.len())),
        });
    }
    crate::scene::object_file::read_regular(path, limit)
}

/// The files rftbN writes for `args`.
pub fn output_paths(program: Program, args: &Args) -> Vec<PathBuf> {
    let mut out = match program.planes() {
        Some(planes) => SeparationSink::paths(&args.output, planes),
        None => vec![
            args.output.clone(),
            with_suffix(&args.output, crate::output::FRAGMENT_SUFFIX),
        ],
    };
    if args.display.is_some() {
        out.push(with_suffix(&args.output, "png"));
    }
    out
}

/// The largest file of fixed size rftbN writes, and its size: the
/// pixel-struct file (8 bytes a pixel), else a mask separation (2), else
/// a byte a pixel.
fn largest_output(program: Program, args: &Args) -> (PathBuf, u64) {
    let pixels = u64::from(args.hres) * u64::from(args.vres);
    let (ext, bytes) = match program {
        Program::Rftb4 => (None, crate::output::PIXEL_STRUCT_BYTES as u64),
        Program::Rftb2 | Program::Rftb3 => (Some("m"), 2),
        Program::Rftb1 => (Some("r"), 1),
    };
    let path = ext.map_or(args.output.clone(), |e| with_suffix(&args.output, e));
    (path, pixels.saturating_mul(bytes))
}

/// The files a run writes.
enum MainSink {
    Separations(SeparationSink),
    PixelStructs(PixelStructSink),
}

/// Every output of one run, fed the same rows.
struct Outputs {
    main: MainSink,
    png: Option<PngSink>,
}

impl RowSink for Outputs {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        crate::cancel::check()?;
        match &mut self.main {
            MainSink::Separations(s) => s.row(row)?,
            MainSink::PixelStructs(s) => s.row(row)?,
        }
        match &mut self.png {
            Some(p) => p.row(row),
            None => Ok(()),
        }
    }

    fn wants_pixel_structs(&self) -> bool {
        matches!(self.main, MainSink::PixelStructs(_))
    }
}

impl Outputs {
    /// Opens every output (which checks that it is writable).
    fn create(program: Program, args: &Args) -> Result<Outputs> {
        let (w, h) = (args.hres, args.vres);
        let main = match program.planes() {
            Some(planes) => {
                MainSink::Separations(SeparationSink::create(&args.output, w, h, planes)?)
            }
            None => MainSink::PixelStructs(PixelStructSink::create(&args.output, w, h)?),
        };
        let png = match args.display {
            Some(mode) => Some(PngSink::create(
                &with_suffix(&args.output, "png"),
                w,
                h,
                mode,
            )?),
            None => None,
        };
        Ok(Outputs { main, png })
    }

    /// Completes and renames everything together; returns notes for the log.
    fn commit(self) -> Result<Vec<String>> {
        crate::cancel::check()?;
        let mut staged: Vec<Staged> = match self.main {
            MainSink::Separations(s) => s.finish()?,
            MainSink::PixelStructs(s) => s.finish()?,
        };
        let mut notes = Vec::new();
        if let Some(p) = self.png {
            let (file, note) = p.finish()?;
            staged.push(file);
            notes.extend(note);
        }
        crate::cancel::check()?;
        commit_all(staged)?;
        Ok(notes)
    }
}

/// What a run did, for the log.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Records in the tree (the background record not counted).
    pub records: usize,
    /// The scan converter's figures.
    pub stats: ScanStats,
    /// Seconds, reading to the last rename.
    pub seconds: f64,
    /// Remarks (e.g. the adaptive table lowered its bits).
    pub notes: Vec<String>,
}

/// Renders `args` with `program`.
pub fn run(program: Program, args: &Args) -> Result<Summary> {
    if let (Some(spec), Some(file)) = (args.part, &args.part_file) {
        return run_part(program, args, spec, file);
    }
    let start = Instant::now();
    check_budgets(program, args)?;
    check_names(
        std::slice::from_ref(&args.input),
        &output_paths(program, args),
        &log_path(program.name()),
    )?;
    let (largest, size) = largest_output(program, args);
    check_output_size(&largest, size)?;
    // The tree and what the scan converter makes of it share the memory
    // budget with the bands.
    let bytes = read_tree_bytes(program, args)?;
    // Every output is opened (and so checked against the input read) before
    // the tree is even parsed.
    let mut outputs = Outputs::create(program, args)?;
    let stream = parse_tree(program, args, &bytes)?;
    crate::cancel::check()?;
    let options = ScanOptions {
        width: args.hres,
        height: args.vres,
        method: program.method(),
        act_lines: args.act_lines,
        paint_background: args.background,
        transparency: program.transparency(),
        threads: 0,
        ids: false,
        max_overdraw: crate::budget::Budgets::default().overdraw,
    };
    let stats = crate::raster::scan::scan_convert(&stream, &options, &mut outputs)?;
    let notes = outputs.commit()?;
    Ok(Summary {
        records: stream.records.len(),
        stats,
        seconds: start.elapsed().as_secs_f64(),
        notes,
    })
}

/// Reads and checks the tree file of `args` for `program`, within the
/// memory budget.
fn read_tree(program: Program, args: &Args) -> Result<RecordStream> {
    parse_tree(program, args, &read_tree_bytes(program, args)?)
}

/// The bytes of the tree file of `args`, refused past the memory the
/// bands of `program` leave (about [`TREE_MEMORY_PER_BYTE`] bytes each).
fn read_tree_bytes(program: Program, args: &Args) -> Result<Vec<u8>> {
    let (bands, _) = band_memory(program, args);
    let limit = args.budgets.frame_memory.saturating_sub(bands) / TREE_MEMORY_PER_BYTE;
    read_input(&args.input, limit, |len| {
        Budgets::exceeded(
            &format!(
                "a tree file of {len} bytes (about {TREE_MEMORY_PER_BYTE} bytes of memory \
                 each, with the bands of act-lines rows)"
            ),
            format!("{} MiB", args.budgets.frame_memory >> 20),
            "--max-frame-memory",
        )
    })
}

/// The tree in `bytes`, checked for `program`, in the blending mode its
/// method wants, with the background record `-B` needs.
fn parse_tree(program: Program, args: &Args, bytes: &[u8]) -> Result<RecordStream> {
    let mut stream = RecordStream::from_bytes(bytes, &args.input)?;
    check_tree(program, &stream, &args.input)?;
    // Accepted with the other blending mode only when one-level, where the
    // modes agree (see `check_tree`): scan it as the mode the method wants.
    stream.blended = program.wants_preblended();
    if args.background && stream.background.is_none() {
        return Err(Error::Invalid(format!(
            "{}: -B paints the background record, and this file has none",
            args.input.display()
        )));
    }
    Ok(stream)
}

/// `--part I/N -o FILE`: the part's rows of the colour image (in the
/// display mode, if one is given) into the part file alone.
fn run_part(
    program: Program,
    args: &Args,
    spec: crate::part::PartSpec,
    file: &Path,
) -> Result<Summary> {
    let start = Instant::now();
    check_budgets(program, args)?;
    check_names(
        std::slice::from_ref(&args.input),
        std::slice::from_ref(&file.to_path_buf()),
        &log_path(program.name()),
    )?;
    let stream = read_tree(program, args)?;
    let options = ScanOptions {
        width: args.hres,
        height: args.vres,
        method: program.method(),
        act_lines: args.act_lines,
        paint_background: args.background,
        transparency: program.transparency(),
        threads: 0,
        ids: false,
        max_overdraw: crate::budget::Budgets::default().overdraw,
    };
    let rows = crate::raster::scan::part_rows(&stream, &options, spec.index, spec.count);
    let flags = format!(
        "{}x{} act-lines {} -B {} display {:?}",
        args.hres, args.vres, args.act_lines, args.background, args.display
    );
    let info = crate::part::PartInfo {
        part: spec,
        image: (args.hres, args.vres),
        first: rows.start,
        rows: rows.len() as u32,
        output: with_suffix(&args.output, "png").display().to_string(),
        fingerprint: crate::part::fingerprint(program.name(), &flags),
    };
    let mode = args.display.unwrap_or(DisplayMode::Color);
    let mut sink = crate::part::PartSink::create(file, info, mode)?;
    crate::cancel::check()?;
    let stats = crate::raster::scan::scan_convert_rows(&stream, &options, rows, &mut sink)?;
    crate::cancel::check()?;
    commit_all(vec![sink.finish()?])?;
    Ok(Summary {
        records: stream.records.len(),
        stats,
        seconds: start.elapsed().as_secs_f64(),
        notes: Vec::new(),
    })
}

/// `t` as `YYYY-MM-DD HH:MM:SS UTC`.
pub fn utc_timestamp(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Appends `line` to `log` (created if missing).
pub fn append_log(log: &Path, line: &str) -> Result<()> {
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
        .map_err(|e| Error::io(log, e))?;
    writeln!(f, "{line}").map_err(|e| Error::io(log, e))
}

/// The statistics line of an rftb run.
pub fn log_line(args: &Args, s: &Summary) -> String {
    let mut line = format!(
        "{}  input {}  output {}  {}x{}  act-lines {}  records {}  polygons tiled {}  \
         fragments peak {} total {}  {:.3} s",
        utc_timestamp(SystemTime::now()),
        args.input.display(),
        args.output.display(),
        args.hres,
        args.vres,
        args.act_lines,
        s.records,
        s.stats.polygons_tiled,
        s.stats.peak_fragments,
        s.stats.total_fragments,
        s.seconds
    );
    for n in &s.notes {
        line.push_str("  note: ");
        line.push_str(n);
    }
    line
}

/// The statistics log of program `name`, in the working directory.
pub fn log_path(name: &str) -> PathBuf {
    PathBuf::from(format!("{name}.log"))
}

/// Installs the signal handlers for program `name` ([`crate::signals`]:
/// every signal ends a batch program, after its run has stopped and
/// removed its temporaries, or after 600 ms), warning if it cannot.
fn install_signals(name: &str) {
    let policy = crate::signals::Policy {
        grace: std::time::Duration::from_millis(600),
        sigint_ends: true,
        sigint_message: "",
        cleanup: || {},
    };
    if let Err(e) = crate::signals::install(policy) {
        eprintln!("{name}: warning: cannot handle signals: {e}");
    }
    crate::signals::rendering(true);
}

/// After a run: a signal received ends the program as it asks (the run
/// stopped, or finished, and either way its temporaries are gone).
fn honour_signal() {
    if let Some(code) = crate::signals::ending() {
        crate::output::remove_temporaries();
        std::process::exit(i32::from(code));
    }
}

/// The whole of rftbN's `main`.
pub fn main(program: Program) -> ExitCode {
    let name = program.name();
    install_signals(name);
    let args = match parse_args(std::env::args_os().skip(1)) {
        Ok(Command::Run(a)) => a,
        Ok(Command::Help) => {
            println!("{}", program.usage());
            return ExitCode::SUCCESS;
        }
        Err(UsageError(msg)) => {
            eprintln!("{name}: {msg}\n{}", program.usage());
            return ExitCode::from(2);
        }
    };
    if args.screen {
        eprintln!(
            "{name}: -Y: there is no graphics display here; the image is not shown while \
             rendering (a display flag -a/-r/-g/-b/-y/-c writes OUTPUT.png instead)"
        );
    }
    let result = run(program, &args);
    honour_signal();
    match result {
        Ok(summary) => {
            for n in &summary.notes {
                eprintln!("{name}: {n}");
            }
            let line = log_line(&args, &summary);
            if args.debug > 0 {
                eprintln!("{name}: {line}");
            }
            finish_log(name, &line)
        }
        Err(e) => {
            eprintln!("{name}: {e}");
            ExitCode::from(1)
        }
    }
}

/// Appends to `NAME.log`; the outputs are written already, so a log that
/// cannot be written is a warning.
fn finish_log(name: &str, line: &str) -> ExitCode {
    if let Err(e) = append_log(&log_path(name), line) {
        eprintln!("{name}: warning: {e}");
    }
    ExitCode::SUCCESS
}

// ---------------------------------------------------------------------------
// getrgb

/// The parsed command line of getrgb.
#[derive(Debug, Clone, PartialEq)]
pub struct GetrgbArgs {
    /// The pixel-struct file, also the seed of `.r .g .b`.
    pub name: PathBuf,
    /// `hres vres` when given: checked against the file (and its side
    /// file); needed for a PNG when there is no side file.
    pub resolution: Option<(u32, u32)>,
    /// Also write this PNG.
    pub png: Option<PathBuf>,
    /// `--max-pixels`, `--max-frame-memory`; the rest are unused.
    pub budgets: Budgets,
}

/// getrgb's usage line.
pub const GETRGB_USAGE: &str =
    "usage: getrgb NAME [hres vres] [-p | --png FILE] [--max-pixels N] [--max-frame-memory MiB]";

/// Parses getrgb's arguments (without the program name).
pub fn parse_getrgb_args(
    argv: impl IntoIterator<Item = OsString>,
) -> std::result::Result<Command<GetrgbArgs>, UsageError> {
    let mut positional = Vec::new();
    let mut png_flag = false;
    let mut png_file = None;
    let mut budgets = Budgets::default();
    let mut it = argv.into_iter();
    while let Some(arg) = it.next() {
        if budget_flag(&arg.to_string_lossy(), &mut it, &mut budgets)? {
            continue;
        }
        match arg.to_string_lossy().as_ref() {
            "-h" | "--help" => return Ok(Command::Help),
            "-p" => png_flag = true,
            "--png" => {
                let f = it.next().ok_or(UsageError("--png needs a FILE".into()))?;
                png_file = Some(PathBuf::from(f));
            }
            s if s.starts_with('-') && s.len() > 1 => {
                return usage_err(format!("unknown flag `{}`", crate::error::printable(s, 40)));
            }
            _ => positional.push(arg),
        }
    }
    let (name, resolution) = match positional.as_slice() {
        [name] => (PathBuf::from(name), None),
        [name, h, v] => (
            PathBuf::from(name),
            Some((number(h, "hres", 1)?, number(v, "vres", 1)?)),
        ),
        [] => return usage_err("no pixel-struct file given"),
        [_, _] => return usage_err("give both hres and vres, or neither"),
        _ => return usage_err("too many arguments"),
    };
    let png = png_file.or_else(|| png_flag.then(|| with_suffix(&name, "png")));
    Ok(Command::Run(GetrgbArgs {
        name,
        resolution,
        png,
        budgets,
    }))
}

/// What a getrgb run did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GetrgbSummary {
    /// Pixel-structs read.
    pub pixels: usize,
    /// Those with fragments (known only with the side file).
    pub complex: usize,
    /// `(hres, vres)`, when known (arguments or side file).
    pub resolution: Option<(u32, u32)>,
}

/// The files getrgb reads for `args`: the pixel-struct file and its side
/// file (read when there is one).
pub fn getrgb_inputs(args: &GetrgbArgs) -> Vec<PathBuf> {
    vec![
        args.name.clone(),
        with_suffix(&args.name, crate::output::FRAGMENT_SUFFIX),
    ]
}

/// The files getrgb writes for `args`.
pub fn getrgb_outputs(args: &GetrgbArgs) -> Vec<PathBuf> {
    let mut out = SeparationSink::paths(&args.name, Planes::default());
    out.extend(args.png.clone());
    out
}

/// Extracts `NAME.r .g .b` (and the PNG) from the pixel-struct file.
///
/// The manual's getrgb takes only the file name (`getrgb [fname]`) and
/// the file is "a linear list of 64-bit data structures": the separations
/// are that list's colours in order, one byte per pixel-struct, whatever
/// the resolution. The resolution, needed for the PNG only, is the
/// optional `hres vres` or else the one rftb4 wrote in the side file
/// `NAME.frag`; when both are there they must agree.
///
/// Before anything is read, the resolution given is checked against the
/// pixel budget and the names against each other; the two files are read
/// (regular files only) when they fit the frame memory budget together,
/// and the pixel-structs are visited in place, a row at a time.
pub fn run_getrgb(args: &GetrgbArgs) -> Result<GetrgbSummary> {
    let budgets = &args.budgets;
    if let Some((w, h)) = args.resolution {
        check_pixels(w, h, budgets)?;
    }
    let inputs = getrgb_inputs(args);
    check_names(&inputs, &getrgb_outputs(args), &log_path("getrgb"))?;
    let (bytes, side) = read_getrgb_inputs(args, &inputs[1])?;
    let n = bytes.len() / crate::output::PIXEL_STRUCT_BYTES;
    let side = side.as_ref().map(|b| (b.as_slice(), inputs[1].as_path()));
    let file_resolution = match side {
        Some((b, p)) => Some(crate::output::side_header(b, p)?),
        None => None,
    };
    let resolution = getrgb_resolution(args, n, bytes.len(), file_resolution)?;
    let (w, h) = getrgb_size(args, n, resolution)?;
    let complex = write_separations(args, &bytes, side, w, h)?;
    Ok(GetrgbSummary {
        pixels: n,
        complex,
        resolution,
    })
}

/// The pixel-struct file and its `.frag` side file (`side_path`, if it
/// exists), both within the frame memory budget, and at most the pixel
/// budget of structs.
fn read_getrgb_inputs(args: &GetrgbArgs, side_path: &Path) -> Result<(Vec<u8>, Option<Vec<u8>>)> {
    let budgets = &args.budgets;
    let memory = |len: u64| {
        Budgets::exceeded(
            &format!("{len} bytes of pixel-structs and fragment lists in memory"),
            format!("{} MiB", budgets.frame_memory >> 20),
            "--max-frame-memory",
        )
    };
    let bytes = read_input(&args.name, budgets.frame_memory, memory)?;
    let n = bytes.len() / crate::output::PIXEL_STRUCT_BYTES;
    if n as u64 > budgets.pixels {
        return Err(Error::Budget {
            flag: "--max-pixels",
            message: format!(
                "{}: {}",
                shown(&args.name),
                Budgets::exceeded(
                    &format!("{n} pixel-structs"),
                    format!("{} pixels", budgets.pixels),
                    "--max-pixels"
                )
            ),
        });
    }
    let side = match std::fs::symlink_metadata(side_path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        _ => {
            let left = budgets.frame_memory - bytes.len() as u64;
            let len = bytes.len() as u64;
            Some(read_input(side_path, left, |side| memory(len + side))?)
        }
    };
    Ok((bytes, side))
}

/// The resolution given or read from the side file (they must agree, and
/// hold the `n` pixel-structs of `len` bytes).
fn getrgb_resolution(
    args: &GetrgbArgs,
    n: usize,
    len: usize,
    file_resolution: Option<(u32, u32)>,
) -> Result<Option<(u32, u32)>> {
    match (args.resolution, file_resolution) {
        (Some((w, h)), _) if u64::from(w) * u64::from(h) != n as u64 => {
            Err(Error::Invalid(format!(
                "{}: {} bytes hold {n} pixel-structs, but {w} x {h} takes {}: is the \
                 resolution right?",
                args.name.display(),
                len,
                u64::from(w) * u64::from(h)
            )))
        }
        (Some(given), Some(side)) if given != side => Err(Error::Invalid(format!(
            "{}: the resolution given, {} x {}, is not the {} x {} of {}.{}: is the \
             resolution right?",
            args.name.display(),
            given.0,
            given.1,
            side.0,
            side.1,
            args.name.display(),
            crate::output::FRAGMENT_SUFFIX
        ))),
        (given, side) => Ok(given.or(side)),
    }
}

/// The image's width and height: the resolution, or without one (and
/// without `--png`) the linear list as one row.
fn getrgb_size(args: &GetrgbArgs, n: usize, resolution: Option<(u32, u32)>) -> Result<(u32, u32)> {
    let (w, h) = match resolution {
        Some(r) => r,
        None if args.png.is_some() => {
            return Err(Error::Invalid(format!(
                "{}: a PNG needs the image's width, and there is no {}.{} (rftb4 writes the \
                 resolution there): give it, `getrgb NAME HRES VRES --png FILE`",
                args.name.display(),
                args.name.display(),
                crate::output::FRAGMENT_SUFFIX
            )));
        }
        // The separations do not depend on the width.
        None => (
            u32::try_from(n).map_err(|_| {
                Error::Invalid(format!(
                    "{}: {n} pixel-structs are more than getrgb can take",
                    args.name.display()
                ))
            })?,
            1,
        ),
    };
    // w x h is n here, within the pixel budget.
    if u64::from(w) * u64::from(h) != n as u64 {
        return Err(Error::Invalid(format!(
            "{}: {n} pixel-structs are not {w} x {h}",
            shown(&args.name)
        )));
    }
    Ok((w, h))
}

/// Visits the pixel-structs row by row into the separations (and the
/// PNG), then commits them together; returns the complex pixels' count.
fn write_separations(
    args: &GetrgbArgs,
    bytes: &[u8],
    side: Option<(&[u8], &Path)>,
    w: u32,
    h: u32,
) -> Result<usize> {
    let mut seps = SeparationSink::create(&args.name, w, h, Planes::default())?;
    let mut png = match &args.png {
        Some(p) => Some(PngSink::create(p, w, h, DisplayMode::Color)?),
        None => None,
    };
    let width = w as usize;
    let mut rgb = Vec::new();
    rgb.try_reserve_exact(width).map_err(|_| {
        Error::Invalid(format!(
            "{}: no memory for a row of {w} pixels",
            shown(&args.name)
        ))
    })?;
    let mut complex = 0usize;
    let mut y = 0u32;
    crate::output::visit_pixel_structs(bytes, &args.name, side, |p| {
        if !p.fragments.is_empty() {
            complex += 1;
        }
        rgb.push(p.rgb.map(|v| f32::from(v) / 255.0));
        if rgb.len() < width {
            return Ok(());
        }
        crate::cancel::check()?;
        let row = Row {
            y,
            rgb: &rgb,
            coverage: None,
            mask: None,
            pixels: None,
            ids: None,
        };
        seps.row(&row)?;
        if let Some(p) = png.as_mut() {
            p.row(&row)?;
        }
        rgb.clear();
        y += 1;
        Ok(())
    })?;
    let mut staged = seps.finish()?;
    if let Some(p) = png {
        staged.push(p.finish()?.0);
    }
    crate::cancel::check()?;
    commit_all(staged)?;
    Ok(complex)
}

/// The whole of getrgb's `main`.
pub fn getrgb_main() -> ExitCode {
    install_signals("getrgb");
    let args = match parse_getrgb_args(std::env::args_os().skip(1)) {
        Ok(Command::Run(a)) => a,
        Ok(Command::Help) => {
            println!("{GETRGB_USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(UsageError(msg)) => {
            eprintln!("getrgb: {msg}\n{GETRGB_USAGE}");
            return ExitCode::from(2);
        }
    };
    let start = Instant::now();
    let result = run_getrgb(&args);
    honour_signal();
    match result {
        Ok(s) => {
            let line = format!(
                "{}  input {}  output {}.[rgb]{}  {}  pixels {}  with fragments {}  {:.3} s",
                utc_timestamp(SystemTime::now()),
                args.name.display(),
                args.name.display(),
                args.png
                    .as_ref()
                    .map_or(String::new(), |p| format!(" {}", p.display())),
                s.resolution
                    .map_or("resolution unknown".to_string(), |(w, h)| format!(
                        "{w}x{h}"
                    )),
                s.pixels,
                s.complex,
                start.elapsed().as_secs_f64()
            );
            finish_log("getrgb", &line)
        }
        Err(e) => {
            eprintln!("getrgb: {e}");
            ExitCode::from(1)
        }
    }
}

#[cfg(test)]
mod tests;

//! The anti-aliasing polygon tilers rftb1-4 and getrgb as programs (Garcia
//! 1986, 004 appendix: the rftb and getrgb manual pages; chapter 5 for the
//! methods). Each binary in `src/bin` is a few lines over this module.
//!
//! ```text
//! rftbN <input> [output] [hres] [vres] [act-lines] [-flags]
//! getrgb NAME [hres vres] [-p | --png FILE]
//! ```
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
             [-a BITS | -r | -g | -b | -y | -c] [-Y]",
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
    };
    let mut positional: Vec<OsString> = Vec::new();
    let mut it = argv.into_iter();
    while let Some(arg) = it.next() {
        let s = arg.to_string_lossy();
        if s == "-h" || s == "--help" {
            return Ok(Command::Help);
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
        match &mut self.main {
            MainSink::Separations(s) => s.row(row)?,
            MainSink::PixelStructs(s) => s.row(row)?,
        }
        match &mut self.png {
            Some(p) => p.row(row),
            None => Ok(()),
        }
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
    let start = Instant::now();
    let bytes = std::fs::read(&args.input).map_err(|e| Error::io(&args.input, e))?;
    let mut stream = RecordStream::from_bytes(&bytes, &args.input)?;
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
    let mut outputs = Outputs::create(program, args)?;
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

/// The whole of rftbN's `main`.
pub fn main(program: Program) -> ExitCode {
    let name = program.name();
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
    match run(program, &args) {
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
    if let Err(e) = append_log(Path::new(&format!("{name}.log")), line) {
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
}

/// getrgb's usage line.
pub const GETRGB_USAGE: &str = "usage: getrgb NAME [hres vres] [-p | --png FILE]";

/// Parses getrgb's arguments (without the program name).
pub fn parse_getrgb_args(
    argv: impl IntoIterator<Item = OsString>,
) -> std::result::Result<Command<GetrgbArgs>, UsageError> {
    let mut positional = Vec::new();
    let mut png_flag = false;
    let mut png_file = None;
    let mut it = argv.into_iter();
    while let Some(arg) = it.next() {
        match arg.to_string_lossy().as_ref() {
            "-h" | "--help" => return Ok(Command::Help),
            "-p" => png_flag = true,
            "--png" => {
                let f = it.next().ok_or(UsageError("--png needs a FILE".into()))?;
                png_file = Some(PathBuf::from(f));
            }
            s if s.starts_with('-') && s.len() > 1 => {
                return usage_err(format!("unknown flag `{s}`"));
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

/// Reads `path`'s fragment side file `path.frag`, if there is one.
fn read_side_file(path: &Path) -> Result<Option<(PathBuf, Vec<u8>)>> {
    let side = with_suffix(path, crate::output::FRAGMENT_SUFFIX);
    match std::fs::read(&side) {
        Ok(bytes) => Ok(Some((side, bytes))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(&side, e)),
    }
}

/// Extracts `NAME.r .g .b` (and the PNG) from the pixel-struct file.
///
/// The manual's getrgb takes only the file name (`getrgb [fname]`) and
/// the file is "a linear list of 64-bit data structures": the separations
/// are that list's colours in order, one byte per pixel-struct, whatever
/// the resolution. The resolution, needed for the PNG only, is the
/// optional `hres vres` or else the one rftb4 wrote in the side file
/// `NAME.frag`; when both are there they must agree.
pub fn run_getrgb(args: &GetrgbArgs) -> Result<GetrgbSummary> {
    let bytes = std::fs::read(&args.name).map_err(|e| Error::io(&args.name, e))?;
    let side = read_side_file(&args.name)?;
    let read = crate::output::read_pixel_structs(
        &bytes,
        &args.name,
        side.as_ref().map(|(p, b)| (b.as_slice(), p.as_path())),
    )?;
    let n = read.pixels.len();
    let resolution = match (args.resolution, read.resolution) {
        (Some((w, h)), _) if u64::from(w) * u64::from(h) != n as u64 => {
            return Err(Error::Invalid(format!(
                "{}: {} bytes hold {n} pixel-structs, but {w} x {h} takes {}: is the \
                 resolution right?",
                args.name.display(),
                bytes.len(),
                u64::from(w) * u64::from(h)
            )));
        }
        (Some(given), Some(side)) if given != side => {
            return Err(Error::Invalid(format!(
                "{}: the resolution given, {} x {}, is not the {} x {} of {}.{}: is the \
                 resolution right?",
                args.name.display(),
                given.0,
                given.1,
                side.0,
                side.1,
                args.name.display(),
                crate::output::FRAGMENT_SUFFIX
            )));
        }
        (given, side) => given.or(side),
    };
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
        // The linear list as one row: the separations do not depend on it.
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
    let mut seps = SeparationSink::create(&args.name, w, h, Planes::default())?;
    let mut png = match &args.png {
        Some(p) => Some(PngSink::create(p, w, h, DisplayMode::Color)?),
        None => None,
    };
    let mut rgb = vec![[0.0f32; 3]; w as usize];
    for (y, row) in read.pixels.chunks_exact(w as usize).enumerate() {
        for (c, p) in rgb.iter_mut().zip(row) {
            *c = p.rgb.map(|v| f32::from(v) / 255.0);
        }
        let row = Row {
            y: y as u32,
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
    }
    let mut staged = seps.finish()?;
    if let Some(p) = png {
        staged.push(p.finish()?.0);
    }
    commit_all(staged)?;
    let complex = read
        .pixels
        .iter()
        .filter(|p| !p.fragments.is_empty())
        .count();
    Ok(GetrgbSummary {
        pixels: n,
        complex,
        resolution,
    })
}

/// The whole of getrgb's `main`.
pub fn getrgb_main() -> ExitCode {
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
    match run_getrgb(&args) {
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
mod tests {
    use super::*;
    use crate::tree::{Record, Shades};

    fn argv(s: &str) -> Vec<OsString> {
        s.split_whitespace().map(OsString::from).collect()
    }

    fn args(s: &str) -> Args {
        match parse_args(argv(s)).unwrap() {
            Command::Run(a) => a,
            Command::Help => panic!("help"),
        }
    }

    #[test]
    fn the_manual_example_parses() {
        let a = args("test test2 512 512 -B");
        assert_eq!(a.input, PathBuf::from("test.out"));
        assert_eq!(a.output, PathBuf::from("test2"));
        assert_eq!((a.hres, a.vres, a.act_lines), (512, 512, 4));
        assert!(a.background && a.display.is_none());
        let a = args("scene.out -3 -a 4");
        assert_eq!(a.input, PathBuf::from("scene.out"));
        assert_eq!(a.output, PathBuf::from("scene"));
        assert_eq!((a.hres, a.vres, a.debug), (256, 256, 3));
        assert_eq!(a.display, Some(DisplayMode::Adaptive(4)));
        assert_eq!(args("x -Ba5").display, Some(DisplayMode::Adaptive(5)));
        assert_eq!(args("x o 8 8 1 -y").act_lines, 1);
    }

    #[test]
    fn bad_command_lines_are_usage_errors() {
        for bad in [
            "",
            "x o 0",
            "x o 8 nine",
            "x o 8 8 0",
            "x o 8 8 4 extra",
            "x -q",
            "x -a",
            "x -a 9",
            "x -r -g",
        ] {
            assert!(parse_args(argv(bad)).is_err(), "`{bad}` parsed");
        }
        assert!(parse_getrgb_args(argv("n 5")).is_err());
        assert!(parse_getrgb_args(argv("n --png")).is_err());
    }

    #[test]
    fn timestamps_are_civil_utc() {
        let t = SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(951_782_400 + 3_661);
        assert_eq!(utc_timestamp(t), "2000-02-29 01:01:01 UTC");
        assert_eq!(
            utc_timestamp(SystemTime::UNIX_EPOCH),
            "1970-01-01 00:00:00 UTC"
        );
    }

    #[test]
    fn trees_for_other_methods_are_refused() {
        let mut s = RecordStream {
            records: Vec::new(),
            background: None,
            front_to_back: true,
            blended: true,
        };
        let p = Path::new("t.out");
        let square = |level| Record {
            level,
            points: vec![[0.1, 0.1], [0.1, 0.9], [0.9, 0.9], [0.9, 0.1]],
            shades: Shades::Faceted([1, 2, 3]),
        };
        // One level: both blending modes suit every tiler.
        s.records = vec![square(1), square(1)];
        for program in [Program::Rftb1, Program::Rftb2, Program::Rftb4] {
            for blended in [false, true] {
                s.blended = blended;
                assert!(check_tree(program, &s, p).is_ok(), "{program:?} {blended}");
            }
        }
        // A child (level 2): the mode matters.
        s.records = vec![square(2), square(1)];
        s.blended = true;
        assert!(check_tree(Program::Rftb2, &s, p).is_ok());
        let e = check_tree(Program::Rftb4, &s, p).unwrap_err().to_string();
        assert!(
            e.contains("setmode b off") && e.contains("1 of its records"),
            "{e}"
        );
        s.front_to_back = false;
        s.blended = false;
        let e = check_tree(Program::Rftb1, &s, p).unwrap_err().to_string();
        assert!(e.contains("sort ftb") && e.contains("setmode b on"), "{e}");
        s.records = vec![square(1)];
        let e = check_tree(Program::Rftb1, &s, p).unwrap_err().to_string();
        assert!(e.contains("sort ftb") && !e.contains("setmode"), "{e}");
    }
}

//! The command line of rftb1-4 (Garcia 1986, appendix B: the rftb manual
//! page): input, output seed, resolution, act-lines and flags, with
//! plytrace's budget flags.

use super::*;

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

pub(super) fn usage_err<T>(msg: impl Into<String>) -> std::result::Result<T, UsageError> {
    Err(UsageError(msg.into()))
}

/// The budget flags both programs take, as in plytrace.
pub(super) const BUDGET_FLAGS: &str = "[--max-pixels N] [--max-frame-memory MiB]";

/// Parses a budget flag (`--max-pixels N`, `--max-frame-memory MiB`, or
/// with `=`) into `budgets`; false when `arg` is not one.
pub(super) fn budget_flag(
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

pub(super) fn number(arg: &OsString, what: &str, min: u32) -> std::result::Result<u32, UsageError> {
    match arg.to_str().and_then(|s| s.parse::<u32>().ok()) {
        Some(n) if n >= min => Ok(n),
        _ => usage_err(format!(
            "{what}: expected a whole number of at least {min}, got `{}`",
            arg.to_string_lossy()
        )),
    }
}

/// Parses `-a BITS`' number.
pub(super) fn bits(s: &str) -> std::result::Result<u8, UsageError> {
    match s.parse::<u8>() {
        Ok(b @ 1..=8) => Ok(b),
        _ => usage_err(format!("-a: bits per colour run from 1 to 8, got `{s}`")),
    }
}

pub(super) fn set_display(
    args: &mut Args,
    mode: DisplayMode,
) -> std::result::Result<(), UsageError> {
    if args.display.is_some_and(|m| m != mode) {
        return usage_err("give at most one display mode (-a, -r, -g, -b, -y, -c)");
    }
    args.display = Some(mode);
    Ok(())
}

/// Parses one flag group such as `-B3`; `rest` gives `-a`'s argument when
/// the group does not hold it.
pub(super) fn flag_group(
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
    let mut args = default_args();
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
            part_flag(&s, &mut it, &mut args)?;
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
    set_positional(&positional, &mut args)?;
    check_part(&args)?;
    Ok(Command::Run(args))
}

/// The arguments before the command line: the manual's defaults.
fn default_args() -> Args {
    Args {
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
    }
}

/// `--part I/N` (or `--part=I/N`) and `-o FILE`, its part file, with the
/// value from `s` or the next argument.
fn part_flag(
    s: &str,
    it: &mut impl Iterator<Item = OsString>,
    args: &mut Args,
) -> std::result::Result<(), UsageError> {
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
    Ok(())
}

/// The positional arguments: input, output seed, hres, vres, act-lines.
fn set_positional(positional: &[OsString], args: &mut Args) -> std::result::Result<(), UsageError> {
    let (input, output) = match positional {
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
    Ok(())
}

/// `--part I/N` and `-o` go together, and the part file is a PNG.
fn check_part(args: &Args) -> std::result::Result<(), UsageError> {
    match (&args.part, &args.part_file) {
        (Some(p), None) => usage_err(format!(
            "--part {p} writes a part file: name it with -o, such as -o parts/{}.png",
            p.index
        )),
        (None, Some(_)) => usage_err("-o names the part file of --part I/N"),
        (Some(_), Some(f)) if !f.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) => {
            usage_err(format!(
                "-o {}: a part file is a PNG; name it .png",
                f.display()
            ))
        }
        _ => Ok(()),
    }
}

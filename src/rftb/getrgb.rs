//! getrgb: the colours of a pixel-struct file (Garcia 1986, section 5.9
//! and figure 5.15; appendix B: the getrgb manual page), written as
//! `NAME.r .g .b` and optionally as a PNG.

use super::*;

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
pub(super) fn read_getrgb_inputs(
    args: &GetrgbArgs,
    side_path: &Path,
) -> Result<(Vec<u8>, Option<Vec<u8>>)> {
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
pub(super) fn getrgb_resolution(
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
pub(super) fn getrgb_size(
    args: &GetrgbArgs,
    n: usize,
    resolution: Option<(u32, u32)>,
) -> Result<(u32, u32)> {
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
pub(super) fn write_separations(
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

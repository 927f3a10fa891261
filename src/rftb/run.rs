//! One run of rftbN: read the virtual image tree file, scan convert it
//! by the program's method (Garcia 1986, sections 5.6-5.9) and write the
//! output files (appendix B: the rftb manual page's FILES).

use super::*;

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
pub(super) fn largest_output(program: Program, args: &Args) -> (PathBuf, u64) {
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
pub(super) enum MainSink {
    Separations(SeparationSink),
    PixelStructs(PixelStructSink),
}

/// Every output of one run, fed the same rows.
pub(super) struct Outputs {
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
pub(super) fn read_tree(program: Program, args: &Args) -> Result<RecordStream> {
    parse_tree(program, args, &read_tree_bytes(program, args)?)
}

/// The bytes of the tree file of `args`, refused past the memory the
/// bands of `program` leave (about [`TREE_MEMORY_PER_BYTE`] bytes each).
pub(super) fn read_tree_bytes(program: Program, args: &Args) -> Result<Vec<u8>> {
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
pub(super) fn parse_tree(program: Program, args: &Args, bytes: &[u8]) -> Result<RecordStream> {
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
pub(super) fn run_part(
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

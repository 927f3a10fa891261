//! Parts of one image: a render split into `N` horizontal bands, each
//! rendered by its own process (on its own machine), and merged.
//!
//! A part is row `first` to `first + rows - 1` of the whole image, each
//! row exactly as a one-process render makes it (the scan converter
//! converts a part's bands as it would for the whole image). The rows of
//! part `I` of `N` are chosen from the records so that the parts have
//! about equal work ([`crate::raster::scan::part_rows`]): every row in
//! exactly one part, boundaries on band boundaries.
//!
//! # The part file
//!
//! A PNG of the part's rows in the output's display mode (the bytes the
//! whole image would have there, dither included), written through a
//! temporary file and renamed when complete, with iTXt chunks:
//!
//! | keyword | value |
//! |---|---|
//! | `plytrace-part` | `I/N`, the part index (from 0) and count |
//! | `plytrace-image` | `WxH`, the size of the whole image |
//! | `plytrace-rows` | `FIRST+COUNT`, the part's first row (from the top) and row count |
//! | `plytrace-output` | the name the whole image is written to |
//! | `plytrace-fingerprint` | 16 hex digits: what decides the pixels |
//!
//! A part with no rows (more parts than rows) is a 1 x 1 PNG that says
//! so. The fingerprint hashes (64 bits, MurmurHash3's steps eight bytes
//! at a time) the program and its version, the hash of the contents of
//! every file read (scene, called files, object files, tree file) and
//! the flags that decide the pixels; parts of one
//! render have the same, and a merge refuses parts that do not.
//!
//! # Merging
//!
//! [`merge`] reads the parts' headers, checks that they are parts of one
//! render that cover every row once, then streams the rows, a part at a
//! time and a row at a time, into the image: PNG (the bytes a one-process
//! render writes), binary PPM, or the colour separations `SEED.r .g .b`.
//! Memory holds a row of each kind, whatever the image size.
//!
//! Every part is hostile input. A part is read only if it is a regular
//! file (a FIFO is refused, never waited on), and it is known by its
//! identity (device and inode, as the inputs of a render are), so no
//! output of the merge, in any format and under any name, replaces one.
//! Without `-o`, the image's name comes from the parts and is taken only
//! inside the working directory. The image's pixels are checked against
//! the budget (`--max-pixels`) before a row is read.

use std::io::{BufReader, Write};
use std::path::{Path, PathBuf};

use crate::budget::Budgets;
use crate::error::{Error, Result};
use crate::input_guard::Inputs;
use crate::output::{self, AtomicFile, DisplayMode, PngSink};
use crate::raster::scan::{Row, RowSink};
use crate::scene::object_file::open_regular;

/// The keyword of the part index and count.
pub const KEY_PART: &str = "plytrace-part";
/// The keyword of the whole image's size.
pub const KEY_IMAGE: &str = "plytrace-image";
/// The keyword of the part's rows.
pub const KEY_ROWS: &str = "plytrace-rows";
/// The keyword of the whole image's name.
pub const KEY_OUTPUT: &str = "plytrace-output";
/// The keyword of the fingerprint.
pub const KEY_FINGERPRINT: &str = "plytrace-fingerprint";

/// Part `index` of `count` (`--part I/N`, `I` from 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PartSpec {
    /// From 0.
    pub index: u32,
    /// At least 1.
    pub count: u32,
}

impl std::fmt::Display for PartSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for PartSpec {
    type Err = String;

    /// `I/N`: `N` from 1 to 65536, `I` from 0 to `N - 1`.
    fn from_str(s: &str) -> std::result::Result<PartSpec, String> {
        let form = || format!("expected I/N (part I of N, I from 0), such as 3/8, found `{s}`");
        let (i, n) = s.split_once('/').ok_or_else(form)?;
        let (i, n) = (
            i.trim().parse::<u32>().map_err(|_| form())?,
            n.trim().parse::<u32>().map_err(|_| form())?,
        );
        if !(1..=65536).contains(&n) {
            return Err(format!("the part count must be 1 to 65536, found {n}"));
        }
        if i >= n {
            return Err(format!(
                "part {i} of {n}: the index runs from 0 to {} (0-based)",
                n - 1
            ));
        }
        Ok(PartSpec { index: i, count: n })
    }
}

/// The fingerprint of a render by `program` with the pixel-deciding
/// `flags` (any text that is the same exactly when they are): the
/// program, its version, the contents of every input this process has
/// read so far and the flags, hashed.
pub fn fingerprint(program: &str, flags: &str) -> String {
    fingerprint_of(program, &crate::input_guard::contents(), flags)
}

/// [`fingerprint`] with the hashes of the inputs' `contents` given.
fn fingerprint_of(program: &str, contents: &[u64], flags: &str) -> String {
    let mut bytes = format!("{program} {}\n", env!("CARGO_PKG_VERSION")).into_bytes();
    for c in contents {
        bytes.extend(c.to_le_bytes());
    }
    bytes.extend(flags.as_bytes());
    format!("{:016x}", crate::input_guard::content_hash(&bytes))
}

/// Notes the contents of an input that is not a file (a scene read from
/// standard input), for [`fingerprint`].
pub fn note_input(bytes: &[u8]) {
    crate::input_guard::note_contents(bytes);
}

/// What a part file says of itself.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PartInfo {
    /// Index and count.
    pub part: PartSpec,
    /// The whole image's width and height.
    pub image: (u32, u32),
    /// The part's first row and row count.
    pub first: u32,
    /// Rows in the part.
    pub rows: u32,
    /// The whole image's name.
    pub output: String,
    /// See [`fingerprint`].
    pub fingerprint: String,
}

/// Writes a part file: the rows of [`PartInfo::first`] .. `+ rows` of an
/// image, given as colours ([`RowSink`]) and converted in `mode`.
pub struct PartSink {
    info: PartInfo,
    mode: DisplayMode,
    // Dropped before `file`: an unfinished stream writes into the temporary.
    stream: Option<png::StreamWriter<'static, std::fs::File>>,
    file: AtomicFile,
    next: u32,
    buf: Vec<u8>,
}

fn png_err(path: &Path, e: png::EncodingError) -> Error {
    match e {
        png::EncodingError::IoError(io) => Error::io(path, io),
        other => Error::io(path, std::io::Error::other(other)),
    }
}

impl PartSink {
    /// Starts the part file `path` (a temporary beside it until
    /// [`PartSink::finish`]).
    pub fn create(path: &Path, info: PartInfo, mode: DisplayMode) -> Result<PartSink> {
        if matches!(mode, DisplayMode::Adaptive(_)) {
            return Err(Error::Invalid(format!(
                "{}: a part cannot be written with an adaptive look-up table (-a): \
                 its palette is chosen from the whole image",
                path.display()
            )));
        }
        let file = AtomicFile::create(path)?;
        let grey = output::is_grey(mode);
        let (w, h) = if info.rows == 0 {
            (1, 1)
        } else {
            (info.image.0, info.rows)
        };
        let out = file.file().try_clone().map_err(|e| Error::io(path, e))?;
        let mut enc = png::Encoder::new(out, w, h);
        enc.set_color(if grey {
            png::ColorType::Grayscale
        } else {
            png::ColorType::Rgb
        });
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let texts = [
            (KEY_PART, info.part.to_string()),
            (KEY_IMAGE, format!("{}x{}", info.image.0, info.image.1)),
            (KEY_ROWS, format!("{}+{}", info.first, info.rows)),
            (KEY_OUTPUT, info.output.clone()),
            (KEY_FINGERPRINT, info.fingerprint.clone()),
        ];
        for (k, v) in texts {
            enc.add_itxt_chunk(k.to_string(), v)
                .map_err(|e| png_err(path, e))?;
        }
        let writer = enc.write_header().map_err(|e| png_err(path, e))?;
        let mut stream = writer.into_stream_writer().map_err(|e| png_err(path, e))?;
        if info.rows == 0 {
            let zero = vec![0u8; if grey { 1 } else { 3 }];
            stream.write_all(&zero).map_err(|e| Error::io(path, e))?;
        }
        Ok(PartSink {
            next: info.first,
            info,
            mode,
            stream: Some(stream),
            file,
            buf: Vec::new(),
        })
    }

    /// Completes the part under its temporary name; committing the
    /// result renames it into place.
    pub fn finish(mut self) -> Result<output::Staged> {
        let end = self.info.first + self.info.rows;
        if self.next != end {
            return Err(Error::Invalid(format!(
                "{}: {} rows of the part's {} written; the part is incomplete",
                self.file.path().display(),
                self.next - self.info.first,
                self.info.rows
            )));
        }
        if let Some(stream) = self.stream.take() {
            stream.finish().map_err(|e| png_err(self.file.path(), e))?;
        }
        self.file.finish()
    }
}

impl RowSink for PartSink {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        let path = self.file.path();
        if row.y != self.next
            || row.y >= self.info.first + self.info.rows
            || row.rgb.len() != self.info.image.0 as usize
        {
            return Err(Error::Invalid(format!(
                "{}: got row {} of {} pixels, expected row {} of {}",
                path.display(),
                row.y,
                row.rgb.len(),
                self.next,
                self.info.image.0
            )));
        }
        self.next += 1;
        output::display_row(self.mode, row.rgb, row.y, &mut self.buf);
        let stream = self.stream.as_mut().expect("open until finished");
        stream.write_all(&self.buf).map_err(|e| Error::io(path, e))
    }

    fn wants_pixel_structs(&self) -> bool {
        false
    }
}

/// An error about part file `path`.
fn bad(path: &Path, what: impl std::fmt::Display) -> Error {
    Error::Invalid(format!(
        "{}: {what}",
        crate::error::printable(&path.display().to_string(), 200)
    ))
}

type Reader = png::Reader<BufReader<std::fs::File>>;

/// Opens part file `path` and reads what it says of itself; the
/// metadata is the open file's (its identity, so that no output of the
/// merge replaces it). The part must be a regular file (a FIFO, device or
/// directory is refused without waiting on it). A part of an image of
/// more than `budgets.pixels` pixels is refused before any row is read.
fn open(path: &Path, budgets: &Budgets) -> Result<(PartInfo, Reader, std::fs::Metadata)> {
    let (file, meta) = open_regular(path).map_err(|e| match e.diagnostic() {
        Some(d) => bad(path, format!("not a part file: {}", d.message)),
        None => e,
    })?;
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_ignore_text_chunk(false);
    let reader = decoder
        .read_info()
        .map_err(|e| bad(path, format!("not a readable PNG part file ({e})")))?;
    let info = read_text(path, reader.info())?;
    let (w, h) = info.image;
    let pixels = u64::from(w) * u64::from(h);
    if pixels > budgets.pixels {
        let what = format!("the image of {w} x {h} = {pixels} pixels");
        return Err(bad(
            path,
            Budgets::exceeded(&what, budgets.pixels, "--max-pixels"),
        ));
    }
    check_png(path, &info, reader.info())?;
    Ok((info, reader, meta))
}

/// What the part's iTXt chunks say, checked: an index below the count,
/// a size of at least 1 x 1, rows within the image.
fn read_text(path: &Path, png_info: &png::Info<'_>) -> Result<PartInfo> {
    let text = |key: &str| -> Result<String> {
        let chunk = png_info
            .utf8_text
            .iter()
            .find(|c| c.keyword == key)
            .ok_or_else(|| {
                bad(
                    path,
                    format!(
                        "not a part file: no `{key}` in its metadata (write parts with \
                         `--part I/N`)"
                    ),
                )
            })?;
        chunk
            .get_text()
            .map_err(|e| bad(path, format!("its `{key}` cannot be read ({e})")))
    };
    let part: PartSpec = text(KEY_PART)?
        .parse()
        .map_err(|e| bad(path, format!("{KEY_PART}: {e}")))?;
    let image = text(KEY_IMAGE)?;
    let image = image
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| w > 0 && h > 0)
        .ok_or_else(|| bad(path, format!("{KEY_IMAGE} `{image}`: expected WxH")))?;
    let rows = text(KEY_ROWS)?;
    let (first, count) = rows
        .split_once('+')
        .and_then(|(f, n)| Some((f.parse::<u32>().ok()?, n.parse::<u32>().ok()?)))
        .ok_or_else(|| bad(path, format!("{KEY_ROWS} `{rows}`: expected FIRST+COUNT")))?;
    if u64::from(first) + u64::from(count) > u64::from(image.1) {
        return Err(bad(
            path,
            format!("rows {first}+{count} pass the image's {} rows", image.1),
        ));
    }
    Ok(PartInfo {
        part,
        image,
        first,
        rows: count,
        output: text(KEY_OUTPUT)?,
        fingerprint: text(KEY_FINGERPRINT)?,
    })
}

/// Checks that the PNG holds the part's rows as a part file has them:
/// `W x COUNT` (1 x 1 for no rows), 8-bit grey or RGB, not interlaced.
fn check_png(path: &Path, info: &PartInfo, i: &png::Info<'_>) -> Result<()> {
    let (w, h) = if info.rows == 0 {
        (1, 1)
    } else {
        (info.image.0, info.rows)
    };
    let grey = i.color_type == png::ColorType::Grayscale;
    if i.width != w
        || i.height != h
        || i.bit_depth != png::BitDepth::Eight
        || !(grey || i.color_type == png::ColorType::Rgb)
    {
        return Err(bad(
            path,
            format!(
                "its PNG is {} x {} {:?} {:?}, not the part's {w} x {h} 8-bit rows",
                i.width, i.height, i.color_type, i.bit_depth
            ),
        ));
    }
    if i.interlaced {
        return Err(bad(
            path,
            "its PNG is interlaced; a part's rows are written in order, not interlaced",
        ));
    }
    Ok(())
}

/// Reads the metadata of part file `path`.
pub fn read_info(path: &Path) -> Result<PartInfo> {
    open(path, &Budgets::default()).map(|(info, ..)| info)
}

/// The parts of one render, checked and in row order.
struct Checked {
    parts: Vec<(PathBuf, PartInfo)>,
    grey: bool,
    /// The part files, which no output may replace.
    inputs: Inputs,
}

/// How the part at `p` differs from `base` (the part at `first`), if it
/// is of another render.
fn differs(p: (&PartInfo, bool), base: (&PartInfo, bool), first: &Path) -> Option<String> {
    let ((info, g), (base, base_grey)) = (p, base);
    let first = first.display();
    if info.fingerprint != base.fingerprint {
        Some(format!(
            "fingerprint {} (what decides the pixels: scene, object files, flags, \
             version), but {first} has {}",
            info.fingerprint, base.fingerprint
        ))
    } else if info.image != base.image {
        Some(format!(
            "an image of {} x {}, but {first} is of {} x {}",
            info.image.0, info.image.1, base.image.0, base.image.1
        ))
    } else if info.part.count != base.part.count {
        Some(format!(
            "one of {} parts, but {first} is one of {}",
            info.part.count, base.part.count
        ))
    } else if info.output != base.output || g != base_grey {
        Some(format!(
            "the image `{}`, but {first} is of `{}`",
            info.output, base.output
        ))
    } else {
        None
    }
}

/// Numbers in ranges: `3, 5-9, 12`, so that a list of thousands of
/// missing parts stays a line.
fn ranges(numbers: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < numbers.len() {
        let mut j = i;
        while j + 1 < numbers.len() && numbers[j + 1] == numbers[j] + 1 {
            j += 1;
        }
        out.push(if j == i {
            numbers[i].to_string()
        } else {
            format!("{}-{}", numbers[i], numbers[j])
        });
        i = j + 1;
    }
    out.join(", ")
}

/// Checks that `paths` are the parts of one render, each part once, all
/// there.
fn check_parts(paths: &[PathBuf], budgets: &Budgets) -> Result<Checked> {
    let Some(first_path) = paths.first() else {
        return Err(Error::Invalid("merge: no part files given".into()));
    };
    let mut parts = Vec::with_capacity(paths.len());
    let mut inputs = Inputs::new();
    for p in paths {
        let (info, reader, meta) = open(p, budgets)?;
        inputs.add(p, &meta);
        let g = reader.info().color_type == png::ColorType::Grayscale;
        parts.push((p.clone(), info, g));
    }
    let (_, base, base_grey) = parts[0].clone();
    for (p, info, g) in &parts[1..] {
        if let Some(d) = differs((info, *g), (&base, base_grey), first_path) {
            return Err(bad(p, format!("a part of another render: {d}")));
        }
    }
    let n = base.part.count as usize;
    let mut seen: Vec<Option<&PathBuf>> = vec![None; n];
    for (p, info, _) in &parts {
        let i = info.part.index as usize;
        if let Some(other) = seen[i] {
            return Err(bad(
                p,
                format!(
                    "part {}/{n} again: {} is the same part; give each part once",
                    info.part.index,
                    other.display()
                ),
            ));
        }
        seen[i] = Some(p);
    }
    let missing: Vec<usize> = (0..n).filter(|&i| seen[i].is_none()).collect();
    if !missing.is_empty() {
        return Err(Error::Invalid(format!(
            "merge: part{} {} of {n} missing (rows of the image no part has); render {} \
             with --part I/{n}",
            if missing.len() == 1 { "" } else { "s" },
            ranges(&missing),
            if missing.len() == 1 { "it" } else { "them" }
        )));
    }
    let mut parts: Vec<(PathBuf, PartInfo)> = parts.into_iter().map(|(p, i, _)| (p, i)).collect();
    parts.sort_by_key(|(_, i)| i.part.index);
    check_cover(&parts, base.image.1)?;
    Ok(Checked {
        parts,
        grey: base_grey,
        inputs,
    })
}

/// Checks that the `parts`, in index order, cover the `height` rows of
/// the image once: each starts where the one before ended.
fn check_cover(parts: &[(PathBuf, PartInfo)], height: u32) -> Result<()> {
    let mut next = 0;
    for (p, info) in parts {
        if info.first != next {
            return Err(bad(
                p,
                format!(
                    "part {} starts at row {}, but the parts before it end at row {next}; \
                     the parts do not cover the image once",
                    info.part, info.first
                ),
            ));
        }
        next = info.first + info.rows;
    }
    if next != height {
        return Err(bad(
            &parts[parts.len() - 1].0,
            format!("the last part ends at row {next}, not at the image's {height} rows"),
        ));
    }
    Ok(())
}

/// The form of a merged image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MergeFormat {
    /// PNG, as the one-process render writes it.
    Png,
    /// Binary PPM (P6).
    Ppm,
    /// The separations `SEED.r .g .b`.
    Separations,
}

impl MergeFormat {
    /// The format `path`'s extension names (PNG unless `.ppm`).
    pub fn of(path: &Path) -> MergeFormat {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("ppm") => MergeFormat::Ppm,
            _ => MergeFormat::Png,
        }
    }
}

/// What [`merge`] did.
#[derive(Debug, Clone)]
pub struct Merged {
    /// The files written.
    pub written: Vec<PathBuf>,
    /// The image's size.
    pub size: (u32, u32),
    /// Parts merged.
    pub parts: usize,
}

/// The image a merge without `-o` writes: the name the parts give
/// (`part`'s `plytrace-output`), which a forged part may have chosen, so
/// it is taken only when it stays inside the working directory
/// ([`output::check_inside`]), names an image (`.png` or `.ppm`) and
/// holds no control characters.
fn name_from_parts(part: &Path, name: &str) -> Result<PathBuf> {
    let refuse = |why: &str| {
        bad(
            part,
            format!(
                "its `{KEY_OUTPUT}` names the image `{}`, {why}; without -o, merge writes \
                 only a name inside the working directory (no `..`, no absolute path, \
                 .png or .ppm): name the image with -o",
                crate::error::printable(name, 200)
            ),
        )
    };
    let path = PathBuf::from(name);
    if name.chars().any(char::is_control) {
        return Err(refuse("which holds control characters"));
    }
    match output::check_inside(&path) {
        Err(output::Outside::ByName) => return Err(refuse("outside the working directory")),
        Err(output::Outside::ByLink) => {
            return Err(refuse(
                "whose directory leads outside the working directory (through a link)",
            ));
        }
        Ok(()) => {}
    }
    if output::check_image_extension(&path).is_err() {
        return Err(refuse("which is not a .png or .ppm image"));
    }
    Ok(path)
}

/// Where the rows go.
enum Target {
    Png(Box<PngSink>),
    Ppm(std::io::BufWriter<std::fs::File>, AtomicFile),
    Separations(Vec<AtomicFile>, Vec<u8>),
}

impl Target {
    /// Creates the output files of `format` (temporaries beside `out`),
    /// each refused if it is one of the parts (under any name) or another
    /// input ([`AtomicFile::create`]).
    fn create(out: &Path, format: MergeFormat, checked: &mut Checked) -> Result<Target> {
        let names = match format {
            MergeFormat::Separations => ["r", "g", "b"]
                .iter()
                .map(|e| output::with_suffix(out, e))
                .collect(),
            _ => vec![out.to_path_buf()],
        };
        for name in &names {
            if let Some(part) = checked.inputs.find(name) {
                let part = crate::error::printable(&part.display().to_string(), 200);
                return Err(bad(
                    name,
                    format!(
                        "this output is the part {part}, an input of the merge; it is not \
                         written over (name another output)"
                    ),
                ));
            }
        }
        let (w, h) = checked.parts[0].1.image;
        Ok(match format {
            MergeFormat::Png => {
                let mode = if checked.grey {
                    DisplayMode::Luminance
                } else {
                    DisplayMode::Color
                };
                Target::Png(Box::new(PngSink::create(out, w, h, mode)?))
            }
            MergeFormat::Ppm => {
                let file = AtomicFile::create(out)?;
                let f = file.file().try_clone().map_err(|e| Error::io(out, e))?;
                let mut bw = std::io::BufWriter::new(f);
                write!(bw, "P6\n{w} {h}\n255\n").map_err(|e| Error::io(out, e))?;
                Target::Ppm(bw, file)
            }
            MergeFormat::Separations => {
                if checked.grey {
                    return Err(Error::Invalid(format!(
                        "{}: the parts are grey; the separations .r .g .b are made from colour \
                         parts",
                        checked.parts[0].0.display()
                    )));
                }
                let files = names
                    .iter()
                    .map(|name| AtomicFile::create(name))
                    .collect::<Result<Vec<_>>>()?;
                Target::Separations(files, Vec::new())
            }
        })
    }

    /// Writes row `y`, the part's `bytes` (grey or RGB).
    fn row(&mut self, y: u32, bytes: &[u8], grey: bool, out: &Path) -> Result<()> {
        match self {
            Target::Png(sink) => sink.row_bytes(y, bytes),
            Target::Ppm(bw, _) if grey => {
                let rgb: Vec<u8> = bytes.iter().flat_map(|&g| [g; 3]).collect();
                bw.write_all(&rgb).map_err(|e| Error::io(out, e))
            }
            Target::Ppm(bw, _) => bw.write_all(bytes).map_err(|e| Error::io(out, e)),
            Target::Separations(files, buf) => {
                for (c, f) in files.iter_mut().enumerate() {
                    buf.clear();
                    buf.extend(bytes.iter().skip(c).step_by(3));
                    f.write_all(buf)?;
                }
                Ok(())
            }
        }
    }

    /// Completes the files under their temporary names.
    fn finish(self, out: &Path) -> Result<Vec<output::Staged>> {
        match self {
            Target::Png(sink) => Ok(vec![sink.finish()?.0]),
            Target::Ppm(mut bw, file) => {
                bw.flush().map_err(|e| Error::io(out, e))?;
                drop(bw);
                Ok(vec![file.finish()?])
            }
            Target::Separations(files, _) => files.into_iter().map(AtomicFile::finish).collect(),
        }
    }
}

/// Copies the rows of the part at `path` (checked as `info`) into
/// `target`.
fn copy_part(
    path: &Path,
    info: &PartInfo,
    checked: &Checked,
    target: &mut Target,
    out: &Path,
    budgets: &Budgets,
) -> Result<()> {
    let (again, mut reader, _) = open(path, budgets)?;
    if again != *info {
        return Err(bad(
            path,
            "changed while the parts were merged; merge again",
        ));
    }
    let width = info.image.0 as usize * if checked.grey { 1 } else { 3 };
    for k in 0..info.rows {
        let row = match reader.next_row() {
            Ok(Some(r)) => r,
            Ok(None) => {
                return Err(bad(
                    path,
                    format!("truncated: {k} of its {} rows", info.rows),
                ));
            }
            Err(e) => {
                return Err(bad(
                    path,
                    format!(
                        "truncated or damaged at row {k} of its {} ({e}); render it again",
                        info.rows
                    ),
                ));
            }
        };
        if row.data().len() != width {
            return Err(bad(path, format!("row {k} is not of {width} bytes")));
        }
        target.row(info.first + k, row.data(), checked.grey, out)?;
    }
    // The PNG's end: its checksums and IEND.
    reader.finish().map_err(|e| {
        bad(
            path,
            format!("truncated or damaged after its rows ({e}); render it again"),
        )
    })
}

/// Merges the part files `paths` into `out` (`None`: the name the parts
/// give, taken only inside the working directory) in `format`, after
/// checking them: parts of one render, every part once, an image within
/// `budgets.pixels`. No output replaces a part, and nothing is written
/// unless every row is.
pub fn merge(
    paths: &[PathBuf],
    out: Option<&Path>,
    format: Option<MergeFormat>,
    budgets: &Budgets,
) -> Result<Merged> {
    let mut checked = check_parts(paths, budgets)?;
    let (first, info) = &checked.parts[0];
    let out = match out {
        Some(p) => p.to_path_buf(),
        None => name_from_parts(first, &info.output)?,
    };
    let format = format.unwrap_or_else(|| MergeFormat::of(&out));
    let mut target = Target::create(&out, format, &mut checked)?;
    for (path, info) in &checked.parts {
        if info.rows > 0 {
            copy_part(path, info, &checked, &mut target, &out, budgets)?;
        }
    }
    let staged = target.finish(&out)?;
    let written = staged.iter().map(|s| s.path().to_path_buf()).collect();
    output::commit_all(staged)?;
    Ok(Merged {
        written,
        size: checked.parts[0].1.image,
        parts: checked.parts.len(),
    })
}

/// The indices of the parts of a render that `paths` (the part files
/// there are) do not hold, for rendering them again. `count` is the part
/// count when no part is there to say it. A part that cannot be read (a
/// damaged file, a FIFO, a part of an image over `budgets.pixels`)
/// counts as missing, with a warning in the result; parts of different
/// renders are an error.
pub fn missing(
    paths: &[PathBuf],
    count: Option<u32>,
    budgets: &Budgets,
) -> Result<(Vec<u32>, Vec<String>)> {
    let mut warnings = Vec::new();
    let mut base: Option<(PathBuf, PartInfo)> = None;
    let mut have = std::collections::BTreeSet::new();
    for p in paths {
        let info = match open(p, budgets).and_then(|(info, reader, _)| complete(p, info, reader)) {
            Ok(i) => i,
            Err(e) => {
                warnings.push(format!("{e}; counted as missing"));
                continue;
            }
        };
        if let Some((bp, b)) = &base {
            if b.fingerprint != info.fingerprint
                || b.image != info.image
                || b.part.count != info.part.count
            {
                return Err(bad(
                    p,
                    format!(
                        "a part of another render than {} (fingerprint, size or part count differ)",
                        bp.display()
                    ),
                ));
            }
        } else {
            base = Some((p.clone(), info.clone()));
        }
        have.insert(info.part.index);
    }
    let n = match (&base, count) {
        (Some((p, b)), Some(c)) if b.part.count != c => {
            return Err(bad(
                p,
                format!("one of {} parts, not of --count {c}", b.part.count),
            ));
        }
        (Some((_, b)), _) => b.part.count,
        (None, Some(c)) => c,
        (None, None) => {
            return Err(Error::Invalid(
                "merge --missing: no readable part given, so the part count is not known; \
                 give it with --count N"
                    .into(),
            ));
        }
    };
    Ok(((0..n).filter(|i| !have.contains(i)).collect(), warnings))
}

/// Reads the rest of a part, to know it is whole.
fn complete(path: &Path, info: PartInfo, mut reader: Reader) -> Result<PartInfo> {
    while reader
        .next_row()
        .map_err(|e| bad(path, format!("truncated or damaged ({e})")))?
        .is_some()
    {}
    reader
        .finish()
        .map_err(|e| bad(path, format!("truncated or damaged ({e})")))?;
    Ok(info)
}

#[cfg(test)]
mod tests;

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

use std::io::{BufReader, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::output::{self, AtomicFile, DisplayMode, PngSink};
use crate::raster::scan::{Row, RowSink};

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
    Error::Invalid(format!("{}: {what}", path.display()))
}

type Reader = png::Reader<BufReader<std::fs::File>>;

/// Opens part file `path` and reads what it says of itself.
fn open(path: &Path) -> Result<(PartInfo, Reader)> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_ignore_text_chunk(false);
    let reader = decoder
        .read_info()
        .map_err(|e| bad(path, format!("not a readable PNG part file ({e})")))?;
    let text = |key: &str| -> Result<String> {
        let chunk = reader
            .info()
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
    let info = PartInfo {
        part,
        image,
        first,
        rows: count,
        output: text(KEY_OUTPUT)?,
        fingerprint: text(KEY_FINGERPRINT)?,
    };
    if u64::from(first) + u64::from(count) > u64::from(image.1) {
        return Err(bad(
            path,
            format!("rows {first}+{count} pass the image's {} rows", image.1),
        ));
    }
    let i = reader.info();
    let (w, h) = if count == 0 { (1, 1) } else { (image.0, count) };
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
    Ok((info, reader))
}

/// Reads the metadata of part file `path`.
pub fn read_info(path: &Path) -> Result<PartInfo> {
    open(path).map(|(info, _)| info)
}

/// The parts of one render, checked and in row order.
struct Checked {
    parts: Vec<(PathBuf, PartInfo)>,
    grey: bool,
}

/// Checks that `paths` are the parts of one render, each part once, all
/// there.
fn check_parts(paths: &[PathBuf]) -> Result<Checked> {
    let Some(first_path) = paths.first() else {
        return Err(Error::Invalid("merge: no part files given".into()));
    };
    let mut parts = Vec::with_capacity(paths.len());
    let mut grey = None;
    for p in paths {
        let (info, reader) = open(p)?;
        let g = reader.info().color_type == png::ColorType::Grayscale;
        parts.push((p.clone(), info, g));
        grey.get_or_insert(g);
    }
    let (_, base, base_grey) = &parts[0];
    let base = base.clone();
    let base_grey = *base_grey;
    for (p, info, g) in &parts[1..] {
        let differs = if info.fingerprint != base.fingerprint {
            Some(format!(
                "fingerprint {} (what decides the pixels: scene, object files, flags, \
                 version), but {} has {}",
                info.fingerprint,
                first_path.display(),
                base.fingerprint
            ))
        } else if info.image != base.image {
            Some(format!(
                "an image of {} x {}, but {} is of {} x {}",
                info.image.0,
                info.image.1,
                first_path.display(),
                base.image.0,
                base.image.1
            ))
        } else if info.part.count != base.part.count {
            Some(format!(
                "one of {} parts, but {} is one of {}",
                info.part.count,
                first_path.display(),
                base.part.count
            ))
        } else if info.output != base.output || *g != base_grey {
            Some(format!(
                "the image `{}`, but {} is of `{}`",
                info.output,
                first_path.display(),
                base.output
            ))
        } else {
            None
        };
        if let Some(d) = differs {
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
    let missing: Vec<String> = (0..n)
        .filter(|&i| seen[i].is_none())
        .map(|i| i.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(Error::Invalid(format!(
            "merge: part{} {} of {n} missing (rows of the image no part has); render {} \
             with --part I/{n}",
            if missing.len() == 1 { "" } else { "s" },
            missing.join(", "),
            if missing.len() == 1 { "it" } else { "them" }
        )));
    }
    let mut parts: Vec<(PathBuf, PartInfo)> = parts.into_iter().map(|(p, i, _)| (p, i)).collect();
    parts.sort_by_key(|(_, i)| i.part.index);
    // Every row once: each part starts where the one before ended.
    let mut next = 0;
    for (p, info) in &parts {
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
    if next != base.image.1 {
        return Err(bad(
            &parts[parts.len() - 1].0,
            format!(
                "the last part ends at row {next}, not at the image's {} rows",
                base.image.1
            ),
        ));
    }
    Ok(Checked {
        parts,
        grey: base_grey,
    })
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

/// Where the rows go.
enum Target {
    Png(Box<PngSink>),
    Ppm(std::io::BufWriter<std::fs::File>, AtomicFile),
    Separations(Vec<AtomicFile>, Vec<u8>),
}

/// Merges the part files `paths` into `out` (`None`: the name the parts
/// give) in `format`, after checking them: parts of one render, every
/// part once. Nothing is written unless every row is.
pub fn merge(paths: &[PathBuf], out: Option<&Path>, format: Option<MergeFormat>) -> Result<Merged> {
    let checked = check_parts(paths)?;
    let info = &checked.parts[0].1;
    let (w, h) = info.image;
    let out = out.map_or_else(|| PathBuf::from(&info.output), Path::to_path_buf);
    let format = format.unwrap_or_else(|| MergeFormat::of(&out));
    for (p, _) in &checked.parts {
        if same_file(p, &out) {
            return Err(bad(&out, "this output is one of the parts; name another"));
        }
    }
    let mut target = match format {
        MergeFormat::Png => {
            let mode = if checked.grey {
                DisplayMode::Luminance
            } else {
                DisplayMode::Color
            };
            Target::Png(Box::new(PngSink::create(&out, w, h, mode)?))
        }
        MergeFormat::Ppm => {
            let file = AtomicFile::create(&out)?;
            let f = file.file().try_clone().map_err(|e| Error::io(&out, e))?;
            let mut bw = std::io::BufWriter::new(f);
            write!(bw, "P6\n{w} {h}\n255\n").map_err(|e| Error::io(&out, e))?;
            Target::Ppm(bw, file)
        }
        MergeFormat::Separations => {
            if checked.grey {
                return Err(Error::Invalid(format!(
                    "{}: the parts are grey; the separations .r .g .b are made from colour parts",
                    checked.parts[0].0.display()
                )));
            }
            let files = ["r", "g", "b"]
                .iter()
                .map(|e| AtomicFile::create(&output::with_suffix(&out, e)))
                .collect::<Result<Vec<_>>>()?;
            Target::Separations(files, Vec::new())
        }
    };
    let mut expanded = Vec::new();
    for (path, info) in &checked.parts {
        if info.rows == 0 {
            continue;
        }
        let (_, mut reader) = open(path)?;
        for k in 0..info.rows {
            let y = info.first + k;
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
            let bytes = row.data();
            match &mut target {
                Target::Png(sink) => sink.row_bytes(y, bytes)?,
                Target::Ppm(bw, _) => {
                    let rgb = if checked.grey {
                        expanded.clear();
                        expanded.extend(bytes.iter().flat_map(|&g| [g; 3]));
                        &expanded[..]
                    } else {
                        bytes
                    };
                    bw.write_all(rgb).map_err(|e| Error::io(&out, e))?;
                }
                Target::Separations(files, buf) => {
                    for (c, f) in files.iter_mut().enumerate() {
                        buf.clear();
                        buf.extend(bytes.iter().skip(c).step_by(3));
                        f.write_all(buf)?;
                    }
                }
            }
        }
        // The PNG's end: its checksums and IEND.
        if let Err(e) = reader.finish() {
            return Err(bad(
                path,
                format!("truncated or damaged after its rows ({e}); render it again"),
            ));
        }
    }
    let staged = match target {
        Target::Png(sink) => vec![sink.finish()?.0],
        Target::Ppm(mut bw, file) => {
            bw.flush().map_err(|e| Error::io(&out, e))?;
            drop(bw);
            vec![file.finish()?]
        }
        Target::Separations(files, _) => files
            .into_iter()
            .map(AtomicFile::finish)
            .collect::<Result<Vec<_>>>()?,
    };
    let written = staged.iter().map(|s| s.path().to_path_buf()).collect();
    output::commit_all(staged)?;
    Ok(Merged {
        written,
        size: (w, h),
        parts: checked.parts.len(),
    })
}

/// Whether `a` and `b` are the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// The indices of the parts of a render that `paths` (the part files
/// there are) do not hold, for rendering them again. `count` is the part
/// count when no part is there to say it. A part that cannot be read (a
/// damaged file) counts as missing, with a warning in the result; parts
/// of different renders are an error.
pub fn missing(paths: &[PathBuf], count: Option<u32>) -> Result<(Vec<u32>, Vec<String>)> {
    let mut warnings = Vec::new();
    let mut base: Option<(PathBuf, PartInfo)> = None;
    let mut have = std::collections::BTreeSet::new();
    for p in paths {
        let info = match open(p).and_then(|(info, reader)| complete(p, info, reader)) {
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
mod tests {
    use super::*;

    /// The fingerprint changes with the program, any input's contents,
    /// their order and the flags: a merge then refuses parts of another
    /// render, whatever it was that differed.
    #[test]
    fn every_thing_that_decides_the_pixels_changes_the_fingerprint() {
        let base = fingerprint_of("plytrace", &[1, 2], "--aa 4");
        assert_eq!(base.len(), 16);
        assert_eq!(base, fingerprint_of("plytrace", &[1, 2], "--aa 4"));
        for other in [
            fingerprint_of("rftb4", &[1, 2], "--aa 4"),
            fingerprint_of("plytrace", &[1, 3], "--aa 4"),
            fingerprint_of("plytrace", &[2, 1], "--aa 4"),
            fingerprint_of("plytrace", &[1], "--aa 4"),
            fingerprint_of("plytrace", &[1, 2], "--aa 2"),
        ] {
            assert_ne!(other, base);
        }
    }
}

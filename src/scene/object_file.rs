//! Object files of the `mkdet`/`mkpcl`/`mkvcl` manual page (Garcia 1986,
//! 004 appendix): ASCII and binary geometry (`.det`, `DET`) and polygon or
//! vertex colour tables (`.pcl`/`PCL`, `.vcl`/`VCL`). The binary counts
//! are the manual's C `short`s: at most 32767, refused above.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::model::{ColorEntry, IndexList, Mesh};

use crate::error::{Diagnostic, Error, Location, Result};

mod ascii;
mod binary;

pub use ascii::*;
pub use binary::*;
/// Which colour table a `PCL`/`VCL` file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorKind {
    /// One entry per polygon (`.pcl`, binary tag `PCL`).
    Polygon,
    /// One entry per vertex (`.vcl`, binary tag `VCL`).
    Vertex,
}

impl ColorKind {
    /// The 3-byte tag that starts the binary file: `PCL` or `VCL`.
    pub fn tag(self) -> &'static [u8; 3] {
        match self {
            ColorKind::Polygon => b"PCL",
            ColorKind::Vertex => b"VCL",
        }
    }

    fn description(self) -> &'static str {
        match self {
            ColorKind::Polygon => "polygon colour file",
            ColorKind::Vertex => "vertex colour file",
        }
    }
}

/// What `convert` does: the `mkdet`, `mkpcl` and `mkvcl` commands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConvertKind {
    /// `mkdet`: geometry to a binary `DET` file.
    Det,
    /// `mkpcl`: polygon colours to a binary `PCL` file.
    Pcl,
    /// `mkvcl`: vertex colours to a binary `VCL` file.
    Vcl,
}

/// Tag of a binary geometry file.
const DET_TAG: &[u8; 3] = b"DET";

/// The largest count a binary file can hold: the manual page declares
/// every count a C `short` (`short num_vtx, num_polys`, `short nvtx,
/// index[nvtx]`, `short num_clr`), signed 16 bits, so 32767; the
/// manual's programs would read 32768 and up as negative.
const BINARY_LIMIT: usize = i16::MAX as usize;

/// Names of the six numbers of a colour entry, in file order.
const COLOR_FIELDS: [&str; 6] = [
    "red",
    "green",
    "blue",
    "diffuse coefficient",
    "reflection coefficient",
    "transmission coefficient",
];

// ---------------------------------------------------------------------------
// Files

/// Whether `bytes` is a binary file with one of `tags`: it starts with the
/// tag and is not plain text (binary counts and floats hold control bytes).
fn is_binary(bytes: &[u8], tags: &[&[u8; 3]]) -> bool {
    tags.iter().any(|tag| bytes.starts_with(*tag)) && !is_plain_text(bytes)
}

fn is_plain_text(bytes: &[u8]) -> bool {
    match std::str::from_utf8(bytes) {
        Ok(text) => text
            .chars()
            .all(|c| !c.is_control() || matches!(c, '\t' | '\n' | '\r' | '\x0c')),
        Err(_) => false,
    }
}

fn read_file(path: &Path) -> Result<Vec<u8>> {
    read_regular(path, MAX_INPUT_BYTES)
}

/// The largest input file read (scene, geometry or colour file): 1 GiB.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// What kind of file `meta` describes, for messages.
fn file_kind(meta: &fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// Opens `path`, which must be a regular file (symbolic links are
/// followed), for reading; the metadata is the open file's. A FIFO, a
/// device, a socket or a directory is refused before it is opened, and
/// again from the open file, which is opened without waiting, so that
/// reading never blocks on a pipe swapped in between.
pub fn open_regular(path: &Path) -> Result<(File, fs::Metadata)> {
    let shown = crate::error::printable(&path.display().to_string(), 200);
    let refuse = |meta: &fs::Metadata| {
        Error::at(
            Location::file(path),
            format!(
                "`{shown}` is {}: only regular files are read",
                file_kind(meta)
            ),
        )
    };
    let meta = fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(refuse(&meta));
    }
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // O_NONBLOCK: should the file have been replaced by a FIFO since
        // the check above, opening it must not wait for a writer.
        options.custom_flags(0o4000);
    }
    let file = options.open(path).map_err(|e| Error::io(path, e))?;
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(refuse(&meta));
    }
    Ok((file, meta))
}

/// Reads the whole of `path`, which must be a regular file (symbolic links
/// are followed) of at most `limit` bytes ([`open_regular`]), so that
/// reading never blocks on a pipe nor runs on an endless stream, and the
/// size is checked before anything is read. The read itself is bounded
/// too, in case the file grows.
pub fn read_regular(path: &Path, limit: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let shown = crate::error::printable(&path.display().to_string(), 200);
    let (file, meta) = open_regular(path)?;
    crate::input_guard::note(path, &meta);
    if meta.len() > limit {
        return Err(Error::at(
            Location::file(path),
            format!(
                "`{shown}` has {} bytes, more than the {limit} bytes an input file may have",
                meta.len()
            ),
        ));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(Error::at(
            Location::file(path),
            format!("`{shown}` grew past the {limit} bytes an input file may have"),
        ));
    }
    crate::input_guard::note_contents(&bytes);
    Ok(bytes)
}

/// The file as UTF-8 text, or an error at the first invalid byte.
fn as_text<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str> {
    std::str::from_utf8(bytes).map_err(|e| {
        let valid = &bytes[..e.valid_up_to()];
        // The prefix is valid UTF-8 by definition.
        let valid = std::str::from_utf8(valid).unwrap_or_default();
        let line = valid.matches('\n').count() + 1;
        let column = valid.rsplit('\n').next().unwrap_or("").chars().count() + 1;
        Error::at(
            Location::new(path, line, column),
            format!(
                "invalid UTF-8 at byte offset {}: expected a text object file \
                 or a binary one",
                e.valid_up_to()
            ),
        )
    })
}

/// Reads a geometry file, binary (starting with `DET`) or ASCII.
pub fn read_det(path: &Path) -> Result<Mesh> {
    read_det_within(path, usize::MAX)
}

/// [`read_det`], refusing an ASCII file that declares more than
/// `max_polygons` polygons before they are read (a binary file has at most
/// 65,535, and is checked by the caller).
pub fn read_det_within(path: &Path, max_polygons: usize) -> Result<Mesh> {
    let bytes = read_file(path)?;
    if is_binary(&bytes, &[DET_TAG]) {
        parse_det_binary(&bytes, path)
    } else {
        parse_det_ascii_within(as_text(&bytes, path)?, path, max_polygons)
    }
}

/// Reads a polygon or vertex colour file, binary (starting with `PCL` or
/// `VCL`; the tag must match `kind`) or ASCII.
pub fn read_colors(path: &Path, kind: ColorKind) -> Result<Vec<ColorEntry>> {
    let bytes = read_file(path)?;
    let tags = [ColorKind::Polygon.tag(), ColorKind::Vertex.tag()];
    if is_binary(&bytes, &tags) {
        parse_color_binary(&bytes, path, kind).map_err(|e| {
            if bytes.starts_with(kind.tag()) {
                e
            } else {
                Error::at(
                    Location::file(path),
                    format!(
                        "expected a binary {} (tag `{}`), found the tag `{}`",
                        kind.description(),
                        String::from_utf8_lossy(kind.tag()),
                        String::from_utf8_lossy(&bytes[..3])
                    ),
                )
            }
        })
    } else {
        parse_color_ascii(as_text(&bytes, path)?, path)
    }
}

/// The `mkdet`, `mkpcl` and `mkvcl` commands: reads `input` (ASCII or
/// binary) and writes its binary form to `output`. The output is written to
/// a temporary file in the same directory and renamed into place, so that
/// an error never leaves a partial output.
pub fn convert(kind: ConvertKind, input: &Path, output: &Path) -> Result<()> {
    let bytes = match kind {
        ConvertKind::Det => write_det_binary(&read_det(input)?),
        ConvertKind::Pcl => {
            write_color_binary(&read_colors(input, ColorKind::Polygon)?, ColorKind::Polygon)
        }
        ConvertKind::Vcl => {
            write_color_binary(&read_colors(input, ColorKind::Vertex)?, ColorKind::Vertex)
        }
    };
    let bytes = bytes.map_err(|e| match e {
        Error::Invalid(message) => Error::at(Location::file(input), message),
        other => other,
    })?;
    write_atomically(output, &bytes)
}

/// Writes `bytes` to `output` through a temporary file and a rename; on
/// error the temporary file is removed and `output` is left untouched.
fn write_atomically(output: &Path, bytes: &[u8]) -> Result<()> {
    let (temp, mut file) = create_temp_beside(output).map_err(|e| Error::io(output, e))?;
    let written = file.write_all(bytes).and_then(|()| file.sync_all());
    drop(file);
    if let Err(e) = written.and_then(|()| fs::rename(&temp, output)) {
        // Best effort: the temporary file may already be gone.
        let _ = fs::remove_file(&temp);
        return Err(Error::io(output, e));
    }
    Ok(())
}

/// A new, uniquely named file in the directory of `output`.
fn create_temp_beside(output: &Path) -> io::Result<(PathBuf, File)> {
    let dir = match output.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let name = output
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?
        .to_string_lossy();
    let mut attempt = 0;
    loop {
        let temp = dir.join(format!(".{name}.{}.{attempt}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((temp, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempt < 100 => attempt += 1,
            Err(e) => return Err(e),
        }
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod scanner_tests {
    use super::*;
    use proptest::prelude::*;

    /// The tokens of `text` by `str`'s own searches (the scanner's first
    /// form): each token's text, line and line start.
    fn by_str_search(text: &str) -> Vec<(String, usize, usize)> {
        let (mut pos, mut line, mut line_start) = (0, 1, 0);
        let mut out = Vec::new();
        loop {
            let rest = &text[pos..];
            let skipped = rest.len() - rest.trim_start_matches(is_separator).len();
            for (i, c) in rest[..skipped].char_indices() {
                if c == '\n' {
                    line += 1;
                    line_start = pos + i + 1;
                }
            }
            pos += skipped;
            let rest = &text[pos..];
            if rest.is_empty() {
                return out;
            }
            let len = rest.find(is_separator).unwrap_or(rest.len());
            out.push((rest[..len].to_string(), line, line_start));
            pos += len;
        }
    }

    proptest! {
        /// Separators of every kind (ASCII, commas, Unicode spaces, a
        /// control character that is not a space, letters outside ASCII):
        /// the scanner finds the same tokens on the same lines.
        #[test]
        fn the_scanner_splits_as_the_string_searches(
            picks in prop::collection::vec(0usize..14, 0..80),
        ) {
            const ALPHABET: [&str; 14] = [
                "1", "-2.5e3", ",", " ", "\t", "\n", "\r\n", "\u{85}", "\u{a0}",
                "\u{2003}", "é", "\u{b}", "\u{1c}", "x\u{3000}y",
            ];
            let text: String = picks.iter().map(|&k| ALPHABET[k]).collect();
            let file = Path::new("t.det");
            let mut scanner = Scanner {
                file,
                text: &text,
                pos: 0,
                line: 1,
                line_start: 0,
                last_end: (0, 1, 0),
            };
            let mut got = Vec::new();
            while let Some(t) = scanner.next() {
                prop_assert_eq!(&text[t.start..t.start + t.text.len()], t.text);
                got.push((t.text.to_string(), t.line, t.line_start));
            }
            prop_assert_eq!(got, by_str_search(&text));
        }
    }
}

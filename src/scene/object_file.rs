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
// ASCII scanning

/// A token of an ASCII object file: a run of characters other than
/// whitespace and commas.
#[derive(Debug, Clone, Copy)]
struct Token<'a> {
    text: &'a str,
    /// Byte offset of the token in the file.
    start: usize,
    /// 1-based line of the token.
    line: usize,
    /// Byte offset where that line starts.
    line_start: usize,
}

fn is_separator(c: char) -> bool {
    c.is_whitespace() || c == ','
}

/// Reads the tokens that follow the `data` keyword, keeping track of lines so
/// that errors can name a line and column.
struct Scanner<'a> {
    file: &'a Path,
    text: &'a str,
    /// Byte offset of the next unread character.
    pos: usize,
    /// 1-based line at `pos`.
    line: usize,
    /// Byte offset where the line at `pos` starts.
    line_start: usize,
    /// Where the last token (or the `data` keyword) ended: offset, line, line start.
    last_end: (usize, usize, usize),
}

impl<'a> Scanner<'a> {
    /// A scanner positioned just after the `data` keyword: the first token of
    /// a line, in any case. Lines before it (the `title` line) are free text.
    fn after_data(text: &'a str, file: &'a Path) -> Result<Self> {
        let mut offset = 0;
        for (index, line) in text.split_inclusive('\n').enumerate() {
            let rest = line.trim_start_matches(is_separator);
            let keyword_len = rest.find(is_separator).unwrap_or(rest.len());
            if rest[..keyword_len].eq_ignore_ascii_case("data") {
                let end = offset + (line.len() - rest.len()) + keyword_len;
                return Ok(Scanner {
                    file,
                    text,
                    pos: end,
                    line: index + 1,
                    line_start: offset,
                    last_end: (end, index + 1, offset),
                });
            }
            offset += line.len();
        }
        let line_count = text.lines().count().max(1);
        Err(Error::at(
            Location::new(file, line_count, 0),
            "expected the keyword `data` at the start of a line, file ended without it",
        ))
    }

    /// The next token, or `None` at the end of the file.
    #[inline(always)]
    fn next(&mut self) -> Option<Token<'a>> {
        while let Some((c, len)) = self.char_at(self.pos) {
            if !is_separator(c) {
                break;
            }
            if c == '\n' {
                self.line += 1;
                self.line_start = self.pos + 1;
            }
            self.pos += len;
        }
        let start = self.pos;
        while let Some((c, len)) = self.char_at(self.pos) {
            if is_separator(c) {
                break;
            }
            self.pos += len;
        }
        if self.pos == start {
            return None;
        }
        self.last_end = (self.pos, self.line, self.line_start);
        Some(Token {
            text: &self.text[start..self.pos],
            start,
            line: self.line,
            line_start: self.line_start,
        })
    }

    /// The character at byte `pos` and its length, decoded only when it is
    /// not ASCII: most of a mesh file is digits, signs and spaces, and the
    /// whole reading of a scene's files is on its critical path.
    #[inline]
    fn char_at(&self, pos: usize) -> Option<(char, usize)> {
        let b = *self.text.as_bytes().get(pos)?;
        if b.is_ascii() {
            return Some((char::from(b), 1));
        }
        let c = self.text[pos..].chars().next()?;
        Some((c, c.len_utf8()))
    }

    /// The next token; at the end of the file an error saying `ended()`.
    #[inline(always)]
    fn next_or(&mut self, ended: impl FnOnce() -> String) -> Result<Token<'a>> {
        match self.next() {
            Some(token) => Ok(token),
            None => Err(self.error_at_end(ended())),
        }
    }

    /// At most `count` items of `tokens` tokens each: what the unread text
    /// could hold (each token takes at least one character and a separator).
    fn capacity(&self, count: u64, tokens: usize) -> usize {
        let room = (self.text.len() - self.pos) / (2 * tokens) + 1;
        usize::try_from(count).unwrap_or(usize::MAX).min(room)
    }

    fn diagnostic(
        &self,
        offset: usize,
        line: usize,
        line_start: usize,
        width: usize,
    ) -> Diagnostic {
        let column = self.text[line_start..offset].chars().count() + 1;
        let line_text = self.text[line_start..].split('\n').next().unwrap_or("");
        Diagnostic::new(Location::new(self.file, line, column), "")
            .with_source(line_text.trim_end_matches('\r'), width)
    }

    /// An error pointing at `token`.
    fn error(&self, token: &Token, message: impl Into<String>) -> Error {
        let width = token.text.chars().count();
        let mut d = self.diagnostic(token.start, token.line, token.line_start, width);
        d.message = message.into();
        d.into()
    }

    /// An error pointing just after the last token read.
    fn error_at_end(&self, message: impl Into<String>) -> Error {
        let (offset, line, line_start) = self.last_end;
        let mut d = self.diagnostic(offset, line, line_start, 1);
        d.message = message.into();
        d.into()
    }

    /// Fails with `message` if anything but whitespace (or commas) is left.
    fn expect_end(&mut self, message: &str) -> Result<()> {
        match self.next() {
            Some(token) => Err(self.error(&token, message)),
            None => Ok(()),
        }
    }

    /// A count: a non-negative integer.
    fn count(&mut self, what: &str) -> Result<u64> {
        let token = self.next_or(|| format!("expected {what}, file ended"))?;
        token.text.parse().map_err(|_| {
            self.error(
                &token,
                format!(
                    "expected {what} (a non-negative integer), found `{}`",
                    crate::error::printable(token.text, crate::error::MAX_SHOWN_TOKEN)
                ),
            )
        })
    }

    /// A finite number, read from `token`.
    fn number(&self, token: &Token, what: &str) -> Result<f64> {
        let value: f64 = token.text.parse().map_err(|_| {
            self.error(
                token,
                format!(
                    "expected {what} (a number), found `{}`",
                    crate::error::printable(token.text, crate::error::MAX_SHOWN_TOKEN)
                ),
            )
        })?;
        if !value.is_finite() {
            return Err(self.error(
                token,
                format!(
                    "non-finite number `{}` where {what} was expected",
                    crate::error::printable(token.text, crate::error::MAX_SHOWN_TOKEN)
                ),
            ));
        }
        Ok(value)
    }
}

// ---------------------------------------------------------------------------
// ASCII geometry

/// Parses an ASCII geometry file (`.det`): free text up to the keyword
/// `data` (the first word of a line, any case), then `num_vtx num_polys`,
/// `num_vtx` vertices `x y z`, and `num_polys` polygons `n i1 .. in` with
/// 1-based vertex indices, clockwise seen from outside. Words are separated by
/// whitespace or commas. The indices of the returned mesh are 0-based.
///
/// Errors name the line and column of the offending word.
pub fn parse_det_ascii(text: &str, file: &Path) -> Result<Mesh> {
    parse_det_ascii_within(text, file, usize::MAX)
}

/// [`parse_det_ascii`], refusing a file that declares more than
/// `max_polygons` polygons before any is read (the polygon budget,
/// `--max-polygons`).
pub fn parse_det_ascii_within(text: &str, file: &Path, max_polygons: usize) -> Result<Mesh> {
    let mut scanner = Scanner::after_data(text, file)?;
    let num_vtx = scanner.count("the number of vertices")?;
    if num_vtx > u64::from(u32::MAX) {
        return Err(scanner.error_at_end(format!(
            "{num_vtx} vertices is too many: at most {} are supported",
            u32::MAX
        )));
    }
    let num_polys = scanner.count("the number of polygons")?;
    if num_polys > max_polygons as u64 {
        return Err(scanner.error_at_end(format!(
            "{num_polys} polygons exceed the {max_polygons} left of the polygon budget; \
             `--max-polygons N` raises it"
        )));
    }
    let vertices = read_vertices(&mut scanner, num_vtx)?;
    let polygons = read_polygons(&mut scanner, num_polys, num_vtx)?;
    scanner.expect_end("unexpected text after the last polygon")?;
    Ok(Mesh::new(vertices, polygons))
}

fn read_vertices(scanner: &mut Scanner, count: u64) -> Result<Vec<DVec3>> {
    let mut vertices = Vec::with_capacity(scanner.capacity(count, 3));
    for _ in 0..count {
        let mut xyz = [0.0; 3];
        for coordinate in &mut xyz {
            let done = vertices.len();
            let token = scanner
                .next_or(|| format!("expected {count} vertices, file ended after {done}"))?;
            *coordinate = scanner.number(&token, "a vertex coordinate")?;
        }
        vertices.push(DVec3::from_array(xyz));
    }
    Ok(vertices)
}

/// The polygons, each read into one reused buffer and held as an
/// [`IndexList`] (a triangle allocates nothing).
fn read_polygons(scanner: &mut Scanner, count: u64, num_vtx: u64) -> Result<Vec<IndexList>> {
    let mut polygons = Vec::with_capacity(scanner.capacity(count, 4));
    let mut polygon = Vec::new();
    for number in 1..=count {
        let ended = || format!("expected {count} polygons, file ended after {}", number - 1);
        let token = scanner.next_or(ended)?;
        let size: u64 = token.text.parse().map_err(|_| {
            scanner.error(
                &token,
                format!(
                    "expected the number of vertices of polygon {number} (an integer), found `{}`",
                    crate::error::printable(token.text, crate::error::MAX_SHOWN_TOKEN)
                ),
            )
        })?;
        if size < 3 {
            return Err(scanner.error(
                &token,
                format!("polygon {number} has {size} vertices; a polygon needs at least 3"),
            ));
        }
        polygon.clear();
        polygon.reserve(scanner.capacity(size, 1));
        for _ in 0..size {
            let token = scanner.next_or(ended)?;
            polygon.push(vertex_index(scanner, &token, number, num_vtx)?);
        }
        polygons.push(IndexList::from(polygon.as_slice()));
    }
    Ok(polygons)
}

/// A 1-based vertex index of polygon `polygon`, returned 0-based.
fn vertex_index(scanner: &Scanner, token: &Token, polygon: u64, num_vtx: u64) -> Result<u32> {
    let index: u64 = token.text.parse().map_err(|_| {
        scanner.error(
            token,
            format!(
                "expected a vertex index (an integer in 1..={num_vtx}), found `{}`",
                crate::error::printable(token.text, crate::error::MAX_SHOWN_TOKEN)
            ),
        )
    })?;
    if index == 0 || index > num_vtx {
        return Err(scanner.error(
            token,
            format!("vertex index {index} out of range 1..={num_vtx} in polygon {polygon}"),
        ));
    }
    // num_vtx <= u32::MAX was checked, so index - 1 fits.
    Ok((index - 1) as u32)
}

/// Writes `mesh` as an ASCII geometry file like the manual's examples, with
/// a `title` line, `data`, the counts, the vertices and 1-based polygons.
/// Numbers are printed so that [`parse_det_ascii`] reads them back exactly.
pub fn write_det_ascii(mesh: &Mesh, title: &str) -> String {
    let mut out = title_lines(title);
    out.push_str(&format!(
        "data\n{} {}\n",
        mesh.vertices.len(),
        mesh.polygons.len()
    ));
    for v in &mesh.vertices {
        out.push_str(&format!("{} {} {}\n", v.x, v.y, v.z));
    }
    for polygon in &mesh.polygons {
        out.push_str(&polygon.len().to_string());
        for index in polygon {
            out.push_str(&format!(" {}", u64::from(*index) + 1));
        }
        out.push('\n');
    }
    out
}

/// The `title` line, kept on one line so that the file stays readable.
fn title_lines(title: &str) -> String {
    let title = title.replace(['\n', '\r'], " ");
    if title.is_empty() {
        "title\n".to_string()
    } else {
        format!("title    {title}\n")
    }
}

// ---------------------------------------------------------------------------
// ASCII colours

/// Parses an ASCII polygon or vertex colour file (`.pcl`, `.vcl`): free
/// text up to the keyword `data`, the number of entries (on the `data` line
/// or after it), then that many entries `r g b dif ref trn`, each in 0..=1.
pub fn parse_color_ascii(text: &str, file: &Path) -> Result<Vec<ColorEntry>> {
    let mut scanner = Scanner::after_data(text, file)?;
    let count = scanner.count("the number of colour entries")?;
    let mut entries = Vec::with_capacity(scanner.capacity(count, 6));
    for number in 1..=count {
        let mut values = [0.0; 6];
        for (value, name) in values.iter_mut().zip(COLOR_FIELDS) {
            *value = color_value(&mut scanner, name, number, count)?;
        }
        entries.push(color_entry(values));
    }
    scanner.expect_end("unexpected text after the last colour entry")?;
    Ok(entries)
}

/// One value of colour entry `number`, checked to lie in 0..=1.
fn color_value(scanner: &mut Scanner, name: &str, number: u64, count: u64) -> Result<f64> {
    let token = scanner.next_or(|| {
        format!(
            "expected {count} colour entries, file ended after {}",
            number - 1
        )
    })?;
    let value = scanner.number(&token, &format!("the {name}"))?;
    if !(0.0..=1.0).contains(&value) {
        return Err(scanner.error(
            &token,
            format!("{name} {value} out of range 0..=1 in colour entry {number}"),
        ));
    }
    Ok(value)
}

fn color_entry(v: [f64; 6]) -> ColorEntry {
    ColorEntry {
        color: DVec3::new(v[0], v[1], v[2]),
        diffuse: v[3],
        reflectance: v[4],
        transmittance: v[5],
    }
}

fn color_values(entry: &ColorEntry) -> [f64; 6] {
    [
        entry.color.x,
        entry.color.y,
        entry.color.z,
        entry.diffuse,
        entry.reflectance,
        entry.transmittance,
    ]
}

/// Writes colour entries as an ASCII colour file like the manual's
/// examples: a `title` line, `data <count>`, one entry per line.
pub fn write_color_ascii(entries: &[ColorEntry], title: &str) -> String {
    let mut out = title_lines(title);
    out.push_str(&format!("data {}\n", entries.len()));
    for entry in entries {
        let [r, g, b, dif, refl, trn] = color_values(entry);
        out.push_str(&format!("{r} {g} {b} {dif} {refl} {trn}\n"));
    }
    out
}

// ---------------------------------------------------------------------------
// Binary files

/// Reads little-endian values from a binary file, failing cleanly (with the
/// byte offset) when the file is too short.
struct ByteReader<'a> {
    file: &'a Path,
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> ByteReader<'a> {
    fn new(bytes: &'a [u8], file: &'a Path) -> Self {
        ByteReader {
            file,
            bytes,
            pos: 0,
        }
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// An error about the data at byte `offset`.
    fn error(&self, offset: usize, message: impl std::fmt::Display) -> Error {
        Error::at(
            Location::file(self.file),
            format!("at byte offset {offset}: {message}"),
        )
    }

    /// Fails unless `len` more bytes (holding `what`) are present.
    fn need(&self, len: usize, what: &str) -> Result<()> {
        if self.remaining() < len {
            return Err(Error::at(
                Location::file(self.file),
                format!(
                    "truncated file: expected {what} ({len} bytes) at byte offset {}, \
                     but only {} bytes remain",
                    self.pos,
                    self.remaining()
                ),
            ));
        }
        Ok(())
    }

    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        self.need(N, what)?;
        let mut out = [0; N];
        out.copy_from_slice(&self.bytes[self.pos..self.pos + N]);
        self.pos += N;
        Ok(out)
    }

    fn u8(&mut self, what: &str) -> Result<u8> {
        Ok(self.take::<1>(what)?[0])
    }

    fn u16(&mut self, what: &str) -> Result<u16> {
        Ok(u16::from_le_bytes(self.take(what)?))
    }

    fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.take(what)?))
    }

    /// Checks the 3-byte file tag.
    fn tag(&mut self, tag: &[u8; 3]) -> Result<()> {
        let found = self.take::<3>(&format!("the tag `{}`", String::from_utf8_lossy(tag)))?;
        if &found != tag {
            return Err(self.error(
                0,
                format!(
                    "expected the tag `{}`, found `{}`",
                    String::from_utf8_lossy(tag),
                    String::from_utf8_lossy(&found).escape_debug()
                ),
            ));
        }
        Ok(())
    }

    /// Fails if bytes are left after `what`.
    fn expect_end(&self, what: &str) -> Result<()> {
        if self.remaining() > 0 {
            return Err(self.error(
                self.pos,
                format!("{} unexpected bytes after {what}", self.remaining()),
            ));
        }
        Ok(())
    }
}

/// Parses a binary geometry file: `DET`, `u16 num_vtx`, `u16 num_polys`, a
/// bounding box of 6 `f32` (ignored: it is recomputed by whoever needs it),
/// `num_vtx` x 3 `f32`, then per polygon `u16 nvtx` and `nvtx` 1-based `u16`
/// indices; all little-endian and packed. The returned indices are 0-based.
/// The manual's fields are C `short`s and [`write_det_binary`] writes at
/// most 32767; reading them unsigned still loads files of up to 65535
/// written before that limit.
///
/// Errors name the byte offset.
pub fn parse_det_binary(bytes: &[u8], file: &Path) -> Result<Mesh> {
    let mut reader = ByteReader::new(bytes, file);
    reader.tag(DET_TAG)?;
    let num_vtx = reader.u16("the number of vertices")?;
    let num_polys = reader.u16("the number of polygons")?;
    reader.take::<24>("the bounding box (6 floats)")?;
    let vertices = read_binary_vertices(&mut reader, num_vtx)?;
    let polygons = read_binary_polygons(&mut reader, num_polys, num_vtx)?;
    reader.expect_end("the last polygon")?;
    Ok(Mesh::new(vertices, polygons))
}

fn read_binary_vertices(reader: &mut ByteReader, count: u16) -> Result<Vec<DVec3>> {
    let count = usize::from(count);
    reader.need(count * 12, &format!("{count} vertices of 3 floats"))?;
    let mut vertices = Vec::with_capacity(count);
    for number in 1..=count {
        let offset = reader.pos;
        let mut xyz = [0.0; 3];
        for coordinate in &mut xyz {
            *coordinate = f64::from(reader.f32("a vertex coordinate")?);
        }
        if !xyz.iter().all(|c| c.is_finite()) {
            return Err(reader.error(offset, format!("non-finite number in vertex {number}")));
        }
        vertices.push(DVec3::from_array(xyz));
    }
    Ok(vertices)
}

fn read_binary_polygons(
    reader: &mut ByteReader,
    count: u16,
    num_vtx: u16,
) -> Result<Vec<Vec<u32>>> {
    // A polygon takes at least 8 bytes: its size and 3 indices.
    let mut polygons = Vec::with_capacity(usize::from(count).min(reader.remaining() / 8));
    for number in 1..=count {
        let offset = reader.pos;
        let size = usize::from(reader.u16(&format!("the vertex count of polygon {number}"))?);
        if size < 3 {
            return Err(reader.error(
                offset,
                format!("polygon {number} has {size} vertices; a polygon needs at least 3"),
            ));
        }
        reader.need(
            2 * size,
            &format!("the {size} vertex indices of polygon {number}"),
        )?;
        let mut polygon = Vec::with_capacity(size);
        for _ in 0..size {
            let offset = reader.pos;
            let index = reader.u16("a vertex index")?;
            if index == 0 || index > num_vtx {
                return Err(reader.error(
                    offset,
                    format!("vertex index {index} out of range 1..={num_vtx} in polygon {number}"),
                ));
            }
            polygon.push(u32::from(index) - 1);
        }
        polygons.push(polygon);
    }
    Ok(polygons)
}

/// A count as the C `short` field `field` of a binary file (see
/// [`BINARY_LIMIT`]), or an error naming the field, the value and the
/// limit.
fn binary_count(count: usize, what: &str, field: &str) -> Result<u16> {
    if count > BINARY_LIMIT {
        return Err(Error::Invalid(format!(
            "{count} {what}: the binary format stores this in the C short `{field}`, \
             which holds at most {BINARY_LIMIT}"
        )));
    }
    // count <= 32767: the same 16 bits as the short.
    Ok(count as u16)
}

/// Writes `mesh` as a binary geometry file (see [`parse_det_binary`]), with
/// its bounding box. Coordinates are stored as `f32`.
///
/// Fails if the mesh exceeds the binary format's limit of 32767 (a C
/// `short`) vertices, polygons or vertices per polygon, has an index out of range, or has a
/// coordinate that is not a finite `f32`.
pub fn write_det_binary(mesh: &Mesh) -> Result<Vec<u8>> {
    let num_vtx = binary_count(mesh.vertices.len(), "vertices", "num_vtx")?;
    let num_polys = binary_count(mesh.polygons.len(), "polygons", "num_polys")?;
    let coordinates = binary_coordinates(&mesh.vertices)?;
    let index_count: usize = mesh.polygons.iter().map(|p| p.len() + 1).sum();
    let mut out = Vec::with_capacity(7 + 24 + 4 * coordinates.len() + 2 * index_count);
    out.extend_from_slice(DET_TAG);
    out.extend_from_slice(&num_vtx.to_le_bytes());
    out.extend_from_slice(&num_polys.to_le_bytes());
    for value in bounding_box(&coordinates) {
        out.extend_from_slice(&value.to_le_bytes());
    }
    for value in &coordinates {
        out.extend_from_slice(&value.to_le_bytes());
    }
    for (number, polygon) in mesh.polygons.iter().enumerate() {
        let what = format!("vertices in polygon {}", number + 1);
        out.extend_from_slice(&binary_count(polygon.len(), &what, "nvtx")?.to_le_bytes());
        for &index in polygon {
            if index >= u32::from(num_vtx) {
                return Err(Error::Invalid(format!(
                    "vertex index {index} (0-based) out of range in polygon {}: \
                     the mesh has {num_vtx} vertices",
                    number + 1
                )));
            }
            // index < num_vtx <= 32767, so index + 1 fits the short `index`.
            out.extend_from_slice(&(index as u16 + 1).to_le_bytes());
        }
    }
    Ok(out)
}

/// The vertices as `f32` x, y, z triples, all finite.
fn binary_coordinates(vertices: &[DVec3]) -> Result<Vec<f32>> {
    let mut out = Vec::with_capacity(3 * vertices.len());
    for (number, v) in vertices.iter().enumerate() {
        for c in v.to_array() {
            let single = c as f32;
            if !single.is_finite() {
                return Err(Error::Invalid(format!(
                    "vertex {} has coordinate {c}, which is not a finite 32-bit float",
                    number + 1
                )));
            }
            out.push(single);
        }
    }
    Ok(out)
}

/// `xmin ymin zmin xmax ymax zmax` of packed x, y, z triples (zeros if none).
fn bounding_box(coordinates: &[f32]) -> [f32; 6] {
    if coordinates.is_empty() {
        return [0.0; 6];
    }
    let mut bbox = [
        f32::INFINITY,
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    ];
    for xyz in coordinates.chunks_exact(3) {
        for axis in 0..3 {
            bbox[axis] = bbox[axis].min(xyz[axis]);
            bbox[axis + 3] = bbox[axis + 3].max(xyz[axis]);
        }
    }
    bbox
}

/// Parses a binary colour file: the tag of `tag` (`PCL` or `VCL`), `u16
/// num_clr`, then per entry 6 bytes `r g b dif ref trn` scaled to 0..=255.
pub fn parse_color_binary(bytes: &[u8], file: &Path, tag: ColorKind) -> Result<Vec<ColorEntry>> {
    let mut reader = ByteReader::new(bytes, file);
    reader.tag(tag.tag())?;
    let count = usize::from(reader.u16("the number of colour entries")?);
    reader.need(6 * count, &format!("{count} colour entries of 6 bytes"))?;
    let mut entries = Vec::with_capacity(count);
    for _ in 0..count {
        let mut values = [0.0; 6];
        for value in &mut values {
            *value = f64::from(reader.u8("a colour value")?) / 255.0;
        }
        entries.push(color_entry(values));
    }
    reader.expect_end("the last colour entry")?;
    Ok(entries)
}

/// Writes colour entries as a binary colour file tagged for `tag` (see
/// [`parse_color_binary`]); each value is stored as `round(v * 255)`.
///
/// Fails if there are more than 32767 entries (a C `short`) or a value is
/// outside 0..=1.
pub fn write_color_binary(entries: &[ColorEntry], tag: ColorKind) -> Result<Vec<u8>> {
    let count = binary_count(entries.len(), "colour entries", "num_clr")?;
    let mut out = Vec::with_capacity(5 + 6 * entries.len());
    out.extend_from_slice(tag.tag());
    out.extend_from_slice(&count.to_le_bytes());
    for (number, entry) in entries.iter().enumerate() {
        for (value, name) in color_values(entry).into_iter().zip(COLOR_FIELDS) {
            if !(0.0..=1.0).contains(&value) {
                return Err(Error::Invalid(format!(
                    "{name} {value} out of range 0..=1 in colour entry {}",
                    number + 1
                )));
            }
            // 0 <= value * 255 <= 255, so the cast is exact after rounding.
            out.push((value * 255.0).round() as u8);
        }
    }
    Ok(out)
}

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

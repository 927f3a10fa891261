//! ASCII object files of the `mkdet`/`mkpcl`/`mkvcl` manual page (Garcia
//! 1986, appendix B): the scanner of their tokens, the geometry (`.det`)
//! and the polygon or vertex colour tables (`.pcl`, `.vcl`), read and
//! written.

use super::*;

// ---------------------------------------------------------------------------
// ASCII scanning

/// A token of an ASCII object file: a run of characters other than
/// whitespace and commas.
#[derive(Debug, Clone, Copy)]
pub(super) struct Token<'a> {
    pub(super) text: &'a str,
    /// Byte offset of the token in the file.
    pub(super) start: usize,
    /// 1-based line of the token.
    pub(super) line: usize,
    /// Byte offset where that line starts.
    pub(super) line_start: usize,
}

pub(super) fn is_separator(c: char) -> bool {
    c.is_whitespace() || c == ','
}

/// Reads the tokens that follow the `data` keyword, keeping track of lines so
/// that errors can name a line and column.
pub(super) struct Scanner<'a> {
    pub(super) file: &'a Path,
    pub(super) text: &'a str,
    /// Byte offset of the next unread character.
    pub(super) pos: usize,
    /// 1-based line at `pos`.
    pub(super) line: usize,
    /// Byte offset where the line at `pos` starts.
    pub(super) line_start: usize,
    /// Where the last token (or the `data` keyword) ended: offset, line, line start.
    pub(super) last_end: (usize, usize, usize),
}

impl<'a> Scanner<'a> {
    /// A scanner positioned just after the `data` keyword: the first token of
    /// a line, in any case. Lines before it (the `title` line) are free text.
    pub(super) fn after_data(text: &'a str, file: &'a Path) -> Result<Self> {
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
    pub(super) fn next(&mut self) -> Option<Token<'a>> {
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
    pub(super) fn char_at(&self, pos: usize) -> Option<(char, usize)> {
        let b = *self.text.as_bytes().get(pos)?;
        if b.is_ascii() {
            return Some((char::from(b), 1));
        }
        let c = self.text[pos..].chars().next()?;
        Some((c, c.len_utf8()))
    }

    /// The next token; at the end of the file an error saying `ended()`.
    #[inline(always)]
    pub(super) fn next_or(&mut self, ended: impl FnOnce() -> String) -> Result<Token<'a>> {
        match self.next() {
            Some(token) => Ok(token),
            None => Err(self.error_at_end(ended())),
        }
    }

    /// At most `count` items of `tokens` tokens each: what the unread text
    /// could hold (each token takes at least one character and a separator).
    pub(super) fn capacity(&self, count: u64, tokens: usize) -> usize {
        let room = (self.text.len() - self.pos) / (2 * tokens) + 1;
        usize::try_from(count).unwrap_or(usize::MAX).min(room)
    }

    pub(super) fn diagnostic(
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
    pub(super) fn error(&self, token: &Token, message: impl Into<String>) -> Error {
        let width = token.text.chars().count();
        let mut d = self.diagnostic(token.start, token.line, token.line_start, width);
        d.message = message.into();
        d.into()
    }

    /// An error pointing just after the last token read.
    pub(super) fn error_at_end(&self, message: impl Into<String>) -> Error {
        let (offset, line, line_start) = self.last_end;
        let mut d = self.diagnostic(offset, line, line_start, 1);
        d.message = message.into();
        d.into()
    }

    /// Fails with `message` if anything but whitespace (or commas) is left.
    pub(super) fn expect_end(&mut self, message: &str) -> Result<()> {
        match self.next() {
            Some(token) => Err(self.error(&token, message)),
            None => Ok(()),
        }
    }

    /// A count: a non-negative integer.
    pub(super) fn count(&mut self, what: &str) -> Result<u64> {
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
    pub(super) fn number(&self, token: &Token, what: &str) -> Result<f64> {
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

pub(super) fn read_vertices(scanner: &mut Scanner, count: u64) -> Result<Vec<DVec3>> {
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
pub(super) fn read_polygons(
    scanner: &mut Scanner,
    count: u64,
    num_vtx: u64,
) -> Result<Vec<IndexList>> {
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
pub(super) fn vertex_index(
    scanner: &Scanner,
    token: &Token,
    polygon: u64,
    num_vtx: u64,
) -> Result<u32> {
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
pub(super) fn title_lines(title: &str) -> String {
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
pub(super) fn color_value(
    scanner: &mut Scanner,
    name: &str,
    number: u64,
    count: u64,
) -> Result<f64> {
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

pub(super) fn color_entry(v: [f64; 6]) -> ColorEntry {
    ColorEntry {
        color: DVec3::new(v[0], v[1], v[2]),
        diffuse: v[3],
        reflectance: v[4],
        transmittance: v[5],
    }
}

pub(super) fn color_values(entry: &ColorEntry) -> [f64; 6] {
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

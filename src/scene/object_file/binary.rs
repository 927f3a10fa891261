//! Binary object files of the `mkdet`/`mkpcl`/`mkvcl` manual page (Garcia
//! 1986, appendix B): `DET` geometry and `PCL`/`VCL` colour tables, their
//! counts the manual's C `short`s (at most 32767, refused above).

use super::*;

// ---------------------------------------------------------------------------
// Binary files

/// Reads little-endian values from a binary file, failing cleanly (with the
/// byte offset) when the file is too short.
pub(super) struct ByteReader<'a> {
    pub(super) file: &'a Path,
    pub(super) bytes: &'a [u8],
    pub(super) pos: usize,
}

impl<'a> ByteReader<'a> {
    pub(super) fn new(bytes: &'a [u8], file: &'a Path) -> Self {
        ByteReader {
            file,
            bytes,
            pos: 0,
        }
    }

    pub(super) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// An error about the data at byte `offset`.
    pub(super) fn error(&self, offset: usize, message: impl std::fmt::Display) -> Error {
        Error::at(
            Location::file(self.file),
            format!("at byte offset {offset}: {message}"),
        )
    }

    /// Fails unless `len` more bytes (holding `what`) are present.
    pub(super) fn need(&self, len: usize, what: &str) -> Result<()> {
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

    pub(super) fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        self.need(N, what)?;
        let mut out = [0; N];
        out.copy_from_slice(&self.bytes[self.pos..self.pos + N]);
        self.pos += N;
        Ok(out)
    }

    pub(super) fn u8(&mut self, what: &str) -> Result<u8> {
        Ok(self.take::<1>(what)?[0])
    }

    pub(super) fn u16(&mut self, what: &str) -> Result<u16> {
        Ok(u16::from_le_bytes(self.take(what)?))
    }

    pub(super) fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.take(what)?))
    }

    /// Checks the 3-byte file tag.
    pub(super) fn tag(&mut self, tag: &[u8; 3]) -> Result<()> {
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
    pub(super) fn expect_end(&self, what: &str) -> Result<()> {
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

pub(super) fn read_binary_vertices(reader: &mut ByteReader, count: u16) -> Result<Vec<DVec3>> {
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

pub(super) fn read_binary_polygons(
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
pub(super) fn binary_count(count: usize, what: &str, field: &str) -> Result<u16> {
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
pub(super) fn binary_coordinates(vertices: &[DVec3]) -> Result<Vec<f32>> {
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
pub(super) fn bounding_box(coordinates: &[f32]) -> [f32; 6] {
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

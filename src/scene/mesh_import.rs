//! Wavefront OBJ, PLY and STL meshes as object geometry, read into the same
//! [`Mesh`] as a `.det` file (Garcia 1986, 004 appendix, `mkdet`).
//!
//! These formats list a face's vertices counter-clockwise seen from outside;
//! a [`Mesh`] lists them clockwise, as `.det` files do, so every polygon's
//! index order is reversed on import. Polygons are kept as given (no
//! triangulation); OBJ points and lines are not surfaces and are skipped.
//!
//! PLY and STL vertices keep the file's order (STL shares equal corners).
//! OBJ vertices are numbered by tobj in the order of their first use in each
//! object, and unused ones are dropped: a vertex colour table for an OBJ
//! mesh must follow that order.

use std::io::Cursor;
use std::path::Path;

use glam::DVec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{BeginList, Property, PropertyAccess, PropertyAccessResult};

use crate::error::{Error, Location, Result};
use crate::model::{IndexList, Mesh};

/// File extensions [`read_mesh`] understands, lower case.
pub const MESH_EXTENSIONS: &[&str] = &["obj", "ply", "stl"];

/// Reads a Wavefront OBJ, PLY (ASCII or binary) or STL (ASCII or binary)
/// mesh, chosen by the file's extension in any case. All OBJ objects and
/// groups are merged into one mesh. Polygons come out clockwise seen from
/// outside, with 0-based indices.
///
/// At most the default `--max-polygons` polygons and
/// [`VERTICES_PER_POLYGON`] times as many vertices: see
/// [`read_mesh_within`], which takes the budget.
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    read_mesh_within(path, crate::budget::Budgets::default().polygons)
}

/// Vertices a mesh may have per polygon of the budget (a closed triangle
/// mesh has about half a vertex per face; an OBJ may list vertices only).
pub const VERTICES_PER_POLYGON: usize = 4;

/// [`read_mesh`] with at most `max_polygons` polygons (and
/// [`VERTICES_PER_POLYGON`] times as many vertices). The counts are
/// checked before the mesh is parsed: from the header where there is one
/// (PLY's `element face N`, binary STL's triangle count), else by a
/// streaming count of the OBJ or ASCII STL lines that stops as soon as
/// it passes the budget, so a huge file is neither read whole nor held.
pub fn read_mesh_within(path: &Path, max_polygons: usize) -> Result<Mesh> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        precount(path, &extension, max_polygons)?;
    }
    let bytes = super::object_file::read_regular(path, super::object_file::MAX_INPUT_BYTES)?;
    let mesh = match extension.as_str() {
        "obj" => read_obj(&bytes, path)?,
        "ply" => read_ply(&bytes, path)?,
        "stl" => read_stl(&bytes, path)?,
        _ => {
            return Err(Error::at(
                Location::file(path),
                format!(
                    "unknown mesh format `.{extension}`: expected one of {}",
                    MESH_EXTENSIONS.join(", ")
                ),
            ));
        }
    };
    check_mesh(&mesh, path)?;
    Ok(mesh)
}

/// An error about `path` as a whole, from one of the mesh crates.
fn format_error(path: &Path, format: &str, message: impl std::fmt::Display) -> Error {
    Error::at(
        Location::file(path),
        format!(
            "cannot read {format}: {}",
            crate::error::printable(&message.to_string(), 200)
        ),
    )
}

/// Checks what the crates do not: finite coordinates, indices in range and
/// at least 3 vertices per polygon.
fn check_mesh(mesh: &Mesh, path: &Path) -> Result<()> {
    if let Some(i) = mesh.vertices.iter().position(|v| !v.is_finite()) {
        return Err(Error::at(
            Location::file(path),
            format!("non-finite number in vertex {}", i + 1),
        ));
    }
    let count = mesh.vertices.len();
    for (number, polygon) in mesh.polygons.iter().enumerate() {
        if polygon.len() < 3 {
            return Err(Error::at(
                Location::file(path),
                format!(
                    "polygon {} has {} vertices; a polygon needs at least 3",
                    number + 1,
                    polygon.len()
                ),
            ));
        }
        if let Some(&index) = polygon.iter().find(|&&i| i as usize >= count) {
            return Err(Error::at(
                Location::file(path),
                format!(
                    "vertex index {index} (0-based) out of range in polygon {}: \
                     the mesh has {count} vertices",
                    number + 1
                ),
            ));
        }
    }
    Ok(())
}

/// A counter-clockwise face turned into a clockwise polygon.
fn clockwise(mut face: Vec<u32>) -> Vec<u32> {
    face.reverse();
    face
}

// ---------------------------------------------------------------------------
// Counting before reading

/// Refuses a mesh file whose faces pass `max_polygons` (or vertices
/// [`VERTICES_PER_POLYGON`] times that), reading no more of it than
/// needed to know.
fn precount(path: &Path, extension: &str, max_polygons: usize) -> Result<()> {
    use std::io::Read;
    let max_vertices = max_polygons.saturating_mul(VERTICES_PER_POLYGON);
    let io = |e: std::io::Error| Error::at(Location::file(path), format!("cannot read: {e}"));
    let mut file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    let check = |faces: u64, vertices: u64, exact: bool| -> Result<()> {
        let more = if exact { "" } else { "more than " };
        if faces > max_polygons as u64 {
            return Err(Error::at(
                Location::file(path),
                crate::budget::Budgets::exceeded(
                    &format!("{more}{faces} faces"),
                    format!("{max_polygons} polygons"),
                    "--max-polygons",
                ),
            ));
        }
        if vertices > max_vertices as u64 {
            return Err(Error::at(
                Location::file(path),
                crate::budget::Budgets::exceeded(
                    &format!("{more}{vertices} vertices"),
                    format!(
                        "{max_vertices} vertices ({VERTICES_PER_POLYGON} a polygon of the \
                         polygon budget)"
                    ),
                    "--max-polygons",
                ),
            ));
        }
        Ok(())
    };
    match extension {
        "ply" => {
            // The header: text lines up to `end_header`, at most 64 KiB.
            let mut head = Vec::new();
            file.by_ref()
                .take(64 << 10)
                .read_to_end(&mut head)
                .map_err(io)?;
            let text = String::from_utf8_lossy(&head);
            let (mut faces, mut vertices) = (0u64, 0u64);
            for line in text.lines() {
                let words: Vec<&str> = line.split_whitespace().collect();
                if words.first() == Some(&"end_header") {
                    break;
                }
                if let ["element", name, n] = words.as_slice() {
                    let n: u64 = n.parse().unwrap_or(0);
                    match *name {
                        "face" => faces = n,
                        "vertex" => vertices = n,
                        _ => {}
                    }
                }
            }
            check(faces, vertices, true)
        }
        "stl" => {
            let mut head = [0u8; 84];
            let got = file.by_ref().take(84).read(&mut head).map_err(io)?;
            if got == 84 {
                let count = u64::from(u32::from_le_bytes([head[80], head[81], head[82], head[83]]));
                if count.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(len) {
                    // Binary: the count is the header's.
                    return check(count, 0, true);
                }
            }
            let mut file = std::fs::File::open(path).map_err(io)?;
            count_lines(
                &mut file,
                |p| starts_with_word(p, b"facet"),
                |p| starts_with_word(p, b"vertex"),
                &check,
            )
        }
        "obj" => count_lines(
            &mut file,
            |p| starts_with_word(p, b"f"),
            |p| starts_with_word(p, b"v"),
            &check,
        ),
        _ => Ok(()),
    }
}

/// Whether `prefix` (a line's start, leading blanks skipped) is `word`
/// followed by a blank or the end, in any case.
fn starts_with_word(prefix: &[u8], word: &[u8]) -> bool {
    prefix.len() > word.len()
        && prefix[..word.len()].eq_ignore_ascii_case(word)
        && matches!(prefix[word.len()], b' ' | b'\t')
}

/// Counts the lines of `file` that `face` and `vertex` accept (given the
/// first bytes of each line), in blocks, calling `check` with the counts
/// (not exact) after each block and exact at the end: it stops reading at
/// the first refusal. Memory: one block and one line start.
fn count_lines(
    file: &mut std::fs::File,
    face: impl Fn(&[u8]) -> bool,
    vertex: impl Fn(&[u8]) -> bool,
    check: &dyn Fn(u64, u64, bool) -> Result<()>,
) -> Result<()> {
    use std::io::Read;
    let mut block = vec![0u8; 1 << 16];
    let (mut faces, mut vertices) = (0u64, 0u64);
    let mut prefix = [0u8; 8];
    let mut plen = 0;
    let mut line_bytes = 0u64;
    let end_line = |prefix: &[u8], faces: &mut u64, vertices: &mut u64| {
        let p = [prefix, b"\n"].concat();
        if face(&p) {
            *faces += 1;
        } else if vertex(&p) {
            *vertices += 1;
        }
    };
    loop {
        let n = match file.read(&mut block) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(Error::Invalid(format!("cannot read a mesh: {e}"))),
        };
        for &b in &block[..n] {
            if b == b'\n' {
                end_line(&prefix[..plen], &mut faces, &mut vertices);
                plen = 0;
                line_bytes = 0;
            } else {
                if plen == 0 && line_bytes == 0 && matches!(b, b' ' | b'\t') {
                    continue;
                }
                line_bytes += 1;
                if plen < prefix.len() {
                    prefix[plen] = b;
                    plen += 1;
                }
            }
        }
        check(faces, vertices, false)?;
    }
    end_line(&prefix[..plen], &mut faces, &mut vertices);
    check(faces, vertices, true)
}

// ---------------------------------------------------------------------------
// Wavefront OBJ

fn read_obj(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials do not matter for geometry: referenced .mtl files are not read.
    let no_materials = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(bytes), &options, no_materials)
        .map_err(|e| format_error(path, "Wavefront OBJ", e))?;
    let mut mesh = Mesh::default();
    for model in &models {
        append_obj_mesh(&mut mesh, &model.mesh, path)?;
    }
    Ok(mesh)
}

/// Appends one OBJ model, whose indices refer to its own positions.
fn append_obj_mesh(mesh: &mut Mesh, model: &tobj::Mesh, path: &Path) -> Result<()> {
    let offset = u32::try_from(mesh.vertices.len())
        .map_err(|_| format_error(path, "Wavefront OBJ", "too many vertices"))?;
    mesh.vertices.extend(
        model
            .positions
            .chunks_exact(3)
            .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))),
    );
    // An empty list of arities means that every face is a triangle.
    let triangles = vec![3; model.indices.len() / 3];
    let arities = if model.face_arities.is_empty() {
        &triangles
    } else {
        &model.face_arities
    };
    let mut rest = model.indices.as_slice();
    for &arity in arities {
        let (face, tail) = rest.split_at_checked(arity as usize).ok_or_else(|| {
            format_error(path, "Wavefront OBJ", "face sizes do not match the indices")
        })?;
        mesh.polygons
            .push(clockwise(face.iter().map(|&i| i + offset).collect()).into());
        rest = tail;
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// PLY

/// A PLY file's `vertex` and `face` elements; other elements are read past.
/// Each element is read into a small typed record ([`PlyVertex`],
/// [`PlyFace`]), not the parser's map of named properties, which took
/// about 400 bytes a face.
fn read_ply(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let error = |e: ply_rs_bw::parser::ParseError| match e.line() {
        Some(line) => Error::at(
            Location::new(path, line, 0),
            format!("cannot read PLY: {e}"),
        ),
        None => format_error(path, "PLY", e),
    };
    let mut reader = Reader::new(Cursor::new(bytes));
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(error)?;
    let (mut vertices, mut faces) = (Vec::new(), Vec::new());
    for (name, element) in &header.elements {
        match name.as_str() {
            "vertex" => {
                vertices = Parser::<PlyVertex>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(error)?;
            }
            "face" => {
                faces = Parser::<PlyFace>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(error)?;
            }
            _ => {
                Parser::<Skip>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(error)?;
            }
        }
    }
    // (Collected in place into the records' larger allocations: shrunk,
    // since the mesh is kept for the scene's lifetime.)
    let mut vertices: Vec<DVec3> = vertices
        .into_iter()
        .enumerate()
        .map(|(i, v)| v.point(i + 1, path))
        .collect::<Result<_>>()?;
    let mut polygons: Vec<IndexList> = faces
        .into_iter()
        .enumerate()
        .map(|(i, f)| f.polygon(i + 1, path).map(IndexList::from))
        .collect::<Result<_>>()?;
    vertices.shrink_to_fit();
    polygons.shrink_to_fit();
    Ok(Mesh::new(vertices, polygons))
}

/// An element read past.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// A PLY vertex as read: `x`, `y`, `z`, and the first of them given as
/// another type than float or double.
#[derive(Default)]
struct PlyVertex {
    xyz: [Option<f64>; 3],
    wrong: Option<&'static str>,
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let Some(axis) = ["x", "y", "z"].iter().position(|a| *a == name) else {
            return PropertyAccessResult::Ignored;
        };
        match property {
            Property::Float(v) => self.xyz[axis] = Some(f64::from(v)),
            Property::Double(v) => self.xyz[axis] = Some(v),
            _ => {
                self.wrong.get_or_insert(["x", "y", "z"][axis]);
            }
        }
        PropertyAccessResult::Set
    }
}

impl PlyVertex {
    /// The point of vertex `number`.
    fn point(self, number: usize, path: &Path) -> Result<DVec3> {
        if let Some(name) = self.wrong {
            return Err(format_error(
                path,
                "PLY",
                format!("vertex {number}: property `{name}` must be a float or double"),
            ));
        }
        let mut xyz = [0.0; 3];
        for ((value, read), name) in xyz.iter_mut().zip(self.xyz).zip(["x", "y", "z"]) {
            *value = read.ok_or_else(|| {
                format_error(
                    path,
                    "PLY",
                    format!("vertex {number} has no property `{name}`"),
                )
            })?;
        }
        Ok(DVec3::from_array(xyz))
    }
}

/// A PLY face as read: its `vertex_indices` (or `vertex_index`) list.
/// Lists of `uint` and `int`, the common types, are filled in place.
#[derive(Default)]
struct PlyFace {
    indices: Vec<u32>,
    signed: Vec<i32>,
    /// Which list was read: none yet, unsigned, signed, or one of
    /// another type that is not a list of non-negative integers.
    read: FaceList,
}

#[derive(Default, Clone, Copy, PartialEq)]
enum FaceList {
    #[default]
    Missing,
    Unsigned,
    Signed,
    Invalid,
}

/// Whether `name` is the face's index list (`vertex_index` only when
/// there was no `vertex_indices` before it).
fn index_list(name: &str, read: FaceList) -> bool {
    name == "vertex_indices" || (name == "vertex_index" && read == FaceList::Missing)
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace::default()
    }

    fn begin_list_uint(&mut self, name: &str, _len: usize) -> BeginList<'_, u32> {
        if !index_list(name, self.read) {
            return BeginList::UseSetter;
        }
        self.read = FaceList::Unsigned;
        BeginList::Fill(&mut self.indices)
    }

    fn begin_list_int(&mut self, name: &str, _len: usize) -> BeginList<'_, i32> {
        if !index_list(name, self.read) {
            return BeginList::UseSetter;
        }
        self.read = FaceList::Signed;
        BeginList::Fill(&mut self.signed)
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if !index_list(name, self.read) {
            return PropertyAccessResult::Ignored;
        }
        match property.to_u32_list() {
            Some(list) => {
                self.indices = list;
                self.read = FaceList::Unsigned;
            }
            None => self.read = FaceList::Invalid,
        }
        PropertyAccessResult::Set
    }
}

impl PlyFace {
    /// The clockwise polygon of face `number`.
    fn polygon(self, number: usize, path: &Path) -> Result<Vec<u32>> {
        let indices = match self.read {
            FaceList::Unsigned => Some(self.indices),
            FaceList::Signed => self
                .signed
                .into_iter()
                .map(|i| u32::try_from(i).ok())
                .collect(),
            FaceList::Invalid => None,
            FaceList::Missing => {
                return Err(format_error(
                    path,
                    "PLY",
                    format!("face {number} has no list property `vertex_indices`"),
                ));
            }
        };
        let indices = indices.ok_or_else(|| {
            format_error(
                path,
                "PLY",
                format!(
                    "face {number}: the vertex indices must be a list of non-negative integers"
                ),
            )
        })?;
        Ok(clockwise(indices))
    }
}

// ---------------------------------------------------------------------------
// STL

fn read_stl(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let stl =
        stl_io::read_stl(&mut Cursor::new(bytes)).map_err(|e| format_error(path, "STL", e))?;
    let vertices = stl
        .vertices
        .iter()
        .map(|v| DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])))
        .collect();
    let polygons: Vec<IndexList> = stl
        .faces
        .iter()
        .map(|face| {
            let indices = face.vertices.iter().map(|&i| u32::try_from(i));
            indices
                .collect::<std::result::Result<Vec<u32>, _>>()
                .map(|face| IndexList::from(clockwise(face)))
                .map_err(|_| format_error(path, "STL", "too many vertices"))
        })
        .collect::<Result<_>>()?;
    Ok(Mesh::new(vertices, polygons))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ply(body: &str) -> Result<Mesh> {
        read_ply(body.as_bytes(), Path::new("m.ply"))
    }

    const HEAD: &str = "ply\nformat ascii 1.0\n";

    #[test]
    fn ply_elements_of_every_index_type_and_others_read_past() {
        let text = format!(
            "{HEAD}element vertex 3\nproperty float x\nproperty double y\nproperty float z\n\
             property uchar red\nelement edge 1\nproperty list uchar int vertex1\n\
             element face 3\nproperty uchar flags\nproperty list uchar uint vertex_indices\n\
             end_header\n0 0 0 9\n1 0 0 9\n0 1.5 0 9\n2 0 1\n7 3 0 1 2\n7 3 2 1 0\n7 3 0 2 1\n"
        );
        let mesh = ply(&text).unwrap();
        assert_eq!(mesh.vertices[2], DVec3::new(0.0, 1.5, 0.0));
        assert_eq!(
            mesh.polygons,
            vec![vec![2, 1, 0], vec![0, 1, 2], vec![1, 2, 0]]
        );
        for (list, name) in [
            ("int", "vertex_indices"),
            ("short", "vertex_index"),
            ("uchar", "vertex_index"),
        ] {
            let text = format!(
                "{HEAD}element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 element face 1\nproperty list uchar {list} {name}\nend_header\n\
                 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
            );
            assert_eq!(
                ply(&text).unwrap().polygons,
                vec![vec![2, 1, 0]],
                "{list} {name}"
            );
        }
    }

    #[test]
    fn bad_ply_elements_are_named() {
        let vertex = |props: &str, rows: &str| {
            format!(
                "{HEAD}element vertex 2\n{props}element face 0\nproperty list uchar int vertex_indices\nend_header\n{rows}"
            )
        };
        let face = |list: &str, row: &str| {
            format!(
                "{HEAD}element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 element face 2\nproperty list uchar {list}\nend_header\n0 0 0\n1 0 0\n0 1 0\n\
                 3 0 1 2\n{row}\n"
            )
        };
        for (text, says) in [
            (
                vertex("property float x\nproperty float y\n", "0 0\n1 1\n"),
                "vertex 1 has no property `z`",
            ),
            (
                vertex(
                    "property int x\nproperty float y\nproperty float z\n",
                    "0 0 0\n1 1 1\n",
                ),
                "vertex 1: property `x` must be a float or double",
            ),
            (
                face("int vertex_indices", "3 0 -1 2"),
                "face 2: the vertex indices must be a list of non-negative integers",
            ),
            (
                face("float vertex_indices", "3 0 1 2"),
                "face 1: the vertex indices must be a list of non-negative integers",
            ),
            (
                face("int corners", "3 0 1 2"),
                "face 1 has no list property `vertex_indices`",
            ),
        ] {
            let e = ply(&text).unwrap_err().to_string();
            assert!(e.contains(says), "{e}\nshould say {says}");
        }
    }

    #[test]
    fn binary_ply_reads_as_its_ascii_twin() {
        let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
            property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n\
            end_header\n"
            .to_vec();
        for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.25]] {
            for c in v {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        bytes.push(3);
        for i in [0i32, 1, 2] {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
        let mesh = read_ply(&bytes, Path::new("m.ply")).unwrap();
        assert_eq!(mesh.vertices[2], DVec3::new(0.0, 1.0, 0.25));
        assert_eq!(mesh.polygons, vec![vec![2, 1, 0]]);
    }

    #[test]
    fn clockwise_reverses_the_order() {
        assert_eq!(clockwise(vec![0, 1, 2, 3]), vec![3, 2, 1, 0]);
    }

    #[test]
    fn obj_objects_are_merged_with_offsets() {
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
            o a\nf 1 2 3\no b\nf 1 3 4 2\np 1\nl 1 2\n";
        let mesh = read_obj(text, Path::new("m.obj")).unwrap();
        assert_eq!(mesh.vertices.len(), 7);
        assert_eq!(mesh.polygons, vec![vec![2, 1, 0], vec![6, 5, 4, 3]]);
        assert_eq!(mesh.vertices[5], DVec3::Z);
        assert_eq!(mesh.vertices[6], DVec3::X);
    }

    #[test]
    fn obj_triangles_only_have_no_arities() {
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
        let mesh = read_obj(text, Path::new("m.obj")).unwrap();
        assert_eq!(mesh.polygons, vec![vec![2, 1, 0], vec![2, 3, 1]]);
    }

    #[test]
    fn check_mesh_refuses_what_the_crates_allow() {
        let path = Path::new("m.stl");
        let mut mesh = Mesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            polygons: vec![vec![0, 1, 2].into()],
        };
        assert!(check_mesh(&mesh, path).is_ok());
        mesh.polygons[0][2] = 3;
        let err = check_mesh(&mesh, path).unwrap_err();
        assert!(err.to_string().contains("vertex index 3"), "{err}");
        mesh.polygons[0] = vec![0, 1].into();
        assert!(check_mesh(&mesh, path).is_err());
        mesh.polygons.clear();
        mesh.vertices[1].y = f64::INFINITY;
        let err = check_mesh(&mesh, path).unwrap_err();
        assert_eq!(err.to_string(), "m.stl: non-finite number in vertex 2");
    }

    #[test]
    fn binary_stl_is_read() {
        let triangle = stl_io::Triangle {
            normal: stl_io::Normal::new([0.0, 0.0, 1.0]),
            vertices: [
                stl_io::Vertex::new([0.0, 0.0, 0.0]),
                stl_io::Vertex::new([1.0, 0.0, 0.0]),
                stl_io::Vertex::new([0.0, 1.0, 0.0]),
            ],
        };
        let mut bytes = Vec::new();
        stl_io::write_stl(&mut bytes, [triangle].iter()).unwrap();
        let mesh = read_stl(&bytes, Path::new("t.stl")).unwrap();
        assert_eq!(mesh.vertices[1], DVec3::X);
        assert_eq!(mesh.polygons, vec![vec![2, 1, 0]]);
    }
}

//! Object files of the `mkdet`/`mkpcl`/`mkvcl` manual page (Garcia 1986,
//! 004 appendix) and imported OBJ/PLY/STL meshes, through the public API.

use std::fs;
use std::path::{Path, PathBuf};

use glam::DVec3;
use plytrace::Error;
use plytrace::internal::model::{ColorEntry, Mesh};
use plytrace::internal::scene::mesh_import::*;
use plytrace::internal::scene::object_file::*;
use proptest::prelude::*;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/objects")
        .join(name)
}

/// A geometry file of the shared benchmark scenes, if they are present.
fn shared_det(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/scenes/det")
        .join(name);
    assert!(path.exists(), "missing fixture {}", path.display());
    path
}

/// (line, column, message) of an input error.
fn place(error: Error) -> (usize, usize, String) {
    let d = error.diagnostic().expect("an input error");
    (d.location.line, d.location.column, d.message.clone())
}

fn message(error: Error) -> String {
    place(error).2
}

fn det(text: &str) -> Result<Mesh, Error> {
    parse_det_ascii(text, Path::new("test.det"))
}

fn colors(text: &str) -> Result<Vec<ColorEntry>, Error> {
    parse_color_ascii(text, Path::new("test.pcl"))
}

fn entry(values: [f64; 6]) -> ColorEntry {
    ColorEntry {
        color: DVec3::new(values[0], values[1], values[2]),
        diffuse: values[3],
        reflectance: values[4],
        transmittance: values[5],
    }
}

// ---------------------------------------------------------------------------
// Orientation

/// Newell's normal of a polygon: by the right-hand rule, it points towards
/// a viewer who sees the vertices counter-clockwise.
fn newell(mesh: &Mesh, polygon: &[u32]) -> DVec3 {
    let mut normal = DVec3::ZERO;
    for (i, &a) in polygon.iter().enumerate() {
        let p = mesh.vertices[a as usize];
        let q = mesh.vertices[polygon[(i + 1) % polygon.len()] as usize];
        normal += DVec3::new(
            (p.y - q.y) * (p.z + q.z),
            (p.z - q.z) * (p.x + q.x),
            (p.x - q.x) * (p.y + q.y),
        );
    }
    normal
}

fn centroid(points: impl ExactSizeIterator<Item = DVec3>) -> DVec3 {
    let n = points.len() as f64;
    points.sum::<DVec3>() / n
}

/// Every polygon of a convex closed mesh is clockwise seen from outside:
/// its Newell normal points inward and that of the reversed order outward.
fn assert_clockwise_from_outside(mesh: &Mesh) {
    let centre = centroid(mesh.vertices.iter().copied());
    for polygon in &mesh.polygons {
        let middle = centroid(polygon.iter().map(|&i| mesh.vertices[i as usize]));
        let outward = middle - centre;
        let reversed: Vec<u32> = polygon.iter().rev().copied().collect();
        assert!(
            newell(mesh, polygon).dot(outward) < 0.0,
            "polygon {polygon:?} is not clockwise from outside"
        );
        assert!(newell(mesh, &reversed).dot(outward) > 0.0);
    }
}

#[test]
fn orientation_helper_tells_the_two_orders_apart() {
    let mut mesh = read_mesh(&fixture("cube.obj")).unwrap();
    assert_clockwise_from_outside(&mesh);
    mesh.polygons[2].reverse();
    let result = std::panic::catch_unwind(|| assert_clockwise_from_outside(&mesh));
    assert!(result.is_err());
}

// ---------------------------------------------------------------------------
// The manual's examples and the shared scenes

#[test]
fn manual_square_parses() {
    let mesh = read_det(&fixture("square.det")).unwrap();
    assert_eq!(
        mesh.vertices,
        vec![
            DVec3::ZERO,
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
        ]
    );
    assert_eq!(mesh.polygons, vec![vec![0, 1, 2, 3]]);
}

#[test]
fn manual_colour_files_parse() {
    let pcl = read_colors(&fixture("square.pcl"), ColorKind::Polygon).unwrap();
    assert_eq!(pcl, vec![entry([0.9, 0.8, 0.2, 0.0, 0.0, 0.0])]);
    let vcl = read_colors(&fixture("square.vcl"), ColorKind::Vertex).unwrap();
    assert_eq!(vcl.len(), 4);
    assert_eq!(vcl[2], entry([0.2, 0.8, 0.9, 0.0, 0.0, 0.0]));
    assert_eq!(vcl[3].color, DVec3::new(0.9, 0.2, 0.8));
}

/// The shared scenes' `cube.det`, for tests that must run without them.
const CUBE_DET: &str = "\
title    cube with corners at (+-1, +-1, +-1); polygons clockwise seen from outside
data
8 6
-1. -1. -1.
 1. -1. -1.
 1.  1. -1.
-1.  1. -1.
-1. -1.  1.
 1. -1.  1.
 1.  1.  1.
-1.  1.  1.
4 5 8 7 6
4 1 2 3 4
4 1 5 6 2
4 4 3 7 8
4 2 6 7 3
4 1 4 8 5
";

#[test]
fn cube_parses_clockwise_from_outside() {
    let mesh = det(CUBE_DET).unwrap();
    assert_eq!((mesh.vertices.len(), mesh.polygons.len()), (8, 6));
    assert_eq!(mesh.vertices[0], DVec3::splat(-1.0));
    assert_eq!(mesh.vertices[6], DVec3::splat(1.0));
    assert_eq!(mesh.polygons[0], vec![4, 7, 6, 5]);
    assert_eq!(mesh.polygons[5], vec![0, 3, 7, 4]);
    assert_clockwise_from_outside(&mesh);
}

#[test]
fn shared_cube_parses_clockwise_from_outside() {
    let path = shared_det("cube.det");
    let mesh = read_det(&path).unwrap();
    assert_eq!(mesh, det(CUBE_DET).unwrap());
    assert_clockwise_from_outside(&mesh);
}

#[test]
fn every_shared_det_file_parses_and_converts() {
    let dir = shared_det("");
    let mut count = 0;
    for item in fs::read_dir(dir).unwrap() {
        let path = item.unwrap().path();
        if path.extension().is_none_or(|e| e != "det") {
            continue;
        }
        let mesh = read_det(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!mesh.polygons.is_empty(), "{}", path.display());
        let back = parse_det_binary(&write_det_binary(&mesh).unwrap(), &path).unwrap();
        assert_eq!(back.polygons, mesh.polygons);
        for (a, b) in back.vertices.iter().zip(&mesh.vertices) {
            assert!((*a - *b).abs().max_element() < 1e-6);
        }
        count += 1;
    }
    assert!(count > 0);
}

// ---------------------------------------------------------------------------
// Round trips

#[test]
fn ascii_det_to_binary_and_back() {
    let mesh = read_det(&fixture("square.det")).unwrap();
    let bytes = write_det_binary(&mesh).unwrap();
    assert_eq!(&bytes[..7], b"DET\x04\x00\x01\x00");
    // tag, counts, bounding box, 4 vertices, 1 polygon of 4
    assert_eq!(bytes.len(), 7 + 24 + 4 * 12 + 2 * 5);
    assert_eq!(parse_det_binary(&bytes, Path::new("b")).unwrap(), mesh);
}

#[test]
fn ascii_colours_to_binary_and_back() {
    for (name, kind) in [
        ("square.pcl", ColorKind::Polygon),
        ("square.vcl", ColorKind::Vertex),
    ] {
        let entries = read_colors(&fixture(name), kind).unwrap();
        let bytes = write_color_binary(&entries, kind).unwrap();
        assert_eq!(&bytes[..3], kind.tag());
        assert_eq!(bytes.len(), 5 + 6 * entries.len());
        let back = parse_color_binary(&bytes, Path::new("b"), kind).unwrap();
        assert_eq!(back.len(), entries.len());
        for (a, b) in back.iter().zip(&entries) {
            assert!((a.color - b.color).abs().max_element() <= 0.5 / 255.0);
            assert!((a.diffuse - b.diffuse).abs() <= 0.5 / 255.0);
        }
        // Values that are multiples of 1/255 survive exactly.
        assert_eq!(write_color_binary(&back, kind).unwrap(), bytes);
    }
}

#[test]
fn ascii_write_then_parse() {
    let mesh = read_det(&fixture("cube.obj").with_file_name("square.det")).unwrap();
    let text = write_det_ascii(&mesh, "a square\nwith data in its title");
    assert!(text.starts_with("title    a square with data in its title\ndata\n4 1\n"));
    assert_eq!(det(&text).unwrap(), mesh);

    let entries = vec![entry([0.1, 0.2, 0.3, 1.0, 0.0, 1.0 / 3.0]), entry([0.0; 6])];
    let text = write_color_ascii(&entries, "two colours");
    assert!(text.starts_with("title    two colours\ndata 2\n0.1 0.2 0.3 1 0 "));
    assert_eq!(colors(&text).unwrap(), entries);
}

#[test]
fn read_det_and_read_colors_detect_binary_files() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = read_det(&fixture("square.det")).unwrap();
    let det_path = dir.path().join("square.det");
    fs::write(&det_path, write_det_binary(&mesh).unwrap()).unwrap();
    assert_eq!(read_det(&det_path).unwrap(), mesh);

    let entries = vec![entry([1.0, 0.0, 51.0 / 255.0, 0.2, 0.4, 1.0])];
    let pcl = dir.path().join("square.pcl");
    fs::write(
        &pcl,
        write_color_binary(&entries, ColorKind::Polygon).unwrap(),
    )
    .unwrap();
    assert_eq!(read_colors(&pcl, ColorKind::Polygon).unwrap(), entries);
    // A polygon colour file where vertex colours were expected.
    let err = message(read_colors(&pcl, ColorKind::Vertex).unwrap_err());
    assert!(err.contains("`VCL`") && err.contains("`PCL`"), "{err}");
}

#[test]
fn convert_writes_binary_files() {
    let dir = tempfile::tempdir().unwrap();
    for (kind, name, tag) in [
        (ConvertKind::Det, "square.det", b"DET"),
        (ConvertKind::Pcl, "square.pcl", b"PCL"),
        (ConvertKind::Vcl, "square.vcl", b"VCL"),
    ] {
        let output = dir.path().join(name);
        convert(kind, &fixture(name), &output).unwrap();
        let bytes = fs::read(&output).unwrap();
        assert_eq!(&bytes[..3], tag);
    }
    let mesh = read_det(&dir.path().join("square.det")).unwrap();
    assert_eq!(mesh, read_det(&fixture("square.det")).unwrap());
    let vcl = read_colors(&dir.path().join("square.vcl"), ColorKind::Vertex).unwrap();
    assert_eq!(vcl.len(), 4);
    assert_eq!(vcl[0].color.x, 230.0 / 255.0);
    // Converting a binary file again gives the same bytes.
    let again = dir.path().join("again.det");
    convert(ConvertKind::Det, &dir.path().join("square.det"), &again).unwrap();
    assert_eq!(
        fs::read(&again).unwrap(),
        fs::read(dir.path().join("square.det")).unwrap()
    );
}

#[test]
fn failed_convert_leaves_the_output_alone() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bad.det");
    fs::write(&input, "data\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 1 2 4\n").unwrap();
    let output = dir.path().join("out.det");
    fs::write(&output, "previous").unwrap();
    let err = convert(ConvertKind::Det, &input, &output).unwrap_err();
    assert_eq!(place(err).0, 6);
    assert_eq!(fs::read_to_string(&output).unwrap(), "previous");
    let missing = dir.path().join("missing.det");
    assert!(convert(ConvertKind::Det, &input, &missing).is_err());
    assert!(!missing.exists());
    let names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn convert_names_the_binary_limit() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = Mesh {
        vertices: vec![DVec3::ZERO; 70_000],
        polygons: vec![],
    };
    let input = dir.path().join("big.det");
    fs::write(&input, write_det_ascii(&mesh, "big")).unwrap();
    let output = dir.path().join("big.bin");
    let err = convert(ConvertKind::Det, &input, &output).unwrap_err();
    assert!(err.to_string().contains("at most 32767"), "{err}");
    assert!(err.to_string().contains("big.det"), "{err}");
    assert!(!output.exists());
}

fn f32_coordinate() -> impl Strategy<Value = f64> {
    any::<f32>()
        .prop_filter("finite", |v| v.is_finite())
        .prop_map(f64::from)
}

fn arbitrary_mesh(coordinate: BoxedStrategy<f64>) -> impl Strategy<Value = Mesh> {
    prop::collection::vec((coordinate.clone(), coordinate.clone(), coordinate), 1..20)
        .prop_flat_map(|points| {
            let n = points.len() as u32;
            let polygon = prop::collection::vec(0..n, 3..7);
            (Just(points), prop::collection::vec(polygon, 0..10))
        })
        .prop_map(|(points, polygons)| {
            Mesh::new(
                points
                    .into_iter()
                    .map(|(x, y, z)| DVec3::new(x, y, z))
                    .collect(),
                polygons,
            )
        })
}

proptest! {
    #[test]
    fn random_meshes_round_trip(mesh in arbitrary_mesh(f32_coordinate().boxed())) {
        let text = write_det_ascii(&mesh, "random");
        prop_assert_eq!(&det(&text).unwrap(), &mesh);
        let bytes = write_det_binary(&mesh).unwrap();
        prop_assert_eq!(&parse_det_binary(&bytes, Path::new("b")).unwrap(), &mesh);
    }

    #[test]
    fn f64_coordinates_round_trip_in_ascii(
        mesh in arbitrary_mesh(any::<f64>().prop_filter("finite", |v| v.is_finite()).boxed())
    ) {
        prop_assert_eq!(&det(&write_det_ascii(&mesh, "")).unwrap(), &mesh);
    }

    #[test]
    fn random_colours_round_trip(
        bytes in prop::collection::vec(prop::array::uniform6(any::<u8>()), 0..20),
        unit in prop::collection::vec(prop::array::uniform6(0.0..=1.0f64), 0..20),
    ) {
        let entries: Vec<ColorEntry> = bytes
            .iter()
            .map(|b| entry(b.map(|v| f64::from(v) / 255.0)))
            .collect();
        let binary = write_color_binary(&entries, ColorKind::Vertex).unwrap();
        let back = parse_color_binary(&binary, Path::new("b"), ColorKind::Vertex).unwrap();
        prop_assert_eq!(&back, &entries);
        let entries: Vec<ColorEntry> = unit.into_iter().map(entry).collect();
        prop_assert_eq!(&colors(&write_color_ascii(&entries, "")).unwrap(), &entries);
    }
}

// ---------------------------------------------------------------------------
// Errors in ASCII files

#[test]
fn wrong_token_is_located_exactly() {
    let text = "title t\ndata\n3 1\n0 0 0\n1  abc 0\n0 1 0\n3 1 2 3\n";
    assert_eq!(
        place(det(text).unwrap_err()),
        (
            5,
            4,
            "expected a vertex coordinate (a number), found `abc`".to_string()
        )
    );
}

#[test]
fn index_out_of_range_is_located() {
    // The third polygon is line 14: `4 1 5 6 2`.
    let text = CUBE_DET.replace("4 1 5 6 2", "4 1 5 9 2");
    assert_eq!(
        place(det(&text).unwrap_err()),
        (
            14,
            7,
            "vertex index 9 out of range 1..=8 in polygon 3".to_string()
        )
    );
}

#[test]
fn index_zero_is_out_of_range() {
    let text = "data\n3 1\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n";
    assert_eq!(
        place(det(text).unwrap_err()),
        (
            4,
            3,
            "vertex index 0 out of range 1..=3 in polygon 1".to_string()
        )
    );
}

#[test]
fn header_counts_larger_than_the_file() {
    let (line, column, text) = place(det("data\n4000000000 6\n0 0 0\n").unwrap_err());
    assert_eq!((line, column), (3, 6));
    assert_eq!(text, "expected 4000000000 vertices, file ended after 1");
    let text = message(det("data\n1000000000000 1\n0 0 0\n").unwrap_err());
    assert!(text.contains("too many"), "{text}");
    let text = message(det("data\n3 6\n0 0 0 1 0 0 0 1 0\n3 1 2 3\n3 3 2 1\n").unwrap_err());
    assert_eq!(text, "expected 6 polygons, file ended after 2");
    let text = message(det("data\n3 1\n0 0 0 1 0 0 0 1 0\n4000000000 1 2 3\n").unwrap_err());
    assert_eq!(text, "expected 1 polygons, file ended after 0");
    let text = message(colors("data 3000000000\n1 1 1 1 1 1\n").unwrap_err());
    assert_eq!(
        text,
        "expected 3000000000 colour entries, file ended after 1"
    );
}

#[test]
fn non_finite_numbers_are_refused() {
    for word in ["nan", "NaN", "inf", "-infinity"] {
        let text = format!("data\n3 1\n0 0 0\n1 0 {word}\n0 1 0\n3 1 2 3\n");
        let (line, column, text) = place(det(&text).unwrap_err());
        assert_eq!((line, column), (4, 5));
        assert!(text.starts_with("non-finite number"), "{text}");
    }
    assert!(colors("data 1\n0 0 nan 0 0 0\n").is_err());
}

#[test]
fn polygons_need_three_vertices() {
    let text = "data\n3 4\n0 0 0 1 0 0 0 1 0\n3 1 2 3\n3 1 2 3\n3 1 2 3\n2 1 2\n";
    assert_eq!(
        place(det(text).unwrap_err()),
        (
            7,
            1,
            "polygon 4 has 2 vertices; a polygon needs at least 3".to_string()
        )
    );
}

#[test]
fn trailing_text_is_an_error_but_whitespace_is_not() {
    let base = "data\n3 1\n0 0 0 1 0 0 0 1 0\n3 1 2 3";
    assert!(det(&format!("{base}\n\n  \t\n")).is_ok());
    assert_eq!(
        place(det(&format!("{base}\n\n  3 1\n")).unwrap_err()),
        (6, 3, "unexpected text after the last polygon".to_string())
    );
    let text = message(colors("data 1\n0 0 0 0 0 0 0\n").unwrap_err());
    assert_eq!(text, "unexpected text after the last colour entry");
}

#[test]
fn colour_values_must_lie_in_zero_to_one() {
    assert_eq!(
        place(colors("title c\ndata 2\n.5 .5 .5 0 0 0\n.5 -0.1 .5 0 0 0\n").unwrap_err()),
        (
            4,
            4,
            "green -0.1 out of range 0..=1 in colour entry 2".to_string()
        )
    );
    let text = message(colors("data 1\n.5 .5 .5 0 0 2\n").unwrap_err());
    assert_eq!(
        text,
        "transmission coefficient 2 out of range 0..=1 in colour entry 1"
    );
    let err = write_color_binary(&[entry([0.0, 0.0, 0.0, 1.5, 0.0, 0.0])], ColorKind::Polygon);
    assert!(
        err.unwrap_err()
            .to_string()
            .contains("diffuse coefficient 1.5")
    );
}

#[test]
fn invalid_utf8_text_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.det");
    fs::write(&path, b"title \xff\ndata\n").unwrap();
    let (line, column, text) = place(read_det(&path).unwrap_err());
    assert_eq!((line, column), (1, 7));
    assert!(text.contains("invalid UTF-8"), "{text}");
    let missing = dir.path().join("missing.det");
    assert!(matches!(read_det(&missing), Err(Error::Io { .. })));
}

// ---------------------------------------------------------------------------
// Errors in binary files

fn binary_square() -> Vec<u8> {
    write_det_binary(&read_det(&fixture("square.det")).unwrap()).unwrap()
}

#[test]
fn binary_header_claiming_more_than_the_file() {
    let mut bytes = b"DET\xff\xff\x01\x00".to_vec();
    bytes.resize(20, 0);
    let text = message(parse_det_binary(&bytes, Path::new("b")).unwrap_err());
    assert_eq!(
        text,
        "truncated file: expected the bounding box (6 floats) (24 bytes) at byte offset 7, \
         but only 13 bytes remain"
    );
    bytes.resize(31 + 12, 0);
    let text = message(parse_det_binary(&bytes, Path::new("b")).unwrap_err());
    assert_eq!(
        text,
        "truncated file: expected 65535 vertices of 3 floats (786420 bytes) at byte offset 31, \
         but only 12 bytes remain"
    );
    let text = message(
        parse_color_binary(b"PCL\xff\xff\x01\x02", Path::new("b"), ColorKind::Polygon).unwrap_err(),
    );
    assert!(text.contains("65535 colour entries"), "{text}");
}

#[test]
fn every_truncation_of_a_binary_file_is_an_error() {
    let bytes = binary_square();
    for len in 0..bytes.len() {
        let err = parse_det_binary(&bytes[..len], Path::new("b.det")).unwrap_err();
        let d = err.diagnostic().unwrap();
        assert_eq!(d.location.file, Path::new("b.det"));
        assert!(
            d.message.starts_with("truncated file: expected"),
            "{}",
            d.message
        );
        assert!(d.message.contains("byte offset"), "{}", d.message);
    }
    let colours = write_color_binary(&[entry([0.0; 6])], ColorKind::Vertex).unwrap();
    for len in 0..colours.len() {
        assert!(parse_color_binary(&colours[..len], Path::new("b"), ColorKind::Vertex).is_err());
    }
}

#[test]
fn binary_errors_name_the_byte_offset() {
    let mut bytes = binary_square();
    let last_index = bytes.len() - 2;
    bytes[last_index] = 5;
    assert_eq!(
        message(parse_det_binary(&bytes, Path::new("b")).unwrap_err()),
        "at byte offset 87: vertex index 5 out of range 1..=4 in polygon 1"
    );

    let mut bytes = binary_square();
    bytes[31 + 12 + 4..31 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        message(parse_det_binary(&bytes, Path::new("b")).unwrap_err()),
        "at byte offset 43: non-finite number in vertex 2"
    );

    let mut bytes = binary_square();
    bytes[79] = 2;
    bytes.truncate(79 + 2 + 4);
    assert_eq!(
        message(parse_det_binary(&bytes, Path::new("b")).unwrap_err()),
        "at byte offset 79: polygon 1 has 2 vertices; a polygon needs at least 3"
    );

    let mut bytes = binary_square();
    bytes.push(0);
    assert_eq!(
        message(parse_det_binary(&bytes, Path::new("b")).unwrap_err()),
        "at byte offset 89: 1 unexpected bytes after the last polygon"
    );
}

// ---------------------------------------------------------------------------
// Imported meshes

#[test]
fn unit_cube_in_obj_ply_and_stl_is_clockwise_after_import() {
    for (name, polygons) in [("cube.obj", 6), ("cube.ply", 6), ("cube.stl", 12)] {
        let mesh = read_mesh(&fixture(name)).unwrap();
        assert_eq!(mesh.vertices.len(), 8, "{name}");
        assert_eq!(mesh.polygons.len(), polygons, "{name}");
        assert!(mesh.vertices.contains(&DVec3::ONE), "{name}");
        assert_clockwise_from_outside(&mesh);
    }
}

#[test]
fn obj_and_ply_faces_are_reversed_but_kept_whole() {
    // Both files list the bottom face as (0,0,0) (0,1,0) (1,1,0) (1,0,0).
    let bottom_clockwise = [DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y, DVec3::ZERO];
    for name in ["cube.obj", "cube.ply"] {
        let mesh = read_mesh(&fixture(name)).unwrap();
        let bottom: Vec<DVec3> = mesh.polygons[0]
            .iter()
            .map(|&i| mesh.vertices[i as usize])
            .collect();
        assert_eq!(bottom, bottom_clockwise, "{name}");
    }
    // PLY keeps the file's vertex order; tobj numbers OBJ vertices in the
    // order of their first use.
    let ply = read_mesh(&fixture("cube.ply")).unwrap();
    assert_eq!(ply.polygons[0], vec![1, 2, 3, 0]);
    assert_eq!(ply.polygons[5], vec![5, 6, 2, 1]);
    let obj = read_mesh(&fixture("cube.obj")).unwrap();
    assert_eq!(obj.polygons[0], vec![3, 2, 1, 0]);
    assert_eq!(obj.vertices[1], DVec3::Y);
}

#[test]
fn extension_is_case_insensitive_and_checked() {
    let dir = tempfile::tempdir().unwrap();
    let upper = dir.path().join("CUBE.OBJ");
    fs::copy(fixture("cube.obj"), &upper).unwrap();
    assert_eq!(read_mesh(&upper).unwrap().polygons.len(), 6);
    let other = dir.path().join("cube.off");
    fs::copy(fixture("cube.obj"), &other).unwrap();
    let text = message(read_mesh(&other).unwrap_err());
    assert_eq!(
        text,
        "unknown mesh format `.off`: expected one of obj, ply, stl"
    );
    assert_eq!(MESH_EXTENSIONS, &["obj", "ply", "stl"]);
}

#[test]
fn bad_meshes_give_clean_errors() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[u8], &str); 5] = [
        (
            "range.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n",
            "cannot read Wavefront OBJ",
        ),
        (
            "nan.obj",
            b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "non-finite number in vertex 1",
        ),
        (
            "range.ply",
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
              property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
              end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
            "vertex index 3 (0-based) out of range in polygon 1",
        ),
        (
            "two.ply",
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n\
              property double z\nelement face 1\nproperty list uchar uint vertex_index\n\
              end_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
            "polygon 1 has 2 vertices; a polygon needs at least 3",
        ),
        ("junk.stl", b"solid x\nfacet nonsense\n", "cannot read STL"),
    ];
    for (name, content, expected) in cases {
        let path = dir.path().join(name);
        fs::write(&path, content).unwrap();
        let err = read_mesh(&path).unwrap_err();
        let d = err.diagnostic().unwrap_or_else(|| panic!("{name}: {err}"));
        assert_eq!(d.location.file, path);
        assert!(d.message.contains(expected), "{name}: {}", d.message);
    }
}

#[test]
fn ply_with_double_coordinates_and_short_indices() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tri.ply");
    fs::write(
        &path,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n\
         property double z\nelement face 1\nproperty list uchar ushort vertex_index\n\
         end_header\n0.1 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    let mesh = read_mesh(&path).unwrap();
    assert_eq!(mesh.vertices[0].x, 0.1);
    assert_eq!(mesh.polygons, vec![vec![2, 1, 0]]);
}

//! Unit tests of `object_file`.

use super::*;

fn det(text: &str) -> Result<Mesh> {
    parse_det_ascii(text, Path::new("t.det"))
}

/// The diagnostic of an input error: (line, column, message).
fn place(error: Error) -> (usize, usize, String) {
    let d = error.diagnostic().expect("an input error").clone();
    (d.location.line, d.location.column, d.message)
}

#[test]
fn data_keyword_must_start_a_line() {
    // The manual's own example has the word `data` in its title.
    let mesh = det("title geometric data file\nDATA 3 1\n0 0 0 1 0 0 0 1 0\n3 1 2 3\n").unwrap();
    assert_eq!(mesh.vertices[1], DVec3::X);
    assert_eq!(mesh.polygons, vec![vec![0, 1, 2]]);
}

#[test]
fn commas_and_tabs_separate_words() {
    let mesh = det("data\n3,1\n0,0,0\n\t1, 0 ,0\n0 2 0\n3,3,2,1,\n").unwrap();
    assert_eq!(mesh.vertices[2], DVec3::new(0.0, 2.0, 0.0));
    assert_eq!(mesh.polygons, vec![vec![2, 1, 0]]);
}

#[test]
fn missing_data_keyword_is_an_error() {
    let (line, _, message) = place(det("title nothing\n3 1\n").unwrap_err());
    assert_eq!(line, 2);
    assert!(message.contains("`data`"), "{message}");
}

#[test]
fn error_shows_the_source_line_and_width() {
    let err = det("data\n3 1\n0 0 0\n1 0 0\n0 1.5x 0\n3 1 2 3\n").unwrap_err();
    let d = err.diagnostic().unwrap();
    assert_eq!((d.location.line, d.location.column), (5, 3));
    assert_eq!(d.source_line.as_deref(), Some("0 1.5x 0"));
    assert_eq!(d.width, 4);
    assert_eq!(
        d.message,
        "expected a vertex coordinate (a number), found `1.5x`"
    );
}

#[test]
fn columns_count_characters_not_bytes() {
    // A no-break space (2 bytes in UTF-8) separates words too.
    let (line, column, _) = place(det("data\n1 0\n0\u{a0}x 0\n").unwrap_err());
    assert_eq!((line, column), (3, 3));
    let (line, column, _) = place(det("data\n1 0 0 0 0\u{a0}é\n").unwrap_err());
    assert_eq!((line, column), (2, 11));
}

#[test]
fn end_of_file_error_points_after_the_last_word() {
    let (line, column, message) = place(det("data\n2 1\n0 0 0\n1 1 \n\n").unwrap_err());
    assert_eq!((line, column), (4, 4));
    assert_eq!(message, "expected 2 vertices, file ended after 1");
}

#[test]
fn polygon_size_and_counts_must_be_integers() {
    let (_, _, message) = place(det("data\n3.0 1\n").unwrap_err());
    assert_eq!(
        message,
        "expected the number of vertices (a non-negative integer), found `3.0`"
    );
    let (_, _, message) = place(det("data\n3 -1\n").unwrap_err());
    assert!(message.contains("found `-1`"), "{message}");
    let (line, column, message) =
        place(det("data\n3 1\n0 0 0 1 0 0 0 1 0\n3.5 1 2 3\n").unwrap_err());
    assert_eq!((line, column), (4, 1));
    assert!(message.contains("polygon 1"), "{message}");
}

#[test]
fn vertex_count_above_u32_is_refused_before_reading() {
    let (_, _, message) = place(det("data\n5000000000 1\n").unwrap_err());
    assert!(message.contains("too many"), "{message}");
}

#[test]
fn capacity_is_bounded_by_the_text() {
    let scanner = Scanner::after_data("data\n1 2 3 4 5 6", Path::new("x")).unwrap();
    assert!(scanner.capacity(1 << 40, 3) <= 3);
    assert_eq!(scanner.capacity(1, 3), 1);
}

#[test]
fn colour_count_may_follow_data_on_the_next_line() {
    let entries = parse_color_ascii("data\n1\n1 0 0 .5 .25 0\n", Path::new("c.pcl")).unwrap();
    assert_eq!(entries[0].color, DVec3::X);
    assert_eq!(entries[0].diffuse, 0.5);
    assert_eq!(entries[0].reflectance, 0.25);
}

#[test]
fn colour_value_out_of_range_is_located() {
    let err = parse_color_ascii("data 1\n1 0 0 .5 1.25 0\n", Path::new("c.pcl")).unwrap_err();
    assert_eq!(
        place(err),
        (
            2,
            10,
            "reflection coefficient 1.25 out of range 0..=1 in colour entry 1".to_string()
        )
    );
}

#[test]
fn byte_reader_reports_offsets() {
    let mut reader = ByteReader::new(&[1, 0, 2], Path::new("b"));
    assert_eq!(reader.u16("a").unwrap(), 1);
    let (_, _, message) = place(reader.u16("the second number").unwrap_err());
    assert_eq!(
        message,
        "truncated file: expected the second number (2 bytes) at byte offset 2, \
         but only 1 bytes remain"
    );
}

#[test]
fn bounding_box_is_computed_from_the_vertices() {
    let bbox = bounding_box(&[1.0, -2.0, 3.0, -1.0, 5.0, 0.0]);
    assert_eq!(bbox, [-1.0, -2.0, 0.0, 1.0, 5.0, 3.0]);
    assert_eq!(bounding_box(&[]), [0.0; 6]);
}

#[test]
fn binary_bounding_box_is_written_but_not_trusted() {
    let mesh = det("data\n3 1\n0 0 0 2 0 0 0 3 -1\n3 1 2 3\n").unwrap();
    let mut bytes = write_det_binary(&mesh).unwrap();
    let bbox: Vec<f32> = bytes[7..31]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(bbox, [0.0, 0.0, -1.0, 2.0, 3.0, 0.0]);
    bytes[7..31].fill(0xff); // NaN bounding box
    assert_eq!(parse_det_binary(&bytes, Path::new("b")).unwrap(), mesh);
}

#[test]
fn binary_detection_needs_tag_and_non_text() {
    assert!(is_binary(b"DET\x08\x00\x06\x00", &[DET_TAG]));
    assert!(!is_binary(b"DETAILS\ndata\n", &[DET_TAG]));
    assert!(!is_binary(b"title\n", &[DET_TAG]));
}

#[test]
fn invalid_utf8_is_located() {
    let err = as_text(b"title\nab\xff", Path::new("x")).unwrap_err();
    let (line, column, message) = place(err);
    assert_eq!((line, column), (2, 3));
    assert!(message.contains("byte offset 8"), "{message}");
}

#[test]
fn binary_limits_are_named() {
    let mesh = Mesh {
        vertices: vec![DVec3::ZERO; 3],
        polygons: vec![vec![0; 70_000].into()],
    };
    let err = write_det_binary(&mesh).unwrap_err();
    assert!(err.to_string().contains("`nvtx`"), "{err}");
    assert!(err.to_string().contains("at most 32767"), "{err}");
    let mesh = Mesh {
        vertices: vec![DVec3::ZERO; 32_768],
        polygons: vec![],
    };
    let err = write_det_binary(&mesh).unwrap_err();
    assert_eq!(
        err.to_string(),
        "32768 vertices: the binary format stores this in the C short `num_vtx`, \
         which holds at most 32767"
    );
}

#[test]
fn coordinates_must_fit_f32() {
    let mesh = Mesh {
        vertices: vec![DVec3::new(0.0, 1e300, 0.0)],
        polygons: vec![],
    };
    assert!(write_det_binary(&mesh).is_err());
}

#[test]
fn colour_bytes_round_to_nearest() {
    let entry = color_entry([0.9, 0.0, 1.0, 0.5, 0.002, 0.998]);
    let bytes = write_color_binary(&[entry], ColorKind::Vertex).unwrap();
    assert_eq!(bytes, b"VCL\x01\x00\xe6\x00\xff\x80\x01\xfe");
}

#[test]
fn atomic_write_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.det");
    write_atomically(&out, b"abc").unwrap();
    assert_eq!(fs::read(&out).unwrap(), b"abc");
    let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1);
    // A directory in the way: the rename fails and the temporary goes.
    let blocked = dir.path().join("sub");
    fs::create_dir(&blocked).unwrap();
    fs::write(blocked.join("f"), b"x").unwrap();
    assert!(write_atomically(&blocked, b"abc").is_err());
    let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 2);
}

//! Mesh files past the polygon budget are refused before they are read.

use std::io::Write;
use std::time::{Duration, Instant};

use plytrace::internal::scene::mesh_import::read_mesh_within;

/// Refused quickly, naming the flag.
fn refused(path: &std::path::Path, budget: usize) -> String {
    let t = Instant::now();
    let err = read_mesh_within(path, budget).unwrap_err().to_string();
    assert!(err.contains("--max-polygons"), "{err}");
    assert!(
        t.elapsed() < Duration::from_secs(20),
        "{:?}: {err}",
        t.elapsed()
    );
    err
}

/// `text`, then a hole making the file `total` bytes long (sparse: no
/// disk), which the readers would take for more of the file.
fn sparse(dir: &std::path::Path, name: &str, text: &[u8], total: u64) -> std::path::PathBuf {
    let path = dir.join(name);
    let mut f = std::fs::File::create(&path).unwrap();
    f.write_all(text).unwrap();
    f.set_len(total).unwrap();
    path
}

#[test]
fn a_ply_header_over_the_budget_is_refused_before_the_body() {
    let dir = tempfile::tempdir().unwrap();
    let head = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
        property float x\nproperty float y\nproperty float z\n\
        element face 40000000\nproperty list uchar int vertex_indices\nend_header\n";
    // 40 million faces announced; the body is a hole of 600 MB.
    let path = sparse(dir.path(), "big.ply", head, 600 << 20);
    let err = refused(&path, 4_000_000);
    assert!(err.contains("40000000 faces"), "{err}");
}

#[test]
fn a_binary_stl_count_over_the_budget_is_refused_before_the_body() {
    let dir = tempfile::tempdir().unwrap();
    let count: u32 = 10_000_000;
    let mut head = vec![0u8; 80];
    head.extend(count.to_le_bytes());
    let path = sparse(dir.path(), "big.stl", &head, 84 + 50 * u64::from(count));
    let err = refused(&path, 4_000_000);
    assert!(err.contains("10000000 faces"), "{err}");
}

#[test]
fn an_obj_stops_being_read_once_its_faces_pass_the_budget() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for _ in 0..200_000 {
        text.push_str("f 1 2 3\n");
    }
    // Past the faces, a hole: 40 GB that a reader would go through (and
    // past the 1 GiB input limit, whose error names no budget).
    let path = sparse(dir.path(), "big.obj", text.as_bytes(), 40 << 30);
    refused(&path, 100_000);
    // Within the budget the same faces are read.
    let small = dir.path().join("small.obj");
    std::fs::write(&small, &text).unwrap();
    assert_eq!(
        read_mesh_within(&small, 200_000).unwrap().polygons.len(),
        200_000
    );
}

#[test]
fn an_obj_of_vertices_only_is_refused_too() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 1 2 3\n".repeat(50_000);
    let path = sparse(dir.path(), "points.obj", text.as_bytes(), 40 << 30);
    let err = refused(&path, 10_000);
    assert!(err.contains("vertices"), "{err}");
}

#[test]
fn an_ascii_stl_stops_being_read_once_its_facets_pass_the_budget() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("solid s\n");
    for _ in 0..20_000 {
        text.push_str(
            "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      \
             vertex 0 1 0\n    endloop\n  endfacet\n",
        );
    }
    let path = sparse(dir.path(), "big.stl", text.as_bytes(), 40 << 30);
    refused(&path, 10_000);
}

/// The command line's `--max-polygons` reaches a mesh file read by a
/// scene (the budget is handed down, not a setting of the process): a PLY
/// announcing a million faces, under the default budget but over the one
/// given, is refused from its header.
#[test]
fn the_command_line_budget_reaches_a_mesh_in_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    let head = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
        property float x\nproperty float y\nproperty float z\n\
        element face 1000000\nproperty list uchar int vertex_indices\nend_header\n";
    sparse(&dir.path().join("det"), "big.ply", head, 20 << 20);
    let scene = "resolution 32 32\nperspective 45 1 0.1 100\npushmatrix\nident\n\
                 translate 0 0 -20\ndefobj big\nendobj\npopmatrix\n";
    std::fs::write(dir.path().join("s.des"), scene).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_plytrace"))
        .args(["-q", "--max-polygons", "1000", "s.des"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("--max-polygons") && err.contains("1000000 faces"),
        "{err}"
    );
}

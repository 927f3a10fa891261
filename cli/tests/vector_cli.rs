//! The command line chooses vector output by the extension of `-o` and
//! writes it through the run's atomic staging; `--hidden-line` works for
//! PNG and vector output.

#[path = "../../tests/support/mod.rs"]
mod support;

use std::process::Command;

fn run(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    let scene = support::scene_fixture("ccube.des");
    Command::new(env!("CARGO_BIN_EXE_plytrace"))
        .current_dir(dir)
        .arg("-q")
        .arg(&scene)
        .args(args)
        .output()
        .unwrap()
}

fn files(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "plytrace.log")
        .collect();
    v.sort();
    v
}

#[test]
fn each_vector_extension_writes_its_format_and_nothing_else() {
    for (name, magic) in [
        ("x.svg", "<?xml"),
        ("x.pdf", "%PDF-"),
        ("x.tex", "% plytrace"),
        ("x.SVG", "<?xml"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = run(dir.path(), &["-o", name]);
        assert!(out.status.success(), "{name}: {out:?}");
        assert_eq!(files(dir.path()), vec![name.to_string()]);
        let bytes = std::fs::read(dir.path().join(name)).unwrap();
        assert!(bytes.starts_with(magic.as_bytes()), "{name}");
    }
}

#[test]
fn hidden_line_writes_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    assert!(
        run(dir.path(), &["--hidden-line", "-o", "h.png"])
            .status
            .success()
    );
    assert!(
        run(dir.path(), &["--hidden-line", "-o", "h.svg"])
            .status
            .success()
    );
    assert_eq!(files(dir.path()), vec!["h.png", "h.svg"]);
    let svg = std::fs::read_to_string(dir.path().join("h.svg")).unwrap();
    assert!(svg.contains("fill=\"#ffffff\""), "white background");
    assert!(svg.contains("stroke=\"#000000\""), "black edges");
}

#[test]
fn unwritable_combinations_are_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["-o", "x.svg", "--id-image", "i.png"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--id-image"));
    let out = run(dir.path(), &["-o", "x.eps"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains(".svg, .pdf and .tex"));
    assert!(files(dir.path()).is_empty());
}

#[test]
fn setmode_o_writes_the_tree_files_with_vector_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["-o", "on", "-o", "x.svg"]);
    assert!(out.status.success(), "{out:?}");
    let names = files(dir.path());
    assert!(names.contains(&"x.svg".to_string()), "{names:?}");
    assert!(names.iter().any(|n| n.ends_with(".out")), "{names:?}");
    assert!(names.iter().any(|n| n.ends_with(".txt")), "{names:?}");
}

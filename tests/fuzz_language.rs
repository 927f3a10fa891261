//! Hostile input never panics: random statements built from the language's
//! words and hostile numbers, and random bytes, go through the interpreter
//! and the renderer; every outcome is a value or a located error.

use std::path::Path;

use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::commands::COMMANDS;
use plytrace::internal::scene::{Interpreter, NoHost};
use proptest::prelude::*;

const WORDS: &[&str] = &[
    "0",
    "1",
    "-1",
    "0.5",
    "2",
    "90",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-0",
    "x",
    "y",
    "z",
    "on",
    "off",
    "y",
    "Point",
    "D",
    "btf",
    "ftb",
    "polygon",
    "open",
    "curved",
    "concave",
    "hidden",
    "a",
    "3",
    "/*",
    "*/",
    "#",
    ",",
    "cube",
    "square",
    "16",
    "65536",
    "99999999999999999999",
];

fn statement() -> impl Strategy<Value = String> {
    (
        0..COMMANDS.len(),
        prop::collection::vec(0..WORDS.len(), 0..8),
    )
        .prop_map(|(c, args)| {
            let mut s = COMMANDS[c].name.to_string();
            for a in args {
                s.push(' ');
                s.push_str(WORDS[a]);
            }
            s
        })
}

/// What one run gave: per line, `ok` or the error's text; then the render's
/// error or its pixels and ids (bit for bit).
#[derive(Debug, PartialEq)]
struct Outcome {
    lines: Vec<Result<(), String>>,
    render: Result<(Vec<[u32; 3]>, Vec<u32>), String>,
}

/// A scratch directory with `det/square.det` and `det/cube.det`.
fn sandbox() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(
        dir.path().join("det/square.det"),
        "title\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n",
    )
    .unwrap();
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det");
    std::fs::copy(cube, dir.path().join("det/cube.det")).unwrap();
    dir
}

fn run_in(dir: &Path, text: &str) -> Outcome {
    let mut interp = Interpreter::new();
    let file = dir.join("f.des");
    // Line by line, as the interactive interpreter does: an error does not
    // stop the rest.
    let lines = text
        .lines()
        .map(|line| {
            interp
                .execute_source(line, &file, dir, &mut NoHost)
                .map(|_| ())
                .map_err(|e| e.to_string())
        })
        .collect();
    let mut scene = interp.scene();
    // Keep renders small whatever the input asked for.
    scene.viewport = plytrace::internal::model::Viewport::of_size(24, 24);
    let render = render(
        &scene,
        &RenderOptions {
            shadows: true,
            ..RenderOptions::default()
        },
    )
    .map(|r| {
        let pixels = r.frame.color.iter().map(|c| c.map(f32::to_bits)).collect();
        (pixels, r.frame.ids.clone())
    })
    .map_err(|e| e.to_string());
    Outcome { lines, render }
}

/// Whether `message` starts with `FILE:LINE:COL: ` (LINE and COL numbers
/// from 1).
fn located(message: &str) -> bool {
    let Some((head, _)) = message.split_once(": ") else {
        return false;
    };
    let mut parts = head.rsplitn(3, ':');
    let (Some(col), Some(line), Some(file)) = (parts.next(), parts.next(), parts.next()) else {
        return false;
    };
    let number = |s: &str| s.parse::<usize>().is_ok_and(|n| n >= 1);
    !file.is_empty() && number(line) && number(col)
}

/// Runs `text` twice in one scratch directory: no panic, every statement's
/// error is located as `file:line:col:`, and both runs give the same
/// outcome, image included.
fn run(text: &str) -> Result<(), TestCaseError> {
    let dir = sandbox();
    let first = run_in(dir.path(), text);
    for (i, line) in first.lines.iter().enumerate() {
        if let Err(message) = line {
            prop_assert!(
                located(message),
                "line {}: the error is not `file:line:col: ...`: {message}",
                i + 1
            );
        }
    }
    let second = run_in(dir.path(), text);
    prop_assert!(first == second, "two runs differ:\n{first:?}\n{second:?}");
    Ok(())
}

#[test]
fn located_accepts_only_file_line_col() {
    assert!(located("/tmp/x/f.des:1:7: expected a number"));
    assert!(!located("/tmp/x/f.des: no such file"));
    assert!(!located("f.des:0:1: x"));
    assert!(!located("image too large"));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    #[test]
    fn random_statements_never_panic(stmts in prop::collection::vec(statement(), 1..25)) {
        let text = format!("ident\n{}\n", stmts.join("\n"));
        run(&text)?;
    }

    #[test]
    fn random_text_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        run(&String::from_utf8_lossy(&bytes))?;
    }
}

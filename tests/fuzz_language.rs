//! Hostile input never panics: random statements built from the language's
//! words and hostile numbers, and random bytes, go through the interpreter
//! and the renderer; every outcome is a value or a located error.

use std::path::Path;

use plytrace::render::{RenderOptions, render};
use plytrace::scene::commands::COMMANDS;
use plytrace::scene::{Interpreter, NoHost};
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

fn run(text: &str) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(
        dir.path().join("det/square.det"),
        "title\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n",
    )
    .unwrap();
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det");
    std::fs::copy(cube, dir.path().join("det/cube.det")).unwrap();
    let mut interp = Interpreter::new();
    let file = dir.path().join("f.des");
    // Line by line, as the interactive interpreter does: an error does not
    // stop the rest.
    for line in text.lines() {
        let _ = interp.execute_source(line, &file, dir.path(), &mut NoHost);
    }
    let mut scene = interp.scene();
    // Keep renders small whatever the input asked for.
    scene.viewport = plytrace::scene::model::Viewport::of_size(24, 24);
    let _ = render(
        &scene,
        &RenderOptions {
            shadows: true,
            ..RenderOptions::default()
        },
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    #[test]
    fn random_statements_never_panic(stmts in prop::collection::vec(statement(), 1..25)) {
        let text = format!("ident\n{}\n", stmts.join("\n"));
        run(&text);
    }

    #[test]
    fn random_text_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        run(&String::from_utf8_lossy(&bytes));
    }
}

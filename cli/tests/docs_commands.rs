//! The documentation cannot drift from the program: every command the
//! README and `docs/` tell a user to run is run here, and every file they
//! name exists in the repository.
//!
//! Runnable commands stand in fenced blocks whose info string is
//! `console`, one per line after `$ `. Each block runs in a fresh copy of
//! the repository's `examples/`, `docs/` and `tests/data/` (commands in a
//! block share it, in order), with the built programs on the `PATH`, and
//! every command must exit 0. `cargo run --release -- ARGS` runs as
//! `plytrace ARGS`; other cargo commands are checked, not run: the
//! benches, examples and features they name must exist.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "../../tests/support/mod.rs"]
mod support;
use support::copy_tree;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// The README and every Markdown file under `docs/`, and ARCHITECTURE.md.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![root().join("README.md"), root().join("ARCHITECTURE.md")];
    let mut stack = vec![root().join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "md") {
                docs.push(p);
            }
        }
    }
    docs.sort();
    docs
}

/// A fenced block: its info string, first line number and lines.
struct Block {
    info: String,
    line: usize,
    lines: Vec<String>,
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        let fence = line.trim_start().starts_with("```");
        match (&mut open, fence) {
            (None, true) => {
                open = Some(Block {
                    info: line.trim_start().trim_start_matches('`').trim().to_string(),
                    line: i + 1,
                    lines: Vec::new(),
                });
            }
            (Some(_), true) => out.extend(open.take()),
            (Some(b), false) => b.lines.push(line.to_string()),
            (None, false) => {}
        }
    }
    assert!(open.is_none(), "an unclosed code block");
    out
}

/// The commands of a console block.
fn commands(block: &Block) -> Vec<String> {
    block
        .lines
        .iter()
        .filter_map(|l| l.trim_start().strip_prefix("$ "))
        .map(str::to_string)
        .collect()
}

/// A cargo command is checked, not run: what it names must exist. Returns
/// the command to run instead (`cargo run --release -- ARGS`), if any.
fn cargo_command(cmd: &str, place: &str) -> Option<String> {
    let words: Vec<&str> = cmd.split_whitespace().collect();
    if let Some(i) = words.iter().position(|w| *w == "--")
        && words[1] == "run"
    {
        return Some(format!("plytrace {}", words[i + 1..].join(" ")));
    }
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    for pair in words.windows(2) {
        match pair[0] {
            "--bench" => assert!(
                ["benches", "cli/benches"]
                    .iter()
                    .any(|d| root().join(d).join(format!("{}.rs", pair[1])).exists()),
                "{place}: no bench `{}`",
                pair[1]
            ),
            "--example" => assert!(
                root()
                    .join("examples")
                    .join(format!("{}.rs", pair[1]))
                    .exists(),
                "{place}: no example `{}`",
                pair[1]
            ),
            "--features" => assert!(
                manifest.contains(&format!("\n{} = ", pair[1])),
                "{place}: no feature `{}`",
                pair[1]
            ),
            "--test" => assert!(
                root()
                    .join("tests")
                    .join(format!("{}.rs", pair[1]))
                    .exists(),
                "{place}: no test `{}`",
                pair[1]
            ),
            _ => {}
        }
    }
    None
}

/// Runs one console block in a fresh copy of the repository's data.
fn run_block(doc: &Path, block: &Block, bin_dir: &Path) {
    let dir = tempfile::tempdir().unwrap();
    for sub in ["examples", "docs", "tests/data"] {
        copy_tree(&root().join(sub), &dir.path().join(sub));
    }
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for cmd in commands(block) {
        let place = format!("{}:{}: `{cmd}`", doc.display(), block.line);
        let cmd = if cmd.starts_with("cargo ") {
            match cargo_command(&cmd, &place) {
                Some(c) => c,
                None => continue,
            }
        } else {
            cmd
        };
        let out = Command::new("sh")
            .args(["-c", &cmd])
            .current_dir(dir.path())
            .env("PATH", &path)
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{place} failed ({}):\n{}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn every_documented_command_works() {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_plytrace")).parent().unwrap();
    for name in ["rftb1", "rftb2", "rftb3", "rftb4", "getrgb", "mkdet"] {
        assert!(
            bin_dir.join(name).exists(),
            "{name} is not built beside plytrace"
        );
    }
    let mut ran = 0;
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        for block in blocks(&text).iter().filter(|b| b.info == "console") {
            run_block(&doc, block, bin_dir);
            ran += commands(block).len();
        }
    }
    assert!(ran >= 10, "only {ran} documented commands");
}

/// Words that look like paths in the repository: `examples/...`,
/// `docs/...`, `src/...`, `tests/...`, `benches/...`, and Markdown links.
fn named_paths(text: &str) -> Vec<String> {
    let mut names = Vec::new();
    for word in text.split(|c: char| c.is_whitespace() || "`()[]<>\"',;".contains(c)) {
        let word = word.trim_end_matches(['.', ':']);
        let repo = [
            "examples/",
            "docs/",
            "src/",
            "tests/",
            "benches/",
            "fuzz/",
            ".ci/",
        ];
        if repo.iter().any(|p| word.starts_with(p))
            && !word.contains('*')
            && !word.contains("NAME")
            && !word.contains("...")
        {
            names.push(word.to_string());
        }
    }
    names
}

#[test]
fn every_named_file_exists_and_pictures_are_tracked() {
    let tracked = Command::new("git")
        .args(["ls-files"])
        .current_dir(root())
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned());
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        let base = doc.parent().unwrap();
        for name in named_paths(&text) {
            assert!(
                root().join(&name).exists(),
                "{} names `{name}`, which is not in the repository",
                doc.display()
            );
        }
        // Markdown links and images, relative to the document.
        for (i, _) in text.match_indices("](") {
            let target: String = text[i + 2..].chars().take_while(|c| *c != ')').collect();
            let target = target.split('#').next().unwrap_or("");
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let p = base.join(target);
            assert!(
                p.exists(),
                "{} links `{target}`, which does not exist",
                doc.display()
            );
            // A picture must be committed, not just present here.
            if let (Ok(list), Some("png" | "svg")) =
                (&tracked, p.extension().and_then(|e| e.to_str()))
            {
                let rel = p.canonicalize().unwrap();
                let rel = rel.strip_prefix(root().canonicalize().unwrap()).unwrap();
                assert!(
                    list.lines().any(|l| Path::new(l) == rel),
                    "{} shows `{target}`, which git does not track",
                    doc.display()
                );
            }
        }
    }
}

#[test]
fn the_readme_is_for_users() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(lines <= 280, "README.md has {lines} lines");
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        // The papers' folder beside a developer's clone, which a user's lacks.
        let papers = format!("{}/shared", "..");
        for banned in [papers.as_str(), "load average"] {
            assert!(
                !text.contains(banned),
                "{} mentions `{banned}`",
                doc.display()
            );
        }
        // No work log: no issue or session numbers.
        let lower = text.to_ascii_lowercase();
        for word in ["issue ", "session ", "part "] {
            for (i, _) in lower.match_indices(word) {
                let next = lower[i + word.len()..].chars().next();
                // `--part 0/2` is a flag, not a work log.
                let flag = lower[..i].ends_with("--");
                assert!(
                    flag || !next.is_some_and(|c| c.is_ascii_digit()),
                    "{} has `{}`",
                    doc.display(),
                    &text[i..(i + word.len() + 3).min(text.len())]
                );
            }
        }
    }
    assert!(text.contains("cargo test --release"));
    assert!(text.contains("cargo install --locked --path cli"));
}

#[test]
fn the_block_reader_reads_blocks() {
    let text = "a\n```console\n$ plytrace x.des\nout\n$ ls\n```\n```text\n$ no\n```\n";
    let b = blocks(text);
    assert_eq!(b.len(), 2);
    assert_eq!(b[0].info, "console");
    assert_eq!(b[0].line, 2);
    assert_eq!(commands(&b[0]), ["plytrace x.des", "ls"]);
    assert_eq!(
        named_paths("see `examples/ccube.des` and docs/vector.md."),
        ["examples/ccube.des", "docs/vector.md"]
    );
}

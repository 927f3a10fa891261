//! Replays every input under `tests/data/fuzz-regressions/<target>/`
//! through the entry point of the cargo-fuzz target of that name (the same
//! functions, from `fuzz/src/lib.rs`, as ordinary code: no libFuzzer,
//! nightly or cargo-fuzz needed). An input passes when the entry point
//! returns, without a panic, within a minute. A missing or empty folder
//! fails loudly.
//!
//! A crash or timeout that fuzzing finds is minimized (`cargo fuzz tmin`)
//! and committed in its target's folder; the folders are also seeded with
//! the corpus seeds, so they are never empty.

#[path = "../fuzz/src/lib.rs"]
mod harness;

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

/// How long one input may take (the fuzzers' `-timeout` is 10 s; a debug
/// build of the tests is slower).
const DEADLINE: Duration = Duration::from_secs(60);

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz-regressions")
}

/// The inputs of `target`, sorted; panics if there are none.
fn inputs(target: &str) -> Vec<PathBuf> {
    let dir = root().join(target);
    assert!(
        dir.is_dir(),
        "missing fixture folder {}: every fuzz target needs its regression inputs",
        dir.display()
    );
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "{} has no inputs: seed it with the corpus seeds",
        dir.display()
    );
    files
}

/// Runs every input of `target`; fails listing each one that panicked or
/// took longer than [`DEADLINE`].
fn replay(target: &'static str) {
    let mut failures = Vec::new();
    let files = inputs(target);
    for file in &files {
        let data = std::fs::read(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let (send, receive) = mpsc::channel();
        // A thread of its own, so that a hang fails this test instead of
        // stopping the suite (the thread is left behind).
        std::thread::Builder::new()
            .name(format!("{target}: {}", file.display()))
            .spawn(move || {
                let outcome = std::panic::catch_unwind(|| harness::run_target(target, &data));
                let _ = send.send(outcome.is_ok());
            })
            .expect("spawn a replay thread");
        match receive.recv_timeout(DEADLINE) {
            Ok(true) => {}
            Ok(false) | Err(mpsc::RecvTimeoutError::Disconnected) => {
                failures.push(format!("{}: panicked (message above)", file.display()));
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                failures.push(format!(
                    "{}: still running after {} s",
                    file.display(),
                    DEADLINE.as_secs()
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} `{target}` regression inputs fail:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

#[test]
fn scene_language_inputs() {
    replay("scene_language");
}

#[test]
fn object_files_inputs() {
    replay("object_files");
}

#[test]
fn meshes_inputs() {
    replay("meshes");
}

#[test]
fn tree_files_inputs() {
    replay("tree_files");
}

#[test]
fn pipeline_inputs() {
    replay("pipeline");
}

#[test]
fn pixel_structs_inputs() {
    replay("pixel_structs");
}

#[test]
fn rftb_args_inputs() {
    replay("rftb_args");
}

#[test]
fn patch_files_inputs() {
    replay("patch_files");
}

#[test]
fn modeling_inputs() {
    replay("modeling");
}

/// Every folder is a target, every target has a folder and a cargo-fuzz
/// source file, so that no input is silently left unreplayed.
#[test]
fn folders_match_the_fuzz_targets() {
    let mut folders: Vec<String> = std::fs::read_dir(root())
        .expect("tests/data/fuzz-regressions exists")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    folders.sort();
    let mut targets: Vec<String> = harness::TARGETS.iter().map(|t| t.to_string()).collect();
    targets.sort();
    assert_eq!(folders, targets, "folders of tests/data/fuzz-regressions");
    for t in harness::TARGETS {
        let source = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fuzz/fuzz_targets")
            .join(format!("{t}.rs"));
        assert!(source.is_file(), "missing {}", source.display());
    }
}

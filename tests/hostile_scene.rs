//! Hostile scene input (issue 9): every input ends with a clear error or a
//! correct scene, never a panic, a hang, a stack overflow or an allocation
//! past the budgets. Each test runs the library on files written into a
//! temporary directory; none reads `../shared`.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use plytrace::budget::Budgets;
use plytrace::error::Error;
use plytrace::scene::{Interpreter, NoHost};

const CUBE: &str = "title cube\ndata\n8 6\n\
-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n\
4 1 2 3 4\n4 8 7 6 5\n4 1 5 6 2\n4 2 6 7 3\n4 3 7 8 4\n4 4 8 5 1\n";

struct Dir {
    dir: tempfile::TempDir,
}

impl Dir {
    fn new() -> Dir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("det")).unwrap();
        std::fs::write(dir.path().join("det/cube.det"), CUBE).unwrap();
        Dir { dir }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// Runs `text` as a scene file with `budgets`.
    fn run_with(&self, text: &str, budgets: Budgets) -> Result<Interpreter, Error> {
        let p = self.write("scene.des", text);
        run_file(&p, budgets)
    }

    fn run(&self, text: &str) -> Result<Interpreter, Error> {
        self.run_with(text, Budgets::default())
    }
}

fn run_file(path: &Path, budgets: Budgets) -> Result<Interpreter, Error> {
    let mut i = Interpreter::new();
    i.set_budgets(budgets);
    i.execute_file(path, true, &mut NoHost)?;
    Ok(i)
}

/// Runs `f` on another thread; fails the test if it takes longer than
/// `secs` seconds (a hang) or panics.
fn within<T: Send + 'static>(secs: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(Duration::from_secs(secs)) {
        Ok(v) => v,
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("still running after {secs} s: a hang"),
        Err(mpsc::RecvTimeoutError::Disconnected) => panic!("the run panicked"),
    }
}

fn message(e: &Error) -> String {
    e.to_string()
}

// Item 1: panics.

#[test]
fn callobj_of_an_object_deleted_before_endobj_is_an_error() {
    let d = Dir::new();
    let e = d
        .run("ident\ndefobj cube 1\nendobj\ndefobj cube\ncallobj 1\ndelobj 1\nendobj\n")
        .err()
        .expect("an error, not a scene");
    let m = message(&e);
    assert!(m.contains("scene.des:5:9"), "{m}");
    assert!(m.contains("deleted"), "{m}");
}

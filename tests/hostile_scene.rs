//! Hostile scene input (issue 9): every input ends with a clear error or a
//! correct scene, never a panic, a hang, a stack overflow or an allocation
//! past the budgets. Each test runs the library on files written into a
//! temporary directory; none reads outside the repository.

use std::path::{Path, PathBuf};
use std::time::Duration;

mod support;

use plytrace::Error;
use plytrace::internal::budget::Budgets;
use plytrace::internal::scene::{Interpreter, NoHost};
use support::within;

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

fn message(e: &Error) -> String {
    e.to_string()
}

// Item 1: panics.

#[test]
fn callobj_of_an_object_deleted_before_endobj_is_an_error() {
    let d = Dir::new();
    let e = d
        .run("ident\ndefobj cube 1\nendobj\ndefobj cube\ncallobj 1\ndelobj 1\nendobj\n")
        .expect_err("an error, not a scene");
    let m = message(&e);
    assert!(m.contains("scene.des:5:9"), "{m}");
    assert!(m.contains("deleted"), "{m}");
}

// Item 2: `call` nesting.

/// Writes `f0.des` .. `f{n-1}.des`, each calling the next; the last is
/// `ident`.
fn chain_of_files(d: &Dir, n: usize) -> PathBuf {
    for i in 0..n {
        let text = if i + 1 < n {
            format!("call f{}.des\n", i + 1)
        } else {
            "ident\n".to_string()
        };
        d.write(&format!("f{i}.des"), &text);
    }
    d.path("f0.des")
}

/// One chain of 4,000 files (writing them is the slow part), three runs.
#[test]
fn a_call_chain_4000_deep_ends_with_the_budget_error_and_never_overflows_the_stack() {
    let d = Dir::new();
    let first = chain_of_files(&d, 4000);
    // Each run on a spawned thread (2 MiB of stack): no recursion may
    // overflow it.
    let f = first.clone();
    let m = within(20, move || {
        let e = run_file(&f, Budgets::default()).expect_err("the call budget stops the chain");
        message(&e)
    });
    assert!(m.contains("--max-call-depth"), "{m}");
    assert!(m.contains("exceeds the budget of 64"), "{m}");
    // The chain in the message, shortened in the middle.
    assert!(m.contains("f0.des -> "), "{m}");
    assert!(m.contains(" more ... -> "), "{m}");
    assert!(m.contains("f64.des -> "), "{m}");
    assert!(!m.contains("f30.des"), "{m}");
    // The "included from" lines too.
    assert!(m.matches("included from").count() <= 6, "{m}");
    assert!(m.len() < 3000, "{} bytes: {m}", m.len());

    // A budget above the chain: all 4,000 levels run.
    let budgets = Budgets {
        call_depth: 10_000,
        ..Budgets::default()
    };
    let f = first.clone();
    within(20, move || run_file(&f, budgets).map(|_| ())).unwrap();

    // A budget just below the chain stops it at its end.
    let budgets = Budgets {
        call_depth: 3998,
        ..Budgets::default()
    };
    let m = within(20, move || message(&run_file(&first, budgets).unwrap_err()));
    assert!(m.contains("f3998.des:1:6"), "{m}");
    assert!(m.contains("budget of 3998"), "{m}");
}

// Item 3: only regular files, bounded reads.

#[cfg(unix)]
#[test]
fn call_of_a_fifo_is_refused_without_hanging() {
    let d = Dir::new();
    let fifo = d.path("pipe.des");
    let status = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(status.success());
    let scene = d.write("scene.des", "ident\ncall pipe.des\n");
    let m = within(10, move || {
        message(&run_file(&scene, Budgets::default()).err().unwrap())
    });
    assert!(m.contains("FIFO"), "{m}");
    assert!(m.contains("pipe.des"), "{m}");
    assert!(m.contains("scene.des:2:6"), "{m}");
    // As geometry: a FIFO is not a geometry file.
    std::fs::rename(&fifo, d.path("det/pipe.det")).unwrap();
    let scene = d.write("scene.des", "ident\ngetobj pipe\n");
    let m = within(10, move || {
        message(&run_file(&scene, Budgets::default()).err().unwrap())
    });
    assert!(m.contains("no geometry file"), "{m}");
    let det = d.path("det/pipe.det");
    let m = within(10, move || {
        message(&plytrace::internal::scene::object_file::read_det(&det).unwrap_err())
    });
    assert!(m.contains("FIFO"), "{m}");
}

#[cfg(unix)]
#[test]
fn dev_zero_and_directories_are_refused() {
    let d = Dir::new();
    let scene = d.write("scene.des", "call /dev/zero\n");
    let m = within(10, move || {
        message(&run_file(&scene, Budgets::default()).err().unwrap())
    });
    assert!(m.contains("/dev/zero"), "{m}");
    assert!(m.contains("character device"), "{m}");
    let m = within(10, || {
        message(
            &plytrace::internal::scene::object_file::read_det(Path::new("/dev/zero")).unwrap_err(),
        )
    });
    assert!(m.contains("character device"), "{m}");
    let m = message(&d.run("call det\n").err().unwrap());
    assert!(m.contains("a directory"), "{m}");
}

#[test]
fn a_file_over_the_size_limit_is_refused_before_reading() {
    let d = Dir::new();
    // Sparse files: nothing is written.
    let big = d.path("big.des");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(plytrace::internal::scene::interpreter::MAX_SCENE_BYTES + 1)
        .unwrap();
    let m = within(10, move || {
        message(&run_file(&big, Budgets::default()).unwrap_err())
    });
    assert!(m.contains("more than the 16777216 bytes"), "{m}");
    let big = d.path("det/big.det");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(plytrace::internal::scene::object_file::MAX_INPUT_BYTES + 1)
        .unwrap();
    let m = within(10, move || {
        message(&plytrace::internal::scene::object_file::read_det(&big).unwrap_err())
    });
    assert!(m.contains("more than the 1073741824 bytes"), "{m}");
}

// Item 4: the polygon budget.

#[test]
fn geodesic_1024_is_refused_at_once() {
    let d = Dir::new();
    let m = within(5, move || {
        let start = std::time::Instant::now();
        let m = message(
            &d.run("ident\ndefobj ball\n  geodesic 1024\nendobj\n")
                .err()
                .unwrap(),
        );
        assert!(start.elapsed() < Duration::from_secs(1));
        m
    });
    assert!(m.contains("scene.des:3:3"), "{m}");
    assert!(m.contains("20971520"), "{m}");
    assert!(m.contains("--max-polygons"), "{m}");
}

#[test]
fn callobj_trees_that_multiply_are_refused() {
    let d = Dir::new();
    d.write("l0.des", &"callobj 1\n".repeat(10));
    d.write("l1.des", &"call l0.des\n".repeat(10));
    d.write("l2.des", &"call l1.des\n".repeat(10));
    let budgets = Budgets {
        polygons: 1000,
        ..Budgets::default()
    };
    let e = d
        .run_with("ident\ndefobj cube 1\nendobj\ncall l2.des\n", budgets)
        .expect_err("refused");
    let m = message(&e);
    assert!(m.contains("l0.des:"), "{m}");
    assert!(m.contains("`callobj 1` (6 polygons)"), "{m}");
    assert!(m.contains("budget of 1000"), "{m}");
    assert!(m.contains("--max-polygons"), "{m}");
    // 166 copies fit besides the original.
    let i = d.run_with("ident\ndefobj cube 1\nendobj\ncall l1.des\n", budgets);
    assert_eq!(i.unwrap().scene().polygon_count(), 606);
}

#[test]
fn polygons_read_from_files_count() {
    let d = Dir::new();
    let budgets = Budgets {
        polygons: 11,
        ..Budgets::default()
    };
    let m = message(
        &d.run_with("ident\ngetobj cube\ngetobj cube\n", budgets)
            .err()
            .unwrap(),
    );
    assert!(m.contains("scene.des:3:1"), "{m}");
    assert!(m.contains("--max-polygons"), "{m}");
}

// Item 7: parse whole before running.

#[derive(Default)]
struct Runs(usize);

impl plytrace::internal::scene::Host for Runs {
    fn run(&mut self, _: &plytrace::internal::scene::Scene, _: bool) -> plytrace::Result<()> {
        self.0 += 1;
        Ok(())
    }
}

#[test]
fn an_error_on_line_200_means_nothing_ran() {
    let d = Dir::new();
    let mut text = String::from("ident\nrun\ngetobj cube\n");
    while text.lines().count() < 199 {
        text.push_str("translate 0 0 0\n");
    }
    text.push_str("scale 1 x 1\n");
    let p = d.write("scene.des", &text);
    let mut i = Interpreter::new();
    let mut runs = Runs::default();
    let e = i.execute_file(&p, true, &mut runs).unwrap_err();
    let m = message(&e);
    assert!(m.contains("scene.des:200:9"), "{m}");
    assert_eq!(runs.0, 0, "a run before the bad line");
    assert_eq!(i.scene().objects.len(), 0, "a statement ran");
    // Unknown commands and argument counts too.
    for bad in [
        "frobnicate\n",
        "color 1 1\n",
        "setmode v maybe\n",
        "lookat(1, 2)\n",
    ] {
        let p = d.write("scene.des", &format!("run\n{bad}"));
        let mut runs = Runs::default();
        let e = Interpreter::new().execute_file(&p, true, &mut runs);
        assert!(e.is_err(), "{bad}");
        assert_eq!(runs.0, 0, "{bad}");
    }
}

#[test]
fn a_called_file_is_checked_whole_when_the_call_is_reached() {
    let d = Dir::new();
    d.write("sub.des", "run\nscale 1 2\n");
    let p = d.write("scene.des", "run\ncall sub.des\n");
    let mut runs = Runs::default();
    let e = Interpreter::new()
        .execute_file(&p, true, &mut runs)
        .unwrap_err();
    let m = message(&e);
    assert!(m.contains("sub.des:2:1"), "{m}");
    assert!(m.contains("included from"), "{m}");
    assert_eq!(runs.0, 1, "the run of scene.des only");
}

// Item 8: quoted input is short and printable.

#[test]
fn messages_escape_control_characters_and_truncate_tokens() {
    let d = Dir::new();
    let token = format!("\x1b[2J\x00{}", "x".repeat(1_000_000));
    let m = message(&d.run(&format!("ident\n{token} 1 2\n")).err().unwrap());
    assert!(!m.contains('\x1b') && !m.contains('\0'), "{m:?}");
    assert!(m.contains("\\x1b[2J\\x00"), "{m:?}");
    assert!(m.contains("characters)"), "{m:?}");
    assert!(m.len() < 1000, "{} bytes", m.len());
    let m = message(&d.run("call a\x07b\x7f.des\n").err().unwrap());
    assert!(m.contains("a\\x07b\\x7f.des"), "{m:?}");
    assert!(!m.contains('\x07') && !m.contains('\x7f'), "{m:?}");
    // A long line with a bad number in the middle.
    let line = format!("color 1 1 {}\x1b", "9".repeat(100_000));
    let m = message(&d.run(&line).err().unwrap());
    assert!(!m.contains('\x1b'), "{m:?}");
    assert!(m.len() < 1000, "{} bytes", m.len());
}

// Item 9: warnings counted per kind.

#[test]
fn repeated_warnings_are_counted() {
    let d = Dir::new();
    let mut det = String::from("title flat\ndata\n3 100\n0 0 0\n1 0 0\n2 0 0\n");
    det.push_str(&"3 1 2 3\n".repeat(100));
    d.write("det/flat.det", &det);
    let mut i = d.run("ident\ngetobj flat\ngetobj flat\n").unwrap();
    let w = i.take_warnings();
    assert_eq!(w.len(), 6, "{w:?}");
    let last = w[5].to_string();
    assert!(
        last.contains("... and 195 more degenerate polygon warnings"),
        "{last}"
    );
    assert!(i.take_warnings().is_empty());
}

#[test]
fn object_file_messages_are_short_and_printable() {
    let d = Dir::new();
    let det = format!("title bad\ndata\n\x1b[31m{} 1\n", "7".repeat(100_000));
    d.write("det/bad.det", &det);
    let m = message(&d.run("ident\ngetobj bad\n").unwrap_err());
    assert!(m.contains("bad.det:3:1"), "{m:?}");
    assert!(!m.contains('\x1b'), "{m:?}");
    assert!(m.contains("\\x1b[31m"), "{m:?}");
    assert!(m.len() < 1000, "{} bytes", m.len());
}

#[test]
fn a_det_file_declaring_too_many_polygons_is_refused_before_reading_them() {
    let d = Dir::new();
    d.write(
        "det/huge.det",
        "title huge\ndata\n3 4000000000\n0 0 0\n1 0 0\n0 1 0\n3 1 2 3\n",
    );
    let m = message(&d.run("ident\ngetobj huge\n").unwrap_err());
    assert!(m.contains("huge.det:3:"), "{m}");
    assert!(m.contains("included from "), "{m}");
    assert!(m.contains("scene.des:2:1"), "{m}");
    assert!(m.contains("4000000000 polygons"), "{m}");
    assert!(m.contains("--max-polygons"), "{m}");
}

#[test]
fn long_object_names_are_shortened_in_messages() {
    let d = Dir::new();
    let name = format!("\x1b]0;{}", "n".repeat(100_000));
    let m = message(
        &d.run(&format!("ident\ndefobj {name}\nendobj\n"))
            .unwrap_err(),
    );
    assert!(m.contains("no geometry file"), "{m:?}");
    assert!(!m.contains('\x1b'), "{m:?}");
    assert!(m.len() < 3000, "{} bytes", m.len());
}

//! The manual's programs rftb1-4 and getrgb against hostile command lines
//! and inputs: no input written over, no panic, no allocation past the
//! budgets, no output the file size limit would cut, and on SIGINT,
//! SIGTERM or SIGHUP a prompt end that leaves nothing behind.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use plytrace::internal::tree::{Record, RecordStream, Shades};

const RFTB1: &str = env!("CARGO_BIN_EXE_rftb1");
const RFTB2: &str = env!("CARGO_BIN_EXE_rftb2");
const RFTB4: &str = env!("CARGO_BIN_EXE_rftb4");
const GETRGB: &str = env!("CARGO_BIN_EXE_getrgb");

fn run(bin: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(bin)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit status 1 with a message holding every one of `words`.
fn refused(o: &Output, words: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    for w in words {
        assert!(e.contains(w), "`{w}` not in: {e}");
    }
}

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A tree of `n` nested squares at level 1 and a background, front to
/// back, pre-blended (one level: every tiler takes it).
fn write_tree(dir: &Path, name: &str, n: usize) -> Vec<u8> {
    let records = (0..n)
        .map(|i| {
            let t = (i % 50) as f32 / 100.0;
            Record {
                level: 1,
                points: vec![[t, t], [t, 1.0 - t], [1.0 - t, 1.0 - t], [1.0 - t, t]],
                shades: Shades::Faceted([i as u8, 100, 50]),
            }
        })
        .collect();
    let stream = RecordStream {
        records,
        background: Some([0, 0, 64]),
        front_to_back: true,
        blended: true,
    };
    let bytes = stream.to_bytes();
    std::fs::write(dir.join(name), &bytes).unwrap();
    bytes
}

#[test]
fn rftb_never_writes_over_its_tree() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tree = write_tree(d, "t.out", 2);
    // The output seed names the tree: rftb4's pixel-struct file would be it.
    for args in [
        vec!["t.out", "t.out", "8", "8"],
        vec!["t", "./t.out", "8", "8"],
    ] {
        let o = run(RFTB4, d, &args);
        refused(&o, &["t.out", "the input"]);
    }
    // Another name for the same file.
    std::fs::hard_link(d.join("t.out"), d.join("link")).unwrap();
    refused(&run(RFTB4, d, &["t", "link", "8", "8"]), &["link", "t.out"]);
    std::fs::remove_file(d.join("link")).unwrap();
    // The log is not an output either.
    refused(
        &run(RFTB4, d, &["t", "rftb4.log", "8", "8"]),
        &["rftb4.log", "log"],
    );
    assert_eq!(std::fs::read(d.join("t.out")).unwrap(), tree);
}

#[test]
fn getrgb_never_writes_over_its_inputs_or_one_output_over_another() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_tree(d, "t.out", 2);
    let o = run(RFTB4, d, &["t", "ps", "4", "4"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ps = std::fs::read(d.join("ps")).unwrap();
    let frag = std::fs::read(d.join("ps.frag")).unwrap();
    let before = listing(d);
    for (png, words) in [
        ("ps", vec!["ps", "the input"]),
        ("./ps.frag", vec!["ps.frag", "the input"]),
        ("ps.g", vec!["ps.g", "also the output"]),
        ("getrgb.log", vec!["getrgb.log", "log"]),
    ] {
        let o = run(GETRGB, d, &["ps", "--png", png]);
        refused(&o, &words);
    }
    assert_eq!(std::fs::read(d.join("ps")).unwrap(), ps);
    assert_eq!(std::fs::read(d.join("ps.frag")).unwrap(), frag);
    assert_eq!(listing(d), before);
}

#[test]
fn getrgb_refuses_resolutions_past_the_budget_without_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("ps"), [0u8; 48]).unwrap();
    for res in [
        ["4294967295", "4294967295"],
        ["65536", "65536"],
        ["4294967295", "1"],
    ] {
        let o = run(GETRGB, d, &["ps", res[0], res[1], "-p"]);
        refused(&o, &["--max-pixels", "exceeds the budget"]);
    }
    // Within the budget, a resolution that is not the file's.
    refused(
        &run(GETRGB, d, &["ps", "1000", "1000"]),
        &["is the resolution right"],
    );
    assert_eq!(listing(d), ["ps"]);
}

#[test]
fn special_files_and_oversized_inputs_are_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::os::unix::fs::symlink("/dev/zero", d.join("z.out")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", d.join("z")).unwrap();
    for bin in [RFTB1, RFTB4] {
        refused(&run(bin, d, &["z", "o", "8", "8"]), &["character device"]);
    }
    refused(&run(GETRGB, d, &["z"]), &["character device"]);
    // A sparse file past the budgets: refused by its size, not read.
    let big = std::fs::File::create(d.join("big.out")).unwrap();
    big.set_len(2 << 30).unwrap();
    let start = Instant::now();
    refused(
        &run(RFTB1, d, &["big", "o", "8", "8"]),
        &["big.out", "--max-frame-memory"],
    );
    std::fs::rename(d.join("big.out"), d.join("big")).unwrap();
    refused(&run(GETRGB, d, &["big"]), &["big", "--max-frame-memory"]);
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "read, not refused"
    );
    let mut left = listing(d);
    left.retain(|n| !n.ends_with(".log"));
    assert_eq!(left, ["big", "z", "z.out"]);
}

#[test]
fn resolutions_and_act_lines_past_the_budgets_are_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_tree(d, "t.out", 2);
    let start = Instant::now();
    for (bin, args, words) in [
        (
            RFTB1,
            vec!["t", "o", "8192", "8192", "8192"],
            vec!["act-lines 8192", "--max-frame-memory"],
        ),
        (
            RFTB1,
            vec!["t", "o", "1000000000", "1"],
            vec!["act-lines", "--max-frame-memory"],
        ),
        (
            RFTB1,
            vec!["t", "o", "1000000000", "1000000000"],
            vec!["--max-pixels"],
        ),
        (
            RFTB2,
            vec!["t", "o", "65536", "65536"],
            vec!["65536 x 65536", "--max-pixels"],
        ),
        (
            RFTB4,
            vec!["t", "o", "64", "64", "--max-pixels", "100"],
            vec!["4096 pixels", "budget of 100 pixels"],
        ),
    ] {
        refused(&run(bin, d, &args), &words);
    }
    assert!(start.elapsed() < Duration::from_secs(30));
    // A budget raised lets it through.
    let o = run(
        RFTB1,
        d,
        &["t", "o", "64", "64", "64", "--max-frame-memory=2048"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut left = listing(d);
    left.retain(|n| !n.ends_with(".log"));
    assert_eq!(left, ["o.a", "o.b", "o.g", "o.r", "t.out"]);
}

#[test]
fn an_output_past_the_file_size_limit_is_refused_before_it_is_started() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_tree(d, "t.out", 2);
    // 1000 blocks of 512 bytes: o.m, 2 x 1024 x 1024 bytes, would not fit.
    let o = Command::new("sh")
        .args(["-c", &format!("ulimit -f 1000; exec {RFTB2} t o 1024 1024")])
        .current_dir(d)
        .output()
        .unwrap();
    refused(&o, &["o.m", "file size limit", "ulimit -f"]);
    assert_eq!(listing(d), ["t.out"]);
}

/// Starts `bin` in `dir`, waits until it writes a temporary file, sends
/// `signal`, and checks that it ends within two seconds with status
/// 128 + the signal's number leaving only `inputs` in the directory.
fn interrupted(bin: &str, dir: &Path, args: &[&str], signal: &str, status: i32, inputs: &[&str]) {
    let mut child = Command::new(bin)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let writing = || {
        std::fs::read_dir(dir).unwrap().any(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            name.starts_with('.') && name.ends_with(".tmp") && e.metadata().unwrap().len() > 0
        })
    };
    while !writing() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "{bin} ended before writing"
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{bin}: no output"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let sent = Instant::now();
    let kill = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        assert!(
            sent.elapsed() < Duration::from_secs(10),
            "{bin} still running"
        );
        std::thread::sleep(Duration::from_millis(5));
    };
    let took = sent.elapsed();
    assert_eq!(code, Some(status), "{bin} after SIG{signal}");
    // A second, with both cores busy with other tests.
    assert!(
        took < Duration::from_secs(10),
        "{bin} took {took:?} to stop"
    );
    assert_eq!(listing(dir), inputs, "{bin} after SIG{signal}");
}

#[test]
fn separations_stop_on_signals_and_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_tree(d, "t.out", 20);
    let args = ["t", "o", "8192", "8192", "-y"];
    interrupted(RFTB2, d, &args, "INT", 130, &["t.out"]);
    interrupted(RFTB1, d, &args, "TERM", 143, &["t.out"]);
}

#[test]
fn pixel_structs_stop_on_signals_and_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_tree(d, "t.out", 20);
    let args = ["t", "o", "8192", "8192"];
    interrupted(RFTB4, d, &args, "HUP", 129, &["t.out"]);
}

#[test]
fn getrgb_stops_on_signals_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 8192 x 8192 simple pixel-structs, black: a sparse file of zeros.
    let f = std::fs::File::create(d.join("ps")).unwrap();
    f.set_len(8192 * 8192 * 8).unwrap();
    drop(f);
    let args = ["ps", "8192", "8192", "-p"];
    interrupted(GETRGB, d, &args, "TERM", 143, &["ps"]);
    interrupted(GETRGB, d, &args, "INT", 130, &["ps"]);
}

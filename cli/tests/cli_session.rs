//! The `plytrace` program as a session (004 appendix, plytrace manual
//! page, and the conventions of issue 9): Ctrl-C cancels the render and
//! the session goes on, `clear` shows the background, the `setmode d`
//! timings are measured, and the prompt keeps its history.

#[path = "../../tests/support/mod.rs"]
mod support;

use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::thread;
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_plytrace");

/// Longest a cancelled run may go on before the test fails.
const TIMEOUT: Duration = Duration::from_secs(60);

/// Starts `plytrace ARGS` in `dir` with piped stdin, stdout and stderr.
fn start(dir: &Path, args: &[&str]) -> Child {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start plytrace")
}

/// Stdout's lines as they come, on a channel.
fn lines_of(child: &mut Child) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    let out = child.stdout.take().expect("piped");
    thread::spawn(move || {
        for line in BufReader::new(out).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// Waits for a line containing `what`; returns every line seen.
fn wait_for(rx: &mpsc::Receiver<String>, what: &str) -> Vec<String> {
    let mut seen = Vec::new();
    let deadline = Instant::now() + TIMEOUT;
    while Instant::now() < deadline {
        match rx.recv_timeout(Duration::from_millis(100)) {
            Ok(line) => {
                let found = line.contains(what);
                seen.push(line);
                if found {
                    return seen;
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
    }
    panic!("no line with {what:?}; stdout so far: {seen:#?}");
}

fn interrupt(child: &Child) {
    let ok = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill(1)")
        .success();
    assert!(ok, "kill -INT failed");
}

/// Waits for the end; (status, stderr).
fn finish(mut child: Child) -> (Option<i32>, String) {
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            panic!("plytrace did not stop within {TIMEOUT:?} of Ctrl-C");
        }
        thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        e.read_to_string(&mut err).expect("stderr");
    }
    assert!(!err.contains("panicked"), "{err}");
    (status.code(), err)
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// office2 with shadows at 8192 x 8192 takes far longer than the test may
/// wait, so only a working Ctrl-C ends it in time.
fn long_render_args(scene: &str) -> Vec<String> {
    ["-i", "-f", scene, "-o", "out.png", "--size", "8192x8192"]
        .map(String::from)
        .to_vec()
}

#[test]
fn ctrl_c_cancels_a_batch_render_with_status_130_and_writes_nothing() {
    let scene = support::scene_fixture("office2.des");
    let dir = tempfile::tempdir().expect("temp dir");
    let args = long_render_args(scene.to_str().expect("utf-8 path"));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut child = start(dir.path(), &args);
    let rx = lines_of(&mut child);
    wait_for(&rx, "Building image.");
    interrupt(&child);
    let (code, err) = finish(child);
    assert_eq!(code, Some(130), "{err}");
    assert!(err.contains("cancelled (Ctrl-C)"), "{err}");
    assert!(
        files(dir.path()).iter().all(|f| f == "plytrace.log"),
        "left behind: {:?}",
        files(dir.path())
    );
}

#[test]
fn ctrl_c_returns_to_the_session_which_goes_on() {
    let scene = support::scene_fixture("office2.des");
    let dir = tempfile::tempdir().expect("temp dir");
    // The session reads commands from stdin (not a terminal here).
    let mut child = start(dir.path(), &["-o", "out.png", "--size", "8192x8192"]);
    let rx = lines_of(&mut child);
    let mut stdin = child.stdin.take().expect("piped");
    writeln!(stdin, "get {}", scene.display()).expect("write");
    writeln!(stdin, "run y").expect("write");
    wait_for(&rx, "Building image.");
    interrupt(&child);
    // The next command is answered: the session survived the Ctrl-C.
    writeln!(stdin, "help clear").expect("write");
    wait_for(&rx, "clear the frame buffer");
    writeln!(stdin, "quit").expect("write");
    drop(stdin);
    let (code, err) = finish(child);
    assert!(err.contains("cancelled (Ctrl-C)"), "{err}");
    // A piped session that met an error ends with status 1.
    assert_eq!(code, Some(1), "{err}");
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn clear_writes_the_background_at_the_run_size() {
    let dir = support::cube_and_square_dir();
    let scene = "resolution 40 30\nbackground 1 0.5 0\nfname shown\nclear\n";
    std::fs::write(dir.path().join("c.des"), scene).expect("write");
    let out = Command::new(BIN)
        .args(["-i", "-f", "c.des"])
        .current_dir(dir.path())
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("Cleared shown.png"), "{stdout}");
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(dir.path().join("shown.png")).expect("written"),
    ));
    let mut reader = decoder.read_info().expect("png");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("frame");
    assert_eq!((info.width, info.height), (40, 30));
    for px in buf[..info.buffer_size()].chunks(3) {
        assert_eq!(px, [255, 128, 0]);
    }
}

#[test]
fn debug_timings_are_measured_on_the_tree_path() {
    let dir = support::cube_and_square_dir();
    let scene = "resolution 32 32\nsetmode 1\npushmatrix\nident\ntranslate 0 0 -5\n\
                 defobj cube\nendobj\npopmatrix\nperspective 45 1 0.1 100\n";
    std::fs::write(dir.path().join("d.des"), scene).expect("write");
    let out = Command::new(BIN)
        .args(["-i", "-f", "d.des", "-o", "d.png"])
        .current_dir(dir.path())
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let line = stdout
        .lines()
        .find(|l| l.contains("virtual image tree"))
        .unwrap_or_else(|| panic!("no timing line:\n{stdout}"));
    assert!(!line.contains(" 0ns"), "a stage timed at zero: {line}");
    // The vector painter and an image-space algorithm name their own.
    for args in [
        &["-o", "d.svg"][..],
        &["-o", "d.png", "--visibility", "z-buffer"],
    ] {
        let out = Command::new(BIN)
            .args(["-f", "d.des"])
            .args(args)
            .current_dir(dir.path())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .and_then(|mut c| {
                c.stdin.take().expect("piped").write_all(b"run\n")?;
                c.wait_with_output()
            })
            .expect("run");
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout
            .lines()
            .find(|l| l.contains("GeometryStats"))
            .unwrap_or_else(|| panic!("{args:?}: no timing line:\n{stdout}"));
        assert!(line.contains("paint"), "{args:?}: {line}");
        assert!(
            !line.contains(" 0ns"),
            "{args:?}: a stage timed at zero: {line}"
        );
    }
}

/// script(1) gives the program a terminal, so the line editor runs,
/// completes with Tab and keeps its history in `PLYTRACE_HISTORY`.
#[test]
fn the_prompt_completes_and_keeps_its_history_between_sessions() {
    let dir = tempfile::tempdir().expect("temp dir");
    let history = dir.path().join("data/plytrace/history");
    let command = format!("{BIN} -q");
    let mut child = Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .current_dir(dir.path())
        .env("PLYTRACE_HISTORY", &history)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("script(1) is needed for this test");
    let mut stdin = child.stdin.take().expect("piped");
    // Give the editor time to take the terminal before typing.
    thread::sleep(Duration::from_millis(300));
    stdin.write_all(b"ambient 0.25 0.5 1\r").expect("type");
    thread::sleep(Duration::from_millis(300));
    // Tab completes a command name (the history shows the whole name).
    stdin.write_all(b"backg\t0.2 0.2 0.2\r").expect("type");
    thread::sleep(Duration::from_millis(300));
    stdin.write_all(b"quit\r").expect("type");
    let (code, err) = finish(child);
    assert_eq!(code, Some(0), "{err}");
    let kept = std::fs::read_to_string(&history).expect("history written");
    assert!(kept.contains("ambient 0.25 0.5 1"), "{kept}");
    assert!(kept.contains("background 0.2 0.2 0.2"), "{kept}");
}

/// A whole-frame render (ray casting, PPM) past `--max-frame-memory` is
/// refused before anything is allocated; the streamed PNG is not limited.
#[test]
fn whole_frames_past_the_memory_budget_are_refused_at_once() {
    let dir = support::cube_and_square_dir();
    let scene = "resolution 64 64\npushmatrix\nident\ntranslate 0 0 -5\n\
                 defobj cube\nendobj\npopmatrix\nperspective 45 1 0.1 100\n";
    std::fs::write(dir.path().join("s.des"), scene).expect("write");
    for extra in [
        &["-o", "x.png", "--visibility", "ray-cast"][..],
        &["-o", "x.ppm"],
    ] {
        let mut args = vec!["-i", "-f", "s.des", "--size", "16384x16384"];
        args.extend_from_slice(extra);
        let out = Command::new(BIN)
            .args(&args)
            .current_dir(dir.path())
            .output()
            .expect("run");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains("--max-frame-memory"), "{stderr}");
        assert!(!dir.path().join(extra[1]).exists());
    }
    // Raised, a small whole frame is fine.
    let out = Command::new(BIN)
        .args([
            "-i",
            "-f",
            "s.des",
            "-o",
            "y.ppm",
            "--max-frame-memory",
            "1",
        ])
        .current_dir(dir.path())
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

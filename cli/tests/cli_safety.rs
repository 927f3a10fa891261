//! The command line made safe and conventional (issue 9): outputs checked
//! before the render and committed together, no writing through links or
//! into special files, scene-chosen names kept inside the working
//! directory, supported extensions only, quiet broken pipes, escaped
//! control characters, `plytrace scene.des`, the aspect warning, sRGB
//! chunks, `plytrace.log`, the mkdet/mkpcl/mkvcl programs, the progress
//! bar and the budget flags.
//!
//! Every test runs the built binaries in a fresh temporary directory (the
//! working directory `work/` inside it, so that writes beside it can be
//! seen) and reads nothing outside the repository.
#![cfg(unix)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

/// The binary under test: this package's, or `PLYTRACE_TEST_BIN` (to show
/// the tests failing against an older build).
fn bin() -> String {
    std::env::var("PLYTRACE_TEST_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_plytrace").into())
}
const TIMEOUT: Duration = Duration::from_secs(20);

/// The manual's square (side 2, facing +z), from the repository.
fn square() -> String {
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tests/data/cli/square.det");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A scene that shows the square: `scene.des` and `det/square.det`.
const SCENE: &str = "background 0.2 0.4 0.6\nperspective 45 1 0.1 100\npushmatrix\nident\n\
                     type polygon open\ncolor 1 0 0\ntranslate 0 0 -5\ndefobj square\nendobj\n\
                     popmatrix\n";

struct Run {
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: Vec<u8>,
    root: tempfile::TempDir,
    args: Vec<String>,
}

impl Run {
    fn work(&self) -> PathBuf {
        self.root.path().join("work")
    }
    fn out(&self) -> String {
        String::from_utf8_lossy(&self.stdout).into_owned()
    }
    fn err(&self) -> String {
        String::from_utf8_lossy(&self.stderr).into_owned()
    }
    /// Files in the root and the working directory (relative to the
    /// root), the log excepted, sorted.
    fn files(&self) -> Vec<String> {
        list(self.root.path())
    }
    fn transcript(&self) -> String {
        format!(
            "plytrace {}\nstatus {:?}\nfiles {:?}\n--- stdout ---\n{}--- stderr ---\n{}",
            self.args.join(" "),
            self.code,
            self.files(),
            self.out(),
            self.err()
        )
    }
}

fn list(root: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).expect("list") {
            let p = e.expect("entry").path();
            if p.file_name().is_some_and(|n| n == "plytrace.log") {
                continue;
            }
            let meta = std::fs::symlink_metadata(&p).expect("metadata");
            if meta.is_dir() {
                walk(root, &p, out);
            } else {
                out.push(
                    p.strip_prefix(root)
                        .unwrap()
                        .to_string_lossy()
                        .replace('\\', "/"),
                );
            }
        }
    }
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out.sort();
    out
}

/// A new root with `work/` holding `files`; `setup` may add more.
fn prepare(files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let root = tempfile::Builder::new()
        .prefix("plytrace-safety-")
        .tempdir()
        .expect("a temporary directory");
    let work = root.path().join("work");
    std::fs::create_dir(&work).unwrap();
    for (name, bytes) in files {
        let p = work.join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }
    root
}

/// Runs `bin ARGS` in `root/work`; with `close_stdout` its stdout is a
/// pipe whose read end is closed before it starts (so that every write
/// there fails with EPIPE, whatever the timing).
fn spawn(bin: &str, root: tempfile::TempDir, args: &[&str], close_stdout: bool) -> Run {
    let stdout_to = if close_stdout {
        let (read, write) = std::io::pipe().expect("a pipe");
        drop(read);
        Stdio::from(write)
    } else {
        Stdio::piped()
    };
    spawn_with(bin, root, args, Input::Null, stdout_to)
}

/// What a run reads on stdin.
enum Input {
    Null,
    /// These bytes, then the end.
    Bytes(Vec<u8>),
    /// These bytes again and again, until the program stops reading.
    Endless(&'static [u8]),
    /// A file (a device).
    File(std::fs::File),
}

/// [`spawn`] with `stdin` and `stdout` given. The program's temporary
/// folder (`TMPDIR`) is `tmp/` in the root, so that what it leaves there
/// is seen.
fn spawn_with(
    bin: &str,
    root: tempfile::TempDir,
    args: &[&str],
    stdin: Input,
    stdout_to: Stdio,
) -> Run {
    let tmp = root.path().join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let (stdin_from, feed) = match stdin {
        Input::Null => (Stdio::null(), None),
        Input::File(f) => (Stdio::from(f), None),
        Input::Bytes(b) => (Stdio::piped(), Some((b, false))),
        Input::Endless(b) => (Stdio::piped(), Some((b.to_vec(), true))),
    };
    let mut child = Command::new(bin)
        .args(args)
        .current_dir(root.path().join("work"))
        .env("TMPDIR", &tmp)
        .stdin(stdin_from)
        .stdout(stdout_to)
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the program");
    if let (Some(mut input), Some((bytes, endless))) = (child.stdin.take(), feed) {
        thread::spawn(move || {
            use std::io::Write;
            while input.write_all(&bytes).is_ok() && endless {}
        });
    }
    let stdout = child.stdout.take().map(reader);
    let stderr = reader(child.stderr.take().unwrap());
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{bin} {args:?} still running after {TIMEOUT:?}");
        }
        thread::sleep(Duration::from_millis(5));
    };
    let run = Run {
        code: status.code().or_else(|| {
            use std::os::unix::process::ExitStatusExt;
            status.signal().map(|s| 128 + s)
        }),
        stdout: stdout.map(|h| h.join().unwrap()).unwrap_or_default(),
        stderr: stderr.join().unwrap(),
        root,
        args: args.iter().map(|s| s.to_string()).collect(),
    };
    assert!(
        !run.err().contains("panicked"),
        "panic\n{}",
        run.transcript()
    );
    run
}

fn reader(mut r: impl Read + Send + 'static) -> thread::JoinHandle<Vec<u8>> {
    thread::spawn(move || {
        let mut v = Vec::new();
        let _ = r.read_to_end(&mut v);
        v
    })
}

fn run_with(scene: &str, args: &[&str]) -> Run {
    let square = square();
    let root = prepare(&[
        ("scene.des", scene.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ]);
    spawn(&bin(), root, args, false)
}

const INPUTS: [&str; 2] = ["work/det/square.det", "work/scene.des"];

fn with_inputs(extra: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = INPUTS.iter().chain(extra).map(|s| s.to_string()).collect();
    v.sort();
    v
}

fn assert_refused(run: &Run, code: i32, message: &[&str]) {
    assert_eq!(run.code, Some(code), "status\n{}", run.transcript());
    for m in message {
        assert!(
            run.err().contains(m),
            "expected `{m}` on stderr\n{}",
            run.transcript()
        );
    }
    assert!(
        !run.out().contains("Building image."),
        "refused only after starting the render\n{}",
        run.transcript()
    );
}

fn has_srgb(path: &Path) -> bool {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG");
    reader.info().srgb.is_some()
}

// ---------------------------------------------------------------------------
// 1. Outputs checked before rendering, committed together

#[test]
fn missing_output_directory_is_refused_before_the_render() {
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "nosuch/dir/x.png",
            "--size",
            "16x16",
        ],
    );
    assert_refused(
        &run,
        1,
        &["error: nosuch/dir/x.png: the directory nosuch/dir does not exist"],
    );
    assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
}

#[test]
fn missing_id_image_directory_leaves_no_image() {
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "out.png",
            "--id-image",
            "nosuch/dir/x.png",
            "--size",
            "16x16",
        ],
    );
    assert_refused(&run, 1, &["nosuch/dir/x.png", "does not exist"]);
    assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
}

#[test]
fn tree_path_that_is_a_directory_leaves_nothing() {
    let square = square();
    let scene = format!("{SCENE}setmode o on\n");
    let root = prepare(&[
        ("scene.des", scene.as_bytes()),
        ("det/square.det", square.as_bytes()),
        ("scene.txt/keep", b""),
    ]);
    let run = spawn(
        &bin(),
        root,
        &["-i", "-f", "scene.des", "--size", "16x16"],
        false,
    );
    assert_refused(&run, 1, &["scene.txt: is a directory"]);
    assert_eq!(
        run.files(),
        with_inputs(&["work/scene.txt/keep"]),
        "{}",
        run.transcript()
    );
    // Control: without the directory, all four outputs are written.
    let scene = format!("{SCENE}setmode o on\n");
    let run = run_with(
        &scene,
        &[
            "-i",
            "-f",
            "scene.des",
            "--id-image",
            "ids.png",
            "--size",
            "16x16",
        ],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&[
            "work/ids.png",
            "work/scene.out",
            "work/scene.png",
            "work/scene.txt"
        ]),
        "{}",
        run.transcript()
    );
}

#[test]
fn failure_after_a_run_keeps_only_the_earlier_runs_files() {
    // The second run fails (its name leaves the working directory): the
    // first run's image stays, complete, and the message names it.
    let scene = format!("{SCENE}fname first\nrun\nfname ../second\nrun\n");
    let run = run_with(&scene, &["-i", "-f", "scene.des", "--size", "16x16"]);
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&["work/first.png"]),
        "{}",
        run.transcript()
    );
    assert!(
        run.err()
            .contains("note: the runs before the error wrote first.png"),
        "{}",
        run.transcript()
    );
    let decoded = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(run.work().join("first.png")).unwrap(),
    ))
    .read_info()
    .unwrap();
    assert_eq!((decoded.info().width, decoded.info().height), (16, 16));
}

// ---------------------------------------------------------------------------
// 2. Never through a link, FIFO or device

#[test]
fn symlink_output_is_refused_and_left_alone() {
    for flag in ["-o", "--id-image"] {
        let square = square();
        let root = prepare(&[
            ("scene.des", SCENE.as_bytes()),
            ("det/square.det", square.as_bytes()),
            ("target.png", b"keep"),
        ]);
        let work = root.path().join("work");
        std::os::unix::fs::symlink("target.png", work.join("link.png")).unwrap();
        let args: Vec<&str> = if flag == "-o" {
            vec!["-i", "-f", "scene.des", "-o", "link.png", "--size", "16x16"]
        } else {
            vec![
                "-i",
                "-f",
                "scene.des",
                "-o",
                "out.png",
                "--id-image",
                "link.png",
                "--size",
                "16x16",
            ]
        };
        let run = spawn(&bin(), root, &args, false);
        assert_refused(&run, 1, &["link.png: is a symbolic link"]);
        let meta = std::fs::symlink_metadata(work.join("link.png")).unwrap();
        assert!(meta.file_type().is_symlink(), "{}", run.transcript());
        assert_eq!(std::fs::read(work.join("target.png")).unwrap(), b"keep");
        assert_eq!(
            run.files(),
            with_inputs(&["work/link.png", "work/target.png"]),
            "{}",
            run.transcript()
        );
    }
}

#[test]
fn fifo_output_is_refused_and_left_alone() {
    let square = square();
    let root = prepare(&[
        ("scene.des", SCENE.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ]);
    let work = root.path().join("work");
    let made = Command::new("mkfifo")
        .arg(work.join("fifo.png"))
        .status()
        .expect("run mkfifo");
    assert!(made.success(), "mkfifo failed");
    let run = spawn(
        &bin(),
        root,
        &["-i", "-f", "scene.des", "-o", "fifo.png", "--size", "16x16"],
        false,
    );
    assert_refused(&run, 1, &["fifo.png: is not a regular file"]);
    use std::os::unix::fs::FileTypeExt;
    let meta = std::fs::symlink_metadata(work.join("fifo.png")).unwrap();
    assert!(meta.file_type().is_fifo(), "{}", run.transcript());
}

#[test]
fn socket_output_is_refused_and_left_alone() {
    // A special file other than a FIFO (the same check refuses devices;
    // they cannot be made without privileges).
    let square = square();
    let root = prepare(&[
        ("scene.des", SCENE.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ]);
    let work = root.path().join("work");
    let _listener = std::os::unix::net::UnixListener::bind(work.join("sock.png")).unwrap();
    let run = spawn(
        &bin(),
        root,
        &["-i", "-f", "scene.des", "-o", "sock.png", "--size", "16x16"],
        false,
    );
    assert_refused(&run, 1, &["sock.png: is not a regular file"]);
    use std::os::unix::fs::FileTypeExt;
    let meta = std::fs::symlink_metadata(work.join("sock.png")).unwrap();
    assert!(meta.file_type().is_socket(), "{}", run.transcript());
}

// ---------------------------------------------------------------------------
// 3. Scene-chosen names stay inside the working directory

#[test]
fn fname_outside_the_working_directory_is_refused() {
    let outside = tempfile::tempdir().unwrap();
    let abs = outside.path().join("abs");
    let abs = abs.to_str().unwrap();
    for (fname, mode) in [
        ("../up", ""),
        (abs, ""),
        ("../tree", "setmode o on\n"),
        ("sub/../../x", ""),
    ] {
        let scene = format!("{SCENE}{mode}fname {fname}\n");
        let run = run_with(&scene, &["-i", "-f", "scene.des", "--size", "16x16"]);
        assert_refused(
            &run,
            1,
            &["must stay inside the working directory", "--allow-outside"],
        );
        assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
    }
    assert_eq!(std::fs::read_dir(outside.path()).unwrap().count(), 0);

    // Through a directory that is a link out of the working directory.
    let square = square();
    let scene = format!("{SCENE}fname sub/x\n");
    let root = prepare(&[
        ("scene.des", scene.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ]);
    std::os::unix::fs::symlink(outside.path(), root.path().join("work/sub")).unwrap();
    let run = spawn(
        &bin(),
        root,
        &["-i", "-f", "scene.des", "--size", "16x16"],
        false,
    );
    assert_refused(
        &run,
        1,
        &["leads outside the working directory", "--allow-outside"],
    );
    assert_eq!(std::fs::read_dir(outside.path()).unwrap().count(), 0);
}

#[test]
fn allow_outside_and_command_line_names_may_leave() {
    let scene = format!("{SCENE}setmode o on\nfname ../up\n");
    let run = run_with(
        &scene,
        &[
            "-i",
            "-f",
            "scene.des",
            "--size",
            "16x16",
            "--allow-outside",
        ],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&["up.out", "up.png", "up.txt"]),
        "{}",
        run.transcript()
    );
    // -o is the user's own name.
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "../mine.png",
            "--size",
            "16x16",
        ],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&["mine.png"]),
        "{}",
        run.transcript()
    );
    // With -o the scene's fname names nothing, so it is not refused.
    let scene = format!("{SCENE}fname ../up\n");
    let run = run_with(
        &scene,
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "16x16"],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&["work/out.png"]),
        "{}",
        run.transcript()
    );
}

// ---------------------------------------------------------------------------
// 4. Only formats that are written

#[test]
fn unsupported_extension_is_refused() {
    for args in [
        &["-i", "-f", "scene.des", "-o", "x.jpg"][..],
        &["-i", "-f", "scene.des", "--output", "x.JPEG"],
        &["-i", "-f", "scene.des", "-o", "noextension"],
    ] {
        let run = run_with(SCENE, args);
        assert_refused(&run, 2, &["the supported image formats are .png and .ppm"]);
        assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
    }
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "x.png",
            "--id-image",
            "ids.ppm",
        ],
    );
    assert_refused(&run, 2, &["--id-image", "PNG only"]);
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "x.png",
            "--id-image",
            "x.png",
        ],
    );
    assert_refused(&run, 2, &["the image and --id-image name the same file"]);
    let run = run_with(
        SCENE,
        &["-i", "-f", "scene.des", "-o", "x.PPM", "--size", "8x8"],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(
        std::fs::read(run.work().join("x.PPM"))
            .unwrap()
            .starts_with(b"P6\n8 8\n255\n")
    );
}

/// Stacked transparent squares: each is a record over the same pixels, so
/// scan conversion time grows with their number times the image; the
/// overdraw budget refuses them before tiling and nothing is written.
#[test]
fn stacked_transparent_squares_past_the_overdraw_budget_are_refused() {
    let mut scene = String::from(
        "perspective 45 1 0.1 100\npushmatrix\nident\ntype polygon open\ntransparency 0.9 0\n",
    );
    for _ in 0..60 {
        scene.push_str(
            "translate 0 0 -0.01\npushmatrix\ntranslate 0 0 -5\ndefobj square\nendobj\npopmatrix\n",
        );
    }
    scene.push_str("popmatrix\n");
    let args = |budget: &'static str| {
        [
            "-i",
            "-f",
            "scene.des",
            "-o",
            "x.png",
            "--size",
            "16x16",
            "--max-overdraw",
            budget,
        ]
    };
    let run = run_with(&scene, &args("10"));
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    for m in [
        "60 records",
        "times over",
        "the budget of 10 times",
        "`--max-overdraw N` raises it",
    ] {
        assert!(
            run.err().contains(m),
            "expected `{m}`\n{}",
            run.transcript()
        );
    }
    assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
    let run = run_with(&scene, &args("20"));
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&["work/x.png"]),
        "{}",
        run.transcript()
    );
}

// ---------------------------------------------------------------------------
// 5. Broken pipes

#[test]
fn help_into_a_closed_pipe_ends_quietly() {
    let run = spawn(&bin(), prepare(&[]), &["--help"], true);
    assert!(matches!(run.code, Some(0 | 141)), "{}", run.transcript());
    assert!(run.stderr.is_empty(), "{}", run.transcript());
}

#[test]
fn statistics_into_a_closed_pipe_end_quietly_and_the_image_is_written() {
    let square = square();
    let root = prepare(&[
        ("scene.des", SCENE.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ]);
    let run = spawn(
        &bin(),
        root,
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "16x16"],
        true,
    );
    // Printing stops; the render goes on and the image is written.
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(run.work().join("out.png").is_file(), "{}", run.transcript());
    assert!(run.stderr.is_empty(), "{}", run.transcript());
}

// ---------------------------------------------------------------------------
// 6. Control characters escaped, stdout too

#[test]
fn control_characters_from_input_are_escaped() {
    let scene = format!("{SCENE}fname a\x1b[31mb\x07\n");
    let run = run_with(&scene, &["-i", "-f", "scene.des", "--size", "8x8"]);
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(
        run.out().contains("Wrote a\\x1b[31mb\\x07.png (8 x 8)"),
        "{}",
        run.transcript()
    );
    let run = run_with(
        "ident\nbogus\x1b]0;title\x07 1\n",
        &["-i", "-f", "scene.des"],
    );
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert!(
        run.err().contains("\\x1b]0;title\\x07"),
        "{}",
        run.transcript()
    );
    for r in [&run.stdout, &run.stderr] {
        assert!(
            !r.iter()
                .any(|&b| (b < 0x20 && b != b'\n' && b != b'\t') || b == 0x7f),
            "a raw control character\n{}",
            run.transcript()
        );
    }
}

#[test]
fn long_input_is_cut_in_messages() {
    let long = "x".repeat(100_000);
    let run = run_with(&format!("{long}\n"), &["-i", "-f", "scene.des"]);
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert!(
        run.stderr.len() < 20_000,
        "{} bytes of stderr",
        run.stderr.len()
    );
    assert!(run.err().contains("characters)"), "{}", run.transcript());
}

// ---------------------------------------------------------------------------
// 7. Conventions

#[test]
fn lone_scene_file_means_immediate_mode() {
    let run = run_with(SCENE, &["scene.des", "-o", "out.png", "--size", "16x16"]);
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_eq!(
        run.files(),
        with_inputs(&["work/out.png"]),
        "{}",
        run.transcript()
    );
    let run = run_with(SCENE, &["scene.des", "--size", "16x16"]);
    assert_eq!(
        run.files(),
        with_inputs(&["work/scene.png"]),
        "{}",
        run.transcript()
    );
    let run = run_with(SCENE, &["scene.des", "-f", "scene.des"]);
    assert_eq!(run.code, Some(2), "{}", run.transcript());
}

#[test]
fn size_changing_the_aspect_ratio_is_warned() {
    let run = run_with(
        SCENE,
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "32x16"],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(
        run.err()
            .contains("warning: --size 32x16 changes the aspect ratio of the scene's"),
        "{}",
        run.transcript()
    );
    let run = run_with(
        SCENE,
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "16x16"],
    );
    assert!(!run.err().contains("aspect"), "{}", run.transcript());
}

#[test]
fn every_png_has_an_srgb_chunk() {
    // Streamed (out.png alone), from a frame buffer (with an id image),
    // painted (z-buffer), the id image itself.
    for extra in [
        &[][..],
        &["--id-image", "ids.png"],
        &["--visibility", "z-buffer"],
    ] {
        let mut args = vec!["-i", "-f", "scene.des", "-o", "out.png", "--size", "16x16"];
        args.extend_from_slice(extra);
        let run = run_with(SCENE, &args);
        assert_eq!(run.code, Some(0), "{}", run.transcript());
        assert!(
            has_srgb(&run.work().join("out.png")),
            "{extra:?}: no sRGB chunk"
        );
        if !extra.is_empty() && extra[0] == "--id-image" {
            assert!(
                has_srgb(&run.work().join("ids.png")),
                "id image: no sRGB chunk"
            );
        }
    }
}

#[test]
fn runs_are_logged_in_plytrace_log() {
    // An animation of two `run`s: each rendered once, and immediate mode
    // adds no render of its own after them.
    let scene = format!("{SCENE}fname one\nrun\nrun\n");
    let run = run_with(&scene, &["-i", "-f", "scene.des", "--size", "16x16"]);
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    let log = std::fs::read_to_string(run.work().join("plytrace.log")).expect("plytrace.log");
    let lines: Vec<&str> = log.lines().collect();
    assert_eq!(lines.len(), 2, "one line per run\n{log}");
    for line in &lines {
        let date = &line[..23];
        assert!(
            date.as_bytes()[4] == b'-' && &date[10..11] == " " && date.ends_with(" UTC"),
            "{line}"
        );
        assert!(
            line.contains(" scene=scene.des image=one.png size=16x16 polygons_tiled="),
            "{line}"
        );
        assert!(line.contains(" max_depth=1 seconds="), "{line}");
    }
    // A failed run adds nothing.
    let run = run_with("bogus\n", &["-i", "-f", "scene.des"]);
    assert!(
        !run.work().join("plytrace.log").exists(),
        "{}",
        run.transcript()
    );
}

#[test]
fn help_refers_only_to_sections_that_exist() {
    let run = spawn(&bin(), prepare(&[]), &["--help"], false);
    assert_eq!(run.code, Some(0));
    let help = run.out();
    let sections: Vec<&str> = help
        .lines()
        .filter(|l| !l.starts_with(' ') && l.ends_with(':'))
        .map(|l| l.trim_end_matches(':').split(" (").next().unwrap_or(""))
        .collect();
    assert!(
        sections.contains(&"The manual's flags") && sections.contains(&"Files"),
        "{sections:?}"
    );
    for (i, _) in help.match_indices("(see ") {
        let word: String = help[i + 5..]
            .chars()
            .take_while(|c| c.is_ascii_alphabetic() || *c == ' ')
            .collect();
        let word = word.trim();
        assert!(
            sections.iter().any(|s| s.starts_with(word)),
            "--help refers to `{word}`, not a section ({sections:?})"
        );
    }
    assert!(!help.contains("MODES"), "the MODES section does not exist");
    assert!(help.contains("plytrace.log"));
}

#[test]
fn mkdet_mkpcl_mkvcl_are_programs_with_the_manuals_synopsis() {
    let objects = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tests/data/objects");
    for (tool, name, tag) in [
        (env!("CARGO_BIN_EXE_mkdet"), "mkdet", "DET"),
        (env!("CARGO_BIN_EXE_mkpcl"), "mkpcl", "PCL"),
        (env!("CARGO_BIN_EXE_mkvcl"), "mkvcl", "VCL"),
    ] {
        let ext = tag.to_ascii_lowercase();
        let input = std::fs::read(objects.join(format!("square.{ext}"))).expect("the fixture");
        let file = format!("in.{ext}");
        let run = spawn(
            tool,
            prepare(&[(&file, &input)]),
            &[&file, "out.bin"],
            false,
        );
        assert_eq!(run.code, Some(0), "{}", run.transcript());
        let out = std::fs::read(run.work().join("out.bin")).unwrap();
        assert!(
            out.starts_with(tag.as_bytes()),
            "{name}: {:?}",
            &out[..3.min(out.len())]
        );
        // The subcommand gives the same bytes.
        let run2 = spawn(
            &bin(),
            prepare(&[(&file, &input)]),
            &[name, &file, "out.bin"],
            false,
        );
        assert_eq!(run2.code, Some(0), "{}", run2.transcript());
        assert_eq!(std::fs::read(run2.work().join("out.bin")).unwrap(), out);
        // Wrong usage: the synopsis, status 2.
        let run = spawn(tool, prepare(&[]), &["only-one"], false);
        assert_eq!(run.code, Some(2), "{}", run.transcript());
        assert!(
            run.err()
                .contains(&format!("usage: {name} <input_file> <output_file>")),
            "{}",
            run.transcript()
        );
    }
}

// ---------------------------------------------------------------------------
// 8. The progress bar, on a terminal only

#[test]
fn progress_bar_only_on_a_terminal() {
    // Piped stderr: no bar.
    let run = run_with(
        SCENE,
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "64x64"],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(
        !run.err().contains("Scan conversion ["),
        "{}",
        run.transcript()
    );
    // A terminal (script(1) gives the program a pseudo-terminal): a bar.
    let square = square();
    let root = prepare(&[
        ("scene.des", SCENE.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ]);
    let command = format!("{} -i -f scene.des -o out.png --size 64x64", bin());
    let run = spawn("script", root, &["-qec", &command, "/dev/null"], false);
    assert_eq!(
        run.code,
        Some(0),
        "script(1) is needed for this test\n{}",
        run.transcript()
    );
    assert!(
        run.out().contains("Scan conversion ["),
        "no progress bar\n{}",
        run.transcript()
    );
    assert!(run.work().join("out.png").is_file());
}

// ---------------------------------------------------------------------------
// 9. Budget flags

#[test]
fn max_pixels_refuses_large_images_before_rendering() {
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "out.png",
            "--size",
            "64x64",
            "--max-pixels",
            "4000",
        ],
    );
    assert_refused(
        &run,
        2,
        &["4096 pixels exceeds the budget of 4000; `--max-pixels N` raises it"],
    );
    assert_eq!(run.files(), with_inputs(&[]));
    let scene = format!("resolution 100 50\n{SCENE}");
    let run = run_with(
        &scene,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "out.png",
            "--max-pixels",
            "4999",
        ],
    );
    assert_refused(
        &run,
        1,
        &[
            "100 x 50 = 5000 pixels exceeds the budget of 4999",
            "--max-pixels",
        ],
    );
    assert_eq!(run.files(), with_inputs(&[]));
    let run = run_with(
        &scene,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "out.png",
            "--max-pixels",
            "5000",
        ],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
}

#[test]
fn budget_flags_are_parsed() {
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "-o",
            "out.png",
            "--size",
            "16x16",
            "--max-polygons",
            "100",
            "--max-call-depth",
            "8",
            "--max-tree-nodes",
            "1000",
            "--max-splits",
            "10",
        ],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    for flag in [
        "--max-polygons",
        "--max-call-depth",
        "--max-tree-nodes",
        "--max-splits",
        "--max-pixels",
    ] {
        for bad in ["0", "x", "-3"] {
            let run = run_with(SCENE, &["-i", "-f", "scene.des", flag, bad]);
            assert_eq!(run.code, Some(2), "{}", run.transcript());
            assert!(run.err().contains(flag), "{}", run.transcript());
        }
        let run = run_with(SCENE, &["-i", "-f", "scene.des", flag]);
        assert_eq!(run.code, Some(2), "{}", run.transcript());
    }
}

/// Immediate mode is `get` + `run y` only for a scene that does not say
/// `run` itself: a scene without `run` is rendered once, with shadows.
#[test]
fn a_scene_without_run_is_rendered_once_in_immediate_mode() {
    let run = run_with(SCENE, &["-i", "-f", "scene.des", "--size", "16x16"]);
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    let log = std::fs::read_to_string(run.work().join("plytrace.log")).expect("plytrace.log");
    assert_eq!(log.lines().count(), 1, "{log}");
}

// ---------------------------------------------------------------------------
// Standard streams and --stats

#[test]
fn the_image_into_a_closed_pipe_or_a_full_disk_is_an_error() {
    let args = ["-i", "-f", "scene.des", "-o", "-", "--size", "16x16"];
    let square = square();
    let files: [(&str, &[u8]); 2] = [
        ("scene.des", SCENE.as_bytes()),
        ("det/square.det", square.as_bytes()),
    ];
    let closed = spawn(&bin(), prepare(&files), &args, true);
    assert_eq!(closed.code, Some(1), "{}", closed.transcript());
    assert!(
        closed
            .err()
            .contains("closed the pipe before the whole image was sent"),
        "{}",
        closed.transcript()
    );
    // Nothing left behind: not in the working directory, not in TMPDIR.
    assert_eq!(closed.files(), with_inputs(&[]), "{}", closed.transcript());
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let run = spawn_with(
        &bin(),
        prepare(&files),
        &args,
        Input::Null,
        Stdio::from(full),
    );
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert!(
        run.err().contains("<stdout>: No space left"),
        "{}",
        run.transcript()
    );
    assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
}

#[test]
fn stats_naming_an_input_is_refused_before_the_render() {
    for (target, says) in [
        ("scene.des", "an input of this run"),
        ("det/square.det", "an input of this run"),
        ("./det/../scene.des", "an input of this run"),
        ("/dev/full", "not a regular file"),
    ] {
        let run = run_with(
            SCENE,
            &[
                "-i",
                "-f",
                "scene.des",
                "--size",
                "16x16",
                "-o",
                "out.png",
                "--stats",
                target,
            ],
        );
        assert_refused(&run, 1, &[says]);
        assert_eq!(run.files(), with_inputs(&[]), "{}", run.transcript());
        let scene = std::fs::read_to_string(run.work().join("scene.des")).unwrap();
        assert_eq!(scene, SCENE, "{}", run.transcript());
        assert_eq!(
            std::fs::read_to_string(run.work().join("det/square.det")).unwrap(),
            square()
        );
    }
    // Another file is written.
    let run = run_with(
        SCENE,
        &[
            "-i",
            "-f",
            "scene.des",
            "--size",
            "16x16",
            "-o",
            "out.png",
            "--stats",
            "s.json",
        ],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(run.work().join("s.json").is_file());
}

/// `plytrace -` reads a scene as a scene file is read: text, at most the
/// scene file's size (an endless stream is refused at it, not held), and
/// its `fname` kept inside the working directory.
#[test]
fn a_scene_on_standard_input_follows_the_rules_of_a_scene_file() {
    let square = square();
    let files: [(&str, &[u8]); 1] = [("det/square.det", square.as_bytes())];
    let stdin = |input: Input, args: &[&str]| {
        spawn_with(&bin(), prepare(&files), args, input, Stdio::piped())
    };
    let binary = stdin(Input::Bytes(b"ident\n\xff\xfe\x00".to_vec()), &["-", "-q"]);
    assert_refused(
        &binary,
        1,
        &["<stdin>: not a text file: invalid UTF-8 at byte 6"],
    );
    let zero = std::fs::File::open("/dev/zero").expect("/dev/zero");
    for input in [Input::File(zero), Input::Endless(b"ident\n")] {
        let endless = stdin(input, &["-", "-q"]);
        assert_refused(
            &endless,
            1,
            &["<stdin>: the scene is longer than 16777216 bytes"],
        );
        assert_eq!(
            endless.files(),
            ["work/det/square.det"],
            "{}",
            endless.transcript()
        );
    }
    for escape in ["../up", "/tmp/plytrace-stdin-escape", "det/../../up"] {
        let scene = format!("{SCENE}fname {escape}\nsetmode o on\n");
        let run = stdin(
            Input::Bytes(scene.into_bytes()),
            &["-", "-q", "--size", "8x8"],
        );
        assert_refused(&run, 1, &["must stay inside the working directory"]);
        assert_eq!(run.files(), ["work/det/square.det"], "{}", run.transcript());
    }
    assert!(!Path::new("/tmp/plytrace-stdin-escape.png").exists());
    // Object files are looked up from the working directory.
    let run = stdin(
        Input::Bytes(SCENE.as_bytes().to_vec()),
        &["-", "-q", "--size", "8x8", "-o", "in.png"],
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(run.work().join("in.png").is_file());
    // A definition left open is refused, as in a scene file.
    let open = stdin(
        Input::Bytes(b"defobj square\n".to_vec()),
        &["-", "-q", "--size", "8x8", "-o", "open.png"],
    );
    assert_refused(&open, 1, &["endobj"]);
    assert!(!open.work().join("open.png").exists());
}

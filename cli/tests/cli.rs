//! End-to-end tests of the `plytrace` binary on bad (and some good) input.
//!
//! Every test runs the real binary in a fresh temporary directory that holds
//! the scene (`scene.des`) and its geometry (`det/NAME.det`), as
//! `plytrace -i -f scene.des -o out.png`, and checks the exit status, the
//! `FILE:LINE:COL: message` diagnostic on stderr (worked out by hand), and
//! that a failed run leaves neither `out.png` nor a temporary file behind.
//! Warnings (degenerate polygons, empty scenes) keep the exit status 0 and
//! the image is written.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_plytrace");

/// Longest a run may take; a run still going is killed and the test fails.
const TIMEOUT: Duration = Duration::from_secs(10);

/// What one run of the binary did.
struct Run {
    /// Exit status (`None` if killed by a signal).
    code: Option<i32>,
    stdout: String,
    stderr: String,
    /// Whether `out.png` exists (as a file).
    image: bool,
    /// Every file in the directory afterwards (relative, `/`-separated,
    /// hidden ones included), sorted.
    files: Vec<String>,
    /// The files the test put there, sorted.
    inputs: Vec<String>,
    /// The arguments, for messages.
    args: Vec<String>,
    dir: tempfile::TempDir,
}

impl Run {
    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// Everything the run printed, for assertion messages.
    fn transcript(&self) -> String {
        format!(
            "plytrace {}\nexit status: {:?}\nfiles: {:?}\n--- stdout ---\n{}--- stderr ---\n{}",
            self.args.join(" "),
            self.code,
            self.files,
            self.stdout,
            self.stderr
        )
    }
}

fn manifest_path(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(rel)
}

fn read_text(rel: &str) -> String {
    let path = manifest_path(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The unit square of `tests/data/cli/square.det` (side 2, facing +z).
fn square() -> String {
    read_text("tests/data/cli/square.det")
}

/// The manual's cube (corners at +-1, 8 vertices, 6 quads).
fn cube() -> String {
    read_text("examples/det/cube.det")
}

/// The files under `root`, except the run log `plytrace.log` that every
/// successful run appends to in the working directory (the manual's FILES;
/// tests/cli_safety.rs checks it).
fn list_files(root: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).expect("list the directory") {
            let path = entry.expect("a directory entry").path();
            if path == root.join("plytrace.log") {
                continue;
            }
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let rel = path.strip_prefix(root).expect("inside the root");
                let parts: Vec<String> = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                out.push(parts.join("/"));
            }
        }
    }
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out.sort();
    out
}

fn pipe_reader(mut r: impl Read + Send + 'static) -> thread::JoinHandle<String> {
    thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = r.read_to_end(&mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

/// Runs `plytrace ARGS` in a new temporary directory holding `files`
/// (relative path, contents), with `stdin` piped in if given (else no
/// input), under [`TIMEOUT`].
fn run_in(files: &[(&str, &str)], args: &[&str], stdin: Option<&str>) -> Run {
    let dir = tempfile::Builder::new()
        .prefix("plytrace-cli-")
        .tempdir()
        .expect("create a temporary directory");
    for (name, text) in files {
        let path = dir.path().join(name);
        std::fs::create_dir_all(path.parent().expect("a parent")).expect("create a directory");
        std::fs::write(&path, text).expect("write an input file");
    }
    let inputs = list_files(dir.path());

    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .env("RUST_BACKTRACE", "1")
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start plytrace");
    let feeder = child.stdin.take().map(|mut pipe| {
        let text = stdin.unwrap_or_default().to_owned();
        // Dropping the pipe at the end closes the program's input.
        thread::spawn(move || {
            let _ = pipe.write_all(text.as_bytes());
        })
    });
    let stdout = pipe_reader(child.stdout.take().expect("stdout"));
    let stderr = pipe_reader(child.stderr.take().expect("stderr"));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for plytrace") {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "plytrace {} still running after {TIMEOUT:?}",
                args.join(" ")
            );
        }
        thread::sleep(Duration::from_millis(5));
    };
    if let Some(f) = feeder {
        let _ = f.join();
    }
    let run = Run {
        code: status.code(),
        stdout: stdout.join().expect("read stdout"),
        stderr: stderr.join().expect("read stderr"),
        image: dir.path().join("out.png").is_file(),
        files: list_files(dir.path()),
        inputs,
        args: args.iter().map(|s| s.to_string()).collect(),
        dir,
    };
    assert!(
        !run.stderr.contains("panicked"),
        "plytrace panicked\n{}",
        run.transcript()
    );
    run
}

/// `plytrace -i -f scene.des -o out.png --size 64x64 EXTRA` with `scene` in
/// `scene.des` and each (name, text) of `dets` in `det/NAME.det`.
fn run_scene(scene: &str, dets: &[(&str, &str)], extra: &[&str]) -> Run {
    let det_paths: Vec<String> = dets
        .iter()
        .map(|(name, _)| format!("det/{name}.det"))
        .collect();
    let mut files = vec![("scene.des", scene)];
    files.extend(
        det_paths
            .iter()
            .map(String::as_str)
            .zip(dets.iter().map(|d| d.1)),
    );
    let mut args = vec!["-i", "-f", "scene.des", "-o", "out.png", "--size", "64x64"];
    args.extend_from_slice(extra);
    run_in(&files, &args, None)
}

/// The run exited with `code`, left exactly its input files (no image, no
/// temporary file), and some line of stderr holds `location: ` followed
/// (anywhere later on the line) by `message`.
fn assert_error(run: &Run, code: i32, location: &str, message: &str) {
    assert_eq!(run.code, Some(code), "exit status\n{}", run.transcript());
    assert!(!run.image, "an image was written\n{}", run.transcript());
    assert_eq!(
        run.files,
        run.inputs,
        "files left behind\n{}",
        run.transcript()
    );
    let prefix = format!("{location}: ");
    let found = run
        .stderr
        .lines()
        .any(|l| l.find(&prefix).is_some_and(|i| l[i..].contains(message)));
    assert!(
        found,
        "expected `{prefix}...{message}` on one line of stderr\n{}",
        run.transcript()
    );
}

/// A failure without a file location (bad flags): `code`, `message` on
/// stderr, nothing written.
fn assert_flag_error(run: &Run, code: i32, message: &str) {
    assert_eq!(run.code, Some(code), "exit status\n{}", run.transcript());
    assert!(!run.image, "an image was written\n{}", run.transcript());
    assert_eq!(run.files, run.inputs, "files left\n{}", run.transcript());
    assert!(
        run.stderr.contains(message),
        "expected `{message}` on stderr\n{}",
        run.transcript()
    );
}

/// Stderr shows source line `line` as `LINE | source` and a caret of
/// `width` under column `column` (1-based, in characters).
fn assert_caret(run: &Run, line: usize, source: &str, column: usize, width: usize) {
    let num = line.to_string();
    let pad = " ".repeat(num.len());
    let lead: String = source
        .chars()
        .take(column - 1)
        .map(|c| if c == '\t' { '\t' } else { ' ' })
        .collect();
    let expected = format!("{num} | {source}\n{pad} | {lead}{}\n", "^".repeat(width));
    assert!(
        run.stderr.contains(&expected),
        "expected the caret display\n{expected}\n{}",
        run.transcript()
    );
}

/// A successful run that wrote `out.png` and nothing else.
fn assert_success(run: &Run) {
    assert_eq!(run.code, Some(0), "exit status\n{}", run.transcript());
    assert!(run.image, "no image written\n{}", run.transcript());
    let mut expected = run.inputs.clone();
    expected.push("out.png".into());
    expected.sort();
    assert_eq!(run.files, expected, "files\n{}", run.transcript());
}

fn assert_stream_contains(run: &Run, stream: &str, text: &str) {
    let s = if stream == "stdout" {
        &run.stdout
    } else {
        &run.stderr
    };
    assert!(
        s.contains(text),
        "expected `{text}` on {stream}\n{}",
        run.transcript()
    );
}

/// A decoded 8-bit RGB PNG.
struct Image {
    width: u32,
    height: u32,
    pixels: Vec<[u8; 3]>,
}

impl Image {
    fn at(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    fn centre(&self) -> [u8; 3] {
        self.at(self.width / 2, self.height / 2)
    }
}

fn read_png(path: &Path) -> Image {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("a PNG header");
    let mut buf = vec![0; reader.output_buffer_size().expect("a sane size")];
    let info = reader.next_frame(&mut buf).expect("PNG image data");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Image {
        width: info.width,
        height: info.height,
        pixels,
    }
}

/// `background 0.2 0.4 0.6` as 8-bit RGB.
const BACKGROUND: [u8; 3] = [51, 102, 153];

fn assert_only_background(image: &Image, run: &Run) {
    let other = image.pixels.iter().position(|p| *p != BACKGROUND);
    assert!(
        other.is_none(),
        "pixel {:?} is {:?}, not the background {BACKGROUND:?}\n{}",
        other,
        other.map(|i| image.pixels[i]),
        run.transcript()
    );
}

// ---------------------------------------------------------------------------
// The command language

#[test]
fn unknown_command() {
    let run = run_scene(
        "# a comment line\nresolution 64 64\n   tranlate 1 2 3\n",
        &[],
        &[],
    );
    assert_error(
        &run,
        1,
        "scene.des:3:4",
        "unknown command `tranlate`; did you mean `translate`?",
    );
    assert_caret(&run, 3, "   tranlate 1 2 3", 4, 8);
}

#[test]
fn ambiguous_prefix() {
    let run = run_scene("ident\ntr 1 2 3\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:2:1",
        "ambiguous command `tr`: it could be translate, transmittance, transparency",
    );
    assert_caret(&run, 2, "tr 1 2 3", 1, 2);
}

#[test]
fn wrong_argument_count() {
    // Too few: the command is blamed. A tab is one column.
    let run = run_scene("ident\n\ttranslate 1 2 # two only\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:2:2",
        "`translate` expects 3 arguments (tx ty tz), found 2",
    );
    assert_caret(&run, 2, "\ttranslate 1 2 # two only", 2, 9);

    // Too many: the first extra argument is blamed.
    let run = run_scene("translate 1 2 3 4\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:17",
        "`translate` expects 3 arguments (tx ty tz), found 4",
    );
}

#[test]
fn non_number() {
    // The statement follows a block comment that spans two lines.
    let run = run_scene("/* header\n comment */ scale 1 x 1\n", &[], &[]);
    assert_error(&run, 1, "scene.des:2:21", "expected a number, found `x`");
    assert_caret(&run, 2, " comment */ scale 1 x 1", 21, 1);
}

#[test]
fn non_finite_numbers() {
    for word in ["nan", "inf", "1e999", "-inf", "NaN", "infinity", "-1e400"] {
        let run = run_scene(&format!("scale 1 {word} 1\n"), &[], &[]);
        assert_error(
            &run,
            1,
            "scene.des:1:9",
            &format!("expected a finite number, found `{word}`"),
        );
        assert_caret(&run, 1, &format!("scale 1 {word} 1"), 9, word.len());
    }
}

#[test]
fn unterminated_comment() {
    let run = run_scene("ident\nscale 1 1 1 /* never closed\nident\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:2:13",
        "unterminated comment: `/*` has no closing `*/`",
    );
    assert_caret(&run, 2, "scale 1 1 1 /* never closed", 13, 2);
}

#[test]
fn get_missing_file() {
    let run = run_scene("ident\n  get missing.des\n", &[], &[]);
    assert_error(&run, 1, "scene.des:2:7", "cannot open `missing.des`");
    assert_caret(&run, 2, "  get missing.des", 7, 11);
}

#[test]
fn get_cycle() {
    // scene.des calls a.des, which calls b.des, which calls a.des again.
    let run = run_in(
        &[
            ("scene.des", "call a.des\n"),
            ("a.des", "# a\ncall b.des\n"),
            ("b.des", "\n\n  call a.des\n"),
        ],
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "64x64"],
        None,
    );
    // The call that closes the cycle is the error's place.
    assert_error(
        &run,
        1,
        "b.des:3:8",
        "`a.des` is already being read: a `get`/`call` cycle",
    );
    // Then the chain back to the top.
    for place in ["included from a.des:2:6", "included from scene.des:1:6"] {
        assert_stream_contains(&run, "stderr", place);
    }
}

#[test]
fn matrix_stack_overflow() {
    // 16 levels are allowed ...
    let scene = format!("{}{}", "pushmatrix\n".repeat(16), "popmatrix\n".repeat(16));
    let run = run_scene(&scene, &[], &[]);
    assert_success(&run);

    // ... the 17th push (line 18, indented) overflows.
    let scene = format!(
        "# 16 levels are allowed\n{}  pushmatrix\n",
        "pushmatrix\n".repeat(16)
    );
    let run = run_scene(&scene, &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:18:3",
        "matrix stack overflow: more than 16 matrices pushed",
    );
    assert_caret(&run, 18, "  pushmatrix", 3, 10);
}

#[test]
fn matrix_stack_underflow() {
    let run = run_scene("   popmatrix\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:4",
        "matrix stack underflow: `popmatrix` without a matching `pushmatrix`",
    );
}

#[test]
fn popmatrix_inside_defobj() {
    // One push before `defobj` so that the stack is not empty when the
    // third `popmatrix` would take the matrix `defobj` saved.
    let scene = "pushmatrix\ndefobj cube\n  pushmatrix\n  popmatrix\n  popmatrix\nendobj\n";
    let cube = cube();
    let run = run_scene(scene, &[("cube", &cube)], &[]);
    assert_error(
        &run,
        1,
        "scene.des:5:3",
        "matrix stack underflow: this would pop the matrix `defobj` saved",
    );
}

#[test]
fn endobj_without_defobj() {
    let cube = cube();
    let run = run_scene("defobj cube\nendobj\nendobj\n", &[("cube", &cube)], &[]);
    assert_error(&run, 1, "scene.des:3:1", "`endobj` without `defobj`");
}

#[test]
fn defobj_without_endobj() {
    let cube = cube();
    let run = run_scene(
        "ident\n  defobj cube 7\n  color 1 0 0\n",
        &[("cube", &cube)],
        &[],
    );
    assert_error(
        &run,
        1,
        "scene.des:2:3",
        "`defobj cube` has no `endobj` before the end of the input",
    );
}

#[test]
fn det_file_not_found() {
    let run = run_scene("\n  defobj nothere\n  endobj\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:2:3",
        "no geometry file for object `nothere` (tried ",
    );
    for tried in [
        "det/nothere.det",
        "det/nothere.obj",
        "det/nothere.ply",
        "det/nothere.stl",
    ] {
        assert_stream_contains(&run, "stderr", tried);
    }
}

#[test]
fn perspective_zero_field_of_view() {
    for fov in ["0", "180", "-10"] {
        let run = run_scene(&format!("perspective {fov} 1 0.01 100\n"), &[], &[]);
        assert_error(
            &run,
            1,
            "scene.des:1:13",
            "expected a field of view between 0 and 180 degrees",
        );
    }
}

#[test]
fn resolution_zero() {
    let run = run_scene("resolution 0 10\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:12",
        "expected a whole number from 1 to 65536, found 0",
    );
    let run = run_scene("resolution 10 0\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:15",
        "expected a whole number from 1 to 65536, found 0",
    );
}

#[test]
fn resolution_too_large() {
    let run = run_scene("resolution 100000 100000\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:12",
        "expected a whole number from 1 to 65536, found 100000",
    );
    assert_caret(&run, 1, "resolution 100000 100000", 12, 6);
    // Each side allowed, the total not.
    let run = run_scene("resolution 65536 65536\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:1",
        "image of 65536 x 65536 pixels: each side must be 1 to 65536 and the total at most 268435456 pixels",
    );
}

#[test]
fn rotate_bad_axis() {
    let run = run_scene("rotate 10 w\n", &[], &[]);
    assert_error(&run, 1, "scene.des:1:11", "expected an axis: x, y or z");
}

#[test]
fn setmode_i_in_file() {
    let run = run_scene("# modes\n  setmode i\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:2:11",
        "mode `i` can only be given on the command line (-i)",
    );
}

#[test]
fn color_out_of_range() {
    let run = run_scene("color 1 1.5 0\n", &[], &[]);
    assert_error(
        &run,
        1,
        "scene.des:1:9",
        "expected a value from 0 to 1, found 1.5",
    );
    assert_caret(&run, 1, "color 1 1.5 0", 9, 3);
}

#[test]
fn light_negative_range() {
    for range in ["-5", "0"] {
        let run = run_scene(&format!("light 0 0 0 1 1 1 {range}\n"), &[], &[]);
        assert_error(&run, 1, "scene.des:1:19", "expected a positive light range");
    }
}

// ---------------------------------------------------------------------------
// Object files

#[test]
fn det_vertex_index_out_of_range() {
    let det = "title out of range\ndata\n3 2\n0 0 0\n1 0 0\n0 1 0\n3 1 2 4\n3 1 2 3\n";
    let run = run_scene("# one object\ndefobj bad\nendobj\n", &[("bad", det)], &[]);
    assert_error(
        &run,
        1,
        "det/bad.det:7:7",
        "vertex index 4 out of range 1..=3 in polygon 1",
    );
    assert_caret(&run, 7, "3 1 2 4", 7, 1);

    // Index 0 (indices are 1-based), in the second polygon, with commas.
    let det = "title out of range\ndata\n3 2\n0 0 0\n1 0 0\n0 1 0\n3 1 2 3\n  3, 2, 0, 1\n";
    let run = run_scene("# one object\ndefobj bad\nendobj\n", &[("bad", det)], &[]);
    assert_error(
        &run,
        1,
        "det/bad.det:8:9",
        "vertex index 0 out of range 1..=3 in polygon 2",
    );
}

#[test]
fn det_huge_vertex_count() {
    // The header claims a billion vertices; the file holds three. The run
    // must fail at the end of the text (within TIMEOUT, without trying to
    // allocate for the claim).
    let det = "title liar\ndata\n1000000000 1\n0 0 0\n1 0 0\n0 1 0\n";
    let start = Instant::now();
    let run = run_scene("defobj liar\nendobj\n", &[("liar", det)], &[]);
    assert!(start.elapsed() < TIMEOUT);
    assert_error(
        &run,
        1,
        "det/liar.det:6:6",
        "expected 1000000000 vertices, file ended after 3",
    );

    // The same for the polygon count (a claim within the polygon budget).
    let det = "title liar\ndata\n3 3000000\n0 0 0\n1 0 0\n0 1 0\n3 1 2 3\n";
    let run = run_scene("defobj liar\nendobj\n", &[("liar", det)], &[]);
    assert_error(
        &run,
        1,
        "det/liar.det:7:8",
        "expected 3000000 polygons, file ended after 1",
    );

    // A claim beyond the polygon budget is refused at the count, before
    // any polygon is read.
    let det = "title liar\ndata\n3 1000000000\n0 0 0\n1 0 0\n0 1 0\n3 1 2 3\n";
    let run = run_scene("defobj liar\nendobj\n", &[("liar", det)], &[]);
    assert_error(
        &run,
        1,
        "det/liar.det:3:13",
        "1000000000 polygons exceed the 4000000 left of the polygon budget; `--max-polygons N` raises it",
    );
}

/// The view of the degenerate-polygon tests: the object 5 units in front
/// of the eye; `endobj` on line 6.
const FRONT_SCENE: &str = "perspective 45 1 0.1 100
pushmatrix
ident
translate 0 0 -5
defobj flat
endobj
popmatrix
";

#[test]
fn polygon_with_too_few_distinct_vertices() {
    let det = "title square and two degenerate polygons
data
4 3
-1 -1 0
-1 1 0
1 1 0
1 -1 0
4 1 2 3 4
4 1 1 2 2
3 1 2 2
";
    let run = run_scene(FRONT_SCENE, &[("flat", det)], &[]);
    assert_success(&run);
    for polygon in [2, 3] {
        assert_stream_contains(
            &run,
            "stderr",
            &format!(
                "scene.des:6:1: warning: object `flat` polygon {polygon}: only 2 distinct vertices; skipped"
            ),
        );
    }
    assert_stream_contains(&run, "stdout", "1 objects, 4 points, 1 polygons");
    let image = read_png(&run.path("out.png"));
    assert_eq!((image.width, image.height), (64, 64));
}

#[test]
fn zero_area_polygon() {
    let det = "title square and a sliver along its lower edge
data
5 2
-1 -1 0
-1 1 0
1 1 0
1 -1 0
0 -1 0
4 1 2 3 4
3 1 5 4
";
    let run = run_scene(FRONT_SCENE, &[("flat", det)], &[]);
    assert_success(&run);
    assert_stream_contains(
        &run,
        "stderr",
        "scene.des:6:1: warning: object `flat` polygon 2: zero area; skipped",
    );
    assert_stream_contains(&run, "stdout", "1 objects, 5 points, 1 polygons");
}

#[test]
fn non_planar_quad() {
    let det = "title a quad with one corner lifted
data
4 1
-1 -1 0
-1 1 0
1 1 0.5
1 -1 0
4 1 2 3 4
";
    let run = run_scene(FRONT_SCENE, &[("flat", det)], &[]);
    assert_success(&run);
    let warning = run
        .stderr
        .lines()
        .find(|l| l.starts_with("scene.des:6:1: warning: object `flat` polygon 1: not planar"));
    assert!(
        warning.is_some_and(|w| w.ends_with("split into triangles")),
        "{}",
        run.transcript()
    );
    assert_stream_contains(&run, "stdout", "1 objects, 4 points, 2 polygons");
    assert_stream_contains(&run, "stdout", "2 Polygons tiled");
}

// ---------------------------------------------------------------------------
// Rendering corner cases

#[test]
fn empty_scene() {
    let run = run_scene("background 0.2 0.4 0.6\n", &[], &[]);
    assert_success(&run);
    assert_stream_contains(
        &run,
        "stderr",
        "warning: the scene has no objects; the image is the background only",
    );
    assert_stream_contains(&run, "stdout", "0 objects, 0 points, 0 polygons");
    let image = read_png(&run.path("out.png"));
    assert_eq!((image.width, image.height), (64, 64));
    assert_only_background(&image, &run);
}

fn square_at_z(z: f64) -> String {
    format!(
        "background 0.2 0.4 0.6
perspective 45 1 0.1 100
pushmatrix
ident
type polygon open
color 1 0 0
translate 0 0 {z}
defobj square
endobj
popmatrix
"
    )
}

#[test]
fn object_behind_eye() {
    let square = square();
    // In front (control): the square covers the centre of the image.
    let run = run_scene(&square_at_z(-5.0), &[("square", &square)], &[]);
    assert_success(&run);
    assert_stream_contains(&run, "stdout", "1 Polygons tiled");
    let image = read_png(&run.path("out.png"));
    assert_ne!(image.centre(), BACKGROUND, "{}", run.transcript());

    // The same square behind the eye (not culled: `type polygon open`).
    let run = run_scene(&square_at_z(5.0), &[("square", &square)], &[]);
    assert_success(&run);
    assert_stream_contains(&run, "stdout", "0 Polygons tiled");
    assert_only_background(&read_png(&run.path("out.png")), &run);

    // A floor 20 wide at y = -1 straddling the eye plane (z from -10 to
    // 10; the command given last acts first): only the part in front may
    // be drawn, below the horizon, so the upper half stays background.
    let scene = "background 0.2 0.4 0.6
perspective 45 1 0.1 100
pushmatrix
ident
type polygon open
color 1 0 0
translate 0 -1 0
rotate 90 x
scale 10 10 10
defobj square
endobj
popmatrix
";
    let run = run_scene(scene, &[("square", &square)], &[]);
    assert_success(&run);
    let image = read_png(&run.path("out.png"));
    for y in 0..image.height / 2 - 1 {
        for x in 0..image.width {
            assert_eq!(
                image.at(x, y),
                BACKGROUND,
                "({x}, {y})\n{}",
                run.transcript()
            );
        }
    }
    assert_ne!(image.at(32, 60), BACKGROUND, "{}", run.transcript());
}

#[test]
fn camera_inside_closed_cube() {
    let cube = cube();
    let scene = |open: &str| {
        format!(
            "background 0.2 0.4 0.6
perspective 45 1 0.1 100
pushmatrix
ident
{open}
scale 3 3 3
defobj cube
endobj
popmatrix
"
        )
    };
    for extra in [&[][..], &["-x", "on"][..]] {
        // Every face is seen from behind and culled.
        let run = run_scene(&scene(""), &[("cube", &cube)], extra);
        assert_success(&run);
        assert_stream_contains(&run, "stdout", "1 objects, 8 points, 6 polygons");
        assert_only_background(&read_png(&run.path("out.png")), &run);

        // Open: the far face (z = -3) fills the view.
        let run = run_scene(&scene("type polygon open"), &[("cube", &cube)], extra);
        assert_success(&run);
        let image = read_png(&run.path("out.png"));
        assert!(
            image.pixels.iter().all(|p| *p != BACKGROUND),
            "{}",
            run.transcript()
        );
    }
}

// ---------------------------------------------------------------------------
// Flags

#[test]
fn bad_flag_value() {
    let run = run_scene("ident\n", &[], &["-n", "maybe"]);
    assert_flag_error(
        &run,
        2,
        "error: flag -n: expected `on` or `off`, found `maybe`",
    );
    let run = run_scene("ident\n", &[], &["-l", "99"]);
    assert_flag_error(
        &run,
        2,
        "error: flag -l: expected a whole number from 1 to 14, found 99",
    );
    let run = run_scene("ident\n", &[], &["--size", "0x10"]);
    assert_flag_error(
        &run,
        2,
        "'--size <WxH>': each side must be 1 to 65536, found 0",
    );
}

#[test]
fn unknown_flag() {
    let run = run_scene("ident\n", &[], &["-z"]);
    assert_flag_error(&run, 2, "error: unexpected argument '-z' found");
}

#[test]
fn immediate_without_scene_file() {
    let run = run_in(&[], &["-i", "-o", "out.png"], None);
    assert_flag_error(
        &run,
        2,
        "error: immediate mode (-i) needs a scene file: plytrace -i -f scene.des",
    );
}

#[test]
fn output_flag_on_is_not_a_file_name() {
    for value in ["on", "OFF"] {
        let run = run_in(
            &[("scene.des", "background 0 0 1\n")],
            &["-i", "-f", "scene.des", "-o", value, "--size", "8x8"],
            None,
        );
        assert_eq!(run.code, Some(0), "{}", run.transcript());
        // The tree-output mode, not a file: the image is named after the
        // scene, and `on` writes the virtual image tree beside it.
        let expected: &[&str] = if value == "on" {
            &["scene.des", "scene.out", "scene.png", "scene.txt"]
        } else {
            &["scene.des", "scene.png"]
        };
        assert_eq!(run.files, expected, "{}", run.transcript());
        let image = read_png(&run.path("scene.png"));
        assert_eq!((image.width, image.height), (8, 8));
        assert_eq!(image.centre(), [0, 0, 255]);
    }
}

#[test]
fn output_write_failure_leaves_no_temporary_file() {
    // `out.png` is a directory: the image cannot be renamed into place.
    let run = run_in(
        &[("scene.des", "ident\n"), ("out.png/keep", "")],
        &["-i", "-f", "scene.des", "-o", "out.png", "--size", "8x8"],
        None,
    );
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert_stream_contains(&run, "stderr", "error: out.png: ");
    assert_eq!(run.files, run.inputs, "{}", run.transcript());
}

// ---------------------------------------------------------------------------
// A whole scene

#[test]
fn ccube_renders() {
    let scene = read_text("examples/ccube.des");
    let cube = cube();
    let cutcube = read_text("examples/det/cutcube.det");
    let run = run_in(
        &[
            ("ccube.des", &scene),
            ("det/cube.det", &cube),
            ("det/cutcube.det", &cutcube),
        ],
        &["-i", "-f", "ccube.des", "-o", "out.png"],
        None,
    );
    assert_success(&run);
    assert_stream_contains(&run, "stdout", "2 objects, 18 points, 13 polygons");
    assert_stream_contains(&run, "stdout", "Polygons tiled");
    assert!(run.stderr.trim().is_empty(), "{}", run.transcript());
    let image = read_png(&run.path("out.png"));
    assert_eq!((image.width, image.height), (512, 512));
}

// ---------------------------------------------------------------------------
// Interactive mode with piped input

const INTERACTIVE_SCENE: &str = "fname picture\nresolution 16 16\nbackground 0 1 0\n";

#[test]
fn interactive_piped_stdin() {
    let run = run_in(
        &[("scene.des", INTERACTIVE_SCENE)],
        &[],
        Some("get scene.des\nrun\nquit\n"),
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert_stream_contains(&run, "stdout", "0 objects, 0 points, 0 polygons");
    assert_stream_contains(&run, "stdout", "Wrote picture.png (16 x 16)");
    assert_eq!(
        run.files,
        ["picture.png", "scene.des"],
        "{}",
        run.transcript()
    );
    let image = read_png(&run.path("picture.png"));
    assert_eq!((image.width, image.height), (16, 16));
    assert!(image.pixels.iter().all(|p| *p == [0, 255, 0]));
}

#[test]
fn interactive_piped_error_location() {
    // The error on line 3 is reported, the session goes on (the image is
    // written), and the exit status says something failed.
    let run = run_in(
        &[("scene.des", INTERACTIVE_SCENE)],
        &[],
        Some("get scene.des\n\n  scale 1 x 1\nrun\nquit\n"),
    );
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert_stream_contains(
        &run,
        "stderr",
        "error: <stdin>:3:11: expected a number, found `x`",
    );
    assert_caret(&run, 3, "  scale 1 x 1", 11, 1);
    assert_eq!(
        run.files,
        ["picture.png", "scene.des"],
        "{}",
        run.transcript()
    );

    // Without `quit`: the end of the input ends the session, still failing.
    let run = run_in(
        &[("scene.des", INTERACTIVE_SCENE)],
        &[],
        Some("get scene.des\nrun\nbogus\n"),
    );
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert_stream_contains(
        &run,
        "stderr",
        "error: <stdin>:3:1: unknown command `bogus`",
    );
}

#[test]
fn interactive_call_error_reports_stdin_line() {
    let run = run_in(
        &[("bad.des", "scale 1 x 1\n")],
        &[],
        Some("ident\n\ncall bad.des\nquit\n"),
    );
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert_stream_contains(
        &run,
        "stderr",
        "error: bad.des:1:9: expected a number, found `x`",
    );
    assert_stream_contains(&run, "stderr", "included from <stdin>:3:6");
}

#[test]
fn interactive_get_missing_file_reports_stdin_location() {
    let run = run_in(&[], &[], Some("\n get missing.des\nquit\n"));
    assert_eq!(run.code, Some(1), "{}", run.transcript());
    assert_stream_contains(&run, "stderr", "error: <stdin>:2:6: cannot open");
}

/// The REPL's `help` and `help CMD` print from the command table that
/// `--help` prints (prefixes as the interpreter accepts them).
#[test]
fn repl_help_prints_the_command_table() {
    let run = run_in(&[], &[], Some("help transl\nhelp zzz\nhelp\nquit\n"));
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert!(
        lines[0].trim_start().starts_with("translate"),
        "{}",
        run.stdout
    );
    assert!(lines[0].contains("tx ty tz"), "{}", run.stdout);
    // The entry's second line says what the command does.
    assert!(lines[1].contains("translation"), "{}", run.stdout);
    assert!(lines[2].contains("no command `zzz`"), "{}", run.stdout);
    let help = run_in(&[], &["--help"], None);
    for line in &lines[3..] {
        assert!(help.stdout.contains(line), "`{line}` is not in --help");
    }
    assert!(lines.len() > 40, "{}", run.stdout);
}

/// Brown's hidden-line drawing (003) as his figures show it, white faces
/// and black edges: with `--aa none` only those two colours, on the very
/// pixels the anti-aliased drawing (the default) darkens; that one has
/// grey levels between. Another method of anti-aliasing is refused.
#[test]
fn hidden_lines_in_black_and_white() {
    let det = "title square\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n";
    let scene = FRONT_SCENE.replace("defobj flat\n", "defobj flat\nrotate 20 z\n");
    let grey = |image: &Image| {
        image
            .pixels
            .iter()
            .filter(|p| **p != [0; 3] && **p != [255; 3])
            .count()
    };
    let aa = run_scene(&scene, &[("flat", det)], &["--hidden-line"]);
    assert_success(&aa);
    let aa = read_png(&aa.path("out.png"));
    assert!(grey(&aa) > 50, "anti-aliased lines: {}", grey(&aa));
    let bw = run_scene(&scene, &[("flat", det)], &["--hidden-line", "--aa", "none"]);
    assert_success(&bw);
    let bw = read_png(&bw.path("out.png"));
    assert_eq!(grey(&bw), 0, "black and white only");
    let black: Vec<usize> = (0..bw.pixels.len())
        .filter(|&k| bw.pixels[k] == [0; 3])
        .collect();
    assert!(
        black.len() > 100,
        "the square's four edges: {}",
        black.len()
    );
    assert!(
        black.iter().all(|&k| aa.pixels[k] != [255; 3]),
        "a black pixel off the lines"
    );
    let area = run_scene(&scene, &[("flat", det)], &["--hidden-line", "--aa", "area"]);
    assert_eq!(area.code, Some(2), "{}", area.transcript());
    assert_stream_contains(&area, "stderr", "only black and white with --aa none");
}

/// `fname` is folded to lower case like every name read (004 appendix B:
/// "all input characters are converted to lower case"), unless an output
/// of the name as written is already there.
#[test]
fn fname_is_folded_to_lower_case() {
    let scene = "resolution 16 16\nsetmode o on\nfname Picture\n";
    let run = run_in(&[("scene.des", scene)], &["-q", "scene.des"], None);
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    for name in ["picture.png", "picture.out", "picture.txt"] {
        assert!(run.path(name).is_file(), "{name}\n{}", run.transcript());
    }
    assert!(!run.path("Picture.png").exists(), "{}", run.transcript());
    // An output named as written is written again under that name.
    let run = run_in(
        &[("scene.des", scene), ("Picture.png", "old")],
        &["-q", "scene.des"],
        None,
    );
    assert_eq!(run.code, Some(0), "{}", run.transcript());
    assert!(
        std::fs::read(run.path("Picture.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );
    assert!(run.path("Picture.out").is_file() && !run.path("picture.png").exists());
}

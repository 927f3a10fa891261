//! The command line as a new user meets it: the manual's flags in their
//! bare forms, the conventions of command-line programs (`--flag=value`,
//! `-o -`, `plytrace -`, suggestions, `--check`, `--stats json`,
//! completions, a man page, help within 80 columns), conflicting flags,
//! and signals that end a render leaving nothing on disk.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

#[path = "../../tests/support/mod.rs"]
mod support;
use support::copy_tree;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_plytrace")
}

/// A working directory holding the bundled example (`ccube.des` and its
/// `det/`) and office2 for the long renders.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    copy_tree(&root.join("examples"), dir.path());
    let scenes = root.join("tests/data/scenes");
    std::fs::copy(scenes.join("office2.des"), dir.path().join("office2.des")).expect("office2");
    copy_tree(&scenes.join("det"), &dir.path().join("det"));
    dir
}

fn run(dir: &Path, args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut child = Command::new(bin())
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("plytrace runs");
    let mut input = child.stdin.take().unwrap();
    if let Some(bytes) = stdin {
        input.write_all(bytes).unwrap();
    }
    drop(input);
    child.wait_with_output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                all.push(p.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    all.sort();
    all
}

const SMALL: &[&str] = &["--size", "64x64"];

fn args<'a>(first: &[&'a str], rest: &[&'a str]) -> Vec<&'a str> {
    first.iter().chain(rest).copied().collect()
}

#[test]
fn a_bare_on_off_flag_means_on() {
    // 004 appendix B: `setmode <mode> [<on, off>]`; the flags "are
    // equivalent to the setmode command parameters".
    let dir = workdir();
    let bare = run(
        dir.path(),
        &args(&["-i", "-v", "-f", "ccube.des", "-o", "a.png"], SMALL),
        None,
    );
    assert!(bare.status.success(), "{}", text(&bare.stderr));
    let on = run(
        dir.path(),
        &args(&["-i", "-v", "on", "-f", "ccube.des", "-o", "b.png"], SMALL),
        None,
    );
    assert!(on.status.success(), "{}", text(&on.stderr));
    let a = std::fs::read(dir.path().join("a.png")).unwrap();
    assert_eq!(a, std::fs::read(dir.path().join("b.png")).unwrap());
    // Before a lone scene file too.
    let before_scene = run(
        dir.path(),
        &args(&["-v", "ccube.des", "-o", "d.png"], SMALL),
        None,
    );
    assert!(
        before_scene.status.success(),
        "{}",
        text(&before_scene.stderr)
    );
    assert_eq!(a, std::fs::read(dir.path().join("d.png")).unwrap());
    // And -v really is the vertex-shade flag: off gives another image.
    let off = run(
        dir.path(),
        &args(&["-v", "off", "ccube.des", "-o", "e.png"], SMALL),
        None,
    );
    assert!(off.status.success(), "{}", text(&off.stderr));
    assert_ne!(a, std::fs::read(dir.path().join("e.png")).unwrap());
    // The digit flags: -3 is debugging level 3, which prints the stages.
    let debug = run(
        dir.path(),
        &args(&["ccube.des", "-3", "-o", "c.png"], SMALL),
        None,
    );
    assert!(debug.status.success(), "{}", text(&debug.stderr));
    assert!(
        text(&debug.stdout).contains("scan conversion"),
        "{}",
        text(&debug.stdout)
    );
}

#[test]
fn flag_equals_value_and_suggestions() {
    let dir = workdir();
    let before = files(dir.path());
    let o = run(
        dir.path(),
        &["ccube.des", "--size=32x32", "--output=x.png"],
        None,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("Wrote x.png (32 x 32)"),
        "{}",
        text(&o.stdout)
    );
    let o = run(dir.path(), &["ccube.des", "--visiblity", "nns"], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("a similar argument exists: '--visibility'"),
        "{}",
        text(&o.stderr)
    );
    let added: Vec<PathBuf> = files(dir.path())
        .into_iter()
        .filter(|f| !before.contains(f))
        .collect();
    assert_eq!(
        added,
        [PathBuf::from("plytrace.log"), PathBuf::from("x.png")]
    );
}

#[test]
fn the_image_to_standard_output_alone() {
    let dir = workdir();
    let file = run(
        dir.path(),
        &args(&["ccube.des", "-o", "file.png"], SMALL),
        None,
    );
    assert!(file.status.success());
    let before = files(dir.path());
    let piped = run(dir.path(), &args(&["ccube.des", "-o", "-"], SMALL), None);
    assert!(piped.status.success(), "{}", text(&piped.stderr));
    assert_eq!(
        piped.stdout,
        std::fs::read(dir.path().join("file.png")).unwrap()
    );
    // The statistics went to stderr; nothing but the log was added.
    assert!(
        text(&piped.stderr).contains("Polygons tiled"),
        "{}",
        text(&piped.stderr)
    );
    assert_eq!(files(dir.path()), before);
    // Vector output too, by --format.
    let svg = run(
        dir.path(),
        &args(&["ccube.des", "-o", "-", "--format", "svg"], SMALL),
        None,
    );
    assert!(svg.status.success(), "{}", text(&svg.stderr));
    assert!(text(&svg.stdout).starts_with("<?xml") || text(&svg.stdout).starts_with("<svg"));
    // A failed run sends nothing.
    let bad = run(dir.path(), &["-", "-o", "-"], Some(b"color 1 1\n"));
    assert_eq!(bad.status.code(), Some(1));
    assert!(bad.stdout.is_empty());
    // --format is for standard output only.
    let o = run(
        dir.path(),
        &["ccube.des", "-o", "a.png", "--format", "svg"],
        None,
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
}

#[test]
fn a_scene_from_standard_input() {
    let dir = workdir();
    let scene = std::fs::read(dir.path().join("ccube.des")).unwrap();
    let file = run(
        dir.path(),
        &args(&["ccube.des", "-o", "file.png"], SMALL),
        None,
    );
    assert!(file.status.success());
    let piped = run(
        dir.path(),
        &args(&["-", "-o", "stdin.png"], SMALL),
        Some(&scene),
    );
    assert!(piped.status.success(), "{}", text(&piped.stderr));
    assert_eq!(
        std::fs::read(dir.path().join("stdin.png")).unwrap(),
        std::fs::read(dir.path().join("file.png")).unwrap()
    );
    // An error names standard input, line and column.
    let bad = run(dir.path(), &["-"], Some(b"ident\ncolor 1 x 1\n"));
    assert_eq!(bad.status.code(), Some(1));
    assert!(
        text(&bad.stderr).contains("<stdin>:2:"),
        "{}",
        text(&bad.stderr)
    );
}

#[test]
fn check_reads_the_scene_and_writes_nothing() {
    let dir = workdir();
    let before = files(dir.path());
    let o = run(dir.path(), &["--check", "ccube.des"], None);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("a run would write ccube.png (512 x 512)"),
        "{}",
        text(&o.stdout)
    );
    assert_eq!(files(dir.path()), before);
    let o = run(dir.path(), &["--check", "-"], Some(b"translate 1 2\n"));
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    let o = run(
        dir.path(),
        &["--check", "ccube.des", "--max-pixels", "100"],
        None,
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("--max-pixels"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(files(dir.path()), before);
}

#[test]
fn statistics_as_one_json_object() {
    let dir = workdir();
    let o = run(
        dir.path(),
        &args(&["ccube.des", "--stats", "json", "-q"], SMALL),
        None,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let doc: serde_json::Value =
        serde_json::from_slice(&o.stderr).expect("stderr is one JSON object");
    assert_eq!(doc["objects"], 2);
    assert_eq!(doc["polygons"], 13);
    assert_eq!(doc["ok"], true);
    assert_eq!(doc["runs"][0]["width"], 64);
    assert!(doc["runs"][0]["polygons_tiled"].as_u64().unwrap() > 0);
    assert!(o.stdout.is_empty(), "--quiet prints nothing else");
    let o = run(
        dir.path(),
        &args(&["ccube.des", "--stats", "s.json"], SMALL),
        None,
    );
    assert!(o.status.success());
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(doc["runs"].as_array().unwrap().len(), 1);
}

#[test]
fn help_completions_and_man_page() {
    let dir = workdir();
    let help = run(dir.path(), &["--help"], None);
    assert!(help.status.success());
    let help = text(&help.stdout);
    for line in help.lines() {
        assert!(line.chars().count() <= 80, "over 80 columns: {line}");
    }
    for word in [
        "-i",
        "--no-shadows",
        "--check",
        "translate tx ty tz",
        "plytrace.log",
    ] {
        assert!(help.contains(word), "{word} is not in --help");
    }
    assert!(!help.contains("not yet acted on"), "`clear` is acted on");
    let bash = run(dir.path(), &["completions", "bash"], None);
    assert!(bash.status.success());
    assert!(text(&bash.stdout).contains("--visibility"));
    let man = run(dir.path(), &["man"], None);
    assert!(man.status.success());
    assert!(
        text(&man.stdout).starts_with(".ie"),
        "{}",
        &text(&man.stdout)[..40]
    );
    assert!(text(&man.stdout).contains("no\\-shadows"));
}

#[cfg(target_os = "linux")]
#[test]
fn help_to_a_full_device_is_an_error() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let o = Command::new(bin())
        .arg("--help")
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("No space left"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn conflicting_flags_name_both() {
    let dir = workdir();
    for (flags, a, b) in [
        (
            &["--hidden-line", "--raytrace"][..],
            "--hidden-line",
            "--raytrace",
        ),
        (
            &["--aa", "none", "--supersample", "4"][..],
            "--supersample",
            "--aa",
        ),
        (&["-o", "a.png", "-o", "b.png"][..], "a.png", "b.png"),
        (&["-o", "on", "-o", "off"][..], "on", "off"),
        (&["-f", "ccube.des"][..], "ccube.des", "ccube.des"),
    ] {
        let o = run(dir.path(), &args(&["ccube.des"], flags), None);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {err}");
        assert!(err.contains(a) && err.contains(b), "{flags:?}: {err}");
    }
    // The tree flag and an image name go together.
    let o = run(
        dir.path(),
        &args(&["ccube.des", "-o", "on", "-o", "t.png"], SMALL),
        None,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(dir.path().join("ccube.out").exists() && dir.path().join("t.png").exists());
}

#[test]
fn the_manuals_timing_line_and_honest_statistics() {
    let dir = workdir();
    let o = run(dir.path(), &args(&["ccube.des"], SMALL), None);
    let out = text(&o.stdout);
    // 004 appendix B: "Time (HR:MIN:SEC) = 00:00:02".
    assert!(
        out.lines().any(|l| l == "Time (HR:MIN:SEC) = 00:00:00"),
        "{out}"
    );
    let o = run(dir.path(), &args(&["ccube.des", "--raytrace"], SMALL), None);
    let out = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(!out.contains("Polygons tiled"), "{out}");
    assert!(out.contains("Ray tracing:"), "{out}");
    let o = run(dir.path(), &["ccube.des", "--size", "1x4000"], None);
    let err = text(&o.stderr);
    assert!(err.contains("1.000 to 0.0002500"), "{err}");
    let o = run(dir.path(), &["ccube.des", "--size", "20000x20000"], None);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.contains("at most 2^28"), "{err}");
}

#[test]
fn every_visibility_algorithm_renders_ccube_without_shadows() {
    let dir = workdir();
    for alg in [
        "depth-sort",
        "nns",
        "z-buffer",
        "scan-line",
        "warnock",
        "brown",
        "ray-cast",
    ] {
        let png = format!("{alg}.png");
        let o = run(
            dir.path(),
            &args(
                &["ccube.des", "--no-shadows", "--visibility", alg, "-o", &png],
                SMALL,
            ),
            None,
        );
        assert!(o.status.success(), "{alg}: {}", text(&o.stderr));
    }
}

/// Starts a long render (office2 at 8192 x 8192), waits until it builds
/// the image, sends `signal` (`count` times) and returns the exit status.
fn interrupted(dir: &Path, signal: &str, count: usize) -> Option<i32> {
    let mut child = Command::new(bin())
        .args([
            "office2.des",
            "--size",
            "8192x8192",
            "-o",
            "big.png",
            "--id-image",
            "ids.png",
        ])
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    for line in lines.by_ref() {
        if line.unwrap().starts_with("Building image") {
            break;
        }
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    for _ in 0..count {
        let sent = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(sent.success());
    }
    let code = child.wait().unwrap().code();
    drop(lines);
    code
}

#[test]
fn signals_end_a_render_and_leave_nothing() {
    for (signal, count, code) in [
        ("TERM", 1, 143),
        ("HUP", 1, 129),
        ("INT", 1, 130),
        ("INT", 2, 130),
    ] {
        let dir = workdir();
        let before = files(dir.path());
        let status = interrupted(dir.path(), signal, count);
        assert_eq!(status, Some(code), "SIG{signal} x{count}");
        assert_eq!(files(dir.path()), before, "SIG{signal} x{count} left files");
    }
}

#[test]
fn an_output_never_writes_over_an_input() {
    // `-o on` writes FNAME.out and FNAME.txt; a scene named scene.txt
    // would be written over by its own tree.
    let dir = workdir();
    let scene = std::fs::read(dir.path().join("ccube.des")).unwrap();
    let scene = String::from_utf8(scene)
        .unwrap()
        .replace("fname      ccube", "fname      scene");
    std::fs::write(dir.path().join("scene.txt"), &scene).unwrap();
    let before = files(dir.path());
    let o = run(
        dir.path(),
        &args(&["-i", "-f", "scene.txt", "-o", "on"], SMALL),
        None,
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stdout));
    assert!(
        text(&o.stderr).contains("an input of this run"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("scene.txt")).unwrap(),
        scene
    );
    assert_eq!(files(dir.path()), before, "nothing written");
    // An object file is an input too.
    let o = run(
        dir.path(),
        &args(&["ccube.des", "-o", "det/cube.ppm"], SMALL),
        None,
    );
    assert!(
        o.status.success(),
        "a new file beside the inputs: {}",
        text(&o.stderr)
    );
}

#[test]
fn the_modeling_budgets_are_flags() {
    let dir = workdir();
    let scene = "resolution 32 32\nperspective 45 1 0.01 100\npushmatrix\nident\ntranslate 0 0 -4\n\
                 defobj ball\nsphere 64 32\nendobj\npopmatrix\n";
    std::fs::write(dir.path().join("ball.des"), scene).unwrap();
    let o = run(dir.path(), &["--check", "ball.des"], None);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = run(
        dir.path(),
        &["--check", "ball.des", "--max-model-memory", "0"],
        None,
    );
    assert_eq!(o.status.code(), Some(2), "0 MiB is not a budget");
    // One MiB holds no 2,048-face sphere? It does (about 0.6 MiB); a
    // 512 x 256 one (131,072 faces) does not.
    std::fs::write(
        dir.path().join("big.des"),
        scene.replace("sphere 64 32", "sphere 512 256"),
    )
    .unwrap();
    let o = run(
        dir.path(),
        &["--check", "big.des", "--max-model-memory=1"],
        None,
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("--max-model-memory"),
        "{}",
        text(&o.stderr)
    );
    assert!(
        text(&o.stderr).contains("big.des:7:1"),
        "{}",
        text(&o.stderr)
    );
}

/// A job of a scheduler often may use fewer CPUs than the machine has (a
/// Slurm or Kubernetes cpuset); `taskset` makes one. A quiet run says
/// nothing there either (the allocator once warned on every run).
#[test]
fn a_quiet_run_on_one_cpu_of_many_says_nothing() {
    let dir = workdir();
    let out = Command::new("taskset")
        .args(["-c", "0", bin(), "-q", "--size", "32x32", "ccube.des"])
        .current_dir(dir.path())
        .output()
        .expect("taskset (util-linux) runs");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stderr), "", "stderr of a quiet run");
}

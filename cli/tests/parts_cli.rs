//! `--part I/N` and `plytrace merge` as programs: parts from separate
//! processes merge into the one-process image byte for byte (plytrace
//! and rftb4 from a tree file), `merge --missing` names the parts still to
//! render, and every bad merge input is an error that names it and writes
//! nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The plytrace under test: this package's, or `PLYTRACE_TEST_BIN` (to
/// show the tests failing against an older build).
fn plytrace_bin() -> String {
    std::env::var("PLYTRACE_TEST_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_plytrace").into())
}

fn program(name: &str, dir: &Path, args: &[&str]) -> Output {
    let exe = match name {
        "plytrace" => plytrace_bin(),
        "rftb4" => env!("CARGO_BIN_EXE_rftb4").to_string(),
        _ => unreachable!(),
    };
    Command::new(exe)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// Far longer than any of these runs takes: only a program stuck for
/// good (on a FIFO) reaches it.
const STUCK: Duration = Duration::from_secs(30);

/// `plytrace ARGS` in `dir` with `stdout`, killed (and the test failed)
/// if it is stuck; no panic allowed.
fn bounded(dir: &Path, args: &[&str], stdout: Stdio) -> Output {
    let mut child = Command::new(plytrace_bin())
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > STUCK {
            let _ = child.kill();
            let _ = child.wait();
            panic!("plytrace {args:?} is stuck");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    o
}

/// A copy of part file `src` at `dst` with the iTXt values of `changes`
/// (keyword, value) put in place of its own: a forged part.
fn forge(src: &Path, dst: &Path, changes: &[(&str, &str)]) {
    let file = std::io::BufReader::new(std::fs::File::open(src).unwrap());
    let mut decoder = png::Decoder::new(file);
    decoder.set_ignore_text_chunk(false);
    let mut reader = decoder.read_info().unwrap();
    let (w, h, color) = {
        let i = reader.info();
        (i.width, i.height, i.color_type)
    };
    let texts: Vec<(String, String)> = reader
        .info()
        .utf8_text
        .iter()
        .map(|c| {
            let v = c.get_text().unwrap();
            let v = changes
                .iter()
                .find(|(k, _)| *k == c.keyword)
                .map_or(v, |(_, v)| v.to_string());
            (c.keyword.clone(), v)
        })
        .collect();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut pixels).unwrap();
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(color);
    enc.set_depth(png::BitDepth::Eight);
    for (k, v) in texts {
        enc.add_itxt_chunk(k, v).unwrap();
    }
    let mut writer = enc.write_header().unwrap();
    writer.write_image_data(&pixels).unwrap();
    writer.finish().unwrap();
    std::fs::write(dst, out).unwrap();
}

/// Every file under `dir` (relative names, sorted) with its bytes.
fn tree(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut all = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            if meta.is_dir() {
                stack.push(p);
            } else if meta.is_file() {
                let bytes = std::fs::read(&p).unwrap();
                all.push((p.strip_prefix(dir).unwrap().to_path_buf(), bytes));
            }
        }
    }
    all.sort();
    all
}

/// Asserts that `o` failed with status 1 and each of `says` on stderr.
fn failed_saying(o: &Output, says: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    for s in says {
        assert!(err.contains(s), "`{s}` not in: {err}");
    }
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A working directory with the test scenes.
fn scenes() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["ccube.des", "mirror.des"] {
        std::fs::copy(
            Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/scenes")).join(name),
            dir.path().join(name),
        )
        .unwrap();
    }
    let det = dir.path().join("det");
    std::fs::create_dir(&det).unwrap();
    for e in std::fs::read_dir(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/scenes/det"
    ))
    .unwrap()
    {
        let e = e.unwrap();
        std::fs::copy(e.path(), det.join(e.file_name())).unwrap();
    }
    std::fs::create_dir(dir.path().join("parts")).unwrap();
    dir
}

/// Renders the parts of `scene` into `parts/`, one process each.
fn render_parts(dir: &Path, scene: &str, n: u32, extra: &[&str]) -> Vec<String> {
    (0..n)
        .map(|i| {
            let file = format!("parts/{i}.png");
            let part = format!("{i}/{n}");
            let mut args = vec![scene, "-q", "--size", "64x48", "--part", &part, "-o", &file];
            args.extend_from_slice(extra);
            ok(&program("plytrace", dir, &args));
            file
        })
        .collect()
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn parts_from_separate_processes_merge_into_the_image() {
    let dir = scenes();
    let d = dir.path();
    ok(&program(
        "plytrace",
        d,
        &["mirror.des", "-q", "--size", "64x48", "-o", "whole.png"],
    ));
    let parts = render_parts(d, "mirror.des", 3, &[]);
    let mut args = vec!["merge", "-o", "merged.png"];
    args.extend(parts.iter().map(String::as_str));
    ok(&program("plytrace", d, &args));
    assert_eq!(
        std::fs::read(d.join("merged.png")).unwrap(),
        std::fs::read(d.join("whole.png")).unwrap()
    );
    // Without -o: the name the parts give (the scene's).
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(String::as_str));
    ok(&program("plytrace", d, &args));
    assert!(d.join("mirror.png").is_file());
    // PPM.
    ok(&program(
        "plytrace",
        d,
        &["mirror.des", "-q", "--size", "64x48", "-o", "whole.ppm"],
    ));
    let mut args = vec!["merge", "-o", "merged.ppm"];
    args.extend(parts.iter().map(String::as_str));
    ok(&program("plytrace", d, &args));
    assert_eq!(
        std::fs::read(d.join("merged.ppm")).unwrap(),
        std::fs::read(d.join("whole.ppm")).unwrap()
    );
}

#[test]
fn rftb4_parts_from_one_tree_file() {
    let dir = scenes();
    let d = dir.path();
    // The manual's programs take a front-to-back tree.
    let text = std::fs::read_to_string(d.join("ccube.des")).unwrap();
    std::fs::write(d.join("ccube.des"), format!("sort ftb\n{text}")).unwrap();
    ok(&program(
        "plytrace",
        d,
        &[
            "ccube.des",
            "-q",
            "--size",
            "64x48",
            "-o",
            "on",
            "-b",
            "off",
        ],
    ));
    ok(&program(
        "rftb4",
        d,
        &["ccube", "whole", "64", "48", "4", "-B", "-y"],
    ));
    for i in 0..7 {
        let part = format!("{i}/7");
        let file = format!("parts/{i}.png");
        ok(&program(
            "rftb4",
            d,
            &[
                "ccube", "x", "64", "48", "4", "-B", "-y", "--part", &part, "-o", &file,
            ],
        ));
    }
    let mut args = vec!["merge".to_string(), "-o".into(), "merged.png".into()];
    args.extend((0..7).map(|i| format!("parts/{i}.png")));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    ok(&program("plytrace", d, &args));
    assert_eq!(
        std::fs::read(d.join("merged.png")).unwrap(),
        std::fs::read(d.join("whole.png")).unwrap()
    );
}

/// Runs `merge -o out.png` on `parts`: it must fail naming `names`, and
/// leave no file behind.
fn refused(d: &Path, parts: &[&str], names: &[&str]) {
    let before = files(d);
    let mut args = vec!["merge", "-o", "out.png"];
    args.extend_from_slice(parts);
    let o = program("plytrace", d, &args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    for n in names {
        assert!(err.contains(n), "`{n}` not in: {err}");
    }
    assert_eq!(files(d), before, "a merge that failed wrote a file");
}

#[test]
fn bad_merge_inputs_are_refused_by_name_and_nothing_is_written() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 3, &[]);
    let p: Vec<&str> = parts.iter().map(String::as_str).collect();
    // Missing.
    refused(d, &[p[0], p[2]], &["part 1 of 3 missing"]);
    // Duplicate (a copy of a part).
    std::fs::copy(d.join(p[1]), d.join("copy.png")).unwrap();
    refused(d, &[p[0], p[1], "copy.png", p[2]], &["copy.png", "again"]);
    // Truncated.
    let bytes = std::fs::read(d.join(p[1])).unwrap();
    std::fs::write(d.join("cut.png"), &bytes[..bytes.len() / 2]).unwrap();
    refused(d, &[p[0], "cut.png", p[2]], &["cut.png", "truncated"]);
    // Foreign: a part of another render (another scene).
    std::fs::create_dir(d.join("other")).unwrap();
    ok(&program(
        "plytrace",
        d,
        &[
            "mirror.des",
            "-q",
            "--size",
            "64x48",
            "--part",
            "1/3",
            "-o",
            "other/1.png",
        ],
    ));
    refused(
        d,
        &[p[0], "other/1.png", p[2]],
        &["other/1.png", "another render"],
    );
    // Foreign: the same scene with other flags.
    ok(&program(
        "plytrace",
        d,
        &[
            "ccube.des",
            "-q",
            "--size",
            "64x48",
            "--aa",
            "none",
            "--part",
            "1/3",
            "-o",
            "other/2.png",
        ],
    ));
    refused(
        d,
        &[p[0], "other/2.png", p[2]],
        &["other/2.png", "fingerprint"],
    );
    // Not a part file at all.
    ok(&program(
        "plytrace",
        d,
        &["ccube.des", "-q", "--size", "64x48", "-o", "plain.png"],
    ));
    refused(
        d,
        &[p[0], "plain.png", p[2]],
        &["plain.png", "not a part file"],
    );
    std::fs::write(d.join("text.png"), "hello").unwrap();
    refused(
        d,
        &[p[0], "text.png", p[2]],
        &["text.png", "not a readable PNG"],
    );
    // A part count that disagrees.
    ok(&program(
        "plytrace",
        d,
        &[
            "ccube.des",
            "-q",
            "--size",
            "64x48",
            "--part",
            "1/4",
            "-o",
            "other/4.png",
        ],
    ));
    refused(d, &[p[0], "other/4.png", p[2]], &["other/4.png"]);
    // A part file that is absent.
    refused(d, &[p[0], "absent.png", p[2]], &["absent.png"]);
    // All well: it merges.
    let mut args = vec!["merge", "-o", "out.png"];
    args.extend_from_slice(&p);
    ok(&program("plytrace", d, &args));
}

#[test]
fn merge_missing_lists_the_parts_to_render() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 8, &[]);
    let missing = |list: &[&str]| {
        let mut args = vec!["merge", "--missing"];
        args.extend_from_slice(list);
        let o = program("plytrace", d, &args);
        ok(&o);
        String::from_utf8_lossy(&o.stdout).trim().to_string()
    };
    let p: Vec<&str> = parts.iter().map(String::as_str).collect();
    assert_eq!(missing(&p), "");
    let some: Vec<&str> = p
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != 3 && *i != 7)
        .map(|(_, s)| *s)
        .collect();
    assert_eq!(missing(&some), "3,7");
    // A damaged part counts as missing.
    let bytes = std::fs::read(d.join(p[5])).unwrap();
    std::fs::write(d.join(p[5]), &bytes[..bytes.len() - 20]).unwrap();
    assert_eq!(missing(&some), "3,5,7");
    // No part yet: --count says how many.
    let o = program("plytrace", d, &["merge", "--missing", "--count", "4"]);
    ok(&o);
    assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), "0,1,2,3");
}

#[test]
fn part_flags_are_checked() {
    let dir = scenes();
    let d = dir.path();
    for (args, says) in [
        (vec!["ccube.des", "--part", "3/3", "-o", "p.png"], "0 to 2"),
        (vec!["ccube.des", "--part", "1/2"], "-o"),
        (vec!["ccube.des", "--part", "1/2", "-o", "p.ppm"], "-o"),
        (vec!["ccube.des", "--part", "x", "-o", "p.png"], "I/N"),
    ] {
        let o = program("plytrace", d, &args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert!(!d.join("p.png").exists());
}

#[test]
fn frames_render_only_their_runs_with_the_whole_numbering() {
    let dir = scenes();
    let d = dir.path();
    let mut text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/spin.des"))
            .unwrap();
    text = text.replace("resolution 256 256", "resolution 32 32");
    std::fs::write(d.join("anim.des"), &text).unwrap();
    ok(&program(
        "plytrace",
        d,
        &["anim.des", "-q", "--frames", "1..2"],
    ));
    let made: Vec<String> = files(d)
        .into_iter()
        .filter(|f| f.starts_with("spin"))
        .collect();
    assert_eq!(made, ["spin1.png", "spin2.png"]);
    let keep: PathBuf = d.join("spin2.png");
    let one = std::fs::read(&keep).unwrap();
    ok(&program("plytrace", d, &["anim.des", "-q"]));
    assert_eq!(
        std::fs::read(&keep).unwrap(),
        one,
        "frame 2 alone is frame 2 of the whole"
    );
}

/// An animation of five frames (`run`s) of a turning four-lobed surface,
/// each frame named by its `fname`, at 48 x 32.
const ANIMATION: &str = "resolution 48 32\nperspective 40 1 0.1 100\n\
    light 4 -6 8 1 1 1 100 Diffuse\npushmatrix\nident\npolarview 4.5 25 65 0\n\
    defobj geo\n  color 0.9 0.6 0.3\n  geodesic 4 angle\n  radial lobes 0.35 4\nendobj\n\
    popmatrix\nfname f0\nrun\nradial rotate 15 z\nfname f1\nrun\nradial rotate 15 z\n\
    fname f2\nrun\nradial rotate 15 z\nfname f3\nrun\nradial rotate 15 z\nfname f4\nrun\n";

#[test]
fn parts_of_an_animation_are_its_frames_each_as_a_whole_render_makes_it() {
    let whole = tempfile::tempdir().unwrap();
    std::fs::write(whole.path().join("anim.des"), ANIMATION).unwrap();
    ok(&program("plytrace", whole.path(), &["anim.des", "-q"]));
    let frames: Vec<String> = (0..5).map(|f| format!("f{f}.png")).collect();
    for f in &frames {
        assert!(whole.path().join(f).is_file(), "{f}");
    }
    // Three parts of five frames: 0, 1-2, 3-4; seven parts: some empty.
    for n in [3u32, 7] {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(d.path().join("anim.des"), ANIMATION).unwrap();
        for i in 0..n {
            let part = format!("{i}/{n}");
            let pngs = || {
                let mut f = files(d.path());
                f.retain(|f| f.ends_with(".png"));
                f
            };
            let before = pngs().len();
            ok(&program(
                "plytrace",
                d.path(),
                &["anim.des", "-q", "--part", &part],
            ));
            let (first, end) = (i * 5 / n, (i + 1) * 5 / n);
            // Each part writes its frames and only those.
            let wrote = pngs();
            assert_eq!(
                wrote.len(),
                before + (end - first) as usize,
                "part {part}: {wrote:?}"
            );
            assert!((first..end).all(|f| wrote.contains(&format!("f{f}.png"))));
        }
        for f in &frames {
            let a = std::fs::read(whole.path().join(f)).unwrap();
            let b = std::fs::read(d.path().join(f)).unwrap();
            assert!(a == b, "{f} of {n} parts differs from the whole render's");
        }
    }
    // A part file name makes no sense for frames: refused, nothing written.
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("anim.des"), ANIMATION).unwrap();
    let out = program(
        "plytrace",
        d.path(),
        &["anim.des", "-q", "--part", "1/2", "-o", "p.png"],
    );
    assert_eq!(out.status.code(), Some(2));
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(msg.contains("animation of 5 frames"), "{msg}");
    assert!(!files(d.path()).iter().any(|f| f.ends_with(".png")));
    // A one-run scene still needs -o for its part file.
    let d = scenes();
    let out = program("plytrace", d.path(), &["ccube.des", "-q", "--part", "1/2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("name it with -o"));
}

/// A forged part may name the image anything: without -o, merge takes
/// the name only inside the working directory, as an image (.png or
/// .ppm), and refuses any other by name, writing nothing; with -o the
/// parts' name is not used at all.
#[test]
fn a_forged_part_cannot_make_merge_write_outside_the_working_directory() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 2, &[]);
    // The merge runs in `inner`; `d` around it stands for the outside.
    let inner = d.join("inner");
    std::fs::create_dir_all(inner.join("sub")).unwrap();
    std::fs::write(d.join("victim.png"), "keep").unwrap();
    std::fs::write(inner.join("keep.des"), "keep").unwrap();
    std::os::unix::fs::symlink(d, inner.join("out")).unwrap();
    let absolute = d.join("absolute.png");
    std::fs::create_dir(d.join("forged")).unwrap();
    let forged = |name: &str| -> Vec<String> {
        (0..2)
            .map(|i| {
                let f = format!("forged/{i}.png");
                forge(
                    &d.join(&parts[i]),
                    &d.join(&f),
                    &[("plytrace-output", name)],
                );
                format!("../{f}")
            })
            .collect()
    };
    let abs = absolute.display().to_string();
    for name in [
        abs.as_str(),
        "../victim.png",
        "sub/../../victim.png",
        "out/victim.png",
        "keep.des",
        "colour\x1b[31m.png",
        "",
    ] {
        let list = forged(name);
        let before = tree(d);
        let mut args = vec!["merge"];
        args.extend(list.iter().map(String::as_str));
        let o = bounded(&inner, &args, Stdio::piped());
        failed_saying(&o, &["plytrace-output", "name the image with -o"]);
        assert!(tree(d) == before, "{name:?}: a refused merge wrote a file");
    }
    assert!(!absolute.exists());
    // With -o the forged name is ignored.
    let list = forged("../victim.png");
    let mut args = vec!["merge", "-o", "given.png"];
    args.extend(list.iter().map(String::as_str));
    ok(&bounded(&inner, &args, Stdio::piped()));
    assert!(inner.join("given.png").is_file());
    assert_eq!(std::fs::read(d.join("victim.png")).unwrap(), b"keep");
    // A name inside the working directory is taken.
    let list = forged("sub/ok.png");
    let mut args = vec!["merge"];
    args.extend(list.iter().map(String::as_str));
    ok(&bounded(&inner, &args, Stdio::piped()));
    assert_eq!(
        std::fs::read(inner.join("sub/ok.png")).unwrap(),
        std::fs::read(inner.join("given.png")).unwrap()
    );
}

/// No output of a merge, in any format, replaces one of its parts, under
/// whatever name (the same path, a hard link, a name the parts give, a
/// separation's suffix); nothing is written then.
#[test]
fn merge_never_writes_over_one_of_its_parts() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 3, &[]);
    std::fs::hard_link(d.join(&parts[1]), d.join("hard.png")).unwrap();
    std::fs::copy(d.join(&parts[1]), d.join("p1.ppm")).unwrap();
    std::fs::copy(d.join(&parts[2]), d.join("s.b")).unwrap();
    std::fs::create_dir(d.join("forged")).unwrap();
    for (i, part) in parts.iter().enumerate() {
        forge(
            &d.join(part),
            &d.join(format!("forged/{i}.png")),
            &[("plytrace-output", "forged/1.png")],
        );
    }
    let cases: [&[&str]; 5] = [
        &[
            "-o",
            "parts/1.png",
            "parts/0.png",
            "parts/1.png",
            "parts/2.png",
        ],
        &[
            "-o",
            "parts/1.png",
            "parts/0.png",
            "hard.png",
            "parts/2.png",
        ],
        &["-o", "p1.ppm", "parts/0.png", "p1.ppm", "parts/2.png"],
        &[
            "--separations",
            "-o",
            "s",
            "parts/0.png",
            "parts/1.png",
            "s.b",
        ],
        &["forged/0.png", "forged/1.png", "forged/2.png"],
    ];
    let mut refusals = Vec::new();
    for case in cases {
        let before = tree(d);
        let mut args = vec!["merge"];
        args.extend_from_slice(case);
        let o = bounded(d, &args, Stdio::piped());
        assert!(tree(d) == before, "{case:?}: a merge wrote over a part");
        refusals.push(o);
    }
    for o in &refusals {
        failed_saying(o, &["is not written over"]);
    }
}

/// A part that is a FIFO, a device or a directory is refused by name,
/// without waiting for a writer, by merge and by merge --missing alike.
#[test]
fn a_part_that_is_not_a_regular_file_is_refused_without_waiting() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 2, &[]);
    let made = Command::new("mkfifo")
        .arg(d.join("fifo.png"))
        .status()
        .expect("run mkfifo");
    assert!(made.success());
    std::fs::create_dir(d.join("dir.png")).unwrap();
    for (name, kind) in [
        ("fifo.png", "a FIFO"),
        ("/dev/null", "a character device"),
        ("dir.png", "a directory"),
    ] {
        let o = bounded(
            d,
            &["merge", "-o", "out.png", &parts[0], name, &parts[1]],
            Stdio::piped(),
        );
        failed_saying(&o, &[name, kind, "not a part file"]);
        let o = bounded(d, &["merge", "--missing", &parts[0], name], Stdio::piped());
        ok(&o);
        assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), "1");
        assert!(String::from_utf8_lossy(&o.stderr).contains(kind));
    }
    assert!(!d.join("out.png").exists());
}

/// Headers no part file of this program has: an interlaced PNG, an image
/// over the pixel budget, an index or rows out of range, a PNG of another
/// program; each refused by name before a row is merged.
#[test]
fn hostile_part_headers_are_refused_by_name() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 2, &[]);
    // A 4 x 4 RGB PNG, Adam7 interlaced, that says it is part 0/1 (made
    // with Python's zlib: passes 1, 4, 5, 6, 7 of a 4 x 4 image).
    let interlaced = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("tests/data/parts/interlaced.png");
    std::fs::copy(&interlaced, d.join("interlaced.png")).unwrap();
    let o = bounded(
        d,
        &["merge", "-o", "out.ppm", "interlaced.png"],
        Stdio::piped(),
    );
    failed_saying(&o, &["interlaced.png", "interlaced"]);
    let forged = |name: &str, changes: &[(&str, &str)]| {
        forge(&d.join(&parts[0]), &d.join(name), changes);
        name.to_string()
    };
    let huge = forged("huge.png", &[("plytrace-image", "100000x100000")]);
    let o = bounded(d, &["merge", "-o", "out.png", &huge], Stdio::piped());
    failed_saying(&o, &["huge.png", "--max-pixels"]);
    let o = bounded(
        d,
        &[
            "merge",
            "--max-pixels",
            "100",
            "-o",
            "out.png",
            &parts[0],
            &parts[1],
        ],
        Stdio::piped(),
    );
    failed_saying(&o, &["3072 pixels", "--max-pixels"]);
    for (changes, says) in [
        (&[("plytrace-part", "5/2")][..], "0 to 1"),
        (&[("plytrace-part", "0/0")][..], "1 to 65536"),
        (
            &[("plytrace-rows", "40+24")][..],
            "pass the image's 48 rows",
        ),
        (&[("plytrace-image", "0x48")][..], "expected WxH"),
    ] {
        let f = forged("bad.png", changes);
        let o = bounded(
            d,
            &["merge", "-o", "out.png", &f, &parts[1]],
            Stdio::piped(),
        );
        failed_saying(&o, &["bad.png", says]);
    }
    // A part of 65536 with nearly all of them missing: the list stays short.
    let lone = forged("lone.png", &[("plytrace-part", "0/65536")]);
    let o = bounded(d, &["merge", "-o", "out.png", &lone], Stdio::piped());
    failed_saying(&o, &["parts 1-65535 of 65536 missing"]);
    assert!(
        o.stderr.len() < 1000,
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // Another program's PNG: 16-bit grey, no metadata.
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, 2, 2);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    let mut w = enc.write_header().unwrap();
    w.write_image_data(&[0; 8]).unwrap();
    w.finish().unwrap();
    std::fs::write(d.join("foreign.png"), bytes).unwrap();
    let o = bounded(
        d,
        &["merge", "-o", "out.png", "foreign.png"],
        Stdio::piped(),
    );
    failed_saying(&o, &["foreign.png", "not a part file"]);
    assert!(!d.join("out.png").exists() && !d.join("out.ppm").exists());
}

/// `merge --missing` prints what a job array is submitted again from: a
/// full disk or a closed pipe on stdout is an error, not an empty list.
#[test]
fn merge_missing_that_cannot_be_written_is_an_error() {
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 3, &[]);
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let o = bounded(d, &["merge", "--missing", &parts[0]], Stdio::from(full));
    failed_saying(&o, &["missing parts", "No space left"]);
    let (read, write) = std::io::pipe().unwrap();
    drop(read);
    let o = bounded(d, &["merge", "--missing", &parts[0]], Stdio::from(write));
    failed_saying(&o, &["missing parts"]);
}

/// Two merges into one output at once, of two different renders: the
/// output is whole and all of one of them, never a mix, as PNG and as
/// separations (each set renamed into place under its directory's lock).
#[test]
fn concurrent_merges_into_one_output_give_one_whole_image() {
    let dir = scenes();
    let d = dir.path();
    std::fs::create_dir(d.join("mparts")).unwrap();
    let a = render_parts(d, "ccube.des", 2, &[]);
    let b: Vec<String> = (0..2)
        .map(|i| {
            let f = format!("mparts/{i}.png");
            let part = format!("{i}/2");
            let args = [
                "mirror.des",
                "-q",
                "--size",
                "64x48",
                "--part",
                &part,
                "-o",
                &f,
            ];
            ok(&program("plytrace", d, &args));
            f
        })
        .collect();
    let merge = |parts: &[String], out: &[&str]| {
        let mut args = vec!["merge".to_string()];
        args.extend(out.iter().map(|s| s.to_string()));
        args.extend(parts.iter().cloned());
        Command::new(plytrace_bin())
            .args(&args)
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    let seps = |seed: &str| -> Vec<Vec<u8>> {
        ["r", "g", "b"]
            .iter()
            .map(|e| std::fs::read(d.join(format!("{seed}.{e}"))).unwrap())
            .collect()
    };
    for (parts, name) in [(&a, "a"), (&b, "b")] {
        assert!(
            merge(parts, &["-o", &format!("{name}.png")])
                .wait()
                .unwrap()
                .success()
        );
        let out = ["--separations", "-o", name];
        assert!(merge(parts, &out).wait().unwrap().success());
    }
    let (png_a, png_b) = (
        std::fs::read(d.join("a.png")).unwrap(),
        std::fs::read(d.join("b.png")).unwrap(),
    );
    let (sep_a, sep_b) = (seps("a"), seps("b"));
    assert!(png_a != png_b && sep_a != sep_b);
    for _ in 0..4 {
        let mut running = Vec::new();
        for parts in [&a, &b, &a, &b] {
            running.push(merge(parts, &["-o", "both.png"]));
            running.push(merge(parts, &["--separations", "-o", "both"]));
        }
        for mut c in running {
            assert!(c.wait().unwrap().success());
        }
        let png = std::fs::read(d.join("both.png")).unwrap();
        assert!(png == png_a || png == png_b, "a mixed or partial PNG");
        let sep = seps("both");
        assert!(
            sep == sep_a || sep == sep_b,
            "separations of two merges mixed"
        );
    }
    assert!(
        !files(d)
            .iter()
            .any(|f| f.ends_with(".tmp") || f.ends_with(".old")),
        "{:?}",
        files(d)
    );
}

/// A merge whose separations would go into a directory another process
/// is committing into waits for it, and says so: the test holds the
/// directory's lock, sees the merge say it waits with nothing renamed
/// into place yet, and lets it go.
#[test]
fn a_merge_takes_its_turn_with_another_process_writing_the_same_directory() {
    use std::io::BufRead;
    let dir = scenes();
    let d = dir.path();
    let parts = render_parts(d, "ccube.des", 2, &[]);
    let lock = nix::fcntl::Flock::lock(
        std::fs::File::open(d).unwrap(),
        nix::fcntl::FlockArg::LockExclusive,
    )
    .unwrap();
    let mut child = Command::new(plytrace_bin())
        .args(["merge", "--separations", "-o", "s", &parts[0], &parts[1]])
        .current_dir(d)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    let waited = line.contains("waiting for another process writing into");
    let early = ["s.r", "s.g", "s.b"].map(|f| d.join(f).exists());
    drop(lock);
    let status = child.wait().unwrap();
    assert!(waited, "the merge did not wait for the lock: {line:?}");
    assert_eq!(early, [false; 3], "renamed into place under another's lock");
    assert!(status.success());
    assert!(["s.r", "s.g", "s.b"].iter().all(|f| d.join(f).is_file()));
}

/// `--frames` past the animation's last frame renders nothing and is an
/// error of the command line; a range that runs past the end renders the
/// frames there are and warns.
#[test]
fn frames_past_the_end_are_an_error_and_partly_past_a_warning() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("anim.des"), ANIMATION).unwrap();
    let pngs = || {
        let mut f = files(d.path());
        f.retain(|f| f.ends_with(".png"));
        f
    };
    for range in ["5", "7..9", "5.."] {
        let o = bounded(
            d.path(),
            &["anim.des", "-q", "--frames", range],
            Stdio::piped(),
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{range}: {err}");
        assert!(
            err.contains("5 frames, 0 to 4") && err.contains("nothing was rendered"),
            "{err}"
        );
        assert!(pngs().is_empty());
    }
    let o = bounded(
        d.path(),
        &["anim.des", "-q", "--frames", "3..9"],
        Stdio::piped(),
    );
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning: --frames 3..9") && err.contains("frames 5 to 9"),
        "{err}"
    );
    assert_eq!(pngs(), ["f3.png", "f4.png"]);
    // An open range is the frames from A on, without a warning.
    let o = bounded(
        d.path(),
        &["anim.des", "-q", "--frames", "4.."],
        Stdio::piped(),
    );
    ok(&o);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // A still is one frame, frame 0.
    let s = scenes();
    let o = bounded(
        s.path(),
        &["ccube.des", "-q", "--frames", "1"],
        Stdio::piped(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("1 frame, frame 0"));
}

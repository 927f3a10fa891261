//! `--part I/N` and `plytrace merge` as programs: parts from separate
//! processes merge into the one-process image byte for byte (plytrace
//! and rftb4 from a tree file), `merge --missing` names the parts still to
//! render, and every bad merge input is an error that names it and writes
//! nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn program(name: &str, dir: &Path, args: &[&str]) -> Output {
    let exe = match name {
        "plytrace" => env!("CARGO_BIN_EXE_plytrace"),
        "rftb4" => env!("CARGO_BIN_EXE_rftb4"),
        _ => unreachable!(),
    };
    Command::new(exe)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A working directory with the test scenes.
fn scenes() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["ccube.des", "mirror.des"] {
        std::fs::copy(
            Path::new("tests/data/scenes").join(name),
            dir.path().join(name),
        )
        .unwrap();
    }
    let det = dir.path().join("det");
    std::fs::create_dir(&det).unwrap();
    for e in std::fs::read_dir("tests/data/scenes/det").unwrap() {
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
    let mut text = std::fs::read_to_string("examples/spin.des").unwrap();
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

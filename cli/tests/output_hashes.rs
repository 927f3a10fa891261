//! Every output byte of every bundled scene, pinned: the hashes of the
//! images (PNG, PPM, `--id-image`), virtual image tree files, vector files
//! (SVG, PDF, TikZ), hidden-line drawings, and the manual's programs
//! (rftb1-rftb4, getrgb) run on the tree files, for each scene in
//! `tests/data/scenes` and `examples` under several flag sets.
//!
//! A refactoring must not change one byte of what users get. When a
//! change of output is intended, regenerate the table with
//! `PLYTRACE_BLESS_HASHES=1 cargo test --release --test output_hashes`
//! and say why in the commit message.
//!
//! Logs (`*.log`: dates and times) are left out. The hash is 64-bit FNV-1a, written here, so the table does not depend
//! on a library's version.

#[path = "../../tests/support/mod.rs"]
mod support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const TABLE: &str = "tests/data/output-hashes.txt";

/// Flag sets run on every scene: a name and the arguments before the scene.
/// The `tree-pre` and `tree-post` sets also put `sort ftb` before the
/// scene's own commands and run the manual's programs on the tree files.
const FLAG_SETS: &[(&str, &[&str])] = &[
    ("default", &["--size", "96x72"]),
    // The default picture is NNS's (checked below, file for file), and
    // the simple sort stays what it was.
    ("n-on", &["--size", "96x72", "-n", "on"]),
    (
        "depth-sort",
        &["--size", "96x72", "--visibility", "depth-sort"],
    ),
    ("tree", &["--size", "64x64", "-o", "on", "-l", "3"]),
    (
        "tree-pre",
        &["--size", "64x64", "-o", "on", "-l", "3", "-b", "on"],
    ),
    (
        "tree-post",
        &["--size", "64x64", "-o", "on", "-l", "3", "-b", "off"],
    ),
    ("modes", &["--size", "64x48", "-v", "-s", "-n", "-b", "-x"]),
    ("aa-none", &["--size", "64x64", "--aa", "none"]),
    ("aa-area", &["--size", "64x64", "--aa", "area"]),
    ("aa-mask", &["--size", "64x64", "--aa", "mask"]),
    ("aa-multilevel", &["--size", "64x64", "--aa", "multilevel"]),
    ("supersample", &["--size", "48x48", "--supersample", "3"]),
    ("donovan", &["--size", "48x48", "--shading", "donovan"]),
    (
        "no-shadows",
        &["--size", "64x64", "--no-shadows", "-h", "off"],
    ),
    (
        "id-image",
        &["--size", "64x64", "--id-image", "id.png", "-o", "img.ppm"],
    ),
    ("svg", &["--size", "96x72", "-o", "v.svg"]),
    ("pdf", &["--size", "96x72", "-o", "v.pdf"]),
    ("tex", &["--size", "96x72", "-o", "v.tex"]),
    (
        "hidden-line",
        &["--size", "96x72", "--hidden-line", "-o", "h.png"],
    ),
    (
        "hidden-line-svg",
        &["--size", "96x72", "--hidden-line", "-o", "h.svg"],
    ),
    ("raytrace", &["--size", "48x48", "--raytrace", "-l", "4"]),
    (
        "raytrace-ss",
        &["--size", "32x32", "--raytrace", "--supersample", "2"],
    ),
    (
        "nns",
        &["--size", "64x64", "--visibility", "nns", "--no-shadows"],
    ),
    (
        "z-buffer",
        &[
            "--size",
            "64x64",
            "--visibility",
            "z-buffer",
            "--no-shadows",
        ],
    ),
    (
        "scan-line",
        &[
            "--size",
            "64x64",
            "--visibility",
            "scan-line",
            "--no-shadows",
        ],
    ),
    (
        "warnock",
        &["--size", "64x64", "--visibility", "warnock", "--no-shadows"],
    ),
    (
        "brown",
        &["--size", "64x64", "--visibility", "brown", "--no-shadows"],
    ),
    (
        "ray-cast",
        &[
            "--size",
            "64x64",
            "--visibility",
            "ray-cast",
            "--no-shadows",
        ],
    ),
];

/// The manual's programs run on the tree files `NAME.out` of a flag set:
/// rftb1-3 take pre-blended trees, rftb4 (and getrgb on its pixel
/// structs) post-blended ones. Each entry: the program and the output's
/// suffix.
const PROGRAMS: &[(&str, &str, &str)] = &[
    ("tree-pre", "rftb1", "r1"),
    ("tree-pre", "rftb2", "r2"),
    ("tree-pre", "rftb3", "r3"),
    ("tree-post", "rftb4", "r4"),
];

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

fn files(dir: &Path) -> BTreeMap<String, u64> {
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            let name = entry.file_name().to_string_lossy().into_owned();
            out.insert(name, fnv1a(&std::fs::read(entry.path()).unwrap()));
        }
    }
    out
}

/// Runs `program`; a refusal is an output too: `None` when it succeeds,
/// else a line naming its exit status and the hash of its message.
fn run(dir: &Path, program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(bin(program))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    let code = out
        .status
        .code()
        .unwrap_or_else(|| panic!("{program} {args:?}: {}", out.status));
    (code != 0).then(|| format!("{program}-exit-{code} {:016x}", fnv1a(&out.stderr)))
}

fn bin(program: &str) -> PathBuf {
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_plytrace"));
    exe.with_file_name(program)
}

/// The scenes: (label, folder to copy, scene file name).
fn scenes() -> Vec<(String, PathBuf, String)> {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let mut out = Vec::new();
    for folder in ["tests/data/scenes", "examples"] {
        let dir = root.join(folder);
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".des"))
            .collect();
        names.sort();
        assert!(names.len() >= 4, "{folder}: scenes missing ({names:?})");
        for name in names {
            out.push((format!("{folder}/{name}"), dir.clone(), name));
        }
    }
    out
}

/// Every output of one scene under one flag set (and, for `tree`, of the
/// manual's programs on its tree file), as `label flags file hash` lines.
fn outputs(label: &str, folder: &Path, scene: &str, flags: (&str, &[&str])) -> Vec<String> {
    let tmp = tempfile::tempdir().unwrap();
    support::copy_tree(folder, tmp.path());
    let before = files(tmp.path());
    let programs = flags.0.starts_with("tree-");
    let scene = if programs {
        front_to_back(tmp.path(), scene)
    } else {
        scene.to_string()
    };
    let mut args: Vec<&str> = vec!["-q"];
    args.extend(flags.1);
    args.push(&scene);
    let mut refusals: Vec<String> = run(tmp.path(), "plytrace", &args).into_iter().collect();
    if programs {
        refusals.extend(run_programs(tmp.path(), &before, flags.0));
    }
    let mut lines: Vec<String> = refusals
        .iter()
        .map(|r| format!("{label} {} {r}", flags.0))
        .collect();
    for (name, hash) in files(tmp.path()) {
        if name.ends_with(".log") || before.get(&name) == Some(&hash) {
            continue;
        }
        lines.push(format!("{label} {} {name} {hash:016x}", flags.0));
    }
    assert!(!lines.is_empty(), "{label} {}: no output", flags.0);
    lines
}

/// A copy of `scene` whose polygons are sorted front to back, as the
/// manual's tilers need; returns its name.
fn front_to_back(dir: &Path, scene: &str) -> String {
    let text = std::fs::read_to_string(dir.join(scene)).unwrap();
    let name = format!("ftb-{scene}");
    std::fs::write(dir.join(&name), format!("sort ftb\n{text}")).unwrap();
    name
}

fn run_programs(dir: &Path, before: &BTreeMap<String, u64>, set: &str) -> Vec<String> {
    let mut refusals = Vec::new();
    let trees: Vec<String> = files(dir)
        .into_keys()
        .filter(|n| n.ends_with(".out") && !before.contains_key(n))
        .collect();
    for tree in trees {
        let stem = tree.trim_end_matches(".out");
        for (_, program, suffix) in PROGRAMS.iter().filter(|p| p.0 == set) {
            refusals.extend(run(
                dir,
                program,
                &[stem, &format!("{stem}.{suffix}"), "64", "64"],
            ));
        }
        if set == "tree-post" {
            let png = format!("{stem}.getrgb.png");
            refusals.extend(run(dir, "getrgb", &[&format!("{stem}.r4"), "--png", &png]));
        }
    }
    refusals
}

fn all_outputs() -> Vec<String> {
    let cases: Vec<_> = scenes()
        .into_iter()
        .flat_map(|s| FLAG_SETS.iter().map(move |f| (s.clone(), *f)))
        .collect();
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    let chunk = cases.len().div_ceil(workers);
    let mut lines: Vec<String> = std::thread::scope(|scope| {
        let handles: Vec<_> = cases
            .chunks(chunk)
            .map(|part| {
                scope.spawn(move || {
                    part.iter()
                        .flat_map(|((label, dir, scene), f)| outputs(label, dir, scene, *f))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    lines.sort();
    lines
}

/// The default picture of every scene is the NNS picture, byte for byte.
fn assert_default_is_nns(lines: &[String]) {
    let set = |name: &str| -> BTreeMap<(&str, &str), &str> {
        lines
            .iter()
            .filter_map(|l| {
                let w: Vec<&str> = l.split(' ').collect();
                (w[1] == name).then(|| ((w[0], w[2]), w[3]))
            })
            .collect()
    };
    let (default, nns) = (set("default"), set("n-on"));
    assert!(default.len() >= scenes().len(), "{default:?}");
    assert_eq!(default, nns, "the default picture is not the NNS picture");
}

#[test]
fn every_output_byte_is_unchanged() {
    let lines = all_outputs();
    assert_default_is_nns(&lines);
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(TABLE);
    if std::env::var_os("PLYTRACE_BLESS_HASHES").is_some() {
        std::fs::write(&path, lines.join("\n") + "\n").unwrap();
        return;
    }
    let table = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (PLYTRACE_BLESS_HASHES=1 writes it)",
            path.display()
        )
    });
    let want: Vec<&str> = table.lines().collect();
    let got: Vec<&str> = lines.iter().map(String::as_str).collect();
    let missing: Vec<_> = want.iter().filter(|l| !got.contains(l)).collect();
    let new: Vec<_> = got.iter().filter(|l| !want.contains(l)).collect();
    assert!(
        missing.is_empty() && new.is_empty(),
        "outputs changed ({} expected lines missing, {} new):\nexpected:\n{}\ngot:\n{}",
        missing.len(),
        new.len(),
        missing
            .iter()
            .take(40)
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join("\n"),
        new.iter()
            .take(40)
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join("\n"),
    );
}

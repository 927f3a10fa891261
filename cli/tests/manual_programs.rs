//! The manual's programs as its pages describe them (Garcia 1986, 004
//! appendix B: the rftb, getrgb and mkdet manual pages; chapter 5). Each
//! test quotes the sentence it checks. The programs run as binaries in a
//! temporary directory.

use std::path::Path;
use std::process::{Command, Output};

use plytrace::internal::tree::{PhongShades, Record, RecordStream, Shades};

fn run(bin: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(bin)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

const RFTB1: &str = env!("CARGO_BIN_EXE_rftb1");
const RFTB2: &str = env!("CARGO_BIN_EXE_rftb2");
const RFTB3: &str = env!("CARGO_BIN_EXE_rftb3");
const RFTB4: &str = env!("CARGO_BIN_EXE_rftb4");
const GETRGB: &str = env!("CARGO_BIN_EXE_getrgb");

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The whole image, the unit square (figure 4.14: "x,y floats 0 to 1").
const FULL: [[f32; 2]; 4] = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];

fn record(level: u16, points: &[[f32; 2]], shades: Shades) -> Record {
    Record {
        level,
        points: points.to_vec(),
        shades,
    }
}

/// A Phong record without highlights: colour and transparency byte `t`
/// at every vertex (figure 4.14: "<r g b t> ... unsigned chars 0 to 255").
fn transparent(level: u16, points: &[[f32; 2]], rgb: [u8; 3], t: u8) -> Record {
    let n = points.len();
    record(
        level,
        points,
        Shades::Phong(Box::new(PhongShades {
            shininess: 1.0,
            light_colors: Vec::new(),
            rgbt: vec![[rgb[0], rgb[1], rgb[2], t]; n],
            normals: vec![Vec::new(); n],
        })),
    )
}

fn write(dir: &Path, name: &str, records: Vec<Record>, blended: bool, background: [u8; 3]) {
    let stream = RecordStream {
        records,
        background: Some(background),
        front_to_back: true,
        blended,
    };
    std::fs::write(dir.join(format!("{name}.out")), stream.to_bytes()).unwrap();
}

/// A triangle over a square, level 1, front to back: partly covered
/// pixels along the edges leave pixel-fragments in rftb4 without `-B`.
fn two_polygons() -> Vec<Record> {
    vec![
        record(
            1,
            &[[0.1, 0.1], [0.5, 0.9], [0.9, 0.1]],
            Shades::Gouraud(vec![[200, 100, 50]; 3]),
        ),
        record(
            1,
            &[[0.2, 0.2], [0.2, 0.8], [0.8, 0.8], [0.8, 0.2]],
            Shades::Gouraud(vec![[10, 220, 30]; 4]),
        ),
    ]
}

// ---------------------------------------------------------------------------
// 1. getrgb needs no resolution

/// getrgb manual page: SYNOPSIS "getrgb [fname]" (no resolution) and "A
/// pixel-struct file is assumed to contain a linear list of 64-bit data
/// structures ... typedef struct { fragment *flist; byte r, g, b; byte
/// pixstat; } pixelstruct;". rftb4's file is exactly hres x vres such
/// structs, at any resolution and with fragments left (no `-B`), and
/// `getrgb fname` extracts "the Red, Green, and Blue color components to
/// separate files", "fname.r, fname.g, fname.b". The oracle is the file's
/// own bytes 4, 5, 6 of each 8-byte struct.
#[test]
fn getrgb_fname_needs_no_resolution_at_any_size() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "t", two_polygons(), false, [0, 0, 64]);
    for (w, h, flags) in [
        ("512", "512", &["-B"][..]),
        ("37", "5", &[][..]),
        ("3", "61", &["-B"][..]),
    ] {
        let mut args = vec!["t", "out4", w, h];
        args.extend_from_slice(flags);
        ok(&run(RFTB4, d, &args));
        let n: usize = w.parse::<usize>().unwrap() * h.parse::<usize>().unwrap();
        let structs = read(d, "out4");
        assert_eq!(
            structs.len(),
            n * 8,
            "{w} x {h}: exactly hres x vres structs"
        );
        let side = read(d, "out4.frag");
        if flags.is_empty() {
            assert!(side.len() > 12, "fragments left without -B go to out4.frag");
            assert!(structs.chunks(8).any(|s| s[..4] != [0; 4]), "flist set");
        } else {
            // "the remaining pixel-fragment structure at each complex
            // pixel is deallocated" (section 5.9, the background pass).
            assert_eq!(side.len(), 12, "-B frees every fragment");
        }
        ok(&run(GETRGB, d, &["out4"]));
        for (k, e) in ["r", "g", "b"].iter().enumerate() {
            let want: Vec<u8> = structs.chunks(8).map(|s| s[4 + k]).collect();
            assert_eq!(read(d, &format!("out4.{e}")), want, "{w} x {h} .{e}");
        }
        // Without the side file too: the linear list is all getrgb needs.
        std::fs::remove_file(d.join("out4.frag")).unwrap();
        std::fs::remove_file(d.join("out4.r")).unwrap();
        ok(&run(GETRGB, d, &["out4"]));
        let want: Vec<u8> = structs.chunks(8).map(|s| s[4]).collect();
        assert_eq!(read(d, "out4.r"), want);
        if w == "512" {
            // Some pixel is the square's green: the colours are real.
            assert!(read(d, "out4.g").contains(&220));
        }
    }
}

/// The PNG (an extension: the manual's getrgb writes only the three
/// separations) needs the width: from the side file rftb4 writes, or from
/// `hres vres`; without either it is refused before anything is written.
#[test]
fn getrgb_png_takes_the_width_from_the_side_file_or_the_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "t", two_polygons(), false, [0, 0, 64]);
    ok(&run(RFTB4, d, &["t", "o", "40", "24", "-B"]));
    ok(&run(GETRGB, d, &["o", "-p"]));
    let png = read(d, "o.png");
    let r = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    assert_eq!((r.info().width, r.info().height), (40, 24));
    // The arguments must agree with the side file.
    let o = run(GETRGB, d, &["o", "24", "40"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("resolution"), "{}", stderr(&o));
    // No side file, no resolution: no PNG, and nothing written.
    let e = tempfile::tempdir().unwrap();
    std::fs::copy(d.join("o"), e.path().join("o")).unwrap();
    let o = run(GETRGB, e.path(), &["o", "--png", "o.png"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("HRES VRES") && stderr(&o).contains("o.frag"),
        "{}",
        stderr(&o)
    );
    assert_eq!(listing(e.path()), ["o"]);
    ok(&run(GETRGB, e.path(), &["o", "40", "24", "--png", "o.png"]));
    assert_eq!(read(e.path(), "o.png"), read(d, "o.png"));
    // Not a whole number of 8-byte structs: a clear error, no output.
    std::fs::write(e.path().join("bad"), [0u8; 13]).unwrap();
    let o = run(GETRGB, e.path(), &["bad"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("8-byte pixel-structs"),
        "{}",
        stderr(&o)
    );
    assert!(!e.path().join("bad.r").exists());
}

// ---------------------------------------------------------------------------
// 2. rftb1-3 take a one-level tree written with the default blending

/// plytrace manual page, SETMODE `b`: "If on, indicates that higher tree
/// level parent polygon intensities are to be blended with each lower
/// level children polygon for output to the virtual image file
/// (pre-blending). If off (default), parent/child polygon intensity
/// blending is performed by the subsequent scan conversion process
/// (post-blending)." With one level there are no children: the default
/// (post-blended) file renders in rftb1-3 exactly as the pre-blended one.
#[test]
fn a_one_level_tree_with_default_blending_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "post", two_polygons(), false, [0, 0, 64]);
    write(d, "pre", two_polygons(), true, [0, 0, 64]);
    for (bin, planes) in [
        (RFTB1, &["r", "g", "b", "a"][..]),
        (RFTB2, &["r", "g", "b", "m"][..]),
        (RFTB3, &["r", "g", "b", "a", "m"][..]),
    ] {
        ok(&run(bin, d, &["post", "a", "24", "16", "-B"]));
        ok(&run(bin, d, &["pre", "b", "24", "16", "-B"]));
        for p in planes {
            assert_eq!(
                read(d, &format!("a.{p}")),
                read(d, &format!("b.{p}")),
                "{bin} .{p}"
            );
        }
    }
    // And rftb4 takes the pre-blended one-level tree.
    ok(&run(RFTB4, d, &["pre", "c", "24", "16", "-B"]));
    ok(&run(RFTB4, d, &["post", "e", "24", "16", "-B"]));
    assert_eq!(read(d, "c"), read(d, "e"));
}

/// The rftb manual page: rftb2 "assumed that the multi-level virtual
/// image tree was created by plytrace using the pre-blending mode", and
/// rftb4 "using the post-blending mode". With a child (level 2) the mode
/// matters and the other one is refused, saying what to do.
#[test]
fn a_two_level_tree_in_the_other_mode_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut records = two_polygons();
    records.insert(
        0,
        record(
            2,
            &[[0.3, 0.3], [0.3, 0.5], [0.5, 0.5]],
            Shades::Faceted([9; 3]),
        ),
    );
    write(d, "post", records.clone(), false, [0, 0, 64]);
    write(d, "pre", records, true, [0, 0, 64]);
    for (bin, input, hint) in [
        (RFTB1, "post", "setmode b on"),
        (RFTB2, "post", "setmode b on"),
        (RFTB3, "post", "setmode b on"),
        (RFTB4, "pre", "setmode b off"),
    ] {
        let o = run(bin, d, &[input, "x", "8", "8", "-B"]);
        assert_eq!(o.status.code(), Some(1), "{bin}");
        let e = stderr(&o);
        assert!(
            e.contains(hint) && e.contains("below level 1"),
            "{bin}: {e}"
        );
    }
    assert_eq!(listing(d), ["post.out", "pre.out"]);
}

// ---------------------------------------------------------------------------
// 3. rftb1 and rftb3 transparency by section 5.6

/// A 0.5-transparent white square (t byte 128) in front of an opaque grey
/// one (51), both covering every pixel, pre-blended, front to back.
fn transparent_over_grey(dir: &Path) {
    write(
        dir,
        "glass",
        vec![
            transparent(1, &FULL, [255, 255, 255], 128),
            record(1, &FULL, Shades::Faceted([51, 51, 51])),
        ],
        true,
        [0, 0, 0],
    );
}

/// The rftb manual page: "Rftb1 performs hidden surface elimination,
/// anti-aliasing, and simulates linear and non-linear transparency using
/// a pixel-coverage byte"; section 5.6: "for transparent surfaces, the
/// new pixel intensity and coverage information are computed by
/// I_new = I_old + A_cov I_cur, A_new = min(A_old + Ā_cur, 1) where
/// Ā_cur = A_cur (1 - T), A_cov = Ā_cur if Ā_cur + A_old <= 1, else
/// 1 - A_old".
///
/// By hand, every pixel: the glass first, A_old = 0, A_cur = 1,
/// T = 128/255, so Ā = 127/255, A_cov = 127/255, I = 127/255 * 1 =
/// 0.49804, A = 127/255. The grey square: Ā = 1, Ā + A_old > 1, so
/// A_cov = 1 - 127/255 = 128/255 and I = 0.49804 + 128/255 * 51/255 =
/// 0.49804 + 0.10039 = 0.59843, i.e. 152.6, byte 153; A = 1, byte 255.
/// (Section 4.9's painter rule I = I_cur + k_t I_old would give
/// 1 + 0.5 * 0.2 = 1.1, clamped to 255.)
#[test]
fn rftb1_blends_transparency_by_section_5_6() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    transparent_over_grey(d);
    let i = 127.0 / 255.0 + (128.0 / 255.0) * (51.0 / 255.0);
    let want = (i * 255.0f64).round() as u8;
    assert_eq!(want, 153);
    ok(&run(RFTB1, d, &["glass", "one", "8", "8"]));
    for e in ["r", "g", "b"] {
        assert_eq!(read(d, &format!("one.{e}")), vec![want; 64], ".{e}");
    }
    assert_eq!(read(d, "one.a"), vec![255; 64]);
}

/// The rftb manual page: rftb3 "essentially combines the features of
/// rftb1 and rftb2 to render ... diffuse, transparent, reflected, and
/// refracted surfaces"; section 5.8: "a transparent surface affects only
/// the pixel coverage and intensity values and not the pixel mask". The
/// same 153 as rftb1, and the mask is the grey square's alone (full).
#[test]
fn rftb3_blends_transparency_by_section_5_6_and_keeps_the_mask() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    transparent_over_grey(d);
    ok(&run(RFTB3, d, &["glass", "three", "8", "8"]));
    for e in ["r", "g", "b"] {
        assert_eq!(read(d, &format!("three.{e}")), vec![153; 64], ".{e}");
    }
    assert_eq!(read(d, "three.a"), vec![255; 64]);
    assert_eq!(read(d, "three.m"), [0xFF; 128].to_vec());
    // The glass alone: coverage 127/255, byte 127; no mask; colour
    // 127/255 of white over the unpainted (black) frame buffer.
    write(
        d,
        "alone",
        vec![transparent(1, &FULL, [255, 255, 255], 128)],
        true,
        [0, 0, 0],
    );
    ok(&run(RFTB3, d, &["alone", "a", "4", "4"]));
    assert_eq!(read(d, "a.r"), vec![127; 16]);
    assert_eq!(read(d, "a.a"), vec![127; 16]);
    assert_eq!(read(d, "a.m"), vec![0; 32]);
}

/// The manual gives rftb2 (pixel masks: "diffuse, reflected, and
/// refracted surfaces") no transparency; it keeps plytrace's section 4.9
/// rule, I = I_cur + k_t I_old: 1 + 0.502 * 0.2 > 1, clamped to 255.
#[test]
fn rftb2_keeps_the_section_4_9_rule() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    transparent_over_grey(d);
    ok(&run(RFTB2, d, &["glass", "two", "8", "8"]));
    assert_eq!(read(d, "two.r"), vec![255; 64]);
}

// ---------------------------------------------------------------------------
// 4. mkdet, mkpcl and mkvcl refuse what a short cannot hold

const MKDET: &str = env!("CARGO_BIN_EXE_mkdet");
const MKPCL: &str = env!("CARGO_BIN_EXE_mkpcl");
const MKVCL: &str = env!("CARGO_BIN_EXE_mkvcl");

/// An ASCII geometry file (the mkdet manual page's format: "data", then
/// "the number of vertices and polygons", the vertices, then "<# of
/// vertices in polygon> <vertex-index list>") of `vertices` points and one
/// polygon of `nvtx` indices (cycling 1, 2, 3).
fn ascii_det(vertices: usize, nvtx: usize) -> String {
    let mut s = format!("title big\ndata\n{vertices} 1\n");
    for k in 0..vertices {
        s.push_str(&format!("{} {} 0\n", k % 7, k % 5));
    }
    s.push_str(&nvtx.to_string());
    for k in 0..nvtx {
        s.push_str(&format!(" {}", k % 3 + 1));
    }
    s.push('\n');
    s
}

/// The mkdet manual page: "short num_vtx, num_polys; /* #-vertices,
/// #-polygons */" and "short nvtx, index[nvtx]; /* For each polygon */";
/// mkpcl/mkvcl: "short num_clr; /* Number of colors in file */". A C
/// short holds -32768 to 32767; 33000 would read back as 33000 - 65536 =
/// -32536. Each is refused with the field, the value and the limit, exit
/// status 1, and no output file; 32767 is written and reads back as the
/// short 32767.
#[test]
fn mkdet_mkpcl_mkvcl_refuse_counts_a_short_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert_eq!(i16::from_le_bytes(33000u16.to_le_bytes()), -32536);
    std::fs::write(d.join("v.det"), ascii_det(33_000, 3)).unwrap();
    std::fs::write(d.join("n.det"), ascii_det(3, 32_768)).unwrap();
    let colours = |n: usize| {
        let mut s = format!("title colours\ndata {n}\n");
        s.push_str(&".9 .8 .2 .0 .0 .0\n".repeat(n));
        s
    };
    std::fs::write(d.join("c.pcl"), colours(40_000)).unwrap();
    for (bin, input, field, value) in [
        (MKDET, "v.det", "num_vtx", "33000"),
        (MKDET, "n.det", "nvtx", "32768"),
        (MKPCL, "c.pcl", "num_clr", "40000"),
        (MKVCL, "c.pcl", "num_clr", "40000"),
    ] {
        let o = run(bin, d, &[input, "out.bin"]);
        assert_eq!(o.status.code(), Some(1), "{bin} {input}");
        let e = stderr(&o);
        assert!(
            e.contains(&format!("`{field}`")) && e.contains(value) && e.contains("32767"),
            "{bin} {input}: {e}"
        );
        assert!(!d.join("out.bin").exists(), "{bin} left an output");
    }
    assert_eq!(listing(d), ["c.pcl", "n.det", "v.det"]);
    // The largest count that fits.
    std::fs::write(d.join("m.det"), ascii_det(32_767, 3)).unwrap();
    ok(&run(MKDET, d, &["m.det", "m.bin"]));
    let b = read(d, "m.bin");
    assert_eq!(&b[..3], b"DET");
    assert_eq!(
        i16::from_le_bytes([b[3], b[4]]),
        32_767,
        "num_vtx as a short"
    );
    assert_eq!(i16::from_le_bytes([b[5], b[6]]), 1, "num_polys");
}

// ---------------------------------------------------------------------------
// 5. Tree-file coordinates run from 0 to 1

const PLYTRACE: &str = env!("CARGO_BIN_EXE_plytrace");

/// The bundled scenes: the benchmark scenes and the examples.
fn bundled_scenes() -> Vec<std::path::PathBuf> {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let mut v = Vec::new();
    for dir in ["tests/data/scenes", "examples"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "des") {
                v.push(p);
            }
        }
    }
    v.sort();
    assert!(v.len() >= 10, "{v:?}");
    v
}

/// Figure 4.14 (virtual image tree polygon formats): "x,y floats 0 to 1".
/// Every bundled scene, written with `setmode o on` in both blending
/// modes: every vertex of every record of `FNAME.out` lies in [0, 1] (no
/// negative zero either, which the text form would print as `-0`), and
/// `FNAME.txt` holds the same records, bit for bit.
#[test]
fn tree_file_coordinates_of_every_bundled_scene_are_within_0_and_1() {
    let mut files = 0;
    for scene in bundled_scenes() {
        for blend in ["on", "off"] {
            let dir = tempfile::tempdir().unwrap();
            let d = dir.path();
            let o = run(
                PLYTRACE,
                d,
                &["-i", "-f", scene.to_str().unwrap(), "-o", "on", "-b", blend],
            );
            ok(&o);
            for name in listing(d) {
                let Some(stem) = name.strip_suffix(".out") else {
                    continue;
                };
                files += 1;
                let out = d.join(&name);
                let bin = RecordStream::from_bytes(&read(d, &name), &out).unwrap();
                let text = String::from_utf8(read(d, &format!("{stem}.txt"))).unwrap();
                let txt = RecordStream::from_text(&text, &out).unwrap();
                assert_eq!(bin, txt, "{}: {name} and its .txt differ", scene.display());
                for (k, r) in bin.records.iter().enumerate() {
                    for c in r.points.iter().flatten() {
                        assert!(
                            (0.0..=1.0).contains(c) && c.is_sign_positive(),
                            "{} (-b {blend}) {name} record {}: coordinate {c:e}",
                            scene.display(),
                            k + 1
                        );
                    }
                }
            }
        }
    }
    assert!(files >= 20, "{files} tree files");
}

// ---------------------------------------------------------------------------
// 6. The manual's example chain, from `examples/`

/// An 8-bit RGB PNG's size and pixels.
fn decode_png(bytes: Vec<u8>) -> (u32, u32, Vec<u8>) {
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// The largest difference between separations `seed.r .g .b` and the RGB
/// pixels `rgb`.
fn max_difference(dir: &Path, seed: &str, rgb: &[u8]) -> u8 {
    let planes: Vec<Vec<u8>> = ["r", "g", "b"]
        .iter()
        .map(|e| read(dir, &format!("{seed}.{e}")))
        .collect();
    let mut worst = 0;
    for (i, px) in rgb.chunks(3).enumerate() {
        for k in 0..3 {
            worst = worst.max(planes[k][i].abs_diff(px[k]));
        }
    }
    worst
}

/// The scene the manual's example renders is the thesis's figure 4.2(a)
/// ("fname test"), `examples/test.des`; the rftb manual page: "To render
/// a virtual image tree file, test.out, using rftb2 at 512 x 512 display
/// resolution and with the background color painted, the following
/// command is issued: rftb2 test test2 512 512 -B"; rftb4 "produces a
/// single composite file ... which must be processed by getrgb". Run as
/// on a fresh clone: `plytrace -i -f examples/test.des -o on`, `rftb2
/// test test2 512 512 -B`, `rftb4 test test4 512 512 -B`, `getrgb test4`.
///
/// Tolerance: plytrace's own picture is method 4 (16-sample masks, the
/// background painted) over the very records it writes to test.out, so
/// getrgb's image may differ only by a rounding level (the file's
/// coordinates are the same f32s, snapped into [0, 1] by at most a
/// rounding error): 1. rftb2's 4 x 4 masks at one tree level are method
/// 4's cases 1 and 3 (section 5.9: the tilers "are identical in both
/// methods"), so the same bound holds for it.
#[test]
fn the_manual_example_chain_runs_from_examples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    std::fs::create_dir_all(d.join("examples/det")).unwrap();
    std::fs::copy(root.join("examples/test.des"), d.join("examples/test.des")).unwrap();
    for f in ["cube.det", "cutcube.det"] {
        std::fs::copy(
            root.join("examples/det").join(f),
            d.join("examples/det").join(f),
        )
        .unwrap();
    }

    ok(&run(
        PLYTRACE,
        d,
        &["-i", "-f", "examples/test.des", "-o", "on"],
    ));
    let out = d.join("test.out");
    let tree = RecordStream::from_bytes(&read(d, "test.out"), &out).unwrap();
    assert!(tree.front_to_back, "sort ftb");
    assert!(!tree.blended, "the manual's default, setmode b off");
    assert!(tree.background.is_some(), "-B needs the background record");
    assert!(!tree.records.is_empty() && tree.records.iter().all(|r| r.level == 1));

    ok(&run(RFTB2, d, &["test", "test2", "512", "512", "-B"]));
    for e in ["r", "g", "b"] {
        assert_eq!(read(d, &format!("test2.{e}")).len(), 512 * 512);
    }
    assert_eq!(read(d, "test2.m").len(), 512 * 512 * 2);

    ok(&run(RFTB4, d, &["test", "test4", "512", "512", "-B"]));
    assert_eq!(read(d, "test4").len(), 512 * 512 * 8);
    assert_eq!(read(d, "test4.frag").len(), 12, "no fragments after -B");

    ok(&run(GETRGB, d, &["test4"]));
    for e in ["r", "g", "b"] {
        assert_eq!(read(d, &format!("test4.{e}")).len(), 512 * 512);
    }

    let (w, h, rgb) = decode_png(read(d, "test.png"));
    assert_eq!((w, h), (512, 512));
    assert!(max_difference(d, "test4", &rgb) <= 1);
    assert!(max_difference(d, "test2", &rgb) <= 1);
    // Sane: the green cut cube, the white table top and the background
    // are all there.
    let (r, g) = (read(d, "test4.r"), read(d, "test4.g"));
    assert!(
        (0..512 * 512).any(|i| g[i] > 100 && r[i] < 30),
        "green cube"
    );
    assert!(
        (0..512 * 512).any(|i| r[i] > 100 && g[i] > 100),
        "white table"
    );
    let bg = tree.background.unwrap();
    assert_eq!([r[0], g[0]], [bg[0], bg[1]], "top-left corner: background");
    for log in ["plytrace.log", "rftb2.log", "rftb4.log", "getrgb.log"] {
        assert!(d.join(log).exists(), "{log}");
    }
}

/// The share of pixels of the PNG `rgb` within `levels` of the
/// separations `seed.r .g .b`.
fn share_within(dir: &Path, seed: &str, rgb: &[u8], levels: u8) -> f64 {
    let planes: Vec<Vec<u8>> = ["r", "g", "b"]
        .iter()
        .map(|e| read(dir, &format!("{seed}.{e}")))
        .collect();
    let close = rgb
        .chunks(3)
        .enumerate()
        .filter(|(i, px)| (0..3).all(|k| planes[k][*i].abs_diff(px[k]) <= levels))
        .count();
    close as f64 / (rgb.len() / 3) as f64
}

/// underwater.des refracts through its water; the default model (`auto`)
/// picks exact refraction, which ray traces the refracted branches. The
/// tree file must hold them anyway: the manual's chain (`-o on`, rftb4,
/// getrgb) draws the picture plytrace draws, within 3 levels at 99 % of
/// the pixels or more. Without them the chain draws the pool with
/// nothing under the water. With a tree budget too small for them the
/// file takes the linearized matrix's branches, and says so.
#[test]
fn the_tree_file_holds_the_refracted_branches_the_picture_has() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scenes = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tests/data/scenes");
    std::fs::create_dir_all(d.join("det")).unwrap();
    for e in std::fs::read_dir(scenes.join("det")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), d.join("det").join(e.file_name())).unwrap();
    }
    let text = std::fs::read_to_string(scenes.join("underwater.des")).unwrap();
    std::fs::write(d.join("uw.des"), format!("sort ftb\n{text}")).unwrap();
    let args = [
        "uw.des", "--size", "160x160", "-o", "on", "-o", "uw.png", "--stats", "json",
    ];
    let out = run(PLYTRACE, d, &args);
    ok(&out);
    assert!(
        stderr(&out).contains("\"refraction\":\"exact"),
        "{}",
        stderr(&out)
    );
    ok(&run(RFTB4, d, &["underwater", "uw4", "160", "160", "-B"]));
    ok(&run(GETRGB, d, &["uw4"]));
    let (_, _, rgb) = decode_png(read(d, "uw.png"));
    let share = share_within(d, "uw4", &rgb, 3);
    assert!(share >= 0.99, "{share}");
    // The budget's way out: the linear maps' branches, with a warning.
    let mut small = args.to_vec();
    small.extend(["--max-tree-nodes", "1000"]);
    let out = run(PLYTRACE, d, &small);
    ok(&out);
    assert!(
        stderr(&out).contains("linearized matrix"),
        "{}",
        stderr(&out)
    );
    let tree = RecordStream::from_bytes(&read(d, "underwater.out"), &d.join("underwater.out"));
    assert!(tree.unwrap().records.iter().any(|r| r.level == 2));
}

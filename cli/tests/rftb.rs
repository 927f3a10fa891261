//! The programs rftb1-4 and getrgb (004 appendix, the rftb and getrgb
//! manual pages) run as binaries in a temporary directory, and their
//! output files checked byte by byte.

use std::path::Path;
use std::process::{Command, Output};

use plytrace::internal::output::{
    DisplayMode, PixelStructSink, Planes, PngSink, SeparationSink, commit_all, dither_level,
    level_byte,
};
use plytrace::internal::raster::scan::{PixelStruct, Row, RowSink, SavedFragment};
use plytrace::internal::tree::{Record, RecordStream, Shades};

fn run(bin: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(bin)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn rftb1() -> &'static str {
    env!("CARGO_BIN_EXE_rftb1")
}
fn rftb2() -> &'static str {
    env!("CARGO_BIN_EXE_rftb2")
}
fn rftb3() -> &'static str {
    env!("CARGO_BIN_EXE_rftb3")
}
fn rftb4() -> &'static str {
    env!("CARGO_BIN_EXE_rftb4")
}
fn getrgb() -> &'static str {
    env!("CARGO_BIN_EXE_getrgb")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
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

/// A small tree: a triangle over a square, front to back, with a
/// background, in the given blending mode.
fn write_tree(dir: &Path, name: &str, front_to_back: bool, blended: bool, background: bool) {
    let shades = |c: [u8; 3]| {
        if blended {
            Shades::Faceted(c)
        } else {
            Shades::Gouraud(vec![c; 4])
        }
    };
    let stream = RecordStream {
        records: vec![
            Record {
                level: 1,
                points: vec![[0.1, 0.1], [0.5, 0.9], [0.9, 0.1]],
                shades: Shades::Faceted([200, 100, 50]),
            },
            Record {
                level: 1,
                points: vec![[0.2, 0.2], [0.2, 0.8], [0.8, 0.8], [0.8, 0.2]],
                shades: shades([10, 220, 30]),
            },
        ],
        background: background.then_some([0, 0, 64]),
        front_to_back,
        blended,
    };
    std::fs::write(dir.join(format!("{name}.out")), stream.to_bytes()).unwrap();
}

fn row<'a>(y: u32, rgb: &'a [[f32; 3]]) -> Row<'a> {
    Row {
        y,
        rgb,
        coverage: None,
        mask: None,
        pixels: None,
        ids: None,
    }
}

#[test]
fn bad_command_lines_exit_2_with_usage() {
    let dir = tempfile::tempdir().unwrap();
    for (bin, args) in [
        (rftb2(), vec![]),
        (rftb1(), vec!["x", "-q"]),
        (rftb3(), vec!["x", "o", "0", "8"]),
        (rftb4(), vec!["x", "-a", "12"]),
        (rftb2(), vec!["x", "o", "8", "8", "4", "more"]),
        (getrgb(), vec![]),
        (getrgb(), vec!["n", "4"]),
    ] {
        let o = run(bin, dir.path(), &args);
        assert_eq!(o.status.code(), Some(2), "{bin} {args:?}");
        assert!(stderr(&o).contains("usage:"), "{}", stderr(&o));
    }
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn trees_for_another_method_exit_1_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    write_tree(dir.path(), "post", true, false, true);
    write_tree(dir.path(), "pre", true, true, true);
    write_tree(dir.path(), "btf", false, true, true);
    // The blending mode matters only with a record below level 1 (a
    // one-level tree is accepted either way: tests/manual_programs.rs).
    for name in ["post", "pre"] {
        let path = dir.path().join(format!("{name}.out"));
        let mut s = RecordStream::from_bytes(&std::fs::read(&path).unwrap(), &path).unwrap();
        s.records[0].level = 2;
        std::fs::write(&path, s.to_bytes()).unwrap();
    }
    for (bin, input, hint) in [
        (rftb1(), "post", "setmode b on"),
        (rftb2(), "post", "setmode b on"),
        (rftb3(), "btf", "sort ftb"),
        (rftb4(), "pre", "setmode b off"),
    ] {
        let o = run(bin, dir.path(), &[input, "out", "-B"]);
        assert_eq!(o.status.code(), Some(1), "{bin} {input}: {}", stderr(&o));
        assert!(stderr(&o).contains(hint), "{bin}: {}", stderr(&o));
    }
    assert_eq!(listing(dir.path()), ["btf.out", "post.out", "pre.out"]);
}

#[test]
fn missing_input_unwritable_output_and_missing_background_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(rftb2(), dir.path(), &["nothere"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("nothere.out"), "{}", stderr(&o));
    // (A file without a background record is post-blended: rftb4's kind.)
    write_tree(dir.path(), "t", true, false, false);
    let o = run(rftb4(), dir.path(), &["t", "-B"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("background"), "{}", stderr(&o));
    write_tree(dir.path(), "t", true, true, true);
    let o = run(rftb2(), dir.path(), &["t", "no/such/dir/x", "-B"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    std::fs::create_dir(dir.path().join("d.r")).unwrap();
    let o = run(rftb1(), dir.path(), &["t", "d"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(listing(dir.path()), ["d.r", "t.out"]);
}

#[test]
fn separations_2x2_byte_layout() {
    let dir = tempfile::tempdir().unwrap();
    let seed = dir.path().join("s");
    let planes = Planes {
        coverage: true,
        mask: true,
    };
    let mut sink = SeparationSink::create(&seed, 2, 2, planes).unwrap();
    let rgb = [[[1.0, 0.0, 0.2], [0.5, 0.25, 1.0]], [[0.0; 3], [1.0; 3]]];
    let cov = [[255u8, 128], [0, 7]];
    let mask = [[0xFFFFu16, 0x00F0], [0, 0x0001]];
    for y in 0..2 {
        let mut r = row(y as u32, &rgb[y]);
        r.coverage = Some(&cov[y]);
        r.mask = Some(&mask[y]);
        sink.row(&r).unwrap();
    }
    commit_all(sink.finish().unwrap()).unwrap();
    let read = |e: &str| std::fs::read(dir.path().join(format!("s.{e}"))).unwrap();
    assert_eq!(read("r"), [255, 128, 0, 255]);
    assert_eq!(read("g"), [0, 64, 0, 255]);
    assert_eq!(read("b"), [51, 255, 0, 255]);
    assert_eq!(read("a"), [255, 128, 0, 7]);
    assert_eq!(read("m"), [0xFF, 0xFF, 0xF0, 0x00, 0, 0, 0x01, 0x00]);
}

#[test]
fn a_failing_sink_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let rgb = [[0.5f32; 3]; 2];
    let mut s = SeparationSink::create(&dir.path().join("s"), 2, 2, Planes::default()).unwrap();
    s.row(&row(0, &rgb)).unwrap();
    assert!(s.row(&row(0, &rgb)).is_err(), "row 0 twice");
    drop(s);
    let mut m = SeparationSink::create(
        &dir.path().join("m"),
        2,
        1,
        Planes {
            coverage: false,
            mask: true,
        },
    )
    .unwrap();
    assert!(m.row(&row(0, &rgb)).is_err(), "no mask in the row");
    drop(m);
    let mut p = PngSink::create(&dir.path().join("p.png"), 2, 2, DisplayMode::Rgb332).unwrap();
    p.row(&row(0, &rgb)).unwrap();
    assert!(p.finish().is_err(), "a row missing");
    let mut q = PixelStructSink::create(&dir.path().join("q"), 2, 1).unwrap();
    let px = vec![
        PixelStruct {
            rgb: [1, 2, 3],
            pixstat: 0x60,
            fragments: vec![SavedFragment {
                pmask: 1,
                pstat: 2,
                pcover: 3,
            }],
        };
        2
    ];
    let mut r = row(0, &rgb);
    r.pixels = Some(&px);
    q.row(&r).unwrap();
    drop(q);
    assert!(listing(dir.path()).is_empty(), "{:?}", listing(dir.path()));
}

#[test]
fn png_has_an_srgb_chunk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.png");
    let mut p = PngSink::create(&path, 2, 2, DisplayMode::Color).unwrap();
    let rgb = [[0.0, 0.5, 1.0], [1.0, 0.5, 0.0]];
    p.row(&row(0, &rgb)).unwrap();
    p.row(&row(1, &rgb)).unwrap();
    p.finish().unwrap().0.commit().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let srgb = bytes.windows(4).position(|w| w == b"sRGB").expect("sRGB");
    let idat = bytes.windows(4).position(|w| w == b"IDAT").unwrap();
    assert!(srgb < idat);
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    r.next_frame(&mut buf).unwrap();
    assert_eq!(buf, [0, 128, 255, 255, 128, 0, 0, 128, 255, 255, 128, 0]);
}

#[test]
fn dithering_keeps_the_mean_of_a_flat_area_and_is_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (64u32, 64u32);
    let v = [0.3f32, 0.55, 0.8];
    let flat = vec![v; w as usize];
    let mut pixels = Vec::new();
    for name in ["a.png", "b.png"] {
        let path = dir.path().join(name);
        let mut p = PngSink::create(&path, w, h, DisplayMode::Rgb332).unwrap();
        for y in 0..h {
            p.row(&row(y, &flat)).unwrap();
        }
        p.finish().unwrap().0.commit().unwrap();
        let mut r = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()))
            .read_info()
            .unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        r.next_frame(&mut buf).unwrap();
        pixels.push(buf);
    }
    assert_eq!(pixels[0], pixels[1], "deterministic");
    for (ch, want) in v.iter().enumerate() {
        let values: Vec<u8> = pixels[0].iter().skip(ch).step_by(3).copied().collect();
        let mean = values.iter().map(|&b| f64::from(b)).sum::<f64>() / values.len() as f64;
        assert!(
            (mean / 255.0 - f64::from(*want)).abs() <= 0.5 / 255.0,
            "channel {ch}: mean {mean}"
        );
        let distinct: std::collections::BTreeSet<u8> = values.into_iter().collect();
        assert_eq!(distinct.len(), 2, "two neighbouring levels");
    }
    // The same through the level function, at other bits.
    for bits in 1..8u32 {
        let levels = (1 << bits) - 1;
        let sum: u32 = (0..64 * 64)
            .map(|i| {
                u32::from(level_byte(
                    dither_level(0.377, levels, i % 64, i / 64, 0),
                    levels,
                ))
            })
            .sum();
        let mean = f64::from(sum) / 4096.0 / 255.0;
        assert!((mean - 0.377).abs() <= 0.5 / 255.0, "{bits} bits: {mean}");
    }
}

/// A 3x2 pixel-struct file with two complex pixels.
fn pixel_struct_rows() -> Vec<Vec<PixelStruct>> {
    let f = |pmask, pstat, pcover| SavedFragment {
        pmask,
        pstat,
        pcover,
    };
    let p = |rgb, pixstat, fragments| PixelStruct {
        rgb,
        pixstat,
        fragments,
    };
    vec![
        vec![
            p([10, 20, 30], 0x21, vec![]),
            p([40, 50, 60], 0x62, vec![f(0xABCD, 0x22, 99)]),
            p([70, 80, 90], 0x21, vec![]),
        ],
        vec![
            p(
                [1, 2, 3],
                0x63,
                vec![f(0x000F, 0x23, 64), f(0xFFF0, 0x21, 192)],
            ),
            p([4, 5, 6], 0, vec![]),
            p([255, 254, 253], 0x21, vec![]),
        ],
    ]
}

#[test]
fn pixel_struct_file_round_trips_through_getrgb() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ps");
    let rows = pixel_struct_rows();
    let rgb = [[0.0f32; 3]; 3];
    let mut sink = PixelStructSink::create(&path, 3, 2).unwrap();
    for (y, r) in rows.iter().enumerate() {
        let mut row = row(y as u32, &rgb);
        row.pixels = Some(r);
        sink.row(&row).unwrap();
    }
    commit_all(sink.finish().unwrap()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    // Exactly 3 x 2 pixel-structs (the getrgb manual page: "a linear list
    // of 64-bit data structures"); the fragment lists are in `ps.frag`.
    #[rustfmt::skip]
    let expected: Vec<u8> = vec![
        0, 0, 0, 0, 10, 20, 30, 0x21,
        1, 0, 0, 0, 40, 50, 60, 0x62,
        0, 0, 0, 0, 70, 80, 90, 0x21,
        9, 0, 0, 0, 1, 2, 3, 0x63,
        0, 0, 0, 0, 4, 5, 6, 0,
        0, 0, 0, 0, 255, 254, 253, 0x21,
    ];
    assert_eq!(bytes, expected);
    let side_path = dir.path().join("ps.frag");
    let side = std::fs::read(&side_path).unwrap();
    #[rustfmt::skip]
    let expected_side: Vec<u8> = vec![
        b'F', b'R', b'A', b'G', 3, 0, 0, 0, 2, 0, 0, 0,
        // the lists: offset 0, then offset 8
        1, 0, 0, 0, 0xCD, 0xAB, 0x22, 99,
        2, 0, 0, 0, 0x0F, 0x00, 0x23, 64, 0xF0, 0xFF, 0x21, 192,
    ];
    assert_eq!(side, expected_side);
    let back =
        plytrace::internal::output::read_pixel_structs(&bytes, &path, Some((&side, &side_path)))
            .unwrap();
    assert_eq!(back.resolution, Some((3, 2)));
    assert_eq!(back.pixels, rows.concat());

    let o = run(getrgb(), dir.path(), &["ps", "3", "2", "-p"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |e: &str| std::fs::read(dir.path().join(format!("ps.{e}"))).unwrap();
    assert_eq!(read("r"), [10, 40, 70, 1, 4, 255]);
    assert_eq!(read("g"), [20, 50, 80, 2, 5, 254]);
    assert_eq!(read("b"), [30, 60, 90, 3, 6, 253]);
    let png = read("png");
    let mut r = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    r.next_frame(&mut buf).unwrap();
    assert_eq!(&buf[..6], &[10, 20, 30, 40, 50, 60]);

    // The log grows by a line a run.
    let o = run(getrgb(), dir.path(), &["ps", "3", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let log = std::fs::read_to_string(dir.path().join("getrgb.log")).unwrap();
    assert_eq!(log.lines().count(), 2, "{log}");
    assert!(log.lines().all(|l| l.contains("UTC") && l.contains("3x2")));
}

#[test]
fn getrgb_refuses_a_wrong_resolution() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ps");
    let rows = pixel_struct_rows();
    let rgb = [[0.0f32; 3]; 3];
    let mut sink = PixelStructSink::create(&path, 3, 2).unwrap();
    for (y, r) in rows.iter().enumerate() {
        let mut row = row(y as u32, &rgb);
        row.pixels = Some(r);
        sink.row(&row).unwrap();
    }
    commit_all(sink.finish().unwrap()).unwrap();
    // 2x3 would be read as 3x2 (the same size): a size says nothing more.
    // (`getrgb ps` needs no resolution: tests/manual_programs.rs.)
    for args in [
        vec!["ps", "2", "3"],
        vec!["ps", "4", "2"],
        vec!["ps", "1", "5"],
        vec!["ps", "1", "1"],
    ] {
        let o = run(getrgb(), dir.path(), &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert!(stderr(&o).contains("resolution"), "{}", stderr(&o));
    }
    assert_eq!(listing(dir.path()), ["ps", "ps.frag"]);
}

#[test]
fn the_manual_example_writes_rgbm_and_logs() {
    let dir = tempfile::tempdir().unwrap();
    write_tree(dir.path(), "test", true, true, true);
    for _ in 0..2 {
        let o = run(rftb2(), dir.path(), &["test", "test2", "512", "512", "-B"]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let size = |e: &str| {
        std::fs::metadata(dir.path().join(format!("test2.{e}")))
            .unwrap()
            .len()
    };
    for e in ["r", "g", "b"] {
        assert_eq!(size(e), 512 * 512);
    }
    assert_eq!(size("m"), 512 * 512 * 2);
    assert!(!dir.path().join("test2.a").exists());
    let log = std::fs::read_to_string(dir.path().join("rftb2.log")).unwrap();
    assert_eq!(log.lines().count(), 2);
    assert!(log.contains("512x512") && log.contains("test.out") && log.contains("test2"));
    // The background is painted: a corner pixel has its colour.
    assert_eq!(std::fs::read(dir.path().join("test2.b")).unwrap()[0], 64);
}

#[test]
fn rftb1_rftb3_write_their_files() {
    let dir = tempfile::tempdir().unwrap();
    write_tree(dir.path(), "t", true, true, true);
    let o = run(rftb1(), dir.path(), &["t", "one", "16", "8", "1", "-c"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(
        rftb3(),
        dir.path(),
        &["t", "three", "16", "8", "-B", "-a", "3"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut want = vec![
        "one.a",
        "one.b",
        "one.g",
        "one.png",
        "one.r",
        "rftb1.log",
        "rftb3.log",
        "t.out",
        "three.a",
        "three.b",
        "three.g",
        "three.m",
        "three.png",
        "three.r",
    ];
    want.sort();
    assert_eq!(listing(dir.path()), want);
    assert_eq!(
        std::fs::read(dir.path().join("three.m")).unwrap().len(),
        16 * 8 * 2
    );
}

#[test]
fn rftb4_then_getrgb() {
    let dir = tempfile::tempdir().unwrap();
    write_tree(dir.path(), "t", true, false, true);
    let o = run(rftb4(), dir.path(), &["t", "ps", "32", "16", "-B"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let len = std::fs::metadata(dir.path().join("ps")).unwrap().len();
    assert_eq!(len, 32 * 16 * 8);
    let o = run(getrgb(), dir.path(), &["ps", "32", "16", "--png", "ps.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(dir.path().join("ps.r")).unwrap().len(),
        32 * 16
    );
    assert!(dir.path().join("ps.png").exists());
    assert!(dir.path().join("rftb4.log").exists());
}

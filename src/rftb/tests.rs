//! Unit tests of `rftb`.

use super::*;
use crate::tree::{Record, Shades};

fn argv(s: &str) -> Vec<OsString> {
    s.split_whitespace().map(OsString::from).collect()
}

fn args(s: &str) -> Args {
    match parse_args(argv(s)).unwrap() {
        Command::Run(a) => a,
        Command::Help => panic!("help"),
    }
}

#[test]
fn the_manual_example_parses() {
    let a = args("test test2 512 512 -B");
    assert_eq!(a.input, PathBuf::from("test.out"));
    assert_eq!(a.output, PathBuf::from("test2"));
    assert_eq!((a.hres, a.vres, a.act_lines), (512, 512, 4));
    assert!(a.background && a.display.is_none());
    let a = args("scene.out -3 -a 4");
    assert_eq!(a.input, PathBuf::from("scene.out"));
    assert_eq!(a.output, PathBuf::from("scene"));
    assert_eq!((a.hres, a.vres, a.debug), (256, 256, 3));
    assert_eq!(a.display, Some(DisplayMode::Adaptive(4)));
    assert_eq!(args("x -Ba5").display, Some(DisplayMode::Adaptive(5)));
    assert_eq!(args("x o 8 8 1 -y").act_lines, 1);
}

#[test]
fn bad_command_lines_are_usage_errors() {
    for bad in [
        "",
        "x o 0",
        "x o 8 nine",
        "x o 8 8 0",
        "x o 8 8 4 extra",
        "x -q",
        "x -a",
        "x -a 9",
        "x -r -g",
    ] {
        assert!(parse_args(argv(bad)).is_err(), "`{bad}` parsed");
    }
    assert!(parse_getrgb_args(argv("n 5")).is_err());
    assert!(parse_getrgb_args(argv("n --png")).is_err());
}

#[test]
fn timestamps_are_civil_utc() {
    let t = SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(951_782_400 + 3_661);
    assert_eq!(utc_timestamp(t), "2000-02-29 01:01:01 UTC");
    assert_eq!(
        utc_timestamp(SystemTime::UNIX_EPOCH),
        "1970-01-01 00:00:00 UTC"
    );
}

#[test]
fn trees_for_other_methods_are_refused() {
    let mut s = RecordStream {
        records: Vec::new(),
        background: None,
        front_to_back: true,
        blended: true,
    };
    let p = Path::new("t.out");
    let square = |level| Record {
        level,
        points: vec![[0.1, 0.1], [0.1, 0.9], [0.9, 0.9], [0.9, 0.1]],
        shades: Shades::Faceted([1, 2, 3]),
    };
    // One level: both blending modes suit every tiler.
    s.records = vec![square(1), square(1)];
    for program in [Program::Rftb1, Program::Rftb2, Program::Rftb4] {
        for blended in [false, true] {
            s.blended = blended;
            assert!(check_tree(program, &s, p).is_ok(), "{program:?} {blended}");
        }
    }
    // A child (level 2): the mode matters.
    s.records = vec![square(2), square(1)];
    s.blended = true;
    assert!(check_tree(Program::Rftb2, &s, p).is_ok());
    let e = check_tree(Program::Rftb4, &s, p).unwrap_err().to_string();
    assert!(
        e.contains("setmode b off") && e.contains("1 of its records"),
        "{e}"
    );
    s.front_to_back = false;
    s.blended = false;
    let e = check_tree(Program::Rftb1, &s, p).unwrap_err().to_string();
    assert!(e.contains("sort ftb") && e.contains("setmode b on"), "{e}");
    s.records = vec![square(1)];
    let e = check_tree(Program::Rftb1, &s, p).unwrap_err().to_string();
    assert!(e.contains("sort ftb") && !e.contains("setmode"), "{e}");
}

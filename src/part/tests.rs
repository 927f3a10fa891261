//! Unit tests of `part`.

use super::*;

#[test]
fn missing_parts_are_listed_in_ranges() {
    assert_eq!(ranges(&[0, 1, 2, 5, 7, 8]), "0-2, 5, 7-8");
    assert_eq!(ranges(&[3]), "3");
    assert_eq!(ranges(&(1..65536).collect::<Vec<_>>()), "1-65535");
}

/// The name a part gives its image is taken only as an image name
/// inside the working directory.
#[test]
fn a_part_names_its_image_only_inside_the_working_directory() {
    let part = Path::new("parts/0.png");
    for ok in ["x.png", "no-such-dir/x.PPM", "./x.png"] {
        assert_eq!(name_from_parts(part, ok).unwrap(), PathBuf::from(ok));
    }
    for bad in [
        "/tmp/x.png",
        "../x.png",
        "a/../../x.png",
        "x.des",
        "x",
        "bell\x07.png",
        "",
    ] {
        let e = name_from_parts(part, bad).unwrap_err().to_string();
        assert!(e.contains("name the image with -o"), "{bad:?}: {e}");
    }
}

/// The fingerprint changes with the program, any input's contents,
/// their order and the flags: a merge then refuses parts of another
/// render, whatever it was that differed.
#[test]
fn every_thing_that_decides_the_pixels_changes_the_fingerprint() {
    let base = fingerprint_of("plytrace", &[1, 2], "--aa 4");
    assert_eq!(base.len(), 16);
    assert_eq!(base, fingerprint_of("plytrace", &[1, 2], "--aa 4"));
    for other in [
        fingerprint_of("rftb4", &[1, 2], "--aa 4"),
        fingerprint_of("plytrace", &[1, 3], "--aa 4"),
        fingerprint_of("plytrace", &[2, 1], "--aa 4"),
        fingerprint_of("plytrace", &[1], "--aa 4"),
        fingerprint_of("plytrace", &[1, 2], "--aa 2"),
    ] {
        assert_ne!(other, base);
    }
}

//! Unit tests of `image_tree`.

use super::*;

/// The cull asks about an outline whose box meets a branching area,
/// and about one with a point that is not finite, wherever its box.
#[test]
fn an_outline_is_asked_about_where_its_box_meets_or_a_point_is_not_finite() {
    let v = glam::DVec2::new;
    let boxes = [(v(0.0, 0.0), v(10.0, 10.0))];
    let asked = |pts: &[glam::DVec2]| overlaps(pts.iter().copied(), &boxes);
    assert!(asked(&[v(9.0, 9.0), v(20.0, 9.0), v(20.0, 20.0)]));
    assert!(!asked(&[v(11.0, 0.0), v(20.0, 0.0), v(20.0, 5.0)]));
    // Far from the box, but a point is not finite.
    assert!(asked(&[v(11.0, 0.0), v(f64::NAN, 0.0), v(20.0, 5.0)]));
    assert!(asked(&[v(11.0, 0.0), v(20.0, 0.0), v(f64::INFINITY, 5.0)]));
}

/// Boxes that meet, directly or through others, become their common
/// box; boxes apart stay apart; every box given lies in one merged.
#[test]
fn screen_boxes_that_meet_are_merged() {
    let b =
        |x0: f64, y0: f64, x1: f64, y1: f64| (glam::DVec2::new(x0, y0), glam::DVec2::new(x1, y1));
    // A chain: the first meets the second, the second the third.
    let given = vec![
        b(0.0, 0.0, 2.0, 2.0),
        b(10.0, 0.0, 12.0, 2.0),
        b(1.0, 1.0, 5.0, 3.0),
        b(4.0, 2.5, 6.0, 6.0),
    ];
    let mut out = merged(given.iter().copied()).unwrap();
    out.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    assert_eq!(out, vec![b(0.0, 0.0, 6.0, 6.0), b(10.0, 0.0, 12.0, 2.0)]);
    for g in &given {
        assert!(
            out.iter()
                .any(|o| o.0.cmple(g.0).all() && g.1.cmple(o.1).all())
        );
    }
    for (i, x) in out.iter().enumerate() {
        assert!(out[i + 1..].iter().all(|y| !meet(x, y)));
    }
    let apart = (0..=MAX_BOXES).map(|k| b(k as f64 * 2.0, 0.0, k as f64 * 2.0 + 1.0, 1.0));
    assert_eq!(
        merged(apart.clone().take(MAX_BOXES)).map(|o| o.len()),
        Some(MAX_BOXES)
    );
    assert_eq!(merged(apart), None, "too many areas apart");
}

fn fixture(name: &str) -> crate::model::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/scenes")
        .join(name);
    crate::scene::load(&path).expect("the fixture loads").0
}

/// Shadows are kept the first time they are cast exactly when levels
/// below the first may ask for them again: a polygon reflects more
/// than the threshold (`mirror.des`: 0.5) and the depth allows it.
#[test]
fn only_a_tree_with_mirror_levels_keeps_shadows_the_first_time() {
    let options = |max_level, threshold| TreeOptions {
        max_level,
        threshold,
        ..TreeOptions::default()
    };
    let (mirror, cube) = (fixture("mirror.des"), fixture("ccube.des"));
    let (mirror, cube) = (Materials::new(&mirror), Materials::new(&cube));
    assert!(may_branch(&mirror, &options(3, 0.0)));
    assert!(may_branch(&mirror, &options(2, 0.4)));
    assert!(!may_branch(&mirror, &options(1, 0.0)), "one level");
    assert!(
        !may_branch(&mirror, &options(3, 0.5)),
        "below the threshold"
    );
    assert!(!may_branch(&cube, &options(3, 0.0)), "nothing reflects");
}

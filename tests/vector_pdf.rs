//! PDF output rasterized by poppler's `pdftoppm` (installed by `.ci/run`,
//! package poppler-utils) at 72 dpi, so one point is one pixel, against
//! the PNG of the same tree: the PDF page is upright and framed as the
//! PNG, and at pixels away from edges it shows the PNG's colours (within
//! 12 levels) in at least 99.5 % of the pixels. A Gouraud sphere checks
//! the type-4 shadings.

mod support;

use plytrace::render::{RenderOptions, Rendered, render};
use plytrace::scene::Scene;
use plytrace::vector::{self, Style};
use plytrace::visibility::Algorithm;

fn options() -> RenderOptions {
    RenderOptions {
        shadows: true,
        ..RenderOptions::default()
    }
}

/// The PDF of `scene` as pdftoppm paints it: RGB rows, top first.
fn pdf_raster(scene: &Scene) -> (Vec<[u8; 3]>, u32, u32) {
    let input = plytrace::render::vector::prepare(scene, &options()).unwrap();
    let pdf = vector::pdf::to_pdf(&vector::picture(&input, Style::Shaded));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.pdf");
    std::fs::write(&path, pdf).unwrap();
    let out = std::process::Command::new("pdftoppm")
        .args(["-r", "72", "-singlefile"])
        .arg(&path)
        .arg(dir.path().join("r"))
        .output()
        .expect("pdftoppm (poppler-utils) is needed: .ci/run installs it");
    assert!(out.status.success(), "{out:?}");
    let ppm = std::fs::read(dir.path().join("r.ppm")).unwrap();
    parse_ppm(&ppm)
}

fn parse_ppm(b: &[u8]) -> (Vec<[u8; 3]>, u32, u32) {
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        while b[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while !b[at].is_ascii_whitespace() {
            at += 1;
        }
        fields.push(String::from_utf8_lossy(&b[start..at]).into_owned());
    }
    assert_eq!(fields[0], "P6");
    let (w, h): (u32, u32) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let data = &b[at + 1..];
    (data.chunks(3).map(|p| [p[0], p[1], p[2]]).collect(), w, h)
}

fn png(scene: &Scene) -> Rendered {
    render(
        scene,
        &RenderOptions {
            visibility: Some(Algorithm::Nns),
            ..options()
        },
    )
    .unwrap()
}

/// (interior pixels, those differing by more than 12 levels).
fn compare(scene: &Scene) -> (usize, usize) {
    let r = png(scene);
    let (raster, w, h) = pdf_raster(scene);
    assert_eq!(
        (w, h),
        (r.frame.width, r.frame.height),
        "one point per pixel"
    );
    let (wi, hi) = (w as i64, h as i64);
    let id = |x: i64, y: i64| r.frame.ids[(y * wi + x) as usize];
    let (mut checked, mut bad) = (0, 0);
    for y in 1..hi - 1 {
        for x in 1..wi - 1 {
            if !(-1..=1).all(|dy| (-1..=1).all(|dx| id(x + dx, y + dy) == id(x, y))) {
                continue;
            }
            checked += 1;
            let k = (y * wi + x) as usize;
            let p = r.frame.color[k].map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as i32);
            let c = raster[k];
            if (0..3).any(|i| (p[i] - c[i] as i32).abs() > 12) {
                bad += 1;
            }
        }
    }
    (checked, bad)
}

#[test]
fn pdf_shows_the_png_s_colours_on_the_scenes() {
    for (name, limit) in [
        ("cycles.des", 0.005),
        ("intersect.des", 0.005),
        ("office1.des", 0.005),
        ("mirror.des", 0.005),
    ] {
        let sc = plytrace::scene::load(&support::scene_fixture(name))
            .unwrap()
            .0;
        let (checked, bad) = compare(&sc);
        eprintln!("{name}: {bad} of {checked} interior pixels differ by > 12 levels");
        assert!(checked > 50_000);
        assert!(
            bad as f64 <= limit * checked as f64,
            "{name}: {bad} of {checked}"
        );
    }
}

#[test]
fn gouraud_sphere_as_type_4_shadings_matches_the_png() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.des");
    std::fs::write(
        &path,
        "resolution 256 256\nbackground 0 0 0\nperspective 40 1 0.1 100\nsetmode v on\n\
         light 2 -3 5 1 1 1 100 Diffuse\npushmatrix\nident\npolarview 4 25 65 0\n\
         color 1 0.6 0.2\ntype polygon curved\ndefobj geo\n  geodesic 16 equal\n  \
         radial sphere\nendobj\npopmatrix\n",
    )
    .unwrap();
    let sc = plytrace::scene::load(&path).unwrap().0;
    let (checked, bad) = compare(&sc);
    eprintln!("gouraud sphere: {bad} of {checked} interior pixels differ by > 12 levels");
    assert!(checked > 10_000);
    assert!(bad as f64 <= 0.005 * checked as f64, "{bad} of {checked}");
}

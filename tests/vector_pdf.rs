//! PDF output rasterized by poppler's `pdftoppm` (installed by `.ci/run`,
//! package poppler-utils) at 72 dpi, so one point is one pixel, against
//! the PNG of the same tree: the PDF page is upright and framed as the
//! PNG, and at pixels away from edges it shows the PNG's colours (within
//! 12 levels) in at least 99.5 % of the pixels. A Gouraud sphere checks
//! the type-4 shadings.

mod support;

use plytrace::internal::scene::Scene;
use plytrace::internal::vector::{self, Style};

/// The PDF of `scene` as pdftoppm paints it: RGB rows, top first.
fn pdf_raster(scene: &Scene) -> (Vec<[u8; 3]>, u32, u32) {
    let input =
        plytrace::internal::render::vector::prepare(scene, &support::vector_options()).unwrap();
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
    support::parse_ppm(&ppm)
}

/// (interior pixels, those differing by more than 12 levels).
fn compare(scene: &Scene) -> (usize, usize) {
    let r = support::vector_png(scene);
    let (raster, w, h) = pdf_raster(scene);
    assert_eq!(
        (w, h),
        (r.frame.width, r.frame.height),
        "one point per pixel"
    );
    support::pixels_off(&raster, &r, &support::interior_pixels(&r, &|a, b| a == b))
}

#[test]
fn pdf_shows_the_png_s_colours_on_the_scenes() {
    for (name, limit) in [
        ("cycles.des", 0.005),
        ("intersect.des", 0.005),
        ("office1.des", 0.005),
        ("mirror.des", 0.005),
    ] {
        let sc = plytrace::internal::scene::load(&support::scene_fixture(name))
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
    let sc = plytrace::internal::scene::load(&path).unwrap().0;
    let (checked, bad) = compare(&sc);
    eprintln!("gouraud sphere: {bad} of {checked} interior pixels differ by > 12 levels");
    assert!(checked > 10_000);
    assert!(bad as f64 <= 0.005 * checked as f64, "{bad} of {checked}");
}

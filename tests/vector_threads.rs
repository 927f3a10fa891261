//! One thread or many, the vector painter writes the same bytes (issue
//! 12, the speed goal: the geometry, the tree's shading terms and
//! projections, the records and the object's planes are made in
//! parallel and kept in order). Scenes: the interpenetrating and cyclic
//! ones (NNS splits), the mirror scene (levels below 1) and a geodesic
//! sphere (the speed benchmark's mesh, smaller).

mod support;

use plytrace::internal::render::RenderOptions;
use plytrace::internal::scene::Scene;
use plytrace::internal::vector::{self, Style};

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

/// Loading included: an object's planes are found in parallel too.
fn load(path: &std::path::Path) -> Scene {
    plytrace::internal::scene::load(path).unwrap().0
}

fn svg(path: &std::path::Path, style: Style) -> Vec<u8> {
    let scene = load(path);
    let options = RenderOptions {
        shadows: true,
        ..RenderOptions::default()
    };
    let input = plytrace::internal::render::vector::prepare_for(&scene, &options, style).unwrap();
    vector::svg::to_svg(&vector::picture(&input, style))
}

fn geodesic_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("geo.des");
    std::fs::write(
        &path,
        "resolution 96 96\nperspective 40 1 0.1 100\nlight 2 -3 5 1 1 1 100 Diffuse\n\
         pushmatrix\nident\npolarview 4 25 65 0\ncolor 1 0.6 0.2\n\
         defobj geo\n  geodesic 16 equal\n  radial sphere\nendobj\npopmatrix\n",
    )
    .unwrap();
    path
}

#[test]
fn the_svg_does_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let mut scenes: Vec<std::path::PathBuf> = ["cycles.des", "intersect.des", "mirror.des"]
        .iter()
        .map(|n| support::scene_fixture(n))
        .collect();
    scenes.push(geodesic_scene(dir.path()));
    for path in &scenes {
        for style in [Style::Shaded, Style::HiddenLine] {
            let one = pool(1).install(|| svg(path, style));
            assert!(one.len() > 1000, "{}: an empty picture", path.display());
            for threads in [2, 3] {
                let many = pool(threads).install(|| svg(path, style));
                assert!(
                    one == many,
                    "{}, {style:?}, {threads} threads: the SVG differs",
                    path.display()
                );
            }
        }
    }
}

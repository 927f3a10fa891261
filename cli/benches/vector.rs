//! `cargo bench --bench vector`: a closed mesh of 69,620 triangles (a
//! geodesic sphere, 59 divisions per edge) to SVG.
//!
//! * `process/plytrace-svg`: the whole process, `plytrace -q geo.des -o
//!   geo.svg` (reading the scene, the tree with NNS, the SVG, the atomic
//!   write);
//! * `process/sketch-tikz`: Sketch (Newell sort with BSP splitting) on the
//!   same triangles, to TikZ, when `sketch` is on the PATH
//!   (`apt-get install sketch`); left out otherwise;
//! * `stage/prepare` (the tree, NNS forced) and `stage/picture+svg`
//!   (merging and writing) in process.
//!
//! `hidden-line-growth`: the hidden-line search
//! (`vector::hidden_line::segments_of`, the faces in painting order) from
//! 10^3 to 10^6 faces, to show how it grows:
//!
//! * `fan/N`: N triangles sharing the centre vertex (every box meets the
//!   centre);
//! * `quads/N`: a sqrt(N) x sqrt(N) grid of squares 1.5 cells wide, each
//!   overlapping its neighbours, painted row by row.

use std::io::Write;
use std::process::Command;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use plytrace::internal::modeling::geodesic::{Division, Radial, geodesic};
use plytrace::internal::render::RenderOptions;
use plytrace::internal::vector::{self, Style};

const N: usize = 59;
const SCENE: &str = "resolution 512 512\nperspective 40 1 0.1 100\n\
    light 2 -3 5 1 1 1 100 Diffuse\npushmatrix\nident\npolarview 4 25 65 0\n\
    color 1 0.6 0.2\ndefobj geo\n  geodesic 59 equal\n  radial sphere\nendobj\npopmatrix\n";

/// The same triangles as Sketch input, seen from the same side.
fn sketch_input(path: &std::path::Path) {
    let mesh = geodesic(N, Division::Equal, Radial::Sphere).unwrap();
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    writeln!(f, "def mesh {{").unwrap();
    for p in &mesh.polygons {
        write!(f, "  polygon[fill=orange]").unwrap();
        // Sketch wants counter-clockwise from outside; ours are clockwise.
        for &i in p.iter().rev() {
            let v = mesh.vertices[i as usize];
            write!(f, "({:.5},{:.5},{:.5})", v.x, v.y, v.z).unwrap();
        }
        writeln!(f).unwrap();
    }
    writeln!(
        f,
        "}}\nput {{ view((1.3,-2.8,1.7)) }} {{mesh}}\nglobal {{ language tikz }}"
    )
    .unwrap();
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let des = dir.path().join("geo.des");
    std::fs::write(&des, SCENE).unwrap();
    let mut g = c.benchmark_group("vector-70k");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let exe = env!("CARGO_BIN_EXE_plytrace");
    g.bench_function("process/plytrace-svg", |b| {
        b.iter(|| {
            let s = Command::new(exe)
                .current_dir(dir.path())
                .args(["-q", "geo.des", "-o", "geo.svg"])
                .status()
                .unwrap();
            assert!(s.success());
        })
    });
    let sk = dir.path().join("geo.sk");
    sketch_input(&sk);
    let has_sketch = Command::new("sketch").arg("-V").output().is_ok();
    if has_sketch {
        g.bench_function("process/sketch-tikz", |b| {
            b.iter(|| {
                let s = Command::new("sketch")
                    .current_dir(dir.path())
                    .args(["geo.sk", "-o", "geo_sketch.tex"])
                    .status()
                    .unwrap();
                assert!(s.success());
            })
        });
    } else {
        eprintln!("sketch not found: `apt-get install sketch` to compare");
    }
    let scene = plytrace::internal::scene::load(&des).unwrap().0;
    let options = RenderOptions {
        shadows: true,
        ..RenderOptions::default()
    };
    g.bench_function("stage/prepare", |b| {
        b.iter(|| plytrace::internal::render::vector::prepare(&scene, &options).unwrap())
    });
    let input = plytrace::internal::render::vector::prepare(&scene, &options).unwrap();
    g.bench_function("stage/picture+svg", |b| {
        b.iter(|| vector::svg::to_svg(&vector::picture(&input, Style::Shaded)))
    });
    g.finish();
}

type Faces = Vec<(Vec<[f64; 2]>, Vec<bool>)>;

/// `n` triangles about the centre of a 1024 x 1024 picture.
fn fan(n: usize) -> Faces {
    let at = |k: usize| {
        let a = k as f64 * std::f64::consts::TAU / n as f64;
        [512.0 + 400.0 * a.cos(), 512.0 + 400.0 * a.sin()]
    };
    (0..n)
        .map(|k| (vec![[512.0, 512.0], at(k + 1), at(k)], vec![true; 3]))
        .collect()
}

/// A grid of about `n` overlapping squares over a 1024 x 1024 picture.
fn quads(n: usize) -> Faces {
    let k = (n as f64).sqrt().round() as usize;
    let cell = 1000.0 / k as f64;
    let side = 1.5 * cell;
    let mut out = Vec::with_capacity(k * k);
    for r in 0..k {
        for c in 0..k {
            let (x, y) = (c as f64 * cell, r as f64 * cell);
            out.push((
                vec![[x, y], [x + side, y], [x + side, y + side], [x, y + side]],
                vec![true; 4],
            ));
        }
    }
    out
}

fn growth(c: &mut Criterion) {
    use plytrace::internal::vector::hidden_line::segments_of;
    let mut g = c.benchmark_group("hidden-line-growth");
    g.sample_size(10);
    for n in [1_000, 10_000, 100_000, 1_000_000] {
        let faces = fan(n);
        g.bench_function(format!("fan/{n}"), |b| {
            b.iter(|| segments_of(&faces, 1024.0, 1024.0).unwrap())
        });
        let faces = quads(n);
        g.bench_function(format!("quads/{n}"), |b| {
            b.iter(|| segments_of(&faces, 1024.0, 1024.0).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench, growth);
criterion_main!(benches);

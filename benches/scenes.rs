//! `cargo bench`: for the bundled example and every scene of
//! `tests/data/scenes` (the benchmark scenes, copied into the repository):
//!
//! * `parse`: reading the .des and .det files;
//! * `render/<algorithm>`: geometry, visibility, shading and painting at the
//!   scene's own resolution, for every visible-surface algorithm;
//! * `nns-sort-1-thread`: the NNS sort alone (face splitting included) on
//!   one thread, the figure the part 2 issue asks for;
//! * `tree-*`: the virtual image tree with 0, 1 and 2 shadow lights;
//! * `aa-*`: every scan conversion method at 512 x 512 on mirror, gallery
//!   and office2 with their shadow lights (the peak and total pixel-fragments
//!   of method 4 are printed once per scene);
//! * `goals`: issue 10's three goal renders at 512 x 512, on one thread
//!   and on all cores.

use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use plytrace::internal::geometry::view::{self, GeometryStats, View};
use plytrace::internal::raster::scan::Method;
use plytrace::internal::render::{RenderOptions, render, scene_scale};
use plytrace::internal::visibility::Algorithm;
use plytrace::internal::visibility::nns::{self, NnsFace};

fn scenes() -> Vec<(String, PathBuf)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut v = vec![("example-ccube".to_string(), root.join("examples/ccube.des"))];
    if let Ok(dir) = std::fs::read_dir(root.join("tests/data/scenes")) {
        let mut found: Vec<PathBuf> = dir
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "des"))
            .collect();
        found.sort();
        v.extend(
            found
                .into_iter()
                .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), p)),
        );
    }
    v
}

fn nns_faces(scene: &plytrace::internal::scene::Scene, view: &View) -> Vec<NnsFace> {
    let mut polys = Vec::new();
    let mut stats = GeometryStats::default();
    for i in 0..scene.objects.len() {
        if !scene.objects[i].surface_type.hidden {
            view::expand_object(&scene.objects, i, view, &mut polys, &mut stats);
        }
    }
    polys
        .into_iter()
        .flat_map(|p| {
            plytrace::internal::geometry::polygon::triangulate_if_needed(&p.world)
                .into_iter()
                .map(move |world| NnsFace {
                    object: p.object,
                    polygon: p.polygon,
                    world: world.into(),
                })
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for (name, path) in scenes() {
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(2));
        group.bench_function("parse", |b| {
            b.iter(|| plytrace::internal::scene::load(&path).unwrap())
        });
        let scene = plytrace::internal::scene::load(&path).unwrap().0;
        for (algorithm, alg_name) in Algorithm::ALL {
            if algorithm == Algorithm::Brown {
                continue; // only meaningful for well-tesselated surfaces
            }
            // Level 1, point sampled: what every algorithm can render.
            let mut level1 = scene.clone();
            level1.modes.max_level = 1;
            let options = RenderOptions {
                visibility: Some(algorithm),
                aa: Some(Method::Point),
                ..RenderOptions::default()
            };
            group.bench_function(format!("render/{alg_name}"), |b| {
                b.iter(|| render(&level1, &options).unwrap())
            });
        }
        let (w, h) = (scene.viewport.width(), scene.viewport.height());
        let view = View::new(&scene, w, h).unwrap();
        let faces = nns_faces(&scene, &view);
        let eps = scene.modes.epsilon * scene_scale(&scene);
        group.bench_function("nns-sort-1-thread", |b| {
            b.iter_batched(
                || faces.clone(),
                |f| single.install(|| nns::sort(f, &view, eps)),
                BatchSize::LargeInput,
            )
        });
        group.finish();
    }
}

/// The virtual image tree of 004 chapter 3 on the thesis scenes of table
/// 6.1 (mirror, gallery, office1, office2) with no shadows, one and two
/// shadow-casting lights (the first Point lights; Diffuse lights kept).
fn tree(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
    for name in ["mirror", "gallery", "office1", "office2"] {
        let path = root.join(format!("{name}.des"));
        if !path.is_file() {
            continue;
        }
        let scene = plytrace::internal::scene::load(&path).unwrap().0;
        let mut group = c.benchmark_group(format!("tree-{name}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        for lights in [0usize, 1, 2] {
            let mut s = scene.clone();
            let mut kept = 0;
            s.lights.retain(|l| {
                if l.kind == plytrace::internal::model::LightKind::Diffuse {
                    return true;
                }
                kept += 1;
                kept <= lights.max(1)
            });
            let options = RenderOptions {
                shadows: lights > 0,
                ..RenderOptions::default()
            };
            group.bench_function(format!("shadow-lights-{lights}"), |b| {
                b.iter(|| render(&s, &options).unwrap())
            });
        }
        group.finish();
    }
}

/// Every scan conversion method at 512 x 512, shadows on (part 4: total
/// time per method; pixels per second = 262144 / time).
fn antialiasing(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
    let methods = [
        ("none", Method::Point),
        ("area", Method::Area),
        ("mask", Method::Mask),
        ("hybrid", Method::Hybrid),
        ("multilevel", Method::Multilevel),
        ("donovan-4", Method::Supersample(4)),
        ("donovan-8", Method::Supersample(8)),
    ];
    for name in ["mirror", "gallery", "office2"] {
        let scene = plytrace::internal::scene::load(&root.join(format!("{name}.des")))
            .unwrap()
            .0;
        let mut group = c.benchmark_group(format!("aa-{name}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        for (label, method) in methods {
            let options = RenderOptions {
                size: Some((512, 512)),
                shadows: true,
                aa: Some(method),
                ..RenderOptions::default()
            };
            let once = render(&scene, &options).unwrap();
            eprintln!(
                "aa-{name}/{label}: {} polygons tiled, peak {} fragments, {} in all",
                once.stats.polygons_tiled,
                once.stats.scan.peak_fragments,
                once.stats.scan.total_fragments
            );
            group.bench_function(label, |b| b.iter(|| render(&scene, &options).unwrap()));
        }
        group.finish();
    }
}

/// Issue 10's goals at 512 x 512, default (anti-aliased) output, in
/// process (the whole-process figures and POV-Ray side by side come from
/// `benches/side_by_side.sh`): office2 with its 2 shadow lights at depth 3
/// (goal 0.3 s), office2 without shadows (50 ms), gallery at depth 14
/// with 4 shadow lights (0.4 s); on one thread and on all cores.
fn goals(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
    let mut group = c.benchmark_group("goals");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    for (label, name, shadows) in [
        ("office2-2-lights", "office2", true),
        ("office2-no-shadows", "office2", false),
        ("gallery-4-lights", "gallery", true),
    ] {
        let scene = plytrace::internal::scene::load(&root.join(format!("{name}.des")))
            .unwrap()
            .0;
        for (threads, suffix) in [(1, "1-thread"), (0, "all-cores")] {
            let options = RenderOptions {
                size: Some((512, 512)),
                shadows,
                threads,
                ..RenderOptions::default()
            };
            group.bench_function(format!("{label}/{suffix}"), |b| {
                b.iter(|| render(&scene, &options).unwrap())
            });
        }
    }
    group.finish();
}

/// The ASCII object files of the scenes (`tests/data/scenes/det`: the
/// 42 that office2 reads and a few more, 0.7 MB), parsed one after
/// another on this thread: the reading threads' work while a scene loads.
fn object_files(c: &mut Criterion) {
    let det = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/det");
    let mut files: Vec<(PathBuf, String)> = std::fs::read_dir(&det)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "det"))
        .filter_map(|p| std::fs::read_to_string(&p).ok().map(|t| (p, t)))
        .filter(|(p, t)| plytrace::internal::scene::object_file::parse_det_ascii(t, p).is_ok())
        .collect();
    files.sort();
    assert!(files.len() >= 42, "only {} ASCII object files", files.len());
    c.bench_function("object-files/parse-ascii", |b| {
        b.iter(|| {
            for (path, text) in &files {
                plytrace::internal::scene::object_file::parse_det_ascii(text, path).unwrap();
            }
        })
    });
}

criterion_group!(benches, bench, tree, antialiasing, goals, object_files);
criterion_main!(benches);

//! Parse and render every scene of `../shared/scenes` (when that folder
//! exists) and the bundled example: `cargo bench`. Reported per scene:
//! `parse` (reading the .des and .det files) and `render` (geometry, sort,
//! shading, painting) at the scene's own resolution.

use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use plytrace::render::{RenderOptions, render};

fn scenes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut v = vec![root.join("examples/ccube.des")];
    let shared = root.join("../shared/scenes");
    if let Ok(dir) = std::fs::read_dir(&shared) {
        let mut found: Vec<PathBuf> = dir
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "des"))
            .collect();
        found.sort();
        v.extend(found);
    }
    v
}

fn bench(c: &mut Criterion) {
    for path in scenes() {
        let name = format!(
            "{}{}",
            if path.starts_with(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")) {
                "example-"
            } else {
                ""
            },
            path.file_stem().unwrap().to_string_lossy()
        );
        let mut group = c.benchmark_group(name);
        group.sample_size(20);
        group.bench_function("parse", |b| {
            b.iter(|| plytrace::scene::load(&path).unwrap())
        });
        let scene = plytrace::scene::load(&path).unwrap().0;
        group.bench_function("render", |b| {
            b.iter(|| render(&scene, &RenderOptions::default()).unwrap())
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

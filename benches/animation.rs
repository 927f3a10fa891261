//! `cargo bench --bench animation`: Brown's approximate rotation (003
//! sections 2-3). A geodesic of 20,480 faces (32 divisions per edge) with
//! four lobes turns inside its fixed vertex directions, one `radial rotate
//! 5 z` per frame, rendered 256 x 256 with `--visibility brown`:
//!
//! * `frame/reused`: the step and the render with the previous frame's
//!   priority order (no re-sort), as the command line does;
//! * `frame/resorted`: the same with Brown's sort done again each frame;
//! * `order/*`: the order alone (cache hit versus sort).
//!
//! Frames per second = 1 / median.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use plytrace::internal::geometry::view::{View, towards_eye};
use plytrace::internal::render::{RenderOptions, Reuse, plan, plan_with};
use plytrace::internal::scene::{Interpreter, NoHost, Scene};
use plytrace::internal::visibility::Algorithm;
use plytrace::internal::visibility::brown::{PriorityCache, priority_order};

const SCENE: &str = "resolution 256 256\nperspective 40 1 0.1 100\n\
    light 4 -6 8 1 1 1 100 Diffuse\npushmatrix\nident\npolarview 4.5 25 65 0\n\
    defobj geo\n color 0.9 0.6 0.3\n geodesic 32 angle\n radial lobes 0.35 4\nendobj\npopmatrix\n";

fn options() -> RenderOptions {
    RenderOptions {
        visibility: Some(Algorithm::Brown),
        ..RenderOptions::default()
    }
}

fn step(interp: &mut Interpreter) -> Scene {
    interp
        .execute_source(
            "radial rotate 5 z\n",
            Path::new("b.des"),
            Path::new("."),
            &mut NoHost,
        )
        .expect("turns");
    interp.scene()
}

fn bench(c: &mut Criterion) {
    let mut interp = Interpreter::new();
    interp
        .execute_source(SCENE, Path::new("b.des"), Path::new("."), &mut NoHost)
        .expect("the scene");
    let reuse = Reuse::default();
    let mut g = c.benchmark_group("frame");
    g.sample_size(20);
    g.bench_function("reused", |b| {
        b.iter(|| {
            let scene = step(&mut interp);
            plan_with(&scene, &options(), &reuse).expect("renders")
        })
    });
    g.bench_function("resorted", |b| {
        b.iter(|| {
            let scene = step(&mut interp);
            plan(&scene, &options()).expect("renders")
        })
    });
    g.finish();

    let scene = interp.scene();
    let o = &scene.objects[0];
    let faces: Vec<Vec<u32>> = o.polygons.iter().map(|p| p.indices.to_vec()).collect();
    let view = View::new(&scene, 256, 256).expect("a view");
    let centre = o.transform.transform_point(DVec3::ZERO);
    let axis = towards_eye(view.eye, centre);
    let cache = PriorityCache::new();
    cache.order(o.number, &o.vertices, &faces, centre, axis, false);
    let mut g = c.benchmark_group("order");
    g.bench_function("reused", |b| {
        b.iter(|| cache.order(o.number, &o.vertices, &faces, centre, axis, false))
    });
    g.bench_function("sorted", |b| {
        b.iter(|| priority_order(&o.vertices, &faces, centre, axis, false))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! `cargo bench --bench modeling`: Firebaugh's generators (faces made per
//! second) and the BSP CSG (input faces combined per second).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec2, DVec3};
use plytrace::modeling::Generated;
use plytrace::modeling::csg::{self, Face, Op};
use plytrace::modeling::parametric::{self, Superquadric};
use plytrace::modeling::patch::{self, Form};
use plytrace::modeling::sweep::{self, Profile};

/// A generated solid as CSG faces, moved by `offset`.
fn faces(g: &Generated, offset: DVec3) -> Vec<Face> {
    g.mesh
        .polygons
        .iter()
        .map(|p| {
            let points: Vec<DVec3> = p
                .iter()
                .map(|&i| g.mesh.vertices[i as usize] + offset)
                .collect();
            let normals = match &g.normals {
                Some(n) => p.iter().map(|&i| n[i as usize]).collect(),
                None => vec![DVec3::Z; p.len()],
            };
            Face {
                points,
                normals,
                attr: 0,
            }
        })
        .collect()
}

fn wave() -> patch::PatchSet {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/det/wave.bpt"
    ))
    .unwrap();
    patch::parse(&text, "wave.bpt".as_ref(), Form::Bezier, |_| Ok(())).unwrap()
}

fn tessellation(c: &mut Criterion) {
    let mut g = c.benchmark_group("tessellation");
    g.throughput(Throughput::Elements(256 * 128));
    g.bench_function("sphere 256 128", |b| {
        b.iter(|| parametric::sphere(256, 128))
    });
    let q = Superquadric {
        e1: 0.5,
        e2: 0.25,
        a: DVec3::new(1.0, 2.0, 1.0),
    };
    g.throughput(Throughput::Elements(2 * 256 * 127));
    g.bench_function("superquadric 256 128", |b| {
        b.iter(|| parametric::superquadric(&q, 256, 128))
    });
    let set = wave();
    g.throughput(Throughput::Elements(4 * 2 * 64 * 64));
    g.bench_function("bezier wave 4 patches 64 64", |b| {
        b.iter(|| patch::tessellate(&set, 64, 64))
    });
    let profile = Profile::new(
        [
            (0.0, 0.0),
            (0.6, 0.0),
            (0.7, 0.15),
            (0.55, 0.5),
            (0.75, 1.1),
            (0.9, 1.6),
            (0.55, 2.3),
            (0.6, 2.8),
        ]
        .map(|(r, z)| DVec2::new(r, z))
        .to_vec(),
    )
    .unwrap();
    g.throughput(Throughput::Elements(
        profile.face_count(1024).unwrap() as u64
    ));
    g.bench_function("lathe vase 1024", |b| {
        b.iter(|| sweep::lathe(&profile, 1024))
    });
    g.finish();
}

fn csg_speed(c: &mut Criterion) {
    let mut g = c.benchmark_group("csg");
    for (nu, nv) in [(32, 16), (64, 32)] {
        let a = faces(&parametric::sphere(nu, nv), DVec3::ZERO);
        let b = faces(&parametric::cylinder(nu, true), DVec3::new(0.5, 0.2, 0.1));
        g.throughput(Throughput::Elements((a.len() + b.len()) as u64));
        for op in [Op::Union, Op::Difference] {
            g.bench_function(format!("sphere {nu}x{nv} {op:?} cylinder {nu}"), |bch| {
                bch.iter(|| csg::combine(a.clone(), b.clone(), op))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, tessellation, csg_speed);
criterion_main!(benches);

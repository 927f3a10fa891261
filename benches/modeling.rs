//! `cargo bench --bench modeling`: Firebaugh's generators (faces made per
//! second) and the BSP CSG (input faces combined per second).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec2, DVec3};
use plytrace::internal::modeling::Generated;
use plytrace::internal::modeling::csg::{self, Face, Op};
use plytrace::internal::modeling::parametric::{self, Superquadric};
use plytrace::internal::modeling::patch::{self, Form};
use plytrace::internal::modeling::sweep::{self, Profile};

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

/// Growth with size, 10^3 to 10^6 faces: the union of two spheres, lathe
/// and extrude outlines of k points (k faces per step), and Bezier patch
/// counts. Each group's medians against the faces give the exponent.
fn growth(c: &mut Criterion) {
    let mut g = c.benchmark_group("growth");
    g.sample_size(10);
    // Two spheres of nu x nu/2 faces each.
    for nu in [32usize, 64, 128, 256, 512] {
        let s = parametric::sphere(nu, nu / 2);
        let a = faces(&s, DVec3::ZERO);
        let b = faces(&s, DVec3::new(0.5, 0.3, 0.2));
        g.throughput(Throughput::Elements((a.len() + b.len()) as u64));
        g.bench_function(format!("csg union {} faces", a.len() + b.len()), |bch| {
            bch.iter(|| csg::combine(a.clone(), b.clone(), Op::Union))
        });
    }
    for k in [1_000usize, 10_000, 100_000, 1_000_000] {
        let circle: Vec<DVec2> = (0..k)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / k as f64;
                DVec2::new(t.cos(), t.sin())
            })
            .collect();
        g.throughput(Throughput::Elements(k as u64));
        g.bench_function(format!("extrude outline {k}"), |bch| {
            bch.iter(|| sweep::extrude(&sweep::extrude_outline(circle.clone()).unwrap(), 1.0))
        });
        let profile: Vec<DVec2> = (0..k)
            .map(|i| {
                let t = std::f64::consts::PI * i as f64 / (k - 1) as f64;
                let r = if i == 0 || i == k - 1 { 0.0 } else { t.sin() };
                DVec2::new(r, -t.cos())
            })
            .collect();
        g.bench_function(format!("lathe profile {k}"), |bch| {
            bch.iter(|| sweep::lathe(&Profile::new(profile.clone()).unwrap(), 3))
        });
    }
    let set = wave();
    for n in [64usize, 640, 6_400, 64_000] {
        let many = patch::PatchSet {
            patches: (0..n)
                .map(|i| {
                    let mut p = set.patches[i % set.patches.len()];
                    for row in p.p.iter_mut() {
                        for q in row.iter_mut() {
                            q.x += 2.0 * (i / set.patches.len()) as f64;
                        }
                    }
                    p
                })
                .collect(),
        };
        g.throughput(Throughput::Elements((n * 2 * 4 * 2) as u64));
        g.bench_function(format!("bezier {n} patches 4x2"), |bch| {
            bch.iter(|| patch::tessellate(&many, 4, 2))
        });
    }
    g.finish();
}

criterion_group!(benches, tessellation, csg_speed, growth);
criterion_main!(benches);

//! `cargo bench --bench scan`: the scan converters of `raster::scan` on a
//! synthetic 512 x 512 frame: a mesh of 8192 Gouraud triangles tiling the
//! screen, with Phong triangles over it, front to back.

use criterion::{Criterion, criterion_group, criterion_main};
use plytrace::internal::raster::scan::{
    Method, Row, RowSink, ScanOptions, TransparencyRule, scan_convert,
};
use plytrace::internal::tree::{PhongShades, Record, RecordStream, Shades};

struct Discard;

impl RowSink for Discard {
    fn row(&mut self, _: &Row<'_>) -> plytrace::Result<()> {
        Ok(())
    }
}

fn records() -> Vec<Record> {
    let g = 64;
    let v = |r: usize, c: usize| [c as f32 / g as f32, r as f32 / g as f32];
    let mut out = Vec::new();
    for k in 0..200 {
        let (x, y) = ((k * 37 % 100) as f32 / 100.0, (k * 53 % 100) as f32 / 100.0);
        let pts = vec![[x, y], [x + 0.05, y + 0.01], [x + 0.02, y + 0.06]];
        out.push(Record {
            level: 1,
            shades: Shades::Phong(Box::new(PhongShades {
                shininess: 10.0,
                light_colors: vec![[100, 100, 100]],
                rgbt: vec![[200, 50, 50, 0]; 3],
                normals: vec![vec![[0.1, 0.2, 1.0]]; 3],
            })),
            points: pts,
        });
    }
    for r in 0..g {
        for c in 0..g {
            let shade = Shades::Gouraud(vec![[(r * 4) as u8, (c * 4) as u8, 90]; 3]);
            for tri in [
                vec![v(r, c), v(r, c + 1), v(r + 1, c + 1)],
                vec![v(r, c), v(r + 1, c + 1), v(r + 1, c)],
            ] {
                out.push(Record {
                    level: 1,
                    points: tri,
                    shades: shade.clone(),
                });
            }
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let mut stream = RecordStream {
        records: records(),
        background: Some([0, 0, 40]),
        front_to_back: true,
        blended: true,
    };
    let methods = [
        Method::Point,
        Method::Area,
        Method::Mask,
        Method::Hybrid,
        Method::Supersample(4),
        Method::Multilevel,
    ];
    let mut group = c.benchmark_group("scan");
    group.sample_size(10);
    for m in methods {
        stream.blended = m != Method::Multilevel;
        let options = ScanOptions {
            width: 512,
            height: 512,
            method: m,
            act_lines: 16,
            paint_background: true,
            transparency: TransparencyRule::Garcia,
            threads: 0,
            ids: false,
            max_overdraw: u64::MAX,
        };
        group.bench_function(format!("{m:?}"), |b| {
            b.iter(|| scan_convert(&stream, &options, &mut Discard).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! `cargo bench --bench table61`: Garcia's table 6.1 (004 chapter 6) on
//! this machine. For every scene of `tests/data/scenes` with no shadows
//! (NS) and with shadows from 1 and 2 lights (1S, 2S; 4S where the scene
//! has four Point lights, as Garcia's gallery): the first k lights cast
//! shadows (Point), the others light without (Diffuse).
//!
//! Columns: polygons tiled; G-Time (the image generation processor: the
//! virtual image tree and its records, `render::plan`); R-Time (scan
//! conversion, method 4, `render::scan_into_frame`); RT-Time (the Whitted
//! ray tracer, `raytrace::render`) at 1 and 4 x 4 rays per pixel; RI, the
//! relative improvement `RT / (G + R)` (Garcia prints `(R + G) / RT` but
//! his figures, 106 to 953, are this ratio); and the difference between
//! the tree's image and the 4 x 4 ray-traced one: mean absolute
//! difference per channel (in 1/255) and the share of pixels differing by
//! more than 8/255 in some channel.
//!
//! Everything at 512 x 512 (`TABLE61_SIZE=N` for N x N). G and R are the
//! medians of 3 runs; RT one run. Whole-process wall times of a machine
//! that may be shared: state its load beside the figures.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use plytrace::internal::model::LightKind;
use plytrace::internal::raytrace::{self, RayTraceOptions};
use plytrace::internal::render::{self, Plan, RenderOptions};
use plytrace::internal::scene::Scene;

fn scenes() -> Vec<(String, PathBuf)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
    let mut found: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/data/scenes")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "des"))
        .collect();
    found.sort();
    found
        .into_iter()
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), p))
        .collect()
}

/// The scene with its first `k` lights casting shadows, the rest not.
fn with_shadow_lights(scene: &Scene, k: usize) -> Scene {
    let mut s = scene.clone();
    for (j, light) in s.lights.iter_mut().enumerate() {
        light.kind = if j < k {
            LightKind::Point
        } else {
            LightKind::Diffuse
        };
    }
    s
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn secs(d: Duration) -> String {
    format!("{:.1}ms", d.as_secs_f64() * 1000.0)
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is taken.
    let size: u32 = std::env::var("TABLE61_SIZE")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(512);
    println!(
        "Table 6.1 on this machine ({} threads available), {size} x {size}",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    println!(
        "{:<16} {:>8} {:>10} {:>10} {:>10} {:>10} {:>7} {:>7} {:>9} {:>9}",
        "Scene", "Tiled", "G-Time", "R-Time", "RT 1", "RT 4x4", "RI 1", "RI 16", "diff", ">8/255"
    );
    for (name, path) in scenes() {
        let scene = plytrace::internal::scene::load(&path).unwrap().0;
        let lights = scene.lights.len();
        let mut variants = vec![(String::from("NS"), 0usize)];
        for k in [1, 2, 4] {
            let points = scene
                .lights
                .iter()
                .filter(|l| l.kind == LightKind::Point)
                .count();
            if k <= lights && (k < 4 || points >= 4) {
                variants.push((format!("{k}S"), k));
            }
        }
        for (label, k) in variants {
            let s = with_shadow_lights(&scene, k);
            let options = RenderOptions {
                size: Some((size, size)),
                shadows: k > 0,
                ..RenderOptions::default()
            };
            let (mut g, mut r) = (Vec::new(), Vec::new());
            let mut last = None;
            for _ in 0..3 {
                let t = Instant::now();
                let Plan::Tree(prepared) = render::plan(&s, &options).unwrap() else {
                    panic!("the tree path");
                };
                g.push(t.elapsed());
                let t = Instant::now();
                let rendered = render::scan_into_frame(*prepared).unwrap();
                r.push(t.elapsed());
                last = Some(rendered);
            }
            let tree = last.unwrap();
            let rt = |samples| {
                let t = Instant::now();
                let (frame, _) = raytrace::render(
                    &s,
                    &RayTraceOptions {
                        size: Some((size, size)),
                        samples,
                        shadows: k > 0,
                        ..RayTraceOptions::default()
                    },
                )
                .unwrap();
                (t.elapsed(), frame)
            };
            let (rt1, _) = rt(1);
            let (rt16, traced) = rt(4);
            let (g, r) = (median(g), median(r));
            let total = (g + r).as_secs_f64();
            let (mut sum, mut far) = (0.0f64, 0usize);
            for (a, b) in tree.frame.color.iter().zip(&traced.color) {
                let d: Vec<f32> = (0..3).map(|c| (a[c] - b[c]).abs()).collect();
                sum += d.iter().map(|&v| v as f64).sum::<f64>() / 3.0;
                if d.iter().any(|&v| v > 8.0 / 255.0) {
                    far += 1;
                }
            }
            let n = traced.color.len().max(1) as f64;
            println!(
                "{:<16} {:>8} {:>10} {:>10} {:>10} {:>10} {:>7.1} {:>7.1} {:>9.2} {:>8.1}%",
                format!("{name}({label})"),
                tree.stats.polygons_tiled,
                secs(g),
                secs(r),
                secs(rt1),
                secs(rt16),
                rt1.as_secs_f64() / total,
                rt16.as_secs_f64() / total,
                sum / n * 255.0,
                far as f64 / n * 100.0
            );
        }
    }
}

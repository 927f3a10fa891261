//! `--stats`: the statistics of a session as one JSON object, for
//! scripts: the manual's figures (objects, points, polygons, polygons
//! tiled, maximum depth, time) and this program's own, per run.

use std::path::Path;
use std::time::Duration;

use plytrace::api::Antialiasing;
use plytrace::api::program::pipeline::RenderStats;
use serde_json::{Value, json};

/// The figures of one run.
#[derive(Debug, Clone)]
pub struct RunStats(Value);

impl RunStats {
    /// The figures of a run that wrote `image` at `size`.
    pub fn new(image: &Path, size: (u32, u32), s: &RenderStats, elapsed: Duration) -> RunStats {
        let mut run = json!({
            "image": image.display().to_string(),
            "width": size.0,
            "height": size.1,
            "polygons_listed": s.polygons_listed,
            "polygons_tiled": s.polygons_tiled,
            "max_depth": s.max_depth,
            "seconds": elapsed.as_secs_f64(),
            "stages": {
                "geometry": s.geometry_time.as_secs_f64(),
                "sort": s.sort_time.as_secs_f64(),
                "shading": s.shading_time.as_secs_f64(),
                "paint": s.paint_time.as_secs_f64(),
            },
            "warnings": s.warnings,
        });
        if let Some(a) = s.algorithm {
            run["visibility"] = json!(a.to_string());
        }
        if let Some(m) = s.method {
            run["scan_conversion"] = json!({
                "method": method_name(m),
                "polygons_tiled": s.scan.polygons_tiled,
                "pixels_written": s.scan.pixels_written,
                "peak_fragments": s.scan.peak_fragments,
                "total_fragments": s.scan.total_fragments,
            });
        }
        if let Some(r) = &s.raytrace {
            run["ray_tracing"] = json!({
                "primary_rays": r.primary,
                "rays": r.rays,
                "shadow_rays": r.shadow_rays,
                "hierarchy_seconds": r.build_time.as_secs_f64(),
                "tracing_seconds": r.trace_time.as_secs_f64(),
            });
        }
        if let Some(n) = &s.nns {
            run["nns"] = json!({
                "faces_in": n.faces_in,
                "faces_out": n.faces_out,
                "splits": n.splits,
                "cycles_of_two": n.cycles_of_two,
                "longer_cycles": n.longer_cycles,
                "unresolved": n.unresolved,
            });
        }
        if let Some(r) = &s.refraction {
            run["refraction"] = json!(r);
        }
        RunStats(run)
    }
}

/// What the scene held when it was read.
#[derive(Debug, Clone, Copy, Default)]
pub struct SceneCounts {
    pub objects: usize,
    pub points: usize,
    pub polygons: usize,
}

/// The session's object: the program, the scene's counts, every run.
pub fn document(scene: Option<&Path>, counts: SceneCounts, runs: &[RunStats], ok: bool) -> String {
    let doc = json!({
        "program": "plytrace",
        "version": env!("CARGO_PKG_VERSION"),
        "scene": scene.map(|p| p.display().to_string()),
        "objects": counts.objects,
        "points": counts.points,
        "polygons": counts.polygons,
        "runs": runs.iter().map(|r| r.0.clone()).collect::<Vec<_>>(),
        "ok": ok,
    });
    let mut text = doc.to_string();
    text.push('\n');
    text
}

/// The scan conversion method in words.
pub fn method_name(m: Antialiasing) -> String {
    use Antialiasing as Method;
    match m {
        Method::Point => "point sampled (--aa none)".into(),
        Method::Area => "method 1, area coverage".into(),
        Method::Mask => "method 2, 4x4 pixel masks".into(),
        Method::Hybrid => "method 3, hybrid area/mask".into(),
        Method::Multilevel => "method 4, multi-level pixel masks".into(),
        Method::Supersample(n) => format!("Donovan's {n} x {n} supersampling"),
    }
}

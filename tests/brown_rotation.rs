//! Brown's approximate rotation (003 sections 2-3): `radial rotate` turns a
//! geodesic's radial function inside its fixed vertex directions, so an
//! animation's later frames reuse the first frame's priority order with no
//! re-sort. Every frame painted with the reused order must equal a fresh
//! sort, pixel for pixel, and both must agree with the ray-cast oracle.
//! A real rotation (the CTM turns the directions) must be sorted again.

mod support;

use std::path::Path;

use plytrace::Result;
use plytrace::internal::render::Reuse;
use plytrace::internal::render::{Plan, RenderOptions, Rendered, plan, plan_with};
use plytrace::internal::scene::{Host, Interpreter, Scene};
use plytrace::internal::visibility::Algorithm;
use plytrace::internal::visibility::brown::BrownStats;
use plytrace::internal::visibility::ray_cast::RayCaster;

/// Renders every `run` twice: with the orders of the previous frame, and
/// with a fresh sort.
#[derive(Default)]
struct Frames {
    reuse: Reuse,
    frames: Vec<(Scene, Rendered, Rendered)>,
}

fn painted(p: Plan) -> Rendered {
    match p {
        Plan::Painted(r) => *r,
        Plan::Tree(_) => panic!("Brown's order paints its own image"),
    }
}

impl Host for Frames {
    fn run(&mut self, scene: &Scene, _shadows: bool) -> Result<()> {
        let options = RenderOptions {
            visibility: Some(Algorithm::Brown),
            ..RenderOptions::default()
        };
        let reused = painted(plan_with(scene, &options, &self.reuse)?);
        let fresh = painted(plan(scene, &options)?);
        self.frames.push((scene.clone(), reused, fresh));
        Ok(())
    }
}

fn animate(source: &str) -> Vec<(Scene, Rendered, Rendered)> {
    let mut host = Frames::default();
    Interpreter::new()
        .execute_source(source, Path::new("spin.des"), Path::new("."), &mut host)
        .unwrap();
    host.frames
}

const HEAD: &str =
    "resolution 128 128\nperspective 40 1 0.1 100\npushmatrix\nident\npolarview 4.5 25 65 0\n";

/// One geodesic, `frames` runs with `turn` between them.
fn spin_source(n: usize, radial: &str, turn: &str, frames: usize) -> String {
    let mut s =
        format!("{HEAD}defobj geo\n geodesic {n} angle\n radial {radial}\nendobj\npopmatrix\n");
    for _ in 0..frames {
        s.push_str("run\n");
        s.push_str(turn);
        s.push('\n');
    }
    s
}

fn check_against_oracle(name: &str, scene: &Scene, r: &Rendered) {
    let (w, h) = (r.frame.width, r.frame.height);
    let oracle: Vec<Option<(u32, u32)>> = RayCaster::new(scene)
        .id_image(w, h)
        .into_iter()
        .map(|hit| hit.map(|hit| (hit.object, hit.polygon)))
        .collect();
    let (checked, bad) = support::mismatches(&oracle, &support::painted_ids(r), w, h);
    assert!(checked > 3000, "{name}: only {checked} pixels checked");
    assert!(
        bad.is_empty(),
        "{name}: {} of {checked} pixels differ from the ray-cast oracle, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

#[test]
fn turned_frames_reuse_the_order_and_paint_what_a_fresh_sort_paints() {
    for (radial, turn) in [
        ("lobes 0.4 4", "radial rotate 25 z"),
        ("bumps 0.3 3", "radial rotate 30 x"),
        ("ellipsoid 1.5 1 0.6", "radial rotate 40 y"),
    ] {
        let frames = animate(&spin_source(6, radial, turn, 4));
        assert_eq!(frames.len(), 4);
        for (k, (scene, reused, fresh)) in frames.iter().enumerate() {
            let name = format!("{radial}, {turn}, frame {k}");
            let want = if k == 0 {
                BrownStats {
                    sorted: 1,
                    reused: 0,
                }
            } else {
                BrownStats {
                    sorted: 0,
                    reused: 1,
                }
            };
            assert_eq!(reused.stats.brown, Some(want), "{name}");
            assert_eq!(
                fresh.stats.brown,
                Some(BrownStats {
                    sorted: 1,
                    reused: 0
                })
            );
            assert!(
                reused.frame.ids == fresh.frame.ids && reused.frame.color == fresh.frame.color,
                "{name}: the reused order paints another image than a fresh sort"
            );
            check_against_oracle(&name, scene, reused);
        }
        // The function did turn: the frames differ.
        assert!(frames[0].1.frame.color != frames[1].1.frame.color);
    }
}

/// A real rotation turns the vertex directions: the order must be sorted
/// again (reusing it would paint the far side over the near side).
#[test]
fn a_real_rotation_is_sorted_again() {
    let mut s = format!(
        "{HEAD}defobj geo 0\n geodesic 6 angle\n radial lobes 0.4 4\nendobj\npopmatrix\nrun\n"
    );
    for angle in [35, 70, 105] {
        s.push_str(&format!(
            "delobj 0\npushmatrix\nident\npolarview 4.5 25 65 0\ndefobj geo 0\n rotate {angle} x\n \
             geodesic 6 angle\n radial lobes 0.4 4\nendobj\npopmatrix\nrun\n"
        ));
    }
    let frames = animate(&s);
    assert_eq!(frames.len(), 4);
    for (k, (scene, reused, _)) in frames.iter().enumerate() {
        let b = reused.stats.brown.unwrap();
        assert_eq!((b.sorted, b.reused), (1, 0), "frame {k}");
        check_against_oracle(&format!("rotated frame {k}"), scene, reused);
    }
}

#[test]
fn radial_rotate_needs_a_geodesic() {
    let mut host = Frames::default();
    let e = Interpreter::new()
        .execute_source(
            "radial rotate 10 z\n",
            Path::new("x.des"),
            Path::new("."),
            &mut host,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("x.des:1:1") && e.contains("geodesic"), "{e}");
    let e = Interpreter::new()
        .execute_source(
            "defobj g\n geodesic 2\n radial rotate 10 w\nendobj\n",
            Path::new("x.des"),
            Path::new("."),
            &mut host,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("x.des:3:") && e.contains("axis"), "{e}");
}

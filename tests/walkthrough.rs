//! A camera moving through a still world: each frame keeps what the
//! frame before left (`render::Reuse`: the shadow casters and the
//! shadows cast on whole polygons, Brown's priority orders, the order
//! of level 1's faces by depth where the next NNS sort starts). Every frame
//! must equal a cold render of the same view, pixel for pixel, and the
//! world's shadows must be cast once, not once per frame; when an object
//! is added mid-path they are cast again. The paths move the scene's own
//! camera, as a user's script does (`pushmatrix`, a move, `run y`,
//! `popmatrix`), and the camera of a view set anew (`ident`).

mod support;

use std::path::Path;

use plytrace::Result;
use plytrace::internal::render::{
    Plan, RenderOptions, Rendered, Reuse, plan_with, scan_into_frame,
};
use plytrace::internal::scene::{Host, Interpreter, Scene};

/// Renders every `run` twice: with what the previous frame left, and cold.
#[derive(Default)]
struct Walk {
    reuse: Reuse,
    size: u32,
    frames: usize,
    /// The walk's name, for the failures.
    label: String,
    /// Whether the host passes on that more frames follow, as the
    /// program does ([`Reuse::frames_follow`]).
    follow: bool,
}

fn picture(plan: Plan) -> Rendered {
    match plan {
        Plan::Tree(prepared) => scan_into_frame(*prepared).expect("scan converts"),
        Plan::Painted(rendered) => *rendered,
    }
}

impl Host for Walk {
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        assert!(shadows, "the walk casts shadows");
        let options = RenderOptions {
            size: Some((self.size, self.size)),
            shadows,
            ..RenderOptions::default()
        };
        let warm = picture(plan_with(scene, &options, &self.reuse)?);
        let cold = picture(plan_with(scene, &options, &Reuse::default())?);
        let unlike = |a: &Rendered, b: &Rendered| {
            let pairs = a.frame.color.iter().zip(&b.frame.color);
            pairs.filter(|(p, q)| p != q).count()
        };
        let k = self.frames;
        assert_eq!(
            unlike(&warm, &cold),
            0,
            "{} frame {k}: pixels differ from its cold render",
            self.label
        );
        if k == 0 {
            // The walk must show shadows for the test to mean anything.
            let unshadowed = RenderOptions {
                shadows: false,
                ..options
            };
            let plain = picture(plan_with(scene, &unshadowed, &Reuse::default())?);
            assert!(unlike(&warm, &plain) > 20, "frame 0 shows no shadow");
        }
        self.frames += 1;
        Ok(())
    }

    fn runs_follow(&mut self, more: bool) {
        self.reuse.frames_follow(self.follow && more);
    }
}

/// `frames` views: the camera turns and moves forward a little each
/// frame (the objects are placed in the eye space of the file's view, so
/// only the projection changes); after `change` frames a box is added.
fn path(file: &Path, fov: f64, frames: usize, change: usize) -> String {
    let mut s = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    for k in 0..frames {
        if k == change {
            s.push_str("pushmatrix\nident\ndefobj cube\n color 0.9 0.2 0.2\n translate 0 0 -9\n scale 0.4 0.4 0.4\nendobj\npopmatrix\n");
        }
        let turn = -6.0 + 12.0 * k as f64 / frames as f64;
        let ahead = 0.02 * k as f64;
        s.push_str(&format!(
            "ident\nperspective {fov} 1.0 0.01 1000.0\nrotate {turn} y\nrotate {} x\ntranslate 0 0 {ahead}\nrun y\n",
            turn / 3.0
        ));
    }
    s
}

fn walk(scene: &str, fov: f64, size: u32, frames: usize, change: usize) -> Walk {
    let mut host = Walk {
        size,
        ..Walk::default()
    };
    let file = support::scene_fixture(scene);
    let dir = file.parent().expect("the scenes' folder");
    Interpreter::new()
        .execute_source(
            &path(&file, fov, frames, change),
            Path::new(scene),
            dir,
            &mut host,
        )
        .expect("the walk renders");
    host
}

/// 60 frames over a partly diffuse mirror floor with a Point light.
#[test]
fn a_walk_over_the_mirror_equals_cold_renders() {
    let host = walk("mirror.des", 40.0, 64, 60, 40);
    assert_eq!(host.frames, 60);
    // Built in the first two frames of each world (the first keeps
    // none), then kept: four builds for two worlds in 60 frames.
    assert_eq!(
        host.reuse.worlds(),
        4,
        "shadows cast per world, not per frame"
    );
}

/// The gallery: mirrors to depth 14, four Point lights.
#[test]
fn a_walk_through_the_gallery_equals_cold_renders() {
    let host = walk("gallery.des", 55.0, 40, 6, 3);
    assert_eq!(host.frames, 6);
    assert_eq!(host.reuse.worlds(), 4);
}

/// An open square between two lights, a cube over it and a cube under
/// it: seen from above it shows the upper cube's shadow, from below the
/// lower's. The shadows kept on the whole square for one side must not
/// be shown on the other: the camera orbits across its plane.
#[test]
fn a_walk_across_an_open_square_equals_cold_renders() {
    let mut des = String::from(
        "ident\nperspective 50 1.0 0.01 1000.0\npushmatrix\nident\npolarview 8 20 30 0\n\
         light 0.3 0.2 4 1 1 1 100 Point\nlight -0.2 0.3 -4 1 1 1 100 Point\n\
         defobj square\n type polygon open\n scale 2 2 1\nendobj\n\
         defobj cube\n translate 0.2 0 1\n scale 0.3 0.3 0.3\nendobj\n\
         defobj cube\n translate -0.3 0.2 -1\n scale 0.3 0.3 0.3\nendobj\npopmatrix\n",
    );
    // About the point the eye looks at: 0 to 60 degrees above the
    // square's plane, then 100 to 180 below it.
    for turn in [0, 20, 40, 60, 100, 130, 150, 180] {
        des.push_str(&format!(
            "ident\nperspective 50 1.0 0.01 1000.0\ntranslate 0 0 -8\nrotate {turn} x\n\
             translate 0 0 8\nrun y\n"
        ));
    }
    let mut host = Walk {
        size: 64,
        ..Walk::default()
    };
    let file = support::scene_fixture("mirror.des");
    let dir = file.parent().expect("the scenes' folder");
    Interpreter::new()
        .execute_source(&des, Path::new("square.des"), dir, &mut host)
        .expect("the walk renders");
    assert_eq!(host.frames, 8);
}

/// A move of the scene's own camera at `s` (0 to 1) along a path of
/// `benches/walk_paths.sh`: the scenes' objects are in eye space, the eye
/// at the origin looking down -z.
fn own_camera_move(path: &str, s: f64) -> String {
    match path {
        "turn" => format!("rotate {} y", -20.0 + 40.0 * s),
        "walk" => format!("translate 0 0 {}", 2.4 * s),
        "look" => format!("rotate {} x", -15.0 + 30.0 * s),
        "roll" => format!("rotate {} z", -10.0 + 20.0 * s),
        "stroll" => format!("rotate {} y\ntranslate 0 0 {}", -12.0 + 24.0 * s, 0.6 * s),
        _ => panic!("no path {path}"),
    }
}

/// The frames of a 120-frame path that the tests render: the first
/// three (a frame's small step from the last), two in the middle and the
/// last (long jumps).
const OWN_CAMERA_FRAMES: [u32; 6] = [0, 1, 2, 60, 61, 119];

/// `scene` walked along `path` with its own camera at `size` x `size`,
/// every frame checked against its cold render.
fn own_camera_walk(scene: &str, path: &str, size: u32) -> Walk {
    let file = support::scene_fixture(scene);
    let dir = file.parent().expect("the scenes' folder");
    let mut des =
        std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    for k in OWN_CAMERA_FRAMES {
        let s = f64::from(k) / 119.0;
        des.push_str(&format!(
            "pushmatrix\n{}\nrun y\npopmatrix\n",
            own_camera_move(path, s)
        ));
    }
    let mut host = Walk {
        size,
        label: format!("{scene} {path}"),
        follow: true,
        ..Walk::default()
    };
    Interpreter::new()
        .execute_source(&des, Path::new(scene), dir, &mut host)
        .expect("the walk renders");
    assert_eq!(host.frames, OWN_CAMERA_FRAMES.len());
    host
}

/// office2 (mirrors to depth 3, two Point lights, a dense sculpture)
/// along every path of the bench with its own camera.
#[test]
fn office2_along_its_own_camera_paths_equals_cold_renders() {
    for path in ["turn", "walk", "look", "roll", "stroll"] {
        let host = own_camera_walk("office2.des", path, 40);
        assert_eq!(host.reuse.worlds(), 1, "{path}: one world, built once");
        // The small steps (frames 1, 2 and 61) start level 1's sort from
        // the order of the frame before.
        let warm = host.reuse.warm_sorts();
        assert!(
            warm >= 3,
            "{path}: {warm} sorts started from the last order"
        );
    }
}

/// The gallery (facing mirrors to depth 14, four Point lights) along
/// every path of the bench with its own camera.
#[test]
fn the_gallery_along_its_own_camera_paths_equals_cold_renders() {
    for path in ["turn", "walk", "look", "roll", "stroll"] {
        let host = own_camera_walk("gallery.des", path, 32);
        assert_eq!(host.reuse.worlds(), 1, "{path}: one world, built once");
    }
}

/// Told that frames follow, a walk builds each world's casters once: on
/// its first frame, not again on its second. The last frame of the file
/// is told that none follows.
#[test]
fn a_walk_told_that_frames_follow_builds_each_world_once() {
    let file = support::scene_fixture("mirror.des");
    let dir = file.parent().expect("the scenes' folder");
    let mut host = Walk {
        size: 32,
        label: "mirror, frames follow".into(),
        follow: true,
        ..Walk::default()
    };
    Interpreter::new()
        .execute_source(
            &path(&file, 40.0, 8, 5),
            Path::new("mirror.des"),
            dir,
            &mut host,
        )
        .expect("the walk renders");
    assert_eq!(host.frames, 8);
    assert_eq!(host.reuse.worlds(), 2, "two worlds, each built once");
}

/// What the interpreter tells its host before each `run`: whether a
/// `run` (or a `call` or `get`, which may hold one) is still to come in
/// the statements left, in this file or in those that called it.
#[test]
fn the_host_is_told_whether_runs_follow() {
    #[derive(Default)]
    struct Told(Vec<bool>, Option<bool>);
    impl Host for Told {
        fn run(&mut self, _scene: &Scene, _shadows: bool) -> Result<()> {
            let told = self.1.take().expect("told before the run");
            self.0.push(told);
            Ok(())
        }
        fn runs_follow(&mut self, more: bool) {
            self.1 = Some(more);
        }
    }
    let dir = tempfile::tempdir().expect("a folder");
    std::fs::write(dir.path().join("inner.des"), "run\nident\nrun\nident\n").expect("written");
    let cases: [(&str, &[bool]); 4] = [
        ("run\nrun\nident\nrun\nident\n", &[true, true, false]),
        ("run\ncall inner.des\n", &[true, true, false]),
        ("call inner.des\nrun\n", &[true, true, false]),
        ("run\ncall inner.des\nident\n", &[true, true, false]),
    ];
    for (source, expected) in cases {
        let mut host = Told::default();
        Interpreter::new()
            .execute_source(source, Path::new("main.des"), dir.path(), &mut host)
            .expect("the file runs");
        assert_eq!(host.0, expected, "{source:?}");
    }
}

//! The live display's frame callback, headless (004 appendix: `disp on`
//! shows the virtual image tree as it is built): one frame per level of
//! the tree, in order, the last equal to the final image; the frame of
//! level `k` equals the render of the same scene with `depth k`.

#[path = "../../tests/support/mod.rs"]
mod support;

use plytrace::internal::display::{FrameObserver, PartialFrame, render_observed};
use plytrace::internal::raster::frame_buffer::FrameBuffer;
use plytrace::internal::render::{RenderOptions, Reuse, render};
use plytrace::internal::scene::Scene;

fn scene(name: &str) -> Scene {
    plytrace::internal::scene::load(&support::scene_fixture(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// Collects the frames handed to the callback.
#[derive(Default)]
struct Collect(Vec<(u32, u32, FrameBuffer)>);

impl FrameObserver for Collect {
    fn frame(&mut self, f: &PartialFrame<'_>) {
        self.0.push((f.level, f.levels, f.frame.clone()));
    }
}

fn options(shadows: bool) -> RenderOptions {
    RenderOptions {
        size: Some((96, 96)),
        shadows,
        ..RenderOptions::default()
    }
}

fn same(a: &FrameBuffer, b: &FrameBuffer) -> bool {
    a.width == b.width && a.height == b.height && a.color == b.color && a.ids == b.ids
}

#[test]
fn one_frame_per_level_the_last_is_the_final_image() {
    for (name, depth) in [("mirror.des", 2), ("underwater.des", 2), ("ccube.des", 1)] {
        let s = scene(name);
        let mut frames = Collect::default();
        let shown = render_observed(&s, &options(true), &Reuse::default(), &mut frames).unwrap();
        let levels: Vec<(u32, u32)> = frames.0.iter().map(|f| (f.0, f.1)).collect();
        let want: Vec<(u32, u32)> = (1..=depth).map(|k| (k, depth)).collect();
        assert_eq!(levels, want, "{name}");
        let last = &frames.0.last().unwrap().2;
        assert!(
            same(last, &shown.frame),
            "{name}: the last frame is not the image returned"
        );
        let plain = render(&s, &options(true)).unwrap();
        assert!(
            same(last, &plain.frame),
            "{name}: the last frame is not the plain render's image"
        );
        // Each level adds something: the frames differ.
        for pair in frames.0.windows(2) {
            assert!(
                !same(&pair[0].2, &pair[1].2),
                "{name}: level {} adds nothing",
                pair[1].0
            );
        }
    }
}

/// The frame of level `k` is the tree cut at level `k`: the render of
/// the same scene limited to `depth k` (an independent build of the tree).
#[test]
fn the_frame_of_a_level_is_the_scene_rendered_to_that_depth() {
    for name in ["mirror.des", "underwater.des"] {
        let s = scene(name);
        let mut frames = Collect::default();
        render_observed(&s, &options(false), &Reuse::default(), &mut frames).unwrap();
        for (level, _, frame) in &frames.0 {
            let mut cut = s.clone();
            cut.modes.max_level = *level;
            let r = render(&cut, &options(false)).unwrap();
            let differ = frame
                .color
                .iter()
                .zip(&r.frame.color)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(differ, 0, "{name}, level {level}: {differ} pixels differ");
        }
    }
}

/// A closure is an observer too; an image painted without the tree
/// (Brown's order) is one frame.
#[test]
fn a_closure_observes_a_painted_image_once() {
    let s = scene("ccube.des");
    let mut seen = Vec::new();
    let mut observer = |f: &PartialFrame<'_>| seen.push((f.level, f.levels, f.is_last()));
    let o = RenderOptions {
        visibility: Some(plytrace::internal::visibility::Algorithm::ZBuffer),
        aa: Some(plytrace::internal::raster::scan::Method::Point),
        ..options(false)
    };
    render_observed(&s, &o, &Reuse::default(), &mut observer).unwrap();
    assert_eq!(seen, vec![(1, 1, true)]);
}

/// The command line: `disp on` without a window says so once, on stderr,
/// and every `run` still writes its file; `disp off` does not stop the
/// file either (it dismisses the display, as the manual says).
#[test]
fn without_a_display_disp_on_says_so_once_and_files_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let des = dir.path().join("d.des");
    std::fs::write(
        &des,
        "resolution 48 48\nperspective 40 1 0.1 100\npushmatrix\nident\npolarview 5 25 65 0\n\
         defobj geo\n geodesic 2\nendobj\npopmatrix\n\
         disp on\nfname a\nrun\nwait\ndisp\nfname b\nrun\ndisp off\nfname c\nrun\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_plytrace"))
        .args(["-q", "-i", "-f", "d.des"])
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(stderr.matches("disp on:").count(), 1, "{stderr}");
    assert!(stderr.contains("written to files only"), "{stderr}");
    for name in ["a.png", "b.png", "c.png"] {
        let len = std::fs::metadata(dir.path().join(name)).map_or(0, |m| m.len());
        assert!(len > 0, "{name} was not written");
    }
}

/// The feature build under a virtual X server (`Xvfb`, installed by
/// `.ci/run`): `disp on` opens the window, each level is shown in it, and
/// nothing is said about a missing display.
#[cfg(feature = "display")]
#[test]
fn under_xvfb_disp_on_opens_the_window() {
    use std::io::{BufRead, BufReader};
    let mut xvfb = std::process::Command::new("Xvfb")
        .args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "320x240x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("Xvfb is needed for the display feature's test (apt-get install xvfb)");
    let mut number = String::new();
    BufReader::new(xvfb.stdout.take().unwrap())
        .read_line(&mut number)
        .unwrap();
    let display = format!(":{}", number.trim());
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("d.des"),
        "resolution 48 48\nperspective 40 1 0.1 100\npushmatrix\nident\npolarview 5 25 65 0\n\
         defobj geo\n geodesic 2\nendobj\npopmatrix\ndisp on\nrun\nrun\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_plytrace"))
        .args(["-q", "-i", "-f", "d.des"])
        .current_dir(dir.path())
        .env("DISPLAY", &display)
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    let _ = xvfb.kill();
    let _ = xvfb.wait();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("disp on:"), "{display}: {stderr}");
    assert!(dir.path().join("d.png").exists());
}

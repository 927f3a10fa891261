//! Parts of one image (`--part I/N`) merged are the image, byte for byte:
//! every scene in `tests/data/scenes`, 1, 2, 3, 7 and 64 parts, every
//! scan conversion method, with and without shadows, through the
//! library's part writer and merge (the program's `--part` runs the same
//! code; tests/parts_cli.rs runs the program itself).

use std::path::{Path, PathBuf};

use plytrace::Result;
use plytrace::internal::model::Scene;
use plytrace::internal::output::{DisplayMode, PngSink};
use plytrace::internal::part::{MergeFormat, PartInfo, PartSink, PartSpec};
use plytrace::internal::raster::frame_buffer::FrameBuffer;
use plytrace::internal::raster::scan::Method;
use plytrace::internal::render::{Plan, Prepared, RenderOptions, plan, scan_rows};
use plytrace::internal::scene::Host;
use plytrace::internal::scene::interpreter::Interpreter;

const SIZE: (u32, u32) = (64, 48);
const COUNTS: [u32; 5] = [1, 2, 3, 7, 64];

/// Keeps the scene of the first `run`.
#[derive(Default)]
struct First(Option<Scene>);

impl Host for First {
    fn run(&mut self, scene: &Scene, _shadows: bool) -> Result<()> {
        if self.0.is_none() {
            self.0 = Some(scene.clone());
        }
        Ok(())
    }
}

fn scene(path: &Path) -> Scene {
    let mut host = First::default();
    let mut interp = Interpreter::new();
    interp
        .execute_file(path, true, &mut host)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    host.0.unwrap_or_else(|| interp.current().clone())
}

fn scenes() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir("tests/data/scenes")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "des"))
        .collect();
    v.sort();
    v
}

/// The one-process PNG, as the program streams it.
fn whole_png(prepared: &Prepared, mode: DisplayMode, dir: &Path) -> Vec<u8> {
    let path = dir.join("whole.png");
    let (w, h) = (prepared.scan.width, prepared.scan.height);
    let mut sink = PngSink::create(&path, w, h, mode).unwrap();
    scan_rows(prepared, 0..h, &mut sink).unwrap();
    sink.finish().unwrap().0.commit().unwrap();
    std::fs::read(&path).unwrap()
}

/// The parts of `count`, written to `dir`.
fn parts(prepared: &Prepared, mode: DisplayMode, count: u32, dir: &Path) -> Vec<PathBuf> {
    let (w, h) = (prepared.scan.width, prepared.scan.height);
    (0..count)
        .map(|index| {
            let spec = PartSpec { index, count };
            let rows = plytrace::internal::raster::scan::part_rows(
                &prepared.picture,
                &prepared.scan,
                index,
                count,
            );
            let path = dir.join(format!("part-{count}-{index}.png"));
            let info = PartInfo {
                part: spec,
                image: (w, h),
                first: rows.start,
                rows: rows.len() as u32,
                output: "whole.png".into(),
                fingerprint: "0123456789abcdef".into(),
            };
            let mut sink = PartSink::create(&path, info, mode).unwrap();
            scan_rows(prepared, rows, &mut sink).unwrap();
            sink.finish().unwrap().commit().unwrap();
            path
        })
        .collect()
}

#[test]
fn merged_parts_are_the_image_byte_for_byte() {
    let methods = [
        None,
        Some(Method::Point),
        Some(Method::Area),
        Some(Method::Mask),
        Some(Method::Hybrid),
        Some(Method::Multilevel),
        Some(Method::Supersample(2)),
    ];
    // Thousands of small files, each synced to disk when written: in
    // memory where there is a RAM file system.
    let shm = Path::new("/dev/shm");
    let dir = if shm.is_dir() {
        tempfile::tempdir_in(shm).unwrap()
    } else {
        tempfile::tempdir().unwrap()
    };
    let mut compared = 0;
    for path in scenes() {
        let scene = scene(&path);
        let mode = DisplayMode::from(scene.outmode);
        for aa in methods {
            for shadows in [true, false] {
                let options = RenderOptions {
                    size: Some(SIZE),
                    aa,
                    shadows,
                    ..RenderOptions::default()
                };
                let what = format!("{} --aa {aa:?} shadows {shadows}", path.display());
                let prepared = match plan(&scene, &options) {
                    Ok(Plan::Tree(p)) => *p,
                    Ok(Plan::Painted(_)) => continue,
                    Err(e) => panic!("{what}: {e}"),
                };
                let whole = whole_png(&prepared, mode, dir.path());
                for count in COUNTS {
                    let files = parts(&prepared, mode, count, dir.path());
                    let out = dir.path().join("merged.png");
                    plytrace::internal::part::merge(&files, Some(&out), None, &Default::default())
                        .unwrap();
                    assert!(
                        std::fs::read(&out).unwrap() == whole,
                        "{what}: {count} parts merged differ from the image"
                    );
                    if count == 3 {
                        // PPM: the bytes of the whole frame written as PPM.
                        let (w, h) = SIZE;
                        let mut frame = FrameBuffer::new(w, h, [0.0; 3]);
                        scan_rows(&prepared, 0..h, &mut frame).unwrap();
                        let ppm = dir.path().join("whole.ppm");
                        plytrace::internal::output::write_ppm(&ppm, &frame, scene.outmode).unwrap();
                        let merged = dir.path().join("merged.ppm");
                        plytrace::internal::part::merge(
                            &files,
                            Some(&merged),
                            Some(MergeFormat::Ppm),
                            &Default::default(),
                        )
                        .unwrap();
                        assert_eq!(
                            std::fs::read(&merged).unwrap(),
                            std::fs::read(&ppm).unwrap(),
                            "{what}: PPM"
                        );
                    }
                    for f in files {
                        std::fs::remove_file(f).unwrap();
                    }
                    compared += 1;
                }
            }
        }
    }
    assert!(
        compared >= 9 * 7 * 2 * COUNTS.len() / 2,
        "{compared} compared"
    );
}

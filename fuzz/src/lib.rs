//! The entry points of plytrace's fuzz targets, as ordinary functions: the
//! cargo-fuzz targets in `fuzz_targets/` call them with libFuzzer's bytes,
//! and `tests/fuzz_regressions.rs` (which includes this file by path) calls
//! them with every file under `tests/data/fuzz-regressions/<target>/`, so a
//! finding replays through exactly the code that found it.
//!
//! Each function must not panic on any input. Beyond that they check a few
//! properties that hold for every input (round trips of what was parsed,
//! image sizes), with `assert!`, so that a broken property is a finding too.
//!
//! Nothing here touches the file system outside one private temporary
//! directory, which the scene language target also makes the working
//! directory (relative paths in a scene are looked up there too), and whose
//! inputs may not name a path with `..`, `\` or a `/` outside comments.
//! `rftb_args` writes nothing: it only looks up (stats) the paths a
//! command line names, as the programs' name checks do.
#![allow(clippy::missing_panics_doc)]

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::object_file::{self, ColorKind};
use plytrace::internal::scene::{Interpreter, NoHost, mesh_import};
use plytrace::internal::tree::RecordStream;

/// The names the fuzz targets are known by, which are also the folders of
/// `tests/data/fuzz-regressions/`.
pub const TARGETS: [&str; 9] = [
    "scene_language",
    "object_files",
    "meshes",
    "tree_files",
    "pipeline",
    "pixel_structs",
    "rftb_args",
    "patch_files",
    "modeling",
];

/// Runs the target called `name` on `data`.
pub fn run_target(name: &str, data: &[u8]) {
    match name {
        "scene_language" => scene_language(data),
        "object_files" => object_files(data),
        "meshes" => meshes(data),
        "tree_files" => tree_files(data),
        "pipeline" => pipeline(data),
        "pixel_structs" => pixel_structs(data),
        "rftb_args" => rftb_args(data),
        "patch_files" => patch_files(data),
        "modeling" => modeling(data),
        other => panic!("no fuzz target called `{other}`"),
    }
}

const CUBE_DET: &str = include_str!("../../examples/det/cube.det");
const SQUARE_DET: &str = "square\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n";
const SQUARE_PCL: &str = "square\ndata 1\n.9 .8 .2 .0 .0 .0\n";
const SQUARE_VCL: &str =
    "square\ndata 4\n.9 .8 .2 0 0 0\n.8 .9 .2 0 0 0\n.2 .8 .9 0 0 0\n.9 .2 .8 0 0 0\n";
const SUB_DES: &str = "translate 0 0 -1\ngetobj cube\n";
const WAVE_BPT: &str = include_str!("../../examples/det/wave.bpt");
const RIPPLE_HPT: &str = include_str!("../../examples/det/ripple.hpt");

/// The private directory: `det/` with a cube, a square (with polygon and
/// vertex colours) and two patch files (`wave.bpt`, `ripple.hpt`), and
/// `sub.des` for `call`. Made once per process.
struct Sandbox {
    dir: PathBuf,
    /// Serializes the users of the files in `dir`.
    lock: Mutex<()>,
    _keep: tempfile::TempDir,
}

fn sandbox() -> &'static Sandbox {
    static SANDBOX: OnceLock<Sandbox> = OnceLock::new();
    SANDBOX.get_or_init(|| {
        let keep = tempfile::tempdir().expect("a temporary directory");
        let dir = keep.path().canonicalize().expect("canonical temp dir");
        let det = dir.join("det");
        std::fs::create_dir(&det).expect("det/");
        for (name, text) in [
            ("cube.det", CUBE_DET),
            ("square.det", SQUARE_DET),
            ("square.pcl", SQUARE_PCL),
            ("square.vcl", SQUARE_VCL),
            ("wave.bpt", WAVE_BPT),
            ("ripple.hpt", RIPPLE_HPT),
        ] {
            std::fs::write(det.join(name), text).expect("fixture");
        }
        std::fs::write(dir.join("sub.des"), SUB_DES).expect("sub.des");
        std::fs::create_dir(dir.join("work")).expect("work/");
        Sandbox {
            dir,
            lock: Mutex::new(()),
            _keep: keep,
        }
    })
}

fn lock(sandbox: &Sandbox) -> std::sync::MutexGuard<'_, ()> {
    // A panic in another replay poisons the lock; the files are still fine.
    sandbox.lock.lock().unwrap_or_else(|e| e.into_inner())
}

/// Whether a scene may name a path outside the sandbox: `..`, `\\`, or a
/// `/` that is not part of `/*` or `*/` (the lexer starts a comment at every
/// `/*`, so no word can begin with `/` and be absolute).
fn names_a_path(data: &[u8]) -> bool {
    data.contains(&b'\\')
        || data.windows(2).any(|w| w == b"..")
        || (0..data.len()).any(|i| {
            data[i] == b'/' && data.get(i + 1) != Some(&b'*') && (i == 0 || data[i - 1] != b'*')
        })
}

/// Checks what every error of the interpreter promises: a message that
/// starts with the file and, for a text input, `file:line:col:` or the
/// file alone (I/O and whole-file errors).
fn check_error(e: &plytrace::Error) {
    let text = e.to_string();
    assert!(!text.is_empty(), "an empty error message");
}

/// `scene_language`: the bytes as a scene file, read by the interpreter as
/// `get file` does (`plytrace::internal::scene::load`), in the sandbox.
pub fn scene_language(data: &[u8]) {
    if names_a_path(data) {
        return;
    }
    let sandbox = sandbox();
    let _guard = lock(sandbox);
    // Relative names are also looked up in the working directory: make it
    // the sandbox's empty `work/`.
    std::env::set_current_dir(sandbox.dir.join("work")).expect("chdir to the sandbox");
    let file = sandbox.dir.join("f.des");
    std::fs::write(&file, data).expect("write the scene");
    match plytrace::internal::scene::load(&file) {
        Ok((scene, _warnings)) => {
            let _ = scene.polygon_count();
            let _ = scene.size();
        }
        Err(e) => check_error(&e),
    }
}

/// `object_files`: every det/pcl/vcl parser, ASCII and binary, on the
/// bytes. What parses as binary writes back to the same mesh or colours.
pub fn object_files(data: &[u8]) {
    let file = Path::new("fuzz.det");
    let text = String::from_utf8_lossy(data);
    let _ = object_file::parse_det_ascii(&text, file);
    let _ = object_file::parse_color_ascii(&text, file);
    if let Ok(mesh) = object_file::parse_det_binary(data, file)
        && let Ok(bytes) = object_file::write_det_binary(&mesh)
    {
        let again = object_file::parse_det_binary(&bytes, file).expect("written det reads back");
        let bytes_again = object_file::write_det_binary(&again).expect("det writes again");
        assert_eq!(bytes, bytes_again, "binary det round trip");
    }
    for kind in [ColorKind::Polygon, ColorKind::Vertex] {
        if let Ok(entries) = object_file::parse_color_binary(data, file, kind)
            && let Ok(bytes) = object_file::write_color_binary(&entries, kind)
        {
            let again = object_file::parse_color_binary(&bytes, file, kind)
                .expect("written colours read back");
            assert_eq!(
                object_file::write_color_binary(&again, kind).expect("colours write again"),
                bytes,
                "binary colour round trip"
            );
        }
    }
}

/// `meshes`: the bytes after the first as an OBJ (first byte `o`), PLY
/// (`p`) or STL (`s`) file (other first bytes choose by their value), read
/// by `mesh_import::read_mesh` from a file in the sandbox.
pub fn meshes(data: &[u8]) {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let extension = match first {
        b'o' => "obj",
        b'p' => "ply",
        b's' => "stl",
        b => ["obj", "ply", "stl"][usize::from(b % 3)],
    };
    let sandbox = sandbox();
    let _guard = lock(sandbox);
    let file = sandbox.dir.join(format!("mesh.{extension}"));
    std::fs::write(&file, rest).expect("write the mesh");
    if let Ok(mesh) = mesh_import::read_mesh(&file) {
        let n = mesh.vertices.len();
        for polygon in &mesh.polygons {
            assert!(
                polygon.len() >= 3,
                "a polygon of {} vertices",
                polygon.len()
            );
            assert!(
                polygon.iter().all(|&i| (i as usize) < n),
                "an index out of range"
            );
        }
    }
}

/// `tree_files`: the bytes as a binary tree file
/// (`RecordStream::from_bytes`) and as a text one (`from_text`). What reads
/// writes back, in both forms, to the same bits.
pub fn tree_files(data: &[u8]) {
    let file = Path::new("fuzz.out");
    if let Ok(stream) = RecordStream::from_bytes(data, file) {
        round_trip(&stream);
    }
    let text = String::from_utf8_lossy(data);
    if let Ok(stream) = RecordStream::from_text(&text, Path::new("fuzz.txt")) {
        round_trip(&stream);
    }
}

fn round_trip(stream: &RecordStream) {
    let bytes = stream.to_bytes();
    let again = RecordStream::from_bytes(&bytes, Path::new("again.out"))
        .unwrap_or_else(|e| panic!("a written tree does not read back: {e}"));
    assert_eq!(again.to_bytes(), bytes, "binary tree round trip");
    let text = stream.to_text();
    let again = RecordStream::from_text(&text, Path::new("again.txt"))
        .unwrap_or_else(|e| panic!("a written text tree does not read back: {e}"));
    assert_eq!(again.to_bytes(), bytes, "text tree round trip");
}

/// The fixed scene of the `pipeline` target: a cube on a square floor, two
/// lights, seen in perspective.
const PIPELINE_SCENE: &str = "\
perspective 45 1 0.1 100
polarview 6 30 60 0
light -4 -2 6 0.8 0.8 0.8 100 Point
light 0 -10 10 0.5 0.5 0.5 50 Diffuse
defobj square 1
  color 1 1 1
  reflectance 0.3
  scale 3 3 1
  translate 0 0 -1
endobj
defobj cube 2
  color 0 1 0
  transmittance 0.4
  index 1.3
  rotate 30 z
endobj
";

/// Numbers the overrides draw from: edges first, then ordinary values.
const NUMBERS: [&str; 32] = [
    "0", "1", "-1", "0.5", "2", "3", "-3", "90", "45", "180", "-90", "0.1", "0.01", "10", "100",
    "1e-9", "1e9", "1e308", "-1e308", "1e-320", "-0", "0.999", "1.5", "4", "6", "14", "15", "30",
    "0.25", "0.75", "360", "7",
];

/// A reader of override bytes.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }

    fn pick<'s>(&mut self, from: &[&'s str]) -> &'s str {
        from[usize::from(self.byte()) % from.len()]
    }

    /// A number: one of [`NUMBERS`], or a small fraction.
    fn number(&mut self) -> String {
        let b = self.byte();
        if b < 128 {
            NUMBERS[usize::from(b) % NUMBERS.len()].to_string()
        } else {
            format!("{}", f64::from(b as i8) / 16.0)
        }
    }

    fn numbers(&mut self, n: usize) -> String {
        (0..n).map(|_| self.number()).collect::<Vec<_>>().join(" ")
    }
}

/// The budgets of the pipeline target: statements, objects, lights,
/// geodesic divisions and recursion depth.
const MAX_STATEMENTS: usize = 24;
const MAX_OBJECTS: usize = 6;
const MAX_LIGHTS: usize = 4;
const MAX_GEODESIC: u8 = 4;
const MAX_DEPTH: u8 = 4;
const MAX_POLYGONS: usize = 2_000;
const SIZE: u32 = 32;

/// The overrides one input makes: statements in the scene language, after
/// the fixed scene.
fn overrides(bytes: &mut Bytes) -> Vec<String> {
    let mut out = Vec::new();
    let (mut objects, mut lights, mut in_object) = (2, 2, false);
    while !bytes.0.is_empty() && out.len() < MAX_STATEMENTS {
        let s = match bytes.byte() % 24 {
            0 => format!("rotate {} {}", bytes.number(), bytes.pick(&["x", "y", "z"])),
            1 => format!("translate {}", bytes.numbers(3)),
            2 => format!("scale {}", bytes.numbers(3)),
            3 => format!("color {}", bytes.numbers(3)),
            4 => format!("reflectance {}", bytes.number()),
            5 => format!("transmittance {}", bytes.number()),
            6 => format!("index {}", bytes.number()),
            7 => format!("transparency {}", bytes.numbers(2)),
            8 => format!(
                "{} {}",
                bytes.pick(&["specular", "shininess", "diffuse"]),
                bytes.number()
            ),
            9 => format!("depth {}", 1 + bytes.byte() % MAX_DEPTH),
            10 => format!("threshold {}", bytes.number()),
            11 => {
                let mode = bytes.pick(&["b", "h", "n", "s", "v", "x", "o", "p"]);
                format!("setmode {mode} {}", bytes.pick(&["on", "off"]))
            }
            12 => format!("setmode l {}", 1 + bytes.byte() % MAX_DEPTH),
            13 => format!("sort {}", bytes.pick(&["btf", "ftb"])),
            14 => format!(
                "type polygon {}",
                bytes.pick(&[
                    "",
                    "open",
                    "curved",
                    "concave",
                    "hidden",
                    "ltsrc",
                    "open curved"
                ])
            ),
            15 if lights < MAX_LIGHTS => {
                lights += 1;
                format!(
                    "light {} {} {}",
                    bytes.numbers(6),
                    bytes.number(),
                    bytes.pick(&["Point", "Diffuse"])
                )
            }
            16 if !in_object && objects < MAX_OBJECTS => {
                objects += 1;
                in_object = true;
                let name = bytes.pick(&["cube", "square", "ball"]);
                format!("defobj {name} {}", objects + 1)
            }
            17 if in_object => {
                in_object = false;
                "endobj".to_string()
            }
            18 if in_object => format!(
                "geodesic {} {}",
                1 + bytes.byte() % MAX_GEODESIC,
                bytes.pick(&["equal", "angle"])
            ),
            19 if in_object => format!(
                "radial {}",
                bytes.pick(&["sphere", "ellipsoid 1 2 3", "bumps 0.2 3", "lobes 0.3 2"])
            ),
            20 => bytes
                .pick(&["pushmatrix", "popmatrix", "ident"])
                .to_string(),
            21 => format!(
                "{} {}",
                bytes.pick(&["polarview", "lookat"]),
                bytes.numbers(4)
            ),
            22 => format!(
                "{} {}",
                bytes.pick(&["ambient", "background"]),
                bytes.numbers(3)
            ),
            23 if objects < MAX_OBJECTS => {
                objects += 1;
                format!(
                    "{} {}",
                    bytes.pick(&["callobj", "delobj"]),
                    1 + bytes.byte() % 4
                )
            }
            _ => continue,
        };
        out.push(s);
    }
    if in_object {
        out.push("endobj".to_string());
    }
    out
}

/// `pipeline`: the fixed scene plus the overrides the bytes choose, then
/// rendered at 32x32 with the options the first bytes choose (visible
/// surface algorithm, scan conversion method, shadows, shading model,
/// refraction), within the budgets above.
pub fn pipeline(data: &[u8]) {
    use plytrace::internal::image_tree::Refraction;
    use plytrace::internal::raster::scan::Method;
    use plytrace::internal::shading::ShadingModel;
    use plytrace::internal::visibility::Algorithm;

    let mut bytes = Bytes(data);
    let visibility = match bytes.byte() % 8 {
        0 => None,
        k => Some(Algorithm::ALL[usize::from(k - 1)].0),
    };
    let aa = match bytes.byte() % 8 {
        0 => None,
        1 => Some(Method::Point),
        2 => Some(Method::Area),
        3 => Some(Method::Mask),
        4 => Some(Method::Hybrid),
        5 => Some(Method::Multilevel),
        _ => Some(Method::Supersample(1 + u32::from(bytes.byte() % 4))),
    };
    let flags = bytes.byte();
    let options = RenderOptions {
        size: Some((SIZE, SIZE)),
        shadows: flags & 1 != 0,
        visibility,
        profile: flags & 2 != 0,
        refraction: [
            Refraction::Linearized,
            Refraction::Orthographic,
            Refraction::Paraxial,
        ][usize::from((flags >> 2) % 3)],
        aa,
        threads: 1,
        shading: if flags & 16 != 0 {
            ShadingModel::Donovan
        } else {
            ShadingModel::Garcia
        },
        // Small budgets: the whole pipeline under its limits.
        budgets: plytrace::internal::budget::Budgets {
            polygons: 20_000,
            call_depth: 8,
            tree_nodes: 20_000,
            splits: 2_000,
            pixels: 1 << 20,
            frame_memory: 1 << 26,
            overdraw: 64,
            pair_tests: 1_000_000,
            model_memory: 1 << 26,
            rays: 1_000_000,
            samples: 1 << 26,
            window_tests: 1 << 24,
            ray_tests: 1 << 24,
        },
    };
    let statements = overrides(&mut bytes);

    let sandbox = sandbox();
    let mut interp = Interpreter::new();
    interp.set_budgets(options.budgets);
    let file = sandbox.dir.join("pipeline.des");
    // The fixed scene must load; each override may fail on its own.
    interp
        .execute_source(PIPELINE_SCENE, &file, &sandbox.dir, &mut NoHost)
        .expect("the fixed scene loads");
    for s in &statements {
        if let Err(e) = interp.execute_source(s, &file, &sandbox.dir, &mut NoHost) {
            check_error(&e);
        }
    }
    let mut scene = interp.scene();
    if scene.polygon_count() > MAX_POLYGONS || scene.lights.len() > MAX_LIGHTS {
        return;
    }
    scene.viewport = plytrace::internal::model::Viewport::of_size(SIZE, SIZE);
    match render(&scene, &options) {
        Ok(r) => {
            assert_eq!((r.frame.width, r.frame.height), (SIZE, SIZE), "image size");
            for y in 0..SIZE {
                for x in 0..SIZE {
                    if let Some((o, p)) = r.polygon_at(x, y) {
                        let object = &scene.objects[o as usize];
                        // `setmode p` paints each object's bounding box:
                        // ids name the box's six faces.
                        let faces = if scene.modes.boxes_only {
                            6
                        } else {
                            object.polygons.len()
                        };
                        assert!((p as usize) < faces, "painted id");
                    }
                }
            }
            if let Some(tree) = &r.tree {
                round_trip(tree);
            }
        }
        Err(e) => check_error(&e),
    }
}

/// `pixel_structs`: the bytes as an rftb4 pixel-struct file and its
/// fragment side file (`read_pixel_structs`, and `visit_pixel_structs` as
/// getrgb calls it). The first byte chooses: even, no side file; odd, the
/// next two bytes (little-endian) are the length of the pixel-struct file
/// and the rest is the side file. What reads has as many pixels as the
/// file has structs and the resolution of the side file, each list
/// decodes to its fragments, and the two readers agree.
pub fn pixel_structs(data: &[u8]) {
    use plytrace::internal::output::{
        FRAGMENT_BYTES, PIXEL_STRUCT_BYTES, read_pixel_structs, visit_pixel_structs,
    };
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let (bytes, side) = if first % 2 == 0 || rest.len() < 2 {
        (rest, None)
    } else {
        let len = usize::from(u16::from_le_bytes([rest[0], rest[1]]));
        let rest = &rest[2..];
        let cut = len.min(rest.len());
        (&rest[..cut], Some(&rest[cut..]))
    };
    let path = Path::new("fuzz.ps");
    let side_path = Path::new("fuzz.ps.frag");
    let side = side.map(|s| (s, side_path));
    let read = read_pixel_structs(bytes, path, side);
    let mut visited = Vec::new();
    let visit = visit_pixel_structs(bytes, path, side, |p| {
        assert_eq!(p.index, visited.len(), "pixels in order");
        assert_eq!(p.fragments.len() % FRAGMENT_BYTES, 0, "whole fragments");
        visited.push((p.rgb, p.pixstat, p.fragments.len() / FRAGMENT_BYTES));
        Ok(())
    });
    match (read, visit) {
        (Ok(read), Ok(resolution)) => {
            assert_eq!(read.resolution, resolution, "the readers' resolutions");
            assert_eq!(read.pixels.len(), bytes.len() / PIXEL_STRUCT_BYTES);
            if let Some((w, h)) = resolution {
                assert_eq!(u64::from(w) * u64::from(h), read.pixels.len() as u64);
            }
            assert_eq!(read.pixels.len(), visited.len(), "the readers' pixels");
            for (p, v) in read.pixels.iter().zip(&visited) {
                assert_eq!((p.rgb, p.pixstat, p.fragments.len()), *v);
                assert!(side.is_some() || p.fragments.is_empty());
            }
        }
        (Err(a), Err(b)) => {
            check_error(&a);
            assert_eq!(a.to_string(), b.to_string(), "the readers' errors");
        }
        (a, b) => panic!("the readers disagree: {:?} and {:?}", a.err(), b.err()),
    }
}

/// `rftb_args`: the bytes as a command line (arguments split at NUL
/// bytes, invalid UTF-8 kept as it is on Unix) for rftbN's and getrgb's
/// parsers, and what parses through the checks that need no file (the
/// budgets, the output names, the file size limit). Nothing is read or
/// written; the checks must not panic whatever the numbers.
pub fn rftb_args(data: &[u8]) {
    use plytrace::internal::rftb::{self, Command, Program};
    use std::ffi::OsString;
    use std::os::unix::ffi::OsStringExt;
    let argv: Vec<OsString> = data
        .split(|&b| b == 0)
        .map(|a| OsString::from_vec(a.to_vec()))
        .collect();
    let sandbox = sandbox();
    let log = sandbox.dir.join("rftb.log");
    for program in [
        Program::Rftb1,
        Program::Rftb2,
        Program::Rftb3,
        Program::Rftb4,
    ] {
        match rftb::parse_args(argv.clone()) {
            Ok(Command::Run(args)) => {
                assert!(args.hres >= 1 && args.vres >= 1 && args.act_lines >= 1);
                assert!(args.debug <= 9);
                let _ = rftb::check_budgets(program, &args);
                let _ = rftb::band_memory(program, &args);
                let outputs = rftb::output_paths(program, &args);
                assert!(!outputs.is_empty());
                let _ = rftb::check_names(std::slice::from_ref(&args.input), &outputs, &log);
                let _ = program.usage();
            }
            Ok(Command::Help) => {}
            Err(rftb::UsageError(msg)) => assert!(!msg.is_empty()),
        }
    }
    match rftb::parse_getrgb_args(argv) {
        Ok(Command::Run(args)) => {
            if let Some((w, h)) = args.resolution {
                assert!(w >= 1 && h >= 1);
                let _ = rftb::check_pixels(w, h, &args.budgets);
            }
            let _ = rftb::check_names(
                &rftb::getrgb_inputs(&args),
                &rftb::getrgb_outputs(&args),
                &log,
            );
        }
        Ok(Command::Help) => {}
        Err(rftb::UsageError(msg)) => assert!(!msg.is_empty()),
    }
}

/// The budget of the `patch_files` target: triangles of one tessellation.
const PATCH_TRIANGLES: usize = 4_000;
/// Edge pairs the continuity check of `patch_files` may compare.
const PATCH_PAIRS: u64 = 10_000;

/// `patch_files`: the bytes after the first as a patch file
/// (`modeling::patch::parse`); the first byte chooses the form (bit 0:
/// Bezier, else Hermite) and the steps `NU` (3-6) and `NV` (2-5), the
/// smallest the scene language accepts upwards. What reads within a budget
/// of [`PATCH_TRIANGLES`] is tessellated, and its continuity checked within
/// [`PATCH_PAIRS`] edge pairs: every triangle names three distinct
/// vertices, there is a unit normal per vertex, and every join names two
/// patches of the file.
pub fn patch_files(data: &[u8]) {
    use plytrace::internal::modeling::patch::{self, Form};
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let form = if first & 1 == 0 {
        Form::Bezier
    } else {
        Form::Hermite
    };
    let nu = 3 + usize::from((first >> 1) & 3);
    let nv = 2 + usize::from((first >> 3) & 3);
    let text = String::from_utf8_lossy(rest);
    let path = Path::new("fuzz.bpt");
    let refused = std::cell::Cell::new(false);
    let read = patch::parse(&text, path, form, |count| {
        match patch::face_count(count, nu, nv) {
            Some(n) if n <= PATCH_TRIANGLES => Ok(()),
            _ => {
                refused.set(true);
                Err(plytrace::Error::at(
                    plytrace::internal::error::Location::file(path),
                    "over the fuzz budget",
                ))
            }
        }
    });
    let set = match read {
        Ok(set) => set,
        Err(e) => {
            check_error(&e);
            return;
        }
    };
    assert!(!refused.get(), "a refused patch count still read");
    assert!(!set.patches.is_empty(), "a patch file of no patches");
    let generated = patch::tessellate(&set, nu, nv);
    let mesh = &generated.mesh;
    let n = mesh.vertices.len();
    assert!(
        mesh.polygons.len() <= patch::face_count(set.patches.len(), nu, nv).unwrap(),
        "more triangles than the count the budget was asked for"
    );
    for t in &mesh.polygons {
        assert_eq!(t.len(), 3, "a tessellation polygon of {} corners", t.len());
        assert!(t.iter().all(|&i| (i as usize) < n), "an index out of range");
        assert!(
            t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
            "a repeated corner"
        );
    }
    let normals = generated.normals.as_ref().expect("patches carry normals");
    assert_eq!(normals.len(), n, "one normal per vertex");
    for v in normals {
        assert!(
            !v.is_finite() || (v.length() - 1.0).abs() < 1e-6,
            "a finite normal not of unit length: {v}"
        );
    }
    match patch::continuity_within(&set, PATCH_PAIRS) {
        Ok(report) => {
            for j in &report.joins {
                assert!(j.patches.0 < j.patches.1 && j.patches.1 < set.patches.len());
            }
        }
        Err(patch::ContinuityStop::Pairs(p)) => assert!(p > PATCH_PAIRS),
        Err(patch::ContinuityStop::Cancelled) => panic!("cancelled with no request"),
    }
}

/// The fixed scene of the `modeling` target: a light and a camera; the
/// objects are all the fuzzer's.
const MODELING_SCENE: &str = "\
perspective 45 1 0.1 100
polarview 8 30 60 0
light -4 -2 6 0.8 0.8 0.8 100 Point
";

/// The object names of the `modeling` target: generated objects, CSG
/// operands, and `cube`/`square` (read from `det/` when no generator is
/// given).
const MODEL_NAMES: [&str; 6] = ["a", "b", "c", "d", "cube", "square"];

/// The budgets of the `modeling` target: statements, polygons (the scene's
/// budget, checked before anything is built), CSG pair tests, image size.
const MODEL_STATEMENTS: usize = 24;
const MODEL_POLYGONS: usize = 3_000;
const MODEL_PAIR_TESTS: u64 = 100_000;
const MODEL_SIZE: u32 = 16;

impl Bytes<'_> {
    /// A whole number in `lo..=hi`.
    fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + u32::from(self.byte()) % (hi - lo + 1)
    }

    /// `k` coordinate pairs, `k` in `lo..=hi`.
    fn pairs(&mut self, lo: u32, hi: u32) -> String {
        let k = self.int(lo, hi) as usize;
        self.numbers(2 * k)
    }
}

/// The statements one `modeling` input makes: objects built by the
/// generator commands (and `geodesic`), patches from `det/` or from a
/// patch file of the fuzzer's numbers, CSG of earlier objects, transforms
/// and surface commands in and between them. Returns the statements and
/// the patch file text, if one is used.
fn modeling_statements(bytes: &mut Bytes) -> (Vec<String>, Option<String>) {
    let mut out = Vec::new();
    let mut patch_file = None;
    let mut in_object = false;
    while !bytes.0.is_empty() && out.len() < MODEL_STATEMENTS {
        let s = match bytes.byte() % 20 {
            0 => format!("translate {}", bytes.numbers(3)),
            1 => format!("rotate {} {}", bytes.number(), bytes.pick(&["x", "y", "z"])),
            2 => format!("scale {}", bytes.numbers(3)),
            3 => bytes
                .pick(&["pushmatrix", "popmatrix", "ident"])
                .to_string(),
            4 => format!("color {}", bytes.numbers(3)),
            5 if !in_object => {
                in_object = true;
                format!("defobj {}", bytes.pick(&MODEL_NAMES))
            }
            6 if in_object => {
                in_object = false;
                "endobj".to_string()
            }
            7 if in_object => format!("sphere {} {}", bytes.int(3, 8), bytes.int(2, 5)),
            8 if in_object => format!(
                "cylinder {} {}",
                bytes.int(3, 12),
                bytes.pick(&["", "capped", "open"])
            ),
            9 if in_object => {
                let scale = if bytes.byte() & 1 == 0 {
                    String::new()
                } else {
                    bytes.numbers(3)
                };
                format!(
                    "superquadric {} {} {} {scale}",
                    bytes.numbers(2),
                    bytes.int(3, 8),
                    bytes.int(2, 5)
                )
            }
            10 if in_object => format!("lathe {} {}", bytes.int(3, 8), bytes.pairs(2, 6)),
            11 if in_object => format!("extrude {} {}", bytes.number(), bytes.pairs(3, 8)),
            12 if in_object => format!(
                "geodesic {} {}",
                bytes.int(1, 2),
                bytes.pick(&["equal", "angle"])
            ),
            13 if in_object => format!(
                "radial {}",
                bytes.pick(&[
                    "sphere",
                    "ellipsoid 1 2 3",
                    "bumps 0.2 3",
                    "lobes 0.3 2",
                    "rotate 30 x"
                ])
            ),
            14 if in_object => format!(
                "{} {} {}",
                bytes.pick(&["bezier wave.bpt", "hermite ripple.hpt"]),
                bytes.int(3, 4),
                bytes.int(2, 3)
            ),
            15 if in_object => {
                // One patch of the fuzzer's control points (Bezier) or
                // geometry matrix (Hermite).
                let bezier = bytes.byte() & 1 == 0;
                let points = bytes.numbers(48);
                patch_file = Some(if bezier {
                    format!("1\n3 3\n{points}\n")
                } else {
                    format!("1\n{points}\n")
                });
                let (form, file) = if bezier {
                    ("bezier", "fuzz.bpt")
                } else {
                    ("hermite", "fuzz.hpt")
                };
                // Both names hold the same text: whichever is asked for.
                format!("{form} {file} {} {}", bytes.int(3, 4), bytes.int(2, 3))
            }
            16 | 17 if in_object => format!(
                "{} {} {}",
                bytes.pick(&["union", "intersection", "difference"]),
                bytes.pick(&MODEL_NAMES),
                bytes.pick(&MODEL_NAMES)
            ),
            18 => format!(
                "type polygon {}",
                bytes.pick(&["", "open", "curved", "concave", "open curved"])
            ),
            19 => format!(
                "{} {}",
                bytes.pick(&["reflectance", "transmittance", "specular"]),
                bytes.number()
            ),
            _ => continue,
        };
        out.push(s);
    }
    if in_object {
        out.push("endobj".to_string());
    }
    (out, patch_file)
}

/// `modeling`: the fixed scene plus the modeling statements the bytes
/// choose (the first byte: whether to render, when it is 1 modulo 4),
/// built within small budgets
/// ([`MODEL_POLYGONS`] polygons, [`MODEL_PAIR_TESTS`] CSG pair tests),
/// then, when asked, rendered at 16x16. Every object has its polygons'
/// vertices and one normal per vertex when it has normals; the scene is
/// within the polygon budget; the image has the size asked.
pub fn modeling(data: &[u8]) {
    let mut bytes = Bytes(data);
    // One input in four is rendered: the building is this target's aim
    // (`pipeline` renders), and a render costs as much as the rest.
    let render_it = bytes.byte() & 3 == 1;
    let (statements, patch_text) = modeling_statements(&mut bytes);
    let budgets = plytrace::internal::budget::Budgets {
        polygons: MODEL_POLYGONS,
        call_depth: 8,
        tree_nodes: 20_000,
        splits: 2_000,
        pixels: 1 << 16,
        frame_memory: 1 << 24,
        overdraw: 64,
        pair_tests: MODEL_PAIR_TESTS,
        model_memory: 1 << 24,
        rays: 100_000,
        samples: 1 << 22,
        window_tests: 1 << 20,
        ray_tests: 1 << 20,
    };
    let sandbox = sandbox();
    let _guard = lock(sandbox);
    if let Some(text) = patch_text {
        // Written when it changes: most inputs reuse the last one's.
        static WRITTEN: Mutex<String> = Mutex::new(String::new());
        let mut written = WRITTEN.lock().unwrap_or_else(|e| e.into_inner());
        if *written != text {
            for name in ["fuzz.bpt", "fuzz.hpt"] {
                std::fs::write(sandbox.dir.join("det").join(name), &text).expect("write the patch");
            }
            *written = text;
        }
    }
    let mut interp = Interpreter::new();
    interp.set_budgets(budgets);
    let file = sandbox.dir.join("modeling.des");
    interp
        .execute_source(MODELING_SCENE, &file, &sandbox.dir, &mut NoHost)
        .expect("the fixed scene loads");
    for s in &statements {
        if let Err(e) = interp.execute_source(s, &file, &sandbox.dir, &mut NoHost) {
            check_error(&e);
        }
    }
    let mut scene = interp.scene();
    assert!(
        scene.polygon_count() <= MODEL_POLYGONS,
        "{} polygons, over the budget of {MODEL_POLYGONS}",
        scene.polygon_count()
    );
    for o in &scene.objects {
        let n = o.vertices.len();
        for p in &o.polygons {
            assert!(
                p.indices.iter().all(|&i| (i as usize) < n),
                "an index out of range"
            );
        }
        if let Some(normals) = &o.vertex_normals {
            assert_eq!(normals.len(), n, "one normal per vertex");
        }
    }
    if !render_it {
        return;
    }
    scene.viewport = plytrace::internal::model::Viewport::of_size(MODEL_SIZE, MODEL_SIZE);
    let options = RenderOptions {
        size: Some((MODEL_SIZE, MODEL_SIZE)),
        threads: 1,
        budgets,
        ..RenderOptions::default()
    };
    match render(&scene, &options) {
        Ok(r) => assert_eq!(
            (r.frame.width, r.frame.height),
            (MODEL_SIZE, MODEL_SIZE),
            "image size"
        ),
        Err(e) => check_error(&e),
    }
}

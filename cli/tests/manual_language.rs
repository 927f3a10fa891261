//! The plytrace manual page (Garcia 1986, 004 appendix B) and Donovan's
//! shader (000 section 6), checked where the implementation had drifted
//! from them: Donovan's transparency rule under every scan conversion
//! method, immediate mode without shadows for every visibility algorithm,
//! the simple depth sort's keys, command abbreviations, a bare `setmode`,
//! lower-case file names, quiet CSG and the default refraction.

#[path = "../../tests/support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};

use plytrace::internal::raster::scan::Method;
use plytrace::internal::raytrace::{self, RayTraceOptions};
use plytrace::internal::render::{RenderOptions, chosen_algorithm, render};
use plytrace::internal::scene::Scene;
use plytrace::internal::shading::ShadingModel;

const BIN: &str = env!("CARGO_BIN_EXE_plytrace");

fn data(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("tests/data/manual")
        .join(name)
}

fn load(path: &Path) -> Scene {
    plytrace::internal::scene::load(path).unwrap().0
}

/// The largest per-channel difference between two frames, and how many
/// pixels differ by more than `tolerance`.
fn difference(a: &[[f32; 3]], b: &[[f32; 3]], tolerance: f32) -> (f32, usize) {
    assert_eq!(a.len(), b.len());
    let mut worst = 0.0f32;
    let mut over = 0;
    for (p, q) in a.iter().zip(b) {
        let d = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f32::max);
        worst = worst.max(d);
        if d > tolerance {
            over += 1;
        }
    }
    (worst, over)
}

// ---------------------------------------------------------------------
// 1. Donovan's shading for every scan conversion method.
// ---------------------------------------------------------------------

/// Donovan 000 section 6: "the face transparency is computed at every
/// sample point by comparing the intensity given by (1) and (2) above
/// (I_a) with the intensity at that point already in the frame buffer
/// (I_b). ... I = I_a if I_a > I_b, I = (1-w)I_a + wI_b otherwise."
///
/// The glass scene (a dark pane of transparency 0.5 before the manual's
/// cut cube, shadows on) is rendered by the tree under every method and
/// compared with the ray tracer's Donovan render at the same sample
/// positions: one ray per pixel for point sampling, 4 x 4 rays for the
/// methods that paint the 16 samples of the 4 x 4 pixel mask, N x N rays
/// for `--supersample N`. Tolerance 2/255 per channel, every pixel: the
/// tree hands its shades downstream as bytes (each rounded by up to 1/2 of
/// 1/255) and a pane pixel blends two of them; the samples are the same
/// points, so edges need no allowance.
#[test]
fn donovan_transparency_under_every_method_matches_the_ray_tracer() {
    let scene = load(&data("glass.des"));
    let traced = |n: u32| {
        raytrace::render(
            &scene,
            &RayTraceOptions {
                samples: n,
                shadows: true,
                shading: ShadingModel::Donovan,
                ..RayTraceOptions::default()
            },
        )
        .unwrap()
        .0
        .color
    };
    let tree = |aa: Method, shading: ShadingModel| {
        render(
            &scene,
            &RenderOptions {
                shadows: true,
                aa: Some(aa),
                shading,
                ..RenderOptions::default()
            },
        )
        .unwrap_or_else(|e| panic!("{aa:?}: {e}"))
        .frame
        .color
    };
    let (one, sixteen, nine) = (traced(1), traced(4), traced(3));
    let tolerance = 2.0 / 255.0;
    for (aa, reference) in [
        (Method::Point, &one),
        (Method::Supersample(1), &one),
        (Method::Area, &sixteen),
        (Method::Mask, &sixteen),
        (Method::Hybrid, &sixteen),
        (Method::Multilevel, &sixteen),
        (Method::Supersample(4), &sixteen),
        (Method::Supersample(3), &nine),
    ] {
        let got = tree(aa, ShadingModel::Donovan);
        let (worst, over) = difference(&got, reference, tolerance);
        assert_eq!(
            over,
            0,
            "{aa:?}: {over} pixels differ from the ray tracer by more than 2/255 (worst {:.1}/255)",
            worst * 255.0
        );
    }
    // The scene does exercise rule (3): Garcia's additive rule
    // (I_a + k_t I_b, 004 section 4.9) gives another picture behind the
    // pane.
    let garcia = tree(Method::Point, ShadingModel::Garcia);
    let (_, changed) = difference(&garcia, &one, 0.1);
    assert!(changed > 500, "only {changed} pixels show rule (3)");
}

// ---------------------------------------------------------------------
// 4. Abbreviations: the manual's commands win.
// ---------------------------------------------------------------------

use plytrace::internal::scene::commands::{self, ADDED, Lookup, MANUAL};

fn resolves_to(word: &str) -> Option<&'static str> {
    match commands::lookup(word) {
        Lookup::Found(c) => Some(c.name),
        _ => None,
    }
}

/// 004 appendix B: "commands are recognized by the first sequence of
/// unique characters". The manual's commands are recognized by their
/// prefixes unique among the manual's commands, whatever commands were
/// added since (`b` is `background` though `bezier` starts with it).
#[test]
fn every_unique_prefix_of_a_manual_command_resolves_to_it() {
    let mut checked = 0;
    for name in MANUAL {
        for k in 1..=name.len() {
            let prefix = &name[..k];
            let among: Vec<&&str> = MANUAL.iter().filter(|m| m.starts_with(prefix)).collect();
            if MANUAL.contains(&prefix) {
                // An exact name wins (`call` versus `callobj`).
                assert_eq!(resolves_to(prefix), Some(prefix), "`{prefix}`");
            } else if among.len() == 1 {
                assert_eq!(resolves_to(prefix), Some(*name), "`{prefix}`");
                assert_eq!(resolves_to(&prefix.to_uppercase()), Some(*name));
                checked += 1;
            } else {
                assert!(
                    matches!(commands::lookup(prefix), Lookup::Ambiguous(_)),
                    "`{prefix}` names several manual commands"
                );
            }
        }
    }
    assert!(checked > 190, "{checked}");
    // The abbreviations that the modeling commands had made ambiguous.
    for (word, name) in [
        ("b", "background"),
        ("dif", "diffuse"),
        ("sp", "specular"),
        ("e", "endobj"),
    ] {
        assert_eq!(resolves_to(word), Some(name), "`{word}`");
    }
}

/// The added (modeling) commands keep every prefix that no manual command
/// claims and that is unique among the added ones; a prefix a manual
/// command claims is that command's (or ambiguous among the manual's).
#[test]
fn added_commands_keep_the_prefixes_no_manual_command_claims() {
    let mut kept = 0;
    for name in ADDED {
        for k in 1..=name.len() {
            let prefix = &name[..k];
            let manual: Vec<&&str> = MANUAL.iter().filter(|m| m.starts_with(prefix)).collect();
            let added: Vec<&&str> = ADDED.iter().filter(|m| m.starts_with(prefix)).collect();
            let got = resolves_to(prefix);
            if prefix == *name {
                assert_eq!(got, Some(*name));
                kept += 1;
            } else if manual.len() == 1 {
                assert_eq!(got, Some(*manual[0]), "`{prefix}`");
            } else if manual.is_empty() && added.len() == 1 {
                assert_eq!(got, Some(*name), "`{prefix}`");
                kept += 1;
            } else {
                assert_eq!(got, None, "`{prefix}` is ambiguous");
            }
        }
    }
    assert!(kept > 40, "{kept}");
    for (word, name) in [
        ("be", "bezier"),
        ("sph", "sphere"),
        ("ex", "extrude"),
        ("diffe", "difference"),
        ("int", "intersection"),
        ("u", "union"),
    ] {
        assert_eq!(resolves_to(word), Some(name), "`{word}`");
    }
}

/// The interpreter uses the same resolution: `b` sets the background.
#[test]
fn an_abbreviated_scene_is_interpreted() {
    let mut interp = plytrace::internal::scene::Interpreter::new();
    interp
        .execute_source(
            "B 0.25 0.5 1\ndif 0.3\nsp 0.2\n",
            Path::new("abbreviations.des"),
            Path::new("."),
            &mut plytrace::internal::scene::NoHost,
        )
        .unwrap();
    let scene = interp.scene();
    assert_eq!(scene.background.to_array(), [0.25, 0.5, 1.0]);
    let g = interp.global_surface();
    assert_eq!((g.diffuse, g.specular), (0.3, 0.2));
}

// ---------------------------------------------------------------------
// 5. `setmode <mode> [<on, off>]`: the value is optional.
// ---------------------------------------------------------------------

fn run_source(
    interp: &mut plytrace::internal::scene::Interpreter,
    source: &str,
) -> plytrace::Result<()> {
    interp
        .execute_source(
            source,
            Path::new("modes.des"),
            Path::new("."),
            &mut plytrace::internal::scene::NoHost,
        )
        .map(|_| ())
}

/// 004 appendix B: "setmode <mode> [<on, off>]" (the value in brackets,
/// optional) and "For all parameters having an on/off condition, the
/// default value is off". A mode is off until set, so the bare form sets
/// it on (as `disp <[(on), off]>` marks on for its bare form, and as the
/// command line's `-i` is a bare flag).
#[test]
fn a_bare_setmode_turns_the_mode_on() {
    let mut interp = plytrace::internal::scene::Interpreter::new();
    assert!(!interp.scene().modes.vertex_shades);
    run_source(&mut interp, "setmode v\nsetmode X\n").unwrap();
    let modes = interp.scene().modes;
    assert!(modes.vertex_shades && modes.expand);
    run_source(&mut interp, "setmode v off\n").unwrap();
    assert!(!interp.scene().modes.vertex_shades);
}

/// The command line's flags go through `Interpreter::force_mode`; an empty
/// value is the bare flag (`-v` alone), on, and it overrides the scene.
#[test]
fn force_mode_takes_an_empty_value_as_the_bare_flag() {
    let mut interp = plytrace::internal::scene::Interpreter::new();
    interp.force_mode('v', "").unwrap();
    interp.force_mode('n', " ").unwrap();
    assert!(interp.scene().modes.vertex_shades && interp.scene().modes.nns);
    run_source(&mut interp, "setmode v off\nsetmode n off\n").unwrap();
    assert!(interp.scene().modes.vertex_shades && interp.scene().modes.nns);
    // Modes with a number still need it: an error, not a panic.
    let e = interp.force_mode('l', "").unwrap_err().to_string();
    assert!(e.contains("needs a value"), "{e}");
    interp.force_mode('l', "3").unwrap();
    assert_eq!(interp.scene().modes.max_level, 3);
}

// ---------------------------------------------------------------------
// 6. File names: as written, then folded to lower case.
// ---------------------------------------------------------------------

/// A folder with the manual's `ccube.des` and its objects, plus a
/// mixed-case scene and object that exist only as written.
fn ccube_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let examples = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("examples");
    std::fs::create_dir(dir.path().join("det")).unwrap();
    for f in ["cube.det", "cutcube.det"] {
        std::fs::copy(examples.join("det").join(f), dir.path().join("det").join(f)).unwrap();
    }
    std::fs::copy(
        examples.join("det/cube.det"),
        dir.path().join("det/Block.det"),
    )
    .unwrap();
    std::fs::copy(examples.join("ccube.des"), dir.path().join("ccube.des")).unwrap();
    std::fs::write(dir.path().join("Mixed.des"), "getobj Block\n").unwrap();
    std::fs::write(
        dir.path().join("det/cube.pcl"),
        format!("title red cube\ndata 6\n{}", "1 0 0 .5 0 0\n".repeat(6)),
    )
    .unwrap();
    dir
}

fn objects_after(dir: &Path, source: &str) -> plytrace::Result<Scene> {
    let mut interp = plytrace::internal::scene::Interpreter::new();
    interp.execute_source(
        source,
        &dir.join("top.des"),
        dir,
        &mut plytrace::internal::scene::NoHost,
    )?;
    Ok(interp.into_scene())
}

/// 004 appendix B: "Note that all input characters are converted to lower
/// case before processing". Names are tried as written first (a
/// mixed-case file that exists opens), then folded to lower case, for
/// `get`/`call`, `getobj` (the detail directory and the object file),
/// `pcolors`, and the scene file given to `execute_file` (`-f`).
#[test]
fn file_names_fall_back_to_lower_case() {
    let folder = ccube_folder();
    let dir = folder.path();
    // Upper case, existing only in lower case.
    let scene = objects_after(dir, "GET CCUBE.DES\n").unwrap();
    assert_eq!(scene.objects.len(), 2);
    let scene = objects_after(dir, "CALL CCUBE.DES\n").unwrap();
    assert_eq!(scene.objects.len(), 2);
    let scene = objects_after(dir, "DET_DIR DET\nGETOBJ CUBE\n").unwrap();
    assert_eq!(scene.objects.len(), 1);
    let scene = objects_after(dir, "DEFOBJ CUBE\nPCOLORS CUBE\nENDOBJ\n").unwrap();
    assert_eq!(scene.objects.len(), 1);
    let mut interp = plytrace::internal::scene::Interpreter::new();
    interp
        .execute_file(
            &dir.join("CCUBE.DES"),
            true,
            &mut plytrace::internal::scene::NoHost,
        )
        .unwrap();
    assert_eq!(interp.into_scene().objects.len(), 2);
    // Mixed case, existing as written.
    let scene = objects_after(dir, "get Mixed.des\n").unwrap();
    assert_eq!(scene.objects.len(), 1);
    // A name that exists neither way is still an error naming it.
    let e = objects_after(dir, "get NONE.des\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("NONE.des"), "{e}");
}

/// The command line: `plytrace -i -f DIR/CCUBE.DES` renders `ccube.des`.
#[test]
fn immediate_mode_opens_an_upper_case_scene_name() {
    let folder = ccube_folder();
    let out = folder.path().join("out.ppm");
    let status = std::process::Command::new(BIN)
        .current_dir(folder.path())
        .args(["--quiet", "-i", "-f", "CCUBE.DES", "--size", "32x32", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    assert!(out.is_file());
}

// ---------------------------------------------------------------------
// 7. A successful CSG is not a warning.
// ---------------------------------------------------------------------

/// The bundled modeling example builds four CSG solids, all closed: no
/// warning (and nothing labelled `warning:` on the command line); their
/// face counts are notes. A real problem (operands whose surfaces differ,
/// so one is lost) still warns.
#[test]
fn a_successful_csg_is_silent() {
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("examples/primitives.des");
    let (_, warnings, notes) = plytrace::internal::scene::load_with_notes(&path).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let csg = notes
        .iter()
        .filter(|n| n.message.contains("input faces kept"))
        .count();
    assert_eq!(csg, 4, "{notes:?}");
    assert!(notes.iter().all(|n| !n.message.contains("warning")));
    // The binary prints no `warning:` for it.
    let out = std::process::Command::new(BIN)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args([
            "--quiet",
            "-i",
            "-f",
            "examples/primitives.des",
            "--size",
            "32x24",
        ])
        .arg("-o")
        .arg(tempfile::tempdir().unwrap().path().join("p.ppm"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");

    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("csg.des");
    std::fs::write(
        &scene,
        "pushmatrix\nident\ndefobj a\nextrude 1 0 0 1 0 1 1 0 1\nendobj\n\
         defobj b\nspecular 0.5\ntranslate 0.5 0.5 0.5\nsphere 8 4\nendobj\n\
         defobj r\nunion a b\nendobj\n",
    )
    .unwrap();
    let (_, warnings, _) = plytrace::internal::scene::load_with_notes(&scene).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.message.contains("operands differ")),
        "{warnings:?}"
    );
}

// ---------------------------------------------------------------------
// 3. The simple depth sort's keys.
// ---------------------------------------------------------------------

use plytrace::internal::model::SortOrder;
use plytrace::internal::visibility::Algorithm;

fn ids_with(scene: &Scene, algorithm: Algorithm) -> Vec<Option<(u32, u32)>> {
    let r = render(
        scene,
        &RenderOptions {
            visibility: Some(algorithm),
            aa: Some(Method::Point),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    support::painted_ids(&r)
}

/// 004 section 4.4's simple sort, and the two orders of `sort btf|ftb`.
///
/// Worked by hand (tests/data/manual/floor.des): depths along the line of
/// sight are 2.54 to 9.46 for the floor and 6.68 to 8.42 for the quad
/// under it. The simple sort paints by the farthest vertex: the floor
/// (9.46) before the quad (8.42), which then shows through, its known
/// failure. Front to back is the same order reversed, so it fails the
/// same way: both orders give one picture. The default sort (NNS) gets the
/// ray caster's picture in both orders.
#[test]
fn both_orders_give_one_picture_of_a_quad_under_a_floor() {
    let mut scene = load(&data("floor.des"));
    let (w, h) = (scene.viewport.width(), scene.viewport.height());
    let cast = ids_with(&scene, Algorithm::RayCast);
    assert!(
        cast.iter().flatten().all(|&(o, _)| o == 0),
        "the quad is hidden"
    );
    assert!(cast.iter().flatten().count() > 1000);
    let mut simple = Vec::new();
    for order in [SortOrder::FrontToBack, SortOrder::BackToFront] {
        scene.sort_order = order;
        let chosen = chosen_algorithm(&scene, &RenderOptions::default());
        assert_eq!(chosen, Algorithm::Nns, "the default sort");
        let ids = ids_with(&scene, chosen);
        let (checked, bad) = support::mismatches(&cast, &ids, w, h);
        assert!(checked > 3000, "{checked}");
        assert_eq!(bad.len(), 0, "{order:?}: {} pixels differ", bad.len());
        simple.push(ids_with(&scene, Algorithm::DepthSort));
    }
    assert!(
        simple[0] == simple[1],
        "the simple sort's two orders differ"
    );
    let quad = simple[0].iter().flatten().filter(|&&(o, _)| o == 1).count();
    assert!(
        quad > 100,
        "the simple sort paints the quad over the floor: {quad}"
    );
}

// ---------------------------------------------------------------------
// 2. Immediate mode without shadows, every visibility algorithm.
// ---------------------------------------------------------------------

fn bundled(name: &str) -> PathBuf {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let examples = root.join("examples").join(name);
    if examples.is_file() {
        examples
    } else {
        support::scene_fixture(name)
    }
}

/// The bundled scenes with no mirror, glass, transparency or smoothly
/// shaded polygon (checked below from the scene model).
const PLAIN: &[&str] = &[
    "ccube.des",
    "primitives.des",
    "spin.des",
    "cycles.des",
    "intersect.des",
];

/// The bundled scenes that need the virtual image tree, and an object
/// (with what about it) that needs it.
const TREE: &[(&str, &str, &str)] = &[
    ("mirror.des", "cube` (#0) with reflectance 0.5", "mirrors"),
    (
        "underwater.des",
        "square` (#11) with reflectance 0.1 and transmittance 0.8",
        "depth 2",
    ),
    (
        "office1.des",
        "champagne` (#87) with transparency 0.75",
        "transparency",
    ),
];

fn plain(scene: &Scene) -> bool {
    !scene.modes.vertex_shades
        && !scene.modes.phong
        && scene.objects.iter().all(|o| {
            o.surface.transparency.0 == 0.0
                && (scene.modes.max_level == 1
                    || (0..o.polygons.len()).all(|p| {
                        let m = o.material(p);
                        m.reflectance == 0.0 && m.transmittance == 0.0
                    }))
        })
}

/// 004 appendix B: "run <[y]> ... the optional parameter, y, indicating
/// that shadow polygons are to be computed and displayed (normally not
/// computed)". Without shadows, level 1 of a scene with no mirror, glass
/// or smooth shading is all there is to paint, and every algorithm paints
/// it; the image-space ones agree with ray casting away from edges.
#[test]
fn without_shadows_every_algorithm_renders_the_plain_bundled_scenes() {
    for name in PLAIN {
        let scene = load(&bundled(name));
        assert!(plain(&scene), "{name} is plain");
        let size = (48, 48);
        let cast = render(
            &scene,
            &RenderOptions {
                size: Some(size),
                visibility: Some(Algorithm::RayCast),
                ..RenderOptions::default()
            },
        )
        .unwrap_or_else(|e| panic!("{name} ray-cast: {e}"));
        let cast = support::painted_ids(&cast);
        for (algorithm, label) in Algorithm::ALL {
            let r = render(
                &scene,
                &RenderOptions {
                    size: Some(size),
                    shadows: false,
                    visibility: Some(algorithm),
                    ..RenderOptions::default()
                },
            )
            .unwrap_or_else(|e| panic!("{name} --visibility {label}: {e}"));
            assert!(r.frame.width == 48 || r.frame.width == 0);
            if matches!(
                algorithm,
                Algorithm::ZBuffer | Algorithm::ScanLine | Algorithm::Warnock
            ) {
                let (checked, bad) =
                    support::mismatches(&cast, &support::painted_ids(&r), size.0, size.1);
                assert!(
                    bad.len() * 50 <= checked,
                    "{name} {label}: {} of {checked} pixels differ from ray casting",
                    bad.len()
                );
            }
        }
    }
}

/// The refusal names the object that needs the tree and what about it,
/// and says what to do; with shadows on, it says that shadows need the
/// tree and how to turn them off.
#[test]
fn refusals_name_the_object_and_the_way_out() {
    let image_space = [
        Algorithm::ZBuffer,
        Algorithm::ScanLine,
        Algorithm::Warnock,
        Algorithm::Brown,
        Algorithm::RayCast,
    ];
    for (name, object, what) in TREE {
        let scene = load(&bundled(name));
        assert!(!plain(&scene), "{name}");
        for algorithm in image_space {
            let e = match render(
                &scene,
                &RenderOptions {
                    size: Some((32, 32)),
                    visibility: Some(algorithm),
                    ..RenderOptions::default()
                },
            ) {
                Ok(_) => panic!("{name} {algorithm:?} rendered"),
                Err(e) => e.to_string(),
            };
            assert!(e.contains(what), "{name}: {e}");
            assert!(e.contains(&format!("object `{object}")), "{name}: {e}");
            assert!(e.contains("depth-sort or nns"), "{name}: {e}");
        }
    }
    let scene = load(&bundled("ccube.des"));
    for algorithm in image_space {
        let e = render(
            &scene,
            &RenderOptions {
                size: Some((32, 32)),
                shadows: true,
                visibility: Some(algorithm),
                ..RenderOptions::default()
            },
        )
        .err()
        .unwrap_or_else(|| panic!("{algorithm:?} cast no shadows"))
        .to_string();
        assert!(e.contains("shadows"), "{e}");
        assert!(e.contains("run n") && e.contains("--no-shadows"), "{e}");
    }
}

/// Curved objects under Gouraud shading (`setmode v`) are named too.
#[test]
fn a_refusal_names_the_curved_objects_under_gouraud_shading() {
    let mut scene = load(&bundled("primitives.des"));
    let curved: Vec<&str> = scene
        .objects
        .iter()
        .filter(|o| o.surface_type.curved)
        .map(|o| o.name.as_str())
        .collect();
    assert!(!curved.is_empty());
    let first = format!("object `{}` (#", curved[0]);
    scene.modes.vertex_shades = true;
    let e = render(
        &scene,
        &RenderOptions {
            size: Some((32, 24)),
            visibility: Some(Algorithm::ZBuffer),
            ..RenderOptions::default()
        },
    )
    .expect_err("Gouraud polygons refused")
    .to_string();
    assert!(
        e.contains("setmode v") && e.contains(&first) && e.contains("is curved"),
        "{e}"
    );
}

/// Through the binary: a scene that says `run n` itself is rendered by
/// every algorithm in immediate mode (no shadows asked, none needed).
#[test]
fn a_scene_saying_run_n_renders_with_every_algorithm() {
    let folder = ccube_folder();
    std::fs::write(folder.path().join("runn.des"), "get ccube.des\nrun n\n").unwrap();
    for (_, label) in Algorithm::ALL {
        let out = folder.path().join(format!("{label}.ppm"));
        let run = std::process::Command::new(BIN)
            .current_dir(folder.path())
            .args(["--quiet", "-i", "-f", "runn.des", "--size", "48x48"])
            .args(["--visibility", label, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{label}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert!(out.is_file(), "{label}");
    }
}

// ---------------------------------------------------------------------
// 8. The default refraction (`auto`).
// ---------------------------------------------------------------------

/// The first row (from the top) with a pixel of the red cube.
fn top_red_row(frame: &plytrace::internal::raster::frame_buffer::FrameBuffer) -> Option<u32> {
    (0..frame.height).find(|&y| {
        (0..frame.width).any(|x| {
            let c = frame.color[(y * frame.width + x) as usize];
            c[0] > c[2] + 0.15
        })
    })
}

/// 004 section 4.6: refracted points "appear at eta times their
/// distance" (the paraxial model, apparent depth = depth / n). Worked by
/// hand for tests/data/manual/pool.des (128 x 128, fovy 45: 64 pixels for
/// tan 22.5 degrees): the cube's far top edge is 1.2 to the side and 2.8
/// under the water, the eye 2 above it.
///
/// - Unrefracted: tan = 1.2 / 4.8 = 0.25, 38.6 pixels above the centre:
///   the edge at 25.4, first row 25.
/// - Snell (1.33): the path crosses the water 0.59 to the side (sin t1 =
///   1.33 sin t2: 0.283 = 1.33 x 0.213), tan = 0.295, 45.6 pixels: the
///   edge at 18.4, first row 18 (the paraxial model: 2 + 2.8 / 1.33,
///   tan = 0.292, row 19).
///
/// Straight down the linearized matrix is the identity, so the tree's
/// level 2 puts the cube at row 25; `auto` must see that it is off by
/// more than a pixel (its old estimate, at the water's corners, saw
/// nothing under them: 0.0) and choose exact refraction: row 18, the
/// ray tracer's.
#[test]
fn auto_refraction_puts_the_cube_under_water_where_snell_does() {
    let scene = load(&data("pool.des"));
    let options = RenderOptions {
        aa: Some(Method::Point),
        ..RenderOptions::default()
    };
    let auto = render(&scene, &options).unwrap();
    let said = auto.stats.refraction.clone().unwrap_or_default();
    assert!(said.starts_with("exact"), "{said}");
    let traced = raytrace::render(&scene, &RayTraceOptions::default())
        .unwrap()
        .0;
    assert_eq!(top_red_row(&traced), Some(18), "the ray tracer");
    assert_eq!(top_red_row(&auto.frame), Some(18), "auto: {said}");
    // The linearized matrix alone: the unrefracted place.
    let linear = render(
        &scene,
        &RenderOptions {
            refraction: plytrace::internal::image_tree::Refraction::Linearized,
            ..options
        },
    )
    .unwrap();
    assert_eq!(top_red_row(&linear.frame), Some(25));
    // The estimate itself is honest: several pixels here.
    let view = plytrace::internal::geometry::view::View::for_scene(&scene, None).unwrap();
    let error = plytrace::internal::raytrace::exact::linear_error(&scene, &view);
    assert!(error > 3.0, "{error}");
}

/// Where Snell's law crosses a plane, worked by hand: the eye 2 above
/// `z = 0`, a point 1.2 to the side and 2.8 below, index 1.33: 0.59.
#[test]
fn snell_crossing_by_hand() {
    use glam::{DVec3, DVec4};
    let c = plytrace::internal::raytrace::exact::snell_crossing(
        DVec3::new(0.0, 0.0, 2.0),
        DVec3::new(1.2, 0.0, -2.8),
        DVec4::new(0.0, 0.0, 1.0, 0.0),
        1.0 / 1.33,
    )
    .unwrap();
    assert!(
        (c.x - 0.59).abs() < 0.005 && c.y == 0.0 && c.z.abs() < 1e-12,
        "{c}"
    );
    let s1 = c.x / (c.x * c.x + 4.0).sqrt();
    let s2 = (1.2 - c.x) / ((1.2 - c.x).powi(2) + 2.8f64.powi(2)).sqrt();
    assert!((s1 - 1.33 * s2).abs() < 1e-9);
}

/// Donovan's shading (a back-to-front picture) keeps the exact refraction
/// layer: nothing is left out, and the cube is where Snell puts it.
#[test]
fn donovan_shading_keeps_exact_refraction() {
    let scene = load(&data("pool.des"));
    for aa in [Method::Point, Method::Multilevel] {
        let r = render(
            &scene,
            &RenderOptions {
                aa: Some(aa),
                shading: ShadingModel::Donovan,
                ..RenderOptions::default()
            },
        )
        .unwrap();
        assert!(r.stats.warnings.is_empty(), "{:?}", r.stats.warnings);
        assert_eq!(top_red_row(&r.frame), Some(18), "{aa:?}");
    }
}

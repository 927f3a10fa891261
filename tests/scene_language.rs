//! The effect of every command of the scene descriptor language on the
//! scene model (004 appendix, plytrace manual page), and the IRIS GL matrix
//! conventions checked against hand-worked numbers.

use std::path::{Path, PathBuf};

use glam::DVec3;
use plytrace::Result;
use plytrace::internal::math::Matrix4;
use plytrace::internal::model::*;
use plytrace::internal::scene::{Flow, Host, Interpreter, NoHost, Scene};

const SQUARE: &str =
    "title square facing +z\ndata\n4 1\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n4 4 3 2 1\n";
const TRIANGLE: &str = "title triangle\ndata\n3 1\n0 0 0\n0 1 0\n1 0 0\n3 1 2 3\n";

struct Fixture {
    dir: tempfile::TempDir,
}

impl Fixture {
    fn new() -> Fixture {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("det")).unwrap();
        std::fs::write(dir.path().join("det/square.det"), SQUARE).unwrap();
        std::fs::write(dir.path().join("det/tri.det"), TRIANGLE).unwrap();
        let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det");
        std::fs::copy(cube, dir.path().join("det/cube.det")).unwrap();
        Fixture { dir }
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    fn run(&self, text: &str) -> Result<Interpreter> {
        let mut i = Interpreter::new();
        self.run_with(&mut i, text, &mut NoHost)?;
        Ok(i)
    }

    /// Runs `text` after an `ident`, so that objects are not transformed by
    /// the default perspective that `init` leaves on the CTM.
    fn run_with(&self, i: &mut Interpreter, text: &str, host: &mut dyn Host) -> Result<Flow> {
        let p = self.write("t.des", &format!("ident\n{text}"));
        i.execute_file(&p, false, host)
    }

    fn scene(&self, text: &str) -> Scene {
        self.run(text).unwrap().scene()
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

fn mat_close(a: &Matrix4, b: &Matrix4) -> bool {
    (0..4).all(|r| (0..4).all(|c| (a.m[r][c] - b.m[r][c]).abs() < 1e-12))
}

#[test]
fn global_and_object_attributes() {
    let f = Fixture::new();
    let s = f.scene(
        "ambient 0.1 0.2 0.3\nbackground 0.4 0.5 0.6\ncolor 0.5 0.5 0\ndiffuse 0.3\nspecular 0.2\n\
         shininess 120\nreflectance 0.25\ntransmittance 0.125\nindex 1.5\ntransparency 0.5 2\n\
         type polygon open concave\n\
         defobj square\n  color 0 0 1\n  diffuse 0.9\n  type polygon curved hidden ltsrc\nendobj\n\
         getobj tri\n",
    );
    assert_eq!(s.ambient, DVec3::new(0.1, 0.2, 0.3));
    assert_eq!(s.background, DVec3::new(0.4, 0.5, 0.6));
    let sq = &s.objects[0];
    assert_eq!(sq.surface.color, DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(sq.surface.diffuse, 0.9);
    assert_eq!(sq.surface.specular, 0.2, "inherited from the globals");
    assert_eq!(
        sq.surface_type,
        SurfaceType {
            open: false,
            curved: true,
            concave: false,
            hidden: true,
            ltsrc: true
        }
    );
    assert!(
        sq.vertex_normals.is_some(),
        "type curved computes vertex normals"
    );
    let tri = &s.objects[1];
    assert_eq!(
        tri.surface,
        Surface {
            color: DVec3::new(0.5, 0.5, 0.0),
            diffuse: 0.3,
            specular: 0.2,
            shininess: 120.0,
            reflectance: 0.25,
            transmittance: 0.125,
            index: 1.5,
            transparency: (0.5, 2.0),
        },
        "the object attributes did not leak into the globals"
    );
    assert!(tri.surface_type.open && tri.surface_type.concave && !tri.surface_type.curved);
    assert!(tri.vertex_normals.is_none());
}

/// One step of a script of objects: defined without a number, with one
/// (if free), or deleted by number (if there).
#[derive(Debug, Clone)]
enum NumberStep {
    Free,
    Given(u32),
    Delete(u32),
}

mod numbering {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// An object defined without a number takes the lowest number no
        /// object then in the scene uses, however objects were numbered and
        /// deleted before: against a model that looks at every number.
        #[test]
        fn a_new_object_takes_the_lowest_free_number(
            steps in proptest::collection::vec(
                prop_oneof![
                    3 => Just(NumberStep::Free),
                    1 => (0u32..24).prop_map(NumberStep::Given),
                    1 => (0u32..24).prop_map(NumberStep::Delete),
                ],
                1..60,
            )
        ) {
            let mut model: Vec<u32> = Vec::new();
            let mut text = String::new();
            for step in steps {
                match step {
                    NumberStep::Free => {
                        let free = (0..).find(|n| !model.contains(n)).unwrap();
                        model.push(free);
                        text += "defobj tri\nendobj\n";
                    }
                    NumberStep::Given(n) if !model.contains(&n) => {
                        model.push(n);
                        text += &format!("defobj tri {n}\nendobj\n");
                    }
                    NumberStep::Given(n) => {
                        // A number in use is refused, the scene so far kept.
                        let f = Fixture::new();
                        let e = f.run(&format!("{text}defobj tri {n}\n")).unwrap_err();
                        prop_assert!(e.to_string().contains("is already in use"), "{}", e);
                    }
                    NumberStep::Delete(n) if model.contains(&n) => {
                        model.retain(|&m| m != n);
                        text += &format!("delobj {n}\n");
                    }
                    _ => {}
                }
            }
            let numbers: Vec<u32> = Fixture::new().scene(&text).objects.iter().map(|o| o.number).collect();
            prop_assert_eq!(numbers, model);
        }
    }
}

/// A file that fails can be executed again by the same interpreter: the
/// error is its own again, not a `get`/`call` cycle.
#[test]
fn a_file_that_failed_runs_again() {
    let f = Fixture::new();
    let p = f.write("bad.des", "ident\ndefobj tri\nendobj\ndelobj 5\n");
    let mut i = Interpreter::new();
    for _ in 0..2 {
        let e = i
            .execute_file(&p, false, &mut NoHost)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no object `5`"), "{e}");
    }
    // A `quit` ends a file without its definitions' `endobj`: no error.
    let q = f.write("quit.des", "ident\ndefobj tri\nquit\n");
    for _ in 0..2 {
        Interpreter::new()
            .execute_file(&q, false, &mut NoHost)
            .expect("quit in a definition");
    }
}

mod deleting {
    use super::*;
    use proptest::prelude::*;

    /// A `delobj` reference: a number or one of three names.
    fn reference() -> impl Strategy<Value = String> {
        prop_oneof![
            (0u32..12).prop_map(|n| n.to_string()),
            prop::sample::select(vec!["tri", "square", "cube"]).prop_map(String::from),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(96))]
        /// `delobj` statements of one or many references delete as the
        /// references one by one would, and stop with an error at the
        /// first that finds nothing left, the references before it
        /// carried out, whether they are one statement or several; a
        /// `defobj` after them sees them gone: against a model that
        /// deletes in turn.
        #[test]
        fn delobj_deletes_as_its_references_in_turn(
            names in proptest::collection::vec(0usize..3, 0..12),
            refs in proptest::collection::vec((reference(), any::<bool>()), 1..12),
            then_define in any::<bool>(),
        ) {
            let files = ["tri", "square", "cube"];
            let mut model: Vec<(u32, String)> = Vec::new();
            let mut text = String::new();
            for (n, &k) in names.iter().enumerate() {
                model.push((n as u32, files[k].to_string()));
                text += &format!("defobj {} {n}\nendobj\n", files[k]);
            }
            let mut missing = None;
            for (r, _) in &refs {
                let before = model.len();
                model.retain(|(n, name)| n.to_string() != *r && name != r);
                if model.len() == before {
                    missing = Some(r.clone());
                    break;
                }
            }
            // A new statement where the flag says so.
            text += "delobj";
            for (k, (r, split)) in refs.iter().enumerate() {
                if k > 0 && *split {
                    text += "\ndelobj";
                }
                text += &format!(" {r}");
            }
            text += "\n";
            if then_define && missing.is_none() {
                let free = (0..).find(|n| !model.iter().any(|(m, _)| m == n)).unwrap();
                model.push((free, "tri".into()));
                text += "defobj tri\nendobj\n";
            }
            let f = Fixture::new();
            let mut i = Interpreter::new();
            let result = f.run_with(&mut i, &text, &mut NoHost);
            match (&missing, result) {
                (None, Ok(_)) => {}
                (Some(r), Err(e)) => prop_assert!(
                    e.to_string().contains(&format!("no object `{r}`")), "{e}"
                ),
                (m, r) => prop_assert!(false, "missing {m:?}, result {:?}", r.map(|_| ())),
            }
            let left: Vec<(u32, String)> =
                i.scene().objects.iter().map(|o| (o.number, o.name.clone())).collect();
            prop_assert_eq!(left, model);
        }
    }

    /// Objects deleted by statements in a row are gone for the statement
    /// after them, by number and by name.
    #[test]
    fn deleted_objects_are_gone_for_the_next_statement() {
        let f = Fixture::new();
        let e = f
            .run("defobj tri 1\nendobj\ndefobj tri 2\nendobj\ndelobj 1\ndelobj 2\ncallobj 1\n")
            .unwrap_err();
        assert!(e.to_string().contains("no object `1`"), "{e}");
        let e = f
            .run("defobj tri\nendobj\ndefobj square\nendobj\ndelobj tri\ndelobj square\ncallobj tri\n")
            .unwrap_err();
        assert!(e.to_string().contains("no object `tri`"), "{e}");
        let s = f.scene("defobj tri 4\nendobj\ndefobj square\nendobj\ndelobj 4\ndelobj square\n");
        assert!(s.objects.is_empty());
    }

    /// A `get` file that ends with deletions is summed without them.
    #[test]
    fn a_file_ending_with_deletions_is_scanned_without_them() {
        struct Scanned(Vec<usize>);
        impl Host for Scanned {
            fn run(&mut self, _: &Scene, _: bool) -> Result<()> {
                Ok(())
            }
            fn scanned(&mut self, _: &Path, scene: &Scene, _: std::time::Duration) {
                self.0.push(scene.objects.len());
            }
        }
        let f = Fixture::new();
        f.write(
            "a.des",
            "ident\ndefobj tri\nendobj\ndefobj tri\nendobj\ndelobj 0\n",
        );
        let mut host = Scanned(Vec::new());
        f.run_with(&mut Interpreter::new(), "get a.des\n", &mut host)
            .unwrap();
        assert_eq!(host.0, [1]);
    }

    /// The polygons of deleted objects leave the budget, also those
    /// deleted before a missing reference.
    #[test]
    fn deleted_polygons_leave_the_budget() {
        let f = Fixture::new();
        let mut i = Interpreter::new();
        i.set_budgets(plytrace::internal::budget::Budgets {
            polygons: 7,
            ..Default::default()
        });
        f.run_with(
            &mut i,
            "defobj cube 1\nendobj\ndelobj 1\ndefobj cube\nendobj\n",
            &mut NoHost,
        )
        .expect("a cube (6 polygons) at a time");
        let e = f
            .run_with(&mut i, "delobj 1 0 5\n", &mut NoHost)
            .unwrap_err();
        assert!(e.to_string().contains("no object `1`"), "{e}");
        f.run_with(&mut i, "delobj 0 5\n", &mut NoHost).unwrap_err();
        f.run_with(&mut i, "defobj cube\nendobj\n", &mut NoHost)
            .expect("cube 0 went before the missing 5");
        // Many references in one statement (looked up by number and name).
        let mut i = Interpreter::new();
        i.set_budgets(plytrace::internal::budget::Budgets {
            polygons: 12,
            ..Default::default()
        });
        let tris = "defobj tri\nendobj\n".repeat(10);
        f.run_with(
            &mut i,
            &format!("{tris}delobj 0 1 2 3 4 5 6 7 8\n"),
            &mut NoHost,
        )
        .expect("ten triangles, nine deleted");
        f.run_with(&mut i, "defobj cube\nendobj\n", &mut NoHost)
            .expect("a triangle and a cube: 7 polygons");
    }
}

/// A CSG result consumes its operands: their numbers are free again,
/// also when the result is given a number of its own.
#[test]
fn csg_operands_free_their_numbers() {
    let s = Fixture::new().scene(
        "defobj a\nsphere 8 4\nendobj\n\
         defobj b\ntranslate 0.5 0 0\nsphere 8 4\nendobj\n\
         defobj tri\nendobj\ndefobj tri\nendobj\n\
         defobj r 9\nunion a b\nendobj\ndefobj tri\nendobj\n",
    );
    let numbers: Vec<u32> = s.objects.iter().map(|o| o.number).collect();
    assert_eq!(numbers, vec![2, 3, 9, 0]);
}

#[test]
fn object_numbers_callobj_and_delobj() {
    let f = Fixture::new();
    let s = f.scene(
        "defobj square 7\nendobj\ngetobj tri\ngetobj tri\n\
         defobj anything\n  callobj 7\n  translate 10 0 0\nendobj\ncallobj 1\ndelobj 0, 2\n",
    );
    let numbers: Vec<u32> = s.objects.iter().map(|o| o.number).collect();
    // 7 given; then the lowest free numbers 0, 1, 2, 3; 0 and 2 deleted.
    assert_eq!(numbers, vec![7, 1, 3]);
    let copy = &s.objects[2];
    assert_eq!(copy.mesh.vertices.len(), 3, "callobj 1 copied the triangle");
    // `anything` (number 2) copied the square and was moved; it is deleted,
    // but the copy relation is visible through the mesh being shared.
    let f2 = Fixture::new();
    let s2 =
        f2.scene("defobj square 7\nendobj\ndefobj nofile\n callobj 7\n translate 10 0 0\nendobj\n");
    assert!(std::sync::Arc::ptr_eq(
        &s2.objects[0].mesh,
        &s2.objects[1].mesh
    ));
    assert!(close(s2.objects[1].vertices[0], DVec3::new(9.0, -1.0, 0.0)));
}

#[test]
fn matrix_commands_premultiply_and_projections_load() {
    let f = Fixture::new();
    let i = f
        .run("ident\ntranslate 1 2 3\nrotate 90 z\nscale 2 2 2\n")
        .unwrap();
    // Points: scale first, then rotate, then translate.
    let p = i.ctm().transform_point(DVec3::new(1.0, 0.0, 0.0));
    assert!(close(p, DVec3::new(1.0, 4.0, 3.0)), "{p}");
    let i = f.run("translate 5 5 5\nperspective 60 2 1 10\n").unwrap();
    assert!(mat_close(
        &i.ctm(),
        &plytrace::internal::math::perspective(60.0, 2.0, 1.0, 10.0)
    ));
    let i = f.run("translate 5 5 5\northo -1 1 -2 2 0 10\n").unwrap();
    assert!(mat_close(
        &i.ctm(),
        &plytrace::internal::math::ortho(-1.0, 1.0, -2.0, 2.0, 0.0, 10.0)
    ));
    let i = f.run("translate 5 5 5\northo2 -1 1 -2 2\n").unwrap();
    assert!(mat_close(
        &i.ctm(),
        &plytrace::internal::scene::interpreter::ortho2(-1.0, 1.0, -2.0, 2.0)
    ));
    let i = f.run("translate 5 5 5\nwindow -1 1 -1 1 1 10\n").unwrap();
    assert!(mat_close(
        &i.ctm(),
        &plytrace::internal::math::window(-1.0, 1.0, -1.0, 1.0, 1.0, 10.0)
    ));
    let i = f.run("translate 5 5 5\nresolution 640 480\n").unwrap();
    assert!(mat_close(
        &i.ctm(),
        &plytrace::internal::math::perspective(45.0, 640.0 / 480.0, 0.01, 10000.0)
    ));
    let s = i.scene();
    assert_eq!((s.viewport.width(), s.viewport.height()), (640, 480));
    assert_eq!(
        (s.viewport.left, s.viewport.bottom),
        (192, 272),
        "centred on 1024 x 1024"
    );
    let s = f.scene("viewport 10 109 20 69\n");
    assert_eq!((s.viewport.width(), s.viewport.height()), (100, 50));
    // pushmatrix duplicates, popmatrix restores; defobj saves and restores.
    let i = f
        .run("ident\npushmatrix\ntranslate 1 0 0\npopmatrix\ndefobj square\nscale 3 3 3\nendobj\n")
        .unwrap();
    assert!(mat_close(&i.ctm(), &Matrix4::IDENTITY));
    assert_eq!(i.stack_depth(), 0);
    // lookat: the viewpoint goes to the origin.
    let i = f.run("ident\nlookat 0 -10 0 0 0 0 0\n").unwrap();
    assert!(close(
        i.ctm().transform_point(DVec3::new(0.0, -10.0, 0.0)),
        DVec3::ZERO
    ));
    assert!(close(
        i.ctm().transform_point(DVec3::ZERO),
        DVec3::new(0.0, 0.0, -10.0)
    ));
}

/// The manual's ccube: the cut cube's corner (1,-1,-1) worked by hand
/// through `rotate 30 z`, `translate 0 0 1.05` (the object's CTM), then
/// `translate 0 0 -1` and `polarview 7 0 75 0` (the view).
#[test]
fn ccube_vertex_hand_worked() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ccube.des");
    let (s, warnings) = plytrace::internal::scene::load(&path).unwrap();
    assert!(warnings.is_empty());
    let (s30, c30) = 30f64.to_radians().sin_cos();
    // rotate 30 z, then translate (0, 0, 1.05), then translate (0, 0, -1):
    let p = DVec3::new(c30 + s30, s30 - c30, -1.0 + 1.05 - 1.0);
    // polarview: rotate -75 about x (y' = y cos - z sin, z' = y sin + z cos
    // with the angle -75), then translate (0, 0, -7).
    let (s75, c75) = (-75f64).to_radians().sin_cos();
    let expected = DVec3::new(p.x, p.y * c75 - p.z * s75, p.y * s75 + p.z * c75 - 7.0);
    let cutcube = &s.objects[1];
    assert!(
        close(cutcube.vertices[1], expected),
        "{} vs {expected}",
        cutcube.vertices[1]
    );
    // The light (-4,-2,6) is transformed by the view when read.
    let q = DVec3::new(-4.0, -2.0, 6.0 - 1.0);
    let light = DVec3::new(q.x, q.y * c75 - q.z * s75, q.y * s75 + q.z * c75 - 7.0);
    assert!(close(s.lights[0].position, light));
    assert_eq!(s.lights[0].kind, LightKind::Point);
    assert_eq!(s.lights[1].kind, LightKind::Diffuse);
    assert_eq!(
        (s.lights[1].range, s.lights[1].color),
        (50.0, DVec3::splat(0.5))
    );
    // The projection left at the end is the perspective.
    assert!(mat_close(
        &s.projection,
        &plytrace::internal::math::perspective(45.0, 1.0, 0.01, 1000.0)
    ));
    assert_eq!(s.fname.as_deref(), Some("ccube"));
}

#[test]
fn lights_modes_and_settings() {
    let f = Fixture::new();
    let s = f.scene(
        "light 1 2 3 1 1 1 10\nlight 0 0 0 0.5 0.5 0.5 5 d\nnolight\nlight 0 0 1 1 0 0 9 Diffuse\n\
         depth 5\nthreshold 0.25\nsort ftb\nfname pic\ndisp off\noutmode a 3\n\
         setmode b on\nsetmode d 0.01\nsetmode e 1e-5\nsetmode h on\nsetmode n on\nsetmode o on\n\
         setmode p on\nsetmode s on\nsetmode v on\nsetmode x on\nsetmode 7\n",
    );
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.lights[0].kind, LightKind::Diffuse);
    assert_eq!(s.modes.max_level, 5);
    assert_eq!(s.threshold, 0.25);
    assert_eq!(s.sort_order, SortOrder::FrontToBack);
    assert_eq!(s.fname.as_deref(), Some("pic"));
    assert!(!s.display);
    assert_eq!(s.outmode, OutMode::Quantized(3));
    let m = s.modes;
    assert!(
        m.blend
            && m.shadow_shades
            && m.nns
            && m.output_tree
            && m.boxes_only
            && m.phong
            && m.vertex_shades
            && m.expand
    );
    assert_eq!((m.min_detail, m.epsilon, m.debug), (0.01, 1e-5, 7));
    let s = f.scene("setmode l 9\nsetmode n on\nsetmode n off\n");
    assert_eq!(s.modes.max_level, 9);
    assert!(!s.modes.nns);
}

#[test]
fn command_line_modes_override_the_file() {
    let f = Fixture::new();
    let mut i = Interpreter::new();
    i.force_mode('n', "on").unwrap();
    i.force_mode('l', "3").unwrap();
    f.run_with(&mut i, "setmode n off\ndepth 7\ninit\n", &mut NoHost)
        .unwrap();
    let s = i.scene();
    assert!(s.modes.nns);
    assert_eq!(s.modes.max_level, 3);
    assert!(i.force_mode('n', "maybe").is_err());
    assert!(i.force_mode('l', "15").is_err());
}

#[derive(Default)]
struct Recorder {
    runs: Vec<(usize, bool)>,
    clears: usize,
    waits: usize,
}

impl Host for Recorder {
    fn run(&mut self, scene: &Scene, shadows: bool) -> Result<()> {
        self.runs.push((scene.objects.len(), shadows));
        Ok(())
    }
    fn clear(&mut self, _: &Scene) -> Result<()> {
        self.clears += 1;
        Ok(())
    }
    fn wait(&mut self) {
        self.waits += 1;
    }
}

#[test]
fn run_clear_wait_and_quit_reach_the_host() {
    let f = Fixture::new();
    let mut i = Interpreter::new();
    let mut h = Recorder::default();
    let flow = f
        .run_with(
            &mut i,
            "getobj tri\nrun\nclear\nrun y\nwait\nquit\ngetobj tri\n",
            &mut h,
        )
        .unwrap();
    assert_eq!(flow, Flow::Quit);
    assert_eq!(h.runs, vec![(1, false), (1, true)]);
    assert_eq!((h.clears, h.waits), (1, 1));
    assert_eq!(i.scene().objects.len(), 1, "nothing after quit is read");
}

#[test]
fn get_initializes_and_call_does_not() {
    let f = Fixture::new();
    f.write("sub.des", "ident\ngetobj tri\n");
    let s = f.scene("getobj square\ncolor 0 1 0\ncall sub.des\n");
    assert_eq!(s.objects.len(), 2);
    assert_eq!(s.objects[1].surface.color, DVec3::new(0.0, 1.0, 0.0));
    let s = f.scene("getobj square\ncolor 0 1 0\nget sub.des\n");
    assert_eq!(s.objects.len(), 1, "get begins with init");
    assert_eq!(s.objects[0].surface.color, DVec3::ONE);
    let s = f.scene("getobj square\nbackground 1 1 1\ninit\n");
    assert!(s.objects.is_empty() && s.background == DVec3::ZERO);
}

#[test]
fn det_dir_pcolors_and_vcolors() {
    let f = Fixture::new();
    std::fs::create_dir(f.dir.path().join("other")).unwrap();
    std::fs::write(f.dir.path().join("other/sq.det"), SQUARE).unwrap();
    std::fs::write(
        f.dir.path().join("other/sq.pcl"),
        "title p\ndata 1\n0.1 0.2 0.3 0.4 0.5 0.25\n",
    )
    .unwrap();
    std::fs::write(
        f.dir.path().join("other/sq.vcl"),
        "title v\ndata 4\n1 0 0 0 0 0\n0 1 0 0 0 0\n0 0 1 0 0 0\n1 1 1 0 0 0\n",
    )
    .unwrap();
    let s = f.scene("det_dir other\ndefobj sq\npcolors sq\nvcolors sq\nendobj\n");
    let o = &s.objects[0];
    let p = o.polygon_colors.as_ref().unwrap();
    assert_eq!(p[0].color, DVec3::new(0.1, 0.2, 0.3));
    assert_eq!(
        (p[0].diffuse, p[0].reflectance, p[0].transmittance),
        (0.4, 0.5, 0.25)
    );
    assert_eq!(o.vertex_colors.as_ref().unwrap().len(), 4);
    // The material of the polygon follows its .pcl entry.
    let m = o.material(0);
    assert_eq!(m.color, DVec3::new(0.1, 0.2, 0.3));
    assert!((m.ambient_coefficient() - 0.0).abs() < 1e-12);
}

#[test]
fn prefixes_case_and_separators() {
    let f = Fixture::new();
    let s = f.scene("BACKGR 0.5,0.25,0 # comment\n/* block\n comment */ TRANSL 1 2 3\nGETO tri\n");
    assert_eq!(s.background, DVec3::new(0.5, 0.25, 0.0));
    assert!(close(s.objects[0].vertices[0], DVec3::new(1.0, 2.0, 3.0)));
}

#[test]
fn clockwise_polygons_face_outward_and_mirrors_keep_them_so() {
    let f = Fixture::new();
    let s = f.scene("getobj cube\ndefobj cube\nscale -1 1 1\nendobj\n");
    for o in &s.objects {
        for p in &o.polygons {
            let centroid: DVec3 = p
                .indices
                .iter()
                .map(|&i| o.vertices[i as usize])
                .sum::<DVec3>()
                / p.indices.len() as f64;
            assert!(
                p.normal().dot(centroid) > 0.0,
                "outward normal for the cube centred at 0"
            );
            assert!((p.normal().length() - 1.0).abs() < 1e-12);
            assert!(
                (p.plane.truncate().dot(centroid) + p.plane.w).abs() < 1e-12,
                "centroid on the plane"
            );
        }
    }
}

// The manual, unbent (004 appendix B).

#[test]
fn ortho2_does_not_clip_z() {
    use plytrace::internal::geometry::clip::outcode;
    let f = Fixture::new();
    let i = f.run("ortho2 -1 1 -1 1\n").unwrap();
    for z in [-1e6, -50.0, 0.0, 50.0, 1e6] {
        let p = i.ctm().transform_point4(DVec3::new(0.5, -0.5, z));
        assert_eq!(outcode(p), 0, "z = {z} is clipped: {p}");
    }
    // x and y are still mapped to -1..1, and depth keeps its order.
    let a = i.ctm().transform_point4(DVec3::new(1.0, -1.0, 2.0));
    let b = i.ctm().transform_point4(DVec3::new(1.0, -1.0, 1.0));
    assert!((a.x - 1.0).abs() < 1e-12 && (a.y + 1.0).abs() < 1e-12);
    assert!(a.z < b.z, "nearer (larger z) is smaller depth");
}

#[test]
fn object_names_are_case_folded() {
    let f = Fixture::new();
    let s = f.scene("defobj Cube 3\nendobj\ngetobj CUBE\ndelobj cube\n");
    assert!(s.objects.is_empty(), "{:?}", s.objects.len());
    let s = f.scene("defobj CUBE 3\nendobj\ncallobj Cube\ndelobj 3\n");
    assert_eq!(s.objects.len(), 1);
    assert_eq!(s.objects[0].name, "#3");
    let s = f.scene("getobj Square\n");
    assert_eq!(s.objects[0].name, "square");
    assert!(f.run("delobj nosuch\n").is_err());
}

#[test]
fn on_off_setmodes_without_a_value_mean_on() {
    let f = Fixture::new();
    let m = f.scene("setmode b\nsetmode h\nsetmode n\nsetmode o\nsetmode p\nsetmode s\nsetmode V\nsetmode x\n").modes;
    assert!(
        m.blend
            && m.shadow_shades
            && m.nns
            && m.output_tree
            && m.boxes_only
            && m.phong
            && m.vertex_shades
            && m.expand
    );
    assert!(!f.scene("setmode v\nsetmode v off\n").modes.vertex_shades);
    assert!(f.run("setmode d\n").is_err(), "d needs a value");
}

#[test]
fn setmode_f_is_accepted_in_scene_files() {
    let f = Fixture::new();
    let s = f.scene("setmode f other.des\n");
    assert_eq!(s.scene_file.as_deref(), Some("other.des"));
    assert!(f.run("setmode f\n").is_err(), "f needs a file name");
}

#[test]
fn lookat_with_parentheses() {
    let f = Fixture::new();
    let a = f.run("lookat(1, 2, 5, 0, 0, 0, 30)\n").unwrap().ctm();
    let b = f.run("lookat 1 2 5 0 0 0 30\n").unwrap().ctm();
    assert!(mat_close(&a, &b));
    let c = f.run("translate(1, 2, 3)\n").unwrap().ctm();
    let d = f.run("translate 1 2 3\n").unwrap().ctm();
    assert!(mat_close(&c, &d));
}

/// `ortho2` end to end: a square 1000 units in front and one 50 behind are
/// both drawn (IRIS GL's near and far of -1 and 1 would clip both), and
/// the nearer hides the farther.
#[test]
fn ortho2_renders_without_z_clipping_and_keeps_depth_order() {
    use plytrace::internal::render::{RenderOptions, render};
    let f = Fixture::new();
    let s = f.scene(
        "viewport 0 63 0 63\northo2 -2 2 -2 2\npushmatrix\nident\n\
         defobj square\n  translate 0 0 -50\nendobj\n\
         defobj square\n  scale 0.5 0.5 1\n  translate 0 0 1000\nendobj\npopmatrix\n",
    );
    let r = render(&s, &RenderOptions::default()).unwrap();
    assert_eq!((r.frame.width, r.frame.height), (64, 64));
    assert_eq!(r.polygon_at(32, 32), Some((1, 0)), "the near square");
    assert_eq!(r.polygon_at(20, 20), Some((0, 0)), "the far square");
    assert_eq!(r.polygon_at(2, 2), None, "the background");
    // Defined the other way round: depth decides, not the order.
    let s = f.scene(
        "viewport 0 63 0 63\northo2 -2 2 -2 2\npushmatrix\nident\n\
         defobj square\n  scale 0.5 0.5 1\n  translate 0 0 1000\nendobj\n\
         defobj square\n  translate 0 0 -50\nendobj\npopmatrix\n",
    );
    let r = render(&s, &RenderOptions::default()).unwrap();
    assert_eq!(r.polygon_at(32, 32), Some((0, 0)), "the near square");
    assert_eq!(r.polygon_at(20, 20), Some((1, 0)), "the far square");
}

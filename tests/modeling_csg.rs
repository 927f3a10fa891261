//! CSG (Firebaugh 001 figures 8.12-8.15) in the scene language. Oracles:
//! inclusion-exclusion of volumes, our own edge count for closedness, and
//! the project's ray caster on the result against the point-in-solid
//! classification of the (convex) operands along each pixel's ray.

mod support;

use std::collections::HashMap;

use glam::DVec3;
use plytrace::internal::error::Diagnostic;
use plytrace::internal::model::Object;
use plytrace::internal::scene::Scene;
use plytrace::internal::visibility::ray_cast::RayCaster;

const PRELUDE: &str =
    "resolution 48 48\nperspective 40 1 0.1 100\npolarview 8 30 60 0\npushmatrix\nident\n";

/// The scene, and its warnings followed by its notes (a CSG operation's
/// figures are a note, not a warning).
fn try_scene(body: &str) -> plytrace::Result<(Scene, Vec<Diagnostic>)> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.des");
    std::fs::write(&path, format!("{PRELUDE}{body}\npopmatrix\n")).unwrap();
    plytrace::internal::scene::load_with_notes(&path).map(|(s, mut w, n)| {
        w.extend(n);
        (s, w)
    })
}

fn scene(body: &str) -> Scene {
    try_scene(body).unwrap().0
}

/// Operand pairs: (definition of `a`, definition of `b`), all convex.
const PAIRS: &[(&str, &str)] = &[
    (
        "color 1 0 0\ntranslate 0 0 -1\nextrude 2 -1 -1 1 -1 1 1 -1 1",
        "color 0 0 1\ntranslate 0.8 0.3 0.2\nscale 1.3 1.3 1.3\nsphere 16 8",
    ),
    (
        "translate 0 0 -1\nextrude 2 -1 -1 1 -1 1 1 -1 1",
        "rotate 30 z\nrotate 20 x\ntranslate 0 0 -0.5\nextrude 1.7 -0.3 -1.5 0.3 -1.5 0.3 1.5 -0.3 1.5",
    ),
    (
        "scale 1 1 1.5\ncylinder 20",
        "translate 0.5 0 0.5\nsuperquadric 0.5 0.5 16 8 1 0.8 0.8",
    ),
];

fn defs(a: &str, b: &str) -> String {
    format!("defobj a\n{a}\nendobj\ndefobj b\n{b}\nendobj\n")
}

fn csg(a: &str, b: &str, op: &str) -> (Object, Vec<Diagnostic>) {
    let (s, w) = try_scene(&format!("{}defobj r\n{op} a b\nendobj", defs(a, b))).unwrap();
    assert_eq!(s.objects.len(), 1, "the operands are consumed");
    (s.objects.into_iter().next().unwrap(), w)
}

#[test]
fn volumes_obey_inclusion_exclusion() {
    for (a, b) in PAIRS {
        let s = scene(&defs(a, b));
        let (va, vb) = (
            support::volume(&s.objects[0]),
            support::volume(&s.objects[1]),
        );
        let mut v = HashMap::new();
        for op in ["union", "intersection", "difference"] {
            let (o, w) = csg(a, b, op);
            assert!(
                support::closed(&o),
                "{op} of\n{a}\n{b}\nis not closed: {w:?}"
            );
            assert!(o.polygons.iter().all(|p| p.indices.len() >= 3));
            v.insert(op, support::volume(&o));
            let stat = w
                .iter()
                .find(|d| d.message.contains("input faces kept"))
                .unwrap();
            assert!(stat.message.contains("split"), "{}", stat.message);
        }
        let tol = 1e-9 * (va + vb);
        assert!(v["intersection"] > 0.05 * va.min(vb), "{v:?}");
        assert!(
            (v["union"] + v["intersection"] - va - vb).abs() < tol,
            "{v:?} {va} {vb}"
        );
        assert!(
            (v["difference"] - (va - v["intersection"])).abs() < tol,
            "{v:?} {va}"
        );
    }
}

#[test]
fn faces_keep_their_operands_surfaces_and_normals() {
    // A red plate with a hole cut by a blue cylinder: blue walls.
    let (o, _) = csg(
        "color 1 0 0\ntranslate 0 0 -0.25\nextrude 0.5 -1 -1 1 -1 1 1 -1 1",
        "color 0 0 1\nscale 0.5 0.5 1\ncylinder 24",
        "difference",
    );
    let pcl = o.polygon_colors.as_ref().expect("per-face colours");
    let (mut walls, mut plate) = (0, 0);
    for (pi, p) in o.polygons.iter().enumerate() {
        let c: DVec3 = p
            .indices
            .iter()
            .map(|&i| o.vertices[i as usize])
            .sum::<DVec3>()
            / p.indices.len() as f64;
        let colour = pcl[o.source_polygon[pi] as usize].color;
        if c.truncate().length() < 0.55 && p.normal().z.abs() < 1e-9 {
            walls += 1;
            assert_eq!(colour, DVec3::Z, "a hole wall");
            // The wall faces the axis (inward of the cylinder).
            assert!(p.normal().truncate().dot(c.truncate()) < 0.0);
        } else {
            plate += 1;
            assert_eq!(colour, DVec3::X, "the plate");
        }
    }
    assert_eq!(walls, 24);
    assert!(plate >= 6);
    // The cylinder is curved: the result carries its normals, reversed on
    // the walls (they face the axis).
    let n = o.vertex_normals.as_ref().unwrap();
    assert!(o.surface_type.curved);
    for p in &o.polygons {
        for &i in &p.indices {
            let q = o.vertices[i as usize];
            if (q.truncate().length() - 0.5).abs() < 1e-9 && p.normal().z.abs() < 1e-9 {
                let want = -q.truncate().normalize().extend(0.0);
                assert!(
                    n[i as usize].distance(want) < 1e-9,
                    "{} vs {want}",
                    n[i as usize]
                );
            }
        }
    }
}

#[test]
fn results_are_operands_and_block_transforms_apply() {
    let body = |extra: &str| {
        format!(
            "defobj a\nsphere 12 6\nendobj\ndefobj b\ntranslate 1 0 0\nsphere 12 6\nendobj\n\
             defobj u\nunion a b\nendobj\ndefobj c\ntranslate 0 0 -2\nextrude 2 -3 -3 3 -3 3 3 -3 3\nendobj\n\
             defobj d\n{extra}intersection u c\nendobj"
        )
    };
    let plain = scene(&body(""));
    assert_eq!(plain.objects.len(), 1);
    let d = &plain.objects[0];
    assert!(support::closed(d));
    // The lower half of the union of two spheres.
    let whole = scene(
        "defobj a\nsphere 12 6\nendobj\ndefobj b\ntranslate 1 0 0\nsphere 12 6\nendobj\ndefobj u\nunion a b\nendobj",
    );
    let vu = support::volume(&whole.objects[0]);
    assert!(
        (support::volume(d) - vu / 2.0).abs() < 1e-9,
        "{} {vu}",
        support::volume(d)
    );
    // A translation inside the block moves the result, nothing else.
    let moved = scene(&body("translate 0 5 0\n"));
    let m = &moved.objects[0];
    assert!((support::volume(m) - support::volume(d)).abs() < 1e-9);
    for (p, q) in d.vertices.iter().zip(&m.vertices) {
        assert!((*q - *p - DVec3::new(0.0, 5.0, 0.0)).length() < 1e-9);
    }
}

#[test]
fn bad_csg_is_a_located_error() {
    let box_ = "extrude 1 0 0 1 0 1 1 0 1";
    let cases = [
        (
            format!("defobj a\n{box_}\nendobj\ndefobj r\nunion a nothing\nendobj"),
            "c.des:10:9",
            "no object `nothing`",
        ),
        (
            format!(
                "defobj a\ncylinder 8 open\nendobj\ndefobj b\n{box_}\nendobj\ndefobj r\nunion a b\nendobj"
            ),
            "c.des:13:7",
            "not a closed solid",
        ),
        (
            format!(
                "defobj a\n{box_}\nendobj\ndefobj b\n{box_}\nendobj\ndefobj r\ncolor 1 0 0\nunion a b\nendobj"
            ),
            "c.des:13:1",
            "surface command inside a CSG block",
        ),
        (
            format!(
                "defobj a\n{box_}\nendobj\ndefobj b\n{box_}\nendobj\ndefobj r\nunion a b\ndiffuse 0.5\nendobj"
            ),
            "c.des:14:1",
            "surface command inside a CSG block",
        ),
        (
            format!("defobj a\n{box_}\nendobj\ndefobj r\nunion a a\nendobj"),
            "c.des:10:9",
            "the same object",
        ),
        (
            "defobj r\nunion a\nendobj".to_string(),
            "c.des:7:1",
            "expects 2 arguments",
        ),
    ];
    for (body, at, what) in cases {
        let e = match try_scene(&body) {
            Ok(_) => panic!("accepted:\n{body}"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(at) && e.contains(what), "{body}\n=> {e}");
    }
    // A hand-made open object (one face of a box missing) is refused too.
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(
        dir.path().join("det/tri.det"),
        "title open\ndata\n4 3\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 1 3 2\n3 1 2 4\n3 1 4 3\n",
    )
    .unwrap();
    let path = dir.path().join("c.des");
    std::fs::write(
        &path,
        format!("{PRELUDE}defobj tri\nendobj\ndefobj b\n{box_}\nendobj\ndefobj r\nunion tri b\nendobj\npopmatrix\n"),
    )
    .unwrap();
    let e = plytrace::internal::scene::load(&path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("not a closed solid") && e.contains("hole"),
        "{e}"
    );
}

/// Coplanar faces and touching solids: the documented results.
#[test]
fn coplanar_and_touching_solids() {
    let cube = |x: f64| format!("translate {x} 0 0\nextrude 1 0 0 1 0 1 1 0 1");
    // Overlapping cubes sharing four face planes (same orientation): exact
    // volumes, closed results.
    for (op, want) in [("union", 1.5), ("intersection", 0.5), ("difference", 0.5)] {
        let (o, _) = csg(&cube(0.0), &cube(0.5), op);
        assert!(
            (support::volume(&o) - want).abs() < 1e-12,
            "{op}: {}",
            support::volume(&o)
        );
        assert!(support::closed(&o), "{op}");
    }
    // Identical cubes: union and intersection are the cube, difference is
    // empty (no faces).
    for (op, want) in [("union", 1.0), ("intersection", 1.0), ("difference", 0.0)] {
        let (o, _) = csg(&cube(0.0), &cube(0.0), op);
        assert!(
            (support::volume(&o) - want).abs() < 1e-12,
            "{op}: {}",
            support::volume(&o)
        );
        assert!(support::closed(&o), "{op}");
    }
    // Cubes touching along a face (opposite orientations): the union
    // drops both touching faces (10 faces, volume 2, closed); the
    // intersection is empty; the difference is the first cube.
    for (op, want, faces) in [
        ("union", 2.0, 10),
        ("intersection", 0.0, 0),
        ("difference", 1.0, 6),
    ] {
        let (o, _) = csg(&cube(0.0), &cube(1.0), op);
        assert!(
            (support::volume(&o) - want).abs() < 1e-12,
            "{op}: {}",
            support::volume(&o)
        );
        assert!(support::closed(&o), "{op}");
        assert_eq!(o.polygons.len(), faces, "{op}");
    }
}

/// Inside interval `[t0, t1]` of the ray `o + t d` in the convex object.
fn interval(obj: &Object, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for p in &obj.polygons {
        let (n, w) = (p.normal(), p.plane.w);
        let (a, b) = (n.dot(o) + w, n.dot(d));
        if b.abs() < 1e-300 {
            if a > 0.0 {
                return None;
            }
            continue;
        }
        let t = -a / b;
        if b > 0.0 {
            t1 = t1.min(t);
        } else {
            t0 = t0.max(t);
        }
    }
    (t0 < t1).then_some((t0, t1))
}

/// The first point along the ray inside the Boolean combination.
fn first_inside(op: &str, a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<f64> {
    match op {
        "union" => match (a, b) {
            (Some(a), Some(b)) => Some(a.0.min(b.0)),
            (Some(a), None) => Some(a.0),
            (None, Some(b)) => Some(b.0),
            _ => None,
        },
        "intersection" => {
            let (a, b) = (a?, b?);
            let t = a.0.max(b.0);
            (t < a.1.min(b.1)).then_some(t)
        }
        _ => {
            let a = a?;
            match b {
                Some(b) if b.0 <= a.0 && a.0 < b.1 => (b.1 < a.1).then_some(b.1),
                _ => Some(a.0),
            }
        }
    }
}

#[test]
fn ray_cast_of_the_result_equals_point_classification_of_the_operands() {
    let size = 48u32;
    for (a, b) in PAIRS {
        let operands = scene(&defs(a, b));
        for op in ["union", "intersection", "difference"] {
            let result = scene(&format!("{}defobj r\n{op} a b\nendobj", defs(a, b)));
            let caster = RayCaster::new(&result);
            let mut oracle = Vec::new();
            let mut cast = Vec::new();
            for row in 0..size {
                for col in 0..size {
                    let x = (col as f64 + 0.5) / size as f64 * 2.0 - 1.0;
                    let y = 1.0 - (row as f64 + 0.5) / size as f64 * 2.0;
                    let (o, d) = caster.ray(x, y).unwrap();
                    oracle.push(first_inside(
                        op,
                        interval(&operands.objects[0], o, d),
                        interval(&operands.objects[1], o, d),
                    ));
                    cast.push(caster.cast(o, d).map(|h| h.t));
                }
            }
            // Compare where the oracle's 3x3 neighbourhood agrees on hit or miss.
            let hit: Vec<Option<(u32, u32)>> = oracle.iter().map(|t| t.map(|_| (0, 0))).collect();
            let shown: Vec<Option<(u32, u32)>> = cast.iter().map(|t| t.map(|_| (0, 0))).collect();
            let (checked, bad) = support::mismatches(&hit, &shown, size, size);
            assert!(checked > 1000, "{checked}");
            assert!(
                bad.is_empty(),
                "{op} of\n{a}\n{b}: {} pixels differ, e.g. {:?}",
                bad.len(),
                &bad[..bad.len().min(5)]
            );
            let hits = oracle.iter().filter(|t| t.is_some()).count();
            assert!(hits > 50, "{op}: {hits}");
            // Depths agree wherever both see the solid.
            for (i, (p, q)) in oracle.iter().zip(&cast).enumerate() {
                if let (Some(p), Some(q)) = (p, q) {
                    let (x, y) = (i as u32 % size, i as u32 / size);
                    if bad.contains(&(x, y)) {
                        continue;
                    }
                    assert!((p - q).abs() < 1e-9, "{op} at ({x}, {y}): {p} vs {q}");
                }
            }
        }
    }
}

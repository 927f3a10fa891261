//! Firebaugh's modeling primitives (001 chapter 8) as scene commands, each
//! checked against an independent oracle: the analytic surface (points and
//! normals), analytic volumes computed here by numerical integration, the
//! Hermite basis evaluated here, our own edge counting for closedness, and
//! renders compared with ray casts of the exact solids.

#[path = "../../tests/support/mod.rs"]
mod support;

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::DVec3;
use plytrace::internal::error::Diagnostic;
use plytrace::internal::model::Object;
use plytrace::internal::modeling::parametric::{Superquadric, spow};
use plytrace::internal::modeling::patch::{self, Form};
use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::Scene;

const PRELUDE: &str =
    "resolution 64 64\nperspective 40 1 0.1 100\npolarview 7 30 60 0\npushmatrix\nident\n";

/// Runs `body` (objects defined in object space = world space) with
/// `files` in its `det` directory.
fn try_scene(body: &str, files: &[(&str, &str)]) -> plytrace::Result<(Scene, Vec<Diagnostic>)> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join("det").join(name), text).unwrap();
    }
    let path = dir.path().join("m.des");
    std::fs::write(&path, format!("{PRELUDE}{body}\npopmatrix\n")).unwrap();
    plytrace::internal::scene::load(&path)
}

fn scene(body: &str) -> Scene {
    try_scene(body, &[]).unwrap().0
}

fn one(body: &str) -> Object {
    let s = scene(&format!("defobj thing\n{body}\nendobj"));
    assert_eq!(s.objects.len(), 1);
    s.objects.into_iter().next().unwrap()
}

fn error_of(body: &str, files: &[(&str, &str)]) -> String {
    match try_scene(body, files) {
        Ok(_) => panic!("accepted: {body}"),
        Err(e) => e.to_string(),
    }
}

/// Every polygon's plane faces away from the origin (star-shaped solids
/// about it).
fn outward_about_origin(o: &Object) -> bool {
    o.polygons.iter().all(|p| {
        let c: DVec3 = p
            .indices
            .iter()
            .map(|&i| o.vertices[i as usize])
            .sum::<DVec3>()
            / p.indices.len() as f64;
        p.normal().dot(c) > 0.0
    })
}

/// Implicit superquadric function (1 on the surface).
fn inside_outside(q: &Superquadric, p: DVec3) -> f64 {
    let (x, y, z) = (
        (p.x / q.a.x).abs(),
        (p.y / q.a.y).abs(),
        (p.z / q.a.z).abs(),
    );
    (x.powf(2.0 / q.e2) + y.powf(2.0 / q.e2)).powf(q.e2 / q.e1) + z.powf(2.0 / q.e1)
}

/// Superquadric volume by numerical integration over z of the
/// superellipse sections (midpoint rule, no Gamma functions).
fn integrated_volume(q: &Superquadric) -> f64 {
    let n = 2.0 / q.e2;
    let steps = 4000;
    // Area of the unit superellipse |x|^n + |y|^n <= 1.
    let unit: f64 = (0..steps)
        .map(|i| {
            let x = (i as f64 + 0.5) / steps as f64;
            (1.0 - x.powf(n)).max(0.0).powf(1.0 / n) / steps as f64
        })
        .sum::<f64>()
        * 4.0;
    (0..steps)
        .map(|i| {
            let z = (i as f64 + 0.5) / steps as f64;
            // Section radius R: (|x|^n + |y|^n) = R^n, R = (1 - z^(2/e1))^(e1/2).
            let r = (1.0 - z.powf(2.0 / q.e1)).max(0.0).powf(q.e1 / 2.0);
            unit * r * r / steps as f64
        })
        .sum::<f64>()
        * 2.0
        * q.a.x
        * q.a.y
        * q.a.z
}

#[test]
fn sphere_points_and_normals_are_exact() {
    let o = one("sphere 16 9");
    assert_eq!(o.polygons.len(), 16 * 9);
    for (v, n) in o.vertices.iter().zip(o.vertex_normals.as_ref().unwrap()) {
        assert!((v.length() - 1.0).abs() < 1e-9, "{v}");
        assert!(n.distance(*v) < 1e-9, "{n} at {v}");
    }
    assert!(o.surface_type.curved && !o.surface_type.open);
    assert!(support::closed(&o) && outward_about_origin(&o));
}

#[test]
fn superquadric_points_lie_on_the_surface_and_normals_follow_8_23() {
    for (e1, e2, a) in [
        (0.5, 1.0, DVec3::ONE),
        (1.0, 0.25, DVec3::new(1.0, 2.0, 0.5)),
        (0.3, 0.3, DVec3::ONE),
        (2.5, 3.0, DVec3::new(2.0, 1.0, 1.5)),
    ] {
        let q = Superquadric { e1, e2, a };
        let o = one(&format!(
            "superquadric {e1} {e2} 12 8 {} {} {}",
            a.x, a.y, a.z
        ));
        for v in &o.vertices {
            assert!(
                (inside_outside(&q, *v) - 1.0).abs() < 1e-9,
                "{e1} {e2}: {v}"
            );
        }
        let normals = o.vertex_normals.as_ref().unwrap();
        assert!(
            normals
                .iter()
                .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-9)
        );
        assert!(support::closed(&o) && outward_about_origin(&o), "{e1} {e2}");
        // Normals against the cross product of the parametrization's
        // numerical derivatives (eq. 8.22), at points off the axes.
        for (s, t) in [(0.3, 0.2), (2.0, -0.7), (4.0, 1.1), (5.5, -0.1)] {
            let h = 1e-6;
            let ds = (q.point(s + h, t) - q.point(s - h, t)) / (2.0 * h);
            let dt = (q.point(s, t + h) - q.point(s, t - h)) / (2.0 * h);
            let want = ds.cross(dt).normalize();
            let got = q.normal(s, t);
            assert!(
                got.distance(want) < 1e-5,
                "{e1} {e2} at ({s}, {t}): {got} vs {want}"
            );
            // And 8.23 as written, normalized.
            let (ct, st, cs, ss) = (t.cos(), t.sin(), s.cos(), s.sin());
            let n = DVec3::new(
                spow(ct, 2.0 - e1) * spow(cs, 2.0 - e2) / a.x,
                spow(ct, 2.0 - e1) * spow(ss, 2.0 - e2) / a.y,
                spow(st, 2.0 - e1) / a.z,
            )
            .normalize();
            assert!(got.distance(n) < 1e-12);
        }
        // On the axes (singular for E > 2) the limit is finite.
        for (s, t) in [
            (0.0, 0.0),
            (FRAC_PI_2, 0.3),
            (PI, FRAC_PI_2),
            (0.4, -FRAC_PI_2),
        ] {
            assert!(q.normal(s, t).is_finite());
        }
    }
}

#[test]
fn volumes_converge_to_the_analytic_volumes() {
    let check = |name: &str, exact: f64, bodies: [String; 3]| {
        let errors: Vec<f64> = bodies
            .iter()
            .map(|b| {
                let o = one(b);
                assert!(support::closed(&o), "{name} {b}");
                (support::volume(&o) - exact).abs() / exact
            })
            .collect();
        assert!(
            errors[0] > errors[1] && errors[1] > errors[2] && errors[2] < 2e-3,
            "{name}: relative errors {errors:?}"
        );
    };
    check(
        "sphere",
        4.0 / 3.0 * PI,
        [
            "sphere 8 4".into(),
            "sphere 32 16".into(),
            "sphere 128 64".into(),
        ],
    );
    check(
        "cylinder",
        2.0 * PI,
        [
            "cylinder 8".into(),
            "cylinder 32".into(),
            "cylinder 128".into(),
        ],
    );
    // Figure 8.9's families, and one with scale factors.
    for (e1, e2, a) in [
        (0.5, 1.0, "1 1 1"),
        (1.0, 0.5, "1 1 1"),
        (0.5, 0.5, "1 1 1"),
        (1.0, 1.0, "2 1 0.5"),
        (1.5, 1.0, "1 1 1"),
    ] {
        let s: Vec<f64> = a.split(' ').map(|x| x.parse().unwrap()).collect();
        let q = Superquadric {
            e1,
            e2,
            a: DVec3::new(s[0], s[1], s[2]),
        };
        let exact = integrated_volume(&q);
        // The library's closed form agrees with the integral.
        assert!(
            (q.volume() - exact).abs() / exact < 1e-4,
            "{} {exact}",
            q.volume()
        );
        check(
            &format!("superquadric {e1} {e2}"),
            exact,
            [16, 64, 256].map(|n| format!("superquadric {e1} {e2} {n} {} {a}", n / 2)),
        );
    }
    // Lathe: a cone (r 1, height 1) closed on the axis at both ends.
    check(
        "lathe cone",
        PI / 3.0,
        [8, 32, 128].map(|n| format!("lathe {n} 0 0 1 0 0 1")),
    );
}

#[test]
fn lathe_and_extrude_volumes_are_exact_for_their_polygons() {
    // A prism of n sides: volume n/2 sin(2 pi/n) r^2 h, whatever the
    // profile direction or capping.
    let n = 12.0;
    let prism = n / 2.0 * (TAU / n).sin() * 2.0;
    for body in [
        "lathe 12 0 0 1 0 1 2 0 2",
        "lathe 12 0 2 1 2 1 0 0 0",
        "lathe 12 1 0 1 2",
        "lathe 12 1 2 1 0",
        "lathe 12 0 0 1 0 1 2",
    ] {
        let o = one(body);
        assert!(support::closed(&o), "{body}");
        assert!(
            (support::volume(&o) - prism).abs() < 1e-12,
            "{body}: {}",
            support::volume(&o)
        );
        assert!(o.surface_type.curved);
    }
    // A ring (tube): profile off the axis, a square section.
    let o = one("lathe 24 1 0 2 0 2 1 1 1 1 0");
    assert!(support::closed(&o));
    let ring = 24.0 / 2.0 * (TAU / 24.0).sin() * (4.0 - 1.0);
    assert!(
        (support::volume(&o) - ring).abs() < 1e-12,
        "{}",
        support::volume(&o)
    );
    // An extruded L (area 3) either way round, with a closing point.
    for body in [
        "extrude 0.5 0 0 2 0 2 1 1 1 1 2 0 2",
        "extrude 0.5 0 2 1 2 1 1 2 1 2 0 0 0 0 2",
    ] {
        let o = one(body);
        assert!(support::closed(&o), "{body}");
        assert!(
            (support::volume(&o) - 1.5).abs() < 1e-12,
            "{body}: {}",
            support::volume(&o)
        );
        assert!(!o.surface_type.curved && o.vertex_normals.is_none());
    }
}

#[test]
fn open_cylinder_is_two_sided_and_capped_one_is_closed() {
    let o = one("cylinder 10 open");
    assert!(o.surface_type.open && !support::closed(&o));
    assert_eq!(o.polygons.len(), 10);
    let o = one("cylinder 10 capped");
    assert!(!o.surface_type.open && support::closed(&o) && outward_about_origin(&o));
    // Side normals are radial, cap normals along z.
    let n = o.vertex_normals.as_ref().unwrap();
    for (v, n) in o.vertices.iter().zip(n) {
        let radial = DVec3::new(v.x, v.y, 0.0);
        assert!(n.distance(radial) < 1e-12 || n.distance(DVec3::Z * v.z.signum()) < 1e-12);
    }
}

#[test]
fn transforms_move_points_and_normals() {
    let o = one("translate 1 2 3\nscale 2 1 1\nsphere 8 4");
    let normals = o.vertex_normals.as_ref().unwrap();
    for (v, n) in o.vertices.iter().zip(normals) {
        let p = *v - DVec3::new(1.0, 2.0, 3.0);
        // The ellipsoid (x/2)^2 + y^2 + z^2 = 1 and its gradient.
        assert!(((p.x / 2.0).powi(2) + p.y * p.y + p.z * p.z - 1.0).abs() < 1e-9);
        let g = DVec3::new(p.x / 4.0, p.y, p.z).normalize();
        assert!(n.distance(g) < 1e-9, "{n} vs {g}");
    }
}

/// The Hermite basis, evaluated directly (eq. 8.16-8.17): h1 = 2s^3 -
/// 3s^2 + 1, h2 = -2s^3 + 3s^2, h3 = s^3 - 2s^2 + s, h4 = s^3 - s^2.
fn hermite_point(g: &[[DVec3; 4]; 4], s: f64, t: f64) -> DVec3 {
    let h = |u: f64| {
        [
            2.0 * u * u * u - 3.0 * u * u + 1.0,
            -2.0 * u * u * u + 3.0 * u * u,
            u * u * u - 2.0 * u * u + u,
            u * u * u - u * u,
        ]
    };
    let (hs, ht) = (h(s), h(t));
    let mut p = DVec3::ZERO;
    for i in 0..4 {
        for j in 0..4 {
            p += g[i][j] * (hs[i] * ht[j]);
        }
    }
    p
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

fn points_text(g: &[[DVec3; 4]; 4]) -> String {
    g.iter()
        .flatten()
        .map(|p| format!("{} {} {}\n", p.x, p.y, p.z))
        .collect()
}

#[test]
fn hermite_patch_equals_its_bezier_conversion_and_the_basis() {
    let mut seed = 7;
    let mut g = [[DVec3::ZERO; 4]; 4];
    for (i, row) in g.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            *p = DVec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed))
                + if i < 2 && j < 2 {
                    DVec3::new(i as f64 * 2.0, j as f64 * 2.0, 0.0)
                } else {
                    DVec3::ZERO
                };
        }
    }
    // The Bezier points of the same cubic: per curve B1 = P0 + P0'/3,
    // B2 = P1 - P1'/3, written out here along s, then along t.
    let conv = |p0: DVec3, p1: DVec3, d0: DVec3, d1: DVec3| [p0, p0 + d0 / 3.0, p1 - d1 / 3.0, p1];
    let mut cols = [[DVec3::ZERO; 4]; 4]; // cols[i][j]: s converted, t still Hermite.
    for j in 0..4 {
        let c = conv(g[0][j], g[1][j], g[2][j], g[3][j]);
        for i in 0..4 {
            cols[i][j] = c[i];
        }
    }
    let mut b = [[DVec3::ZERO; 4]; 4];
    for i in 0..4 {
        b[i] = conv(cols[i][0], cols[i][1], cols[i][2], cols[i][3]);
    }
    let hpt = format!("1\n{}", points_text(&g));
    let bpt = format!("1\n3 3\n{}", points_text(&b));
    let files = [("h.hpt", hpt.as_str()), ("b.bpt", bpt.as_str())];
    let (s, _) = try_scene(
        "defobj h\nhermite h.hpt 6 5\nendobj\ndefobj b\nbezier b.bpt 6 5\nendobj",
        &files,
    )
    .unwrap();
    let (h, bz) = (&s.objects[0], &s.objects[1]);
    assert_eq!(h.vertices.len(), 7 * 6);
    assert_eq!(h.polygons.len(), 2 * 6 * 5);
    assert!(h.surface_type.open && h.surface_type.curved);
    for (p, q) in h.vertices.iter().zip(&bz.vertices) {
        assert!(p.distance(*q) < 1e-12, "{p} {q}");
    }
    // Every Hermite vertex is on the patch of the basis functions.
    for i in 0..=6 {
        for j in 0..=5 {
            let want = hermite_point(&g, i as f64 / 6.0, j as f64 / 5.0);
            assert!(
                h.vertices.iter().any(|v| v.distance(want) < 1e-12),
                "({i}, {j}): {want}"
            );
        }
    }
}

/// A closed surface of Bezier patches: the 6 faces of a cube, each a
/// bilinear patch written as bicubic.
fn cube_patches() -> String {
    let mut text = String::from("6\n");
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            text += "3 3\n";
            for i in 0..4 {
                for j in 0..4 {
                    let (u, v) = (i as f64 / 1.5 - 1.0, j as f64 / 1.5 - 1.0);
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[(axis + 1) % 3] = u;
                    p[(axis + 2) % 3] = v * side;
                    text += &format!("{} {} {}\n", p[0], p[1], p[2]);
                }
            }
        }
    }
    text
}

#[test]
fn closed_patch_surfaces_are_oriented_outward() {
    let text = cube_patches();
    let (s, _) = try_scene(
        "defobj c\nbezier cube.bpt 3 3\nendobj",
        &[("cube.bpt", &text)],
    )
    .unwrap();
    let o = &s.objects[0];
    assert!(!o.surface_type.open, "closed patches are one-sided");
    assert!(support::closed(o));
    assert!(
        (support::volume(o) - 8.0).abs() < 1e-12,
        "{}",
        support::volume(o)
    );
    assert!(outward_about_origin(o));
}

#[test]
fn patch_continuity_is_checked() {
    // Two patches sharing the edge s = 1 / s = 0; the second continues the
    // first's control polygon across it (C1), then is bent (C0 only).
    let row = |x0: f64, k: f64| -> String {
        (0..4)
            .flat_map(|i| {
                (0..4).map(move |j| {
                    let x = x0 + i as f64;
                    let z = if x0 > 0.0 && i >= 1 {
                        k * (i as f64)
                    } else {
                        0.0
                    };
                    format!("{x} {j} {z}\n")
                })
            })
            .collect()
    };
    for (k, c1) in [(0.0, true), (0.5, false)] {
        let text = format!("2\n3 3\n{}3 3\n{}", row(0.0, 0.0), row(3.0, k));
        let set = patch::parse(&text, "two.bpt".as_ref(), Form::Bezier, |_| Ok(())).unwrap();
        let r = patch::continuity(&set);
        assert_eq!(r.joins.len(), 1, "{r:?}");
        assert!(r.c0(1e-9));
        assert_eq!(r.c1(1e-9), c1, "{r:?}");
    }
}

#[test]
fn bad_parameters_are_located_errors() {
    let cases: &[(&str, &str)] = &[
        ("defobj a\nsphere 2 4\nendobj", "m.des:7:8"),
        ("defobj a\nsphere 8 1\nendobj", "m.des:7:10"),
        ("defobj a\ncylinder 2\nendobj", "m.des:7:10"),
        (
            "defobj a\ncylinder 8 half\nendobj",
            "expected `capped` or `open`",
        ),
        (
            "defobj a\nsuperquadric 0 1 8 4\nendobj",
            "E1 must be positive",
        ),
        (
            "defobj a\nsuperquadric 1 1 8 4 1 1\nendobj",
            "all three scale factors",
        ),
        ("defobj a\nlathe 2 0 0 1 0 0 1\nendobj", "m.des:7:7"),
        ("defobj a\nlathe 8 0 0 -1 0 0 1\nendobj", "negative"),
        (
            "defobj a\nlathe 8 0 0 1 0 0 1 1 2\nendobj",
            "only at the ends",
        ),
        ("defobj a\nlathe 8 0 0 1 0 1 1 2\nendobj", "no partner"),
        (
            "defobj a\nextrude 1 0 0 1 1 1 0 0 1\nendobj",
            "intersects itself",
        ),
        ("defobj a\nextrude 1 0 0 1 0 2 0\nendobj", "zero area"),
        (
            "defobj a\nextrude 1 0 0 1 0 0 0\nendobj",
            "at least 3 distinct",
        ),
        (
            "defobj a\nextrude 0 0 0 1 0 1 1\nendobj",
            "DEPTH must be positive",
        ),
        ("sphere 8 4", "outside an object definition"),
        ("defobj a\nsphere 8 4\ncylinder 8\nendobj", "one generator"),
        ("defobj a\nsphere 100000 100000\nendobj", "--max-polygons"),
        ("defobj a\nbezier nothere.bpt 4 4\nendobj", "not found"),
    ];
    for (body, want) in cases {
        let e = error_of(body, &[]);
        assert!(e.contains(want), "{body}: {e}");
        assert!(e.contains("m.des:"), "{body}: {e}");
    }
}

#[test]
fn patch_files_with_the_wrong_number_of_points_are_refused() {
    let short = "1\n3 3\n0 0 0\n1 0 0\n";
    let e = error_of("defobj a\nbezier s.bpt 4 4\nendobj", &[("s.bpt", short)]);
    assert!(e.contains("s.bpt:") && e.contains("16 points"), "{e}");
    assert!(e.contains("m.des:7"), "names the command: {e}");
    let degrees = format!("1\n3 2\n{}", "0 0 0\n".repeat(16));
    let e = error_of("defobj a\nbezier d.bpt 4 4\nendobj", &[("d.bpt", &degrees)]);
    assert!(e.contains("d.bpt:2:3") && e.contains("`3 3`"), "{e}");
    let long = format!("1\n{}", "0 0 0\n".repeat(17));
    let e = error_of("defobj a\nhermite l.hpt 4 4\nendobj", &[("l.hpt", &long)]);
    assert!(e.contains("l.hpt:18:1") && e.contains("17 points"), "{e}");
    // The budget refuses a huge patch count before reading the points.
    let huge = "1000000000\n3 3\n";
    let e = error_of("defobj a\nbezier h.bpt 64 64\nendobj", &[("h.bpt", huge)]);
    assert!(e.contains("--max-polygons"), "{e}");
}

/// Renders `body` flat (id image) and compares each pixel with the exact
/// solid: pixels whose ray meets the solid shrunk by the tessellation error
/// (`inner`) must show it, pixels whose ray misses the exact solid
/// (`outer`) must not; the band between is the tessellation error.
fn render_matches_exact(
    body: &str,
    inner: impl Fn(DVec3, DVec3) -> bool,
    outer: impl Fn(DVec3, DVec3) -> bool,
) {
    render_matches_exact_with(body, &[], inner, outer);
}

/// [`render_matches_exact`] with `files` in the scene's `det` directory.
fn render_matches_exact_with(
    body: &str,
    files: &[(&str, &str)],
    inner: impl Fn(DVec3, DVec3) -> bool,
    outer: impl Fn(DVec3, DVec3) -> bool,
) {
    let s = try_scene(&format!("defobj thing\n{body}\nendobj"), files)
        .unwrap()
        .0;
    let size = 64;
    // Point sampled: the id of a pixel is the polygon at its centre, as
    // the oracle's ray asks. (Method 4 gives a pixel covered only by
    // slivers that miss all 16 subpixel centres, as near the ellipsoid's
    // poles, the background's id while its colour is right.)
    let options = RenderOptions {
        size: Some((size, size)),
        aa: Some(plytrace::internal::raster::scan::Method::Point),
        ..RenderOptions::default()
    };
    let painted = support::painted_ids(&render(&s, &options).unwrap());
    let inv = support::invert(&s.projection).unwrap();
    let (mut checked, mut bad) = (0, Vec::new());
    for row in 0..size {
        for col in 0..size {
            let x = (col as f64 + 0.5) / size as f64 * 2.0 - 1.0;
            let y = 1.0 - (row as f64 + 0.5) / size as f64 * 2.0;
            let o = support::unproject(&inv, x, y, -1.0);
            let d = (support::unproject(&inv, x, y, 1.0) - o).normalize();
            let shown = painted[(row * size + col) as usize].is_some();
            let want = if inner(o, d) {
                true
            } else if !outer(o, d) {
                false
            } else {
                continue;
            };
            checked += 1;
            if shown != want {
                bad.push((col, row));
            }
        }
    }
    assert!(
        checked > size as usize * size as usize / 2,
        "{body}: {checked}"
    );
    assert!(
        bad.is_empty(),
        "{body}: {} of {checked} differ, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

/// Whether the ray `o + t d` (unit `d`) meets the sphere of radius `r`.
fn hits_sphere(o: DVec3, d: DVec3, r: f64) -> bool {
    let b = o.dot(d);
    b * b - (o.length_squared() - r * r) >= 0.0 && -b > 0.0
}

/// Whether the ray `o + t d` meets the solid cone with its apex at
/// (0, 0, 1) and a base of radius `r` at z = -1: its side (the quadratic
/// x^2 + y^2 = (r (1 - z) / 2)^2 within -1 <= z <= 1) or its base disc.
fn hits_cone(o: DVec3, d: DVec3, r: f64) -> bool {
    let k = r / 2.0;
    let (a, b, c) = (
        d.x * d.x + d.y * d.y - k * k * d.z * d.z,
        2.0 * (o.x * d.x + o.y * d.y + k * k * (1.0 - o.z) * d.z),
        o.x * o.x + o.y * o.y - k * k * (1.0 - o.z) * (1.0 - o.z),
    );
    let disc = b * b - 4.0 * a * c;
    let side = disc >= 0.0
        && [-1.0, 1.0].iter().any(|s| {
            let t = (-b + s * disc.sqrt()) / (2.0 * a);
            t > 0.0 && (-1.0..=1.0).contains(&(o.z + t * d.z))
        });
    let t = (-1.0 - o.z) / d.z;
    let p = o + t * d;
    side || (t > 0.0 && p.x * p.x + p.y * p.y <= r * r)
}

/// Whether the ray meets the cylinder of radius `r`, |z| <= 1.
fn hits_cylinder(o: DVec3, d: DVec3, r: f64) -> bool {
    // Interval inside the infinite cylinder, then clipped to the slab.
    let (a, b, c) = (
        d.x * d.x + d.y * d.y,
        o.x * d.x + o.y * d.y,
        o.x * o.x + o.y * o.y - r * r,
    );
    let (t0, t1) = if a < 1e-15 {
        if c > 0.0 {
            return false;
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
    } else {
        let disc = b * b - a * c;
        if disc < 0.0 {
            return false;
        }
        ((-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a)
    };
    let (z0, z1) = if d.z.abs() < 1e-15 {
        if o.z.abs() > 1.0 {
            return false;
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
    } else {
        let (p, q) = ((-1.0 - o.z) / d.z, (1.0 - o.z) / d.z);
        (p.min(q), p.max(q))
    };
    t0.max(z0) <= t1.min(z1) && t1.min(z1) > 0.0
}

#[test]
fn renders_match_ray_casts_of_the_exact_solids() {
    // Sphere 24 x 12: every face plane is at least this far from the centre.
    let o = one("sphere 24 12");
    let inner = o
        .polygons
        .iter()
        .map(|p| -p.plane.w)
        .fold(f64::INFINITY, f64::min);
    assert!(inner > 0.95 && inner < 1.0, "{inner}");
    render_matches_exact(
        "sphere 24 12",
        |o, d| hits_sphere(o, d, inner - 1e-6),
        |o, d| hits_sphere(o, d, 1.0 + 1e-6),
    );
    // An extruded square is its exact solid: only rounding between.
    let hits_box = |o: DVec3, d: DVec3, grow: f64| {
        let (lo, hi) = (
            DVec3::new(-1.0, -1.0, 0.0) - grow,
            DVec3::new(1.0, 1.0, 1.0) + grow,
        );
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for k in 0..3 {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    };
    render_matches_exact(
        "extrude 1 -1 -1 1 -1 1 1 -1 1",
        |o, d| hits_box(o, d, -1e-6),
        |o, d| hits_box(o, d, 1e-6),
    );
    // A superquadric with E1 = E2 = 1 and scale factors is an ellipsoid:
    // the sphere's tessellation stretched, so the same bounds stretched.
    let scale = DVec3::new(1.4, 0.8, 0.6);
    render_matches_exact(
        "superquadric 1 1 24 12 1.4 0.8 0.6",
        |o, d| hits_sphere(o / scale, (d / scale).normalize(), inner - 1e-6),
        |o, d| hits_sphere(o / scale, (d / scale).normalize(), 1.0 + 1e-6),
    );
    // A lathe of a straight profile from the apex to the rim is a cone:
    // its 24 facets lie between the cones of the rim's inscribed and
    // circumscribed circles.
    let inscribed = (PI / 24.0).cos();
    render_matches_exact(
        "lathe 24 0 1 1 -1",
        |o, d| hits_cone(o, d, inscribed - 1e-6),
        |o, d| hits_cone(o, d, 1.0 + 1e-6),
    );
    // Patches whose control points (Bezier) or geometry matrix (Hermite)
    // describe the flat square |x|, |y| <= 1.5 at z = 0: the surface is
    // that square exactly, two-sided (an open patch).
    let in_square = |o: DVec3, d: DVec3, half: f64| {
        let t = -o.z / d.z;
        let p = o + t * d;
        t > 0.0 && p.x.abs() <= half && p.y.abs() <= half
    };
    let mut bpt = String::from("1\n3 3\n");
    for i in 0..4 {
        for j in 0..4 {
            bpt.push_str(&format!("{} {} 0\n", i as f64 - 1.5, j as f64 - 1.5));
        }
    }
    let hpt = "1\n-1.5 -1.5 0\n-1.5 1.5 0\n0 3 0\n0 3 0\n\
               1.5 -1.5 0\n1.5 1.5 0\n0 3 0\n0 3 0\n\
               3 0 0\n3 0 0\n0 0 0\n0 0 0\n\
               3 0 0\n3 0 0\n0 0 0\n0 0 0\n";
    for (body, name, text) in [
        ("bezier sq.bpt 5 4", "sq.bpt", bpt.as_str()),
        ("hermite sq.hpt 5 4", "sq.hpt", hpt),
    ] {
        render_matches_exact_with(
            body,
            &[(name, text)],
            |o, d| in_square(o, d, 1.5 - 1e-6),
            |o, d| in_square(o, d, 1.5 + 1e-6),
        );
    }
    let c = (PI / 24.0).cos();
    render_matches_exact(
        "cylinder 24",
        |o, d| hits_cylinder(o, d, c - 1e-6),
        |o, d| hits_cylinder(o, d, 1.0 + 1e-6),
    );
}

#[test]
fn the_example_scene_builds_closed_solids() {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("examples/primitives.des");
    let (s, warnings, notes) = plytrace::internal::scene::load_with_notes(&path).unwrap();
    // 9 superquadrics, vase, letter, bolt, die, wave, ripple, post, knob.
    assert_eq!(s.objects.len(), 17, "{warnings:?}");
    for o in &s.objects {
        if o.name == "wave" || o.name == "ripple" {
            assert!(o.surface_type.open, "{}", o.name);
        } else {
            assert!(support::closed(o) && support::volume(o) > 0.0, "{}", o.name);
        }
    }
    let csg = notes
        .iter()
        .filter(|w| w.message.contains("input faces kept"))
        .count();
    assert_eq!(csg, 4);
    assert!(
        warnings.iter().all(|w| !w.message.contains("not closed")),
        "{warnings:?}"
    );
}

#[test]
fn continuity_subcommand_reports_c0_and_c1() {
    let bin = env!("CARGO_BIN_EXE_plytrace");
    let wave = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("examples/det/wave.bpt");
    let out = std::process::Command::new(bin)
        .arg("continuity")
        .arg(&wave)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("4 shared edges") && text.contains("C1 everywhere: yes"),
        "{text}"
    );
    // P21 of the first patch (line 14) lifted: still C0, not C1 across
    // its edge s = 1.
    let bent: String = std::fs::read_to_string(&wave)
        .unwrap()
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 13 {
                "-0.666667 -1.33333 1.24\n".to_string()
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bent.bpt");
    std::fs::write(&p, bent).unwrap();
    let out = std::process::Command::new(bin)
        .arg("continuity")
        .arg(&p)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("C0 everywhere: yes") && text.contains("C1 everywhere: NO"),
        "{text}"
    );
    let out = std::process::Command::new(bin)
        .args(["continuity", "nothere.bpt"])
        .output()
        .unwrap();
    assert!(!out.status.success());
}

//! Hostile inputs for the vector outputs: the hidden-line search against
//! its brute force, and its time on identical faces and fans.

use plytrace::internal::vector::hidden_line::{segments_brute_force, segments_of};
use proptest::prelude::*;

type Pt = [f64; 2];
type Faces = Vec<(Vec<Pt>, Vec<bool>)>;

fn dist(x: Pt, s: &[Pt; 2]) -> f64 {
    let (p, q) = (s[0], s[1]);
    let d = [q[0] - p[0], q[1] - p[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 {
        (((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x[0] - p[0] - d[0] * t).hypot(x[1] - p[1] - d[1] * t)
}

fn drawn(x: Pt, segs: &[[Pt; 2]]) -> bool {
    segs.iter().any(|s| dist(x, s) < 1e-6)
}

/// Every flagged edge, sampled: drawn by one exactly when by the other.
fn same_drawing(faces: &Faces, fast: &[[Pt; 2]], brute: &[[Pt; 2]]) -> Result<(), String> {
    for (pts, flags) in faces {
        for e in 0..pts.len() {
            if !flags[e] {
                continue;
            }
            let (a, b) = (pts[e], pts[(e + 1) % pts.len()]);
            for k in 0..61 {
                let t = (k as f64 + 0.37) / 61.0;
                let x = [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
                let (f, g) = (drawn(x, fast), drawn(x, brute));
                if f != g {
                    return Err(format!("{x:?} on {a:?}-{b:?}: fast {f}, brute force {g}"));
                }
            }
        }
    }
    Ok(())
}

/// Faces on a coarse lattice (shared vertices, collinear and identical
/// edges), fans about a common vertex and copies of earlier faces.
fn scene() -> impl Strategy<Value = Faces> {
    let pt = (0..9i32, 0..9i32).prop_map(|(x, y)| [x as f64 * 12.5, y as f64 * 12.5]);
    let face = prop_oneof![
        // A triangle.
        (pt.clone(), pt.clone(), pt.clone()).prop_map(|(a, b, c)| vec![a, b, c]),
        // An axis-aligned rectangle.
        (pt.clone(), 1..5i32, 1..5i32).prop_map(|(a, w, h)| {
            let (w, h) = (w as f64 * 12.5, h as f64 * 12.5);
            vec![a, [a[0] + w, a[1]], [a[0] + w, a[1] + h], [a[0], a[1] + h]]
        }),
        // A wedge of a fan about the centre.
        (0..24i32, 1..4i32).prop_map(|(k, n)| {
            let at = |k: i32| {
                let a = k as f64 * std::f64::consts::TAU / 24.0;
                [50.0 + 40.0 * a.cos(), 50.0 + 40.0 * a.sin()]
            };
            vec![[50.0, 50.0], at(k), at(k + n)]
        }),
    ];
    let flagged = (face, any::<u8>()).prop_map(|(pts, bits)| {
        let flags = (0..pts.len())
            .map(|k| bits & (1 << k) != 0 || bits > 200)
            .collect();
        (pts, flags)
    });
    (
        prop::collection::vec(flagged, 1..40),
        prop::collection::vec(any::<prop::sample::Index>(), 0..20),
    )
        .prop_map(|(mut faces, copies)| {
            for c in copies {
                let f = faces[c.index(faces.len())].clone();
                let at = c.index(faces.len() + 1);
                faces.insert(at, f);
            }
            faces
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn hidden_lines_match_the_brute_force(faces in scene()) {
        let fast = segments_of(&faces, 100.0, 100.0).unwrap();
        let brute = segments_brute_force(&faces);
        prop_assert!(same_drawing(&faces, &fast, &brute).is_ok(), "{:?}", same_drawing(&faces, &fast, &brute));
    }
}

fn timed(faces: &Faces) -> (usize, std::time::Duration) {
    let t = std::time::Instant::now();
    let segs = segments_of(faces, 256.0, 256.0).unwrap();
    (segs.len(), t.elapsed())
}

#[test]
fn identical_triangles_cost_one_triangle() {
    let tri = vec![[28.0, 200.0], [128.0, 28.0], [228.0, 200.0]];
    let faces: Faces = vec![(tri, vec![true; 3]); 65_535];
    let (n, time) = timed(&faces);
    assert_eq!(n, 3);
    assert!(time.as_secs_f64() < 5.0, "{time:?}");
}

#[test]
fn a_fan_of_150000_triangles_is_near_linear() {
    let n = 150_000;
    let at = |k: usize| {
        let a = k as f64 * std::f64::consts::TAU / n as f64;
        [128.0 + 77.0 * a.cos(), 128.0 + 77.0 * a.sin()]
    };
    let faces: Faces = (0..n)
        .map(|k| (vec![[128.0, 128.0], at(k + 1), at(k)], vec![true; 3]))
        .collect();
    let (segs, time) = timed(&faces);
    assert!(segs >= n, "{segs}");
    assert!(time.as_secs_f64() < 10.0, "{time:?}");
}

/// Runs `plytrace` on a scene of one det object made of `polygons` over
/// `points`, with `args`; returns its status, stderr and the time taken.
fn run_det(
    points: &[[f64; 3]],
    polygons: &[Vec<usize>],
    args: &[&str],
) -> (std::process::ExitStatus, String, std::time::Duration) {
    use std::fmt::Write as _;
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    let mut det = format!("title hostile\ndata\n{} {}\n", points.len(), polygons.len());
    for p in points {
        writeln!(det, "{} {} {}", p[0], p[1], p[2]).unwrap();
    }
    for p in polygons {
        write!(det, "{}", p.len()).unwrap();
        for i in p {
            write!(det, " {}", i + 1).unwrap();
        }
        det.push('\n');
    }
    std::fs::write(dir.path().join("det/thing.det"), det).unwrap();
    std::fs::write(
        dir.path().join("scene.des"),
        "resolution 256 256\nperspective 45 1 0.01 100\npushmatrix\nident\ntranslate 0 0 -4\n\
         light 0 0 10 1 1 1 100 Point\ngetobj thing\npopmatrix\n",
    )
    .unwrap();
    let t = std::time::Instant::now();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_plytrace"))
        .current_dir(dir.path())
        .arg("scene.des")
        .args(args)
        .output()
        .unwrap();
    (
        out.status,
        String::from_utf8_lossy(&out.stderr).into_owned() + &String::from_utf8_lossy(&out.stdout),
        t.elapsed(),
    )
}

#[test]
fn hidden_lines_of_65535_identical_triangles_in_seconds() {
    let points = [[-1.0, -1.0, 0.0], [0.0, 1.0, 0.0], [1.0, -1.0, 0.0]];
    let polygons = vec![vec![0, 1, 2]; 65_535];
    let (status, log, time) = run_det(&points, &polygons, &["--hidden-line", "-o", "s.svg", "-3"]);
    assert!(status.success(), "{log}");
    // NNS sorted them itself, without falling back.
    assert!(!log.contains("NNS stopped"), "{log}");
    assert!(time.as_secs_f64() < 15.0, "{time:?}\n{log}");
}

#[test]
fn hidden_lines_of_a_150000_triangle_fan_in_seconds() {
    let n = 150_000;
    let mut points = vec![[0.0, 0.0, 0.0]];
    for k in 0..=n {
        let a = k as f64 * std::f64::consts::TAU / n as f64;
        points.push([a.cos(), a.sin(), 0.0]);
    }
    let polygons: Vec<Vec<usize>> = (0..n).map(|k| vec![0, k + 2, k + 1]).collect();
    let (status, log, time) = run_det(&points, &polygons, &["--hidden-line", "-o", "f.svg", "-3"]);
    assert!(status.success(), "{log}");
    assert!(!log.contains("NNS stopped"), "{log}");
    assert!(time.as_secs_f64() < 20.0, "{time:?}\n{log}");
}

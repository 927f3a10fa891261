//! Hostile input for the modeling primitives (Firebaugh 001 chapter 8):
//! sizes that were quadratic, budgets that refuse before allocating, and
//! CSG results that must stay closed solids.

use glam::{DVec2, DVec3};
use plytrace::internal::modeling::Generated;
use plytrace::internal::modeling::csg::{self, Face, Op};
use plytrace::internal::modeling::{parametric, solid};

/// A generated solid as CSG faces, scaled by `scale` and moved by `offset`.
fn faces(g: &Generated, scale: f64, offset: DVec3) -> Vec<Face> {
    g.mesh
        .polygons
        .iter()
        .map(|p| Face {
            points: p
                .iter()
                .map(|&i| g.mesh.vertices[i as usize] * scale + offset)
                .collect(),
            normals: match &g.normals {
                Some(n) => p.iter().map(|&i| n[i as usize]).collect(),
                None => vec![DVec3::Z; p.len()],
            },
            attr: 0,
        })
        .collect()
}

/// The result as a mesh: closed (or why not) and its volume.
fn closed_volume(r: &[Face]) -> (Result<(), String>, f64) {
    let (mesh, _, _) = csg::to_mesh(r, false);
    let closed = solid::check_closed(&solid::weld_exact(&mesh.vertices), &mesh.polygons)
        .map_err(|e| e.to_string());
    (closed, solid::mesh_volume(&mesh))
}

#[test]
fn union_of_two_fine_spheres_is_closed() {
    for (nu, nv) in [(32, 16), (64, 32), (128, 64), (256, 128)] {
        let s = parametric::sphere(nu, nv);
        let a = faces(&s, 1.0, DVec3::ZERO);
        let b = faces(&s, 1.0, DVec3::new(0.5, 0.3, 0.2));
        for op in [Op::Union, Op::Intersection, Op::Difference] {
            let r = csg::combine(a.clone(), b.clone(), op);
            let (closed, v) = closed_volume(&r.faces);
            assert!(closed.is_ok(), "{nu}x{nv} {op:?}: {closed:?} (volume {v})");
        }
    }
}

/// An axis-aligned box as faces, clockwise from outside.
fn cuboid(lo: DVec3, hi: DVec3) -> Vec<Face> {
    let v = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ]
    .iter()
    .map(|q| Face {
        points: q.iter().map(|&i| v(i)).collect(),
        normals: vec![DVec3::Z; 4],
        attr: 0,
    })
    .collect()
}

/// Point-in-solid of a convex operand: behind every face plane. The
/// oracle is independent of the CSG code (no cutting, no rays).
fn inside_convex(f: &[Face], p: DVec3) -> bool {
    f.iter().all(|face| {
        let q = &face.points;
        // Clockwise from outside: (q1 - q0) x (q2 - q0) points inward.
        let inward = (q[1] - q[0]).cross(q[2] - q[0]);
        inward.dot(p - q[0]) >= 0.0
    })
}

fn eval(ops: &[Op], solids: &[Vec<Face>], p: DVec3) -> bool {
    let mut r = inside_convex(&solids[0], p);
    for (op, s) in ops.iter().zip(&solids[1..]) {
        let x = inside_convex(s, p);
        r = match op {
            Op::Union => r || x,
            Op::Intersection => r && x,
            Op::Difference => r && !x,
        };
    }
    r
}

/// A chain of operations: closed at every step, and the final volume
/// against a Monte Carlo estimate over the operands.
fn check_chain(ops: &[Op], solids: &[Vec<Face>], samples: usize, seed: u64) {
    let mut r = solids[0].clone();
    for (k, (op, s)) in ops.iter().zip(&solids[1..]).enumerate() {
        r = csg::combine(r, s.clone(), *op).faces;
        let (closed, _) = closed_volume(&r);
        assert!(closed.is_ok(), "step {k} ({op:?}): {closed:?}");
    }
    let (_, v) = closed_volume(&r);
    let (lo, hi) = (DVec3::splat(-2.0), DVec3::splat(2.0));
    let mut state = seed | 1;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut hits = 0usize;
    for _ in 0..samples {
        let p = lo + (hi - lo) * DVec3::new(next(), next(), next());
        if eval(ops, solids, p) {
            hits += 1;
        }
    }
    let total = (hi - lo).x * (hi - lo).y * (hi - lo).z;
    let frac = hits as f64 / samples as f64;
    let estimate = total * frac;
    // A binomial sigma, at the larger of the share measured and the share
    // the solid claims (and at least one sample's): a tiny solid catches
    // a handful of samples or none, and the measured share alone then
    // gives a sigma far too small (a right volume of 0.0229 whose 20,000
    // samples caught 1 failed at 6 sigma).
    let p = frac.max(v / total).max(1.0 / samples as f64);
    let sigma = total * (p * (1.0 - p) / samples as f64).sqrt();
    assert!(
        (v - estimate).abs() <= 5.0 * sigma + 1e-3,
        "{ops:?}: volume {v}, Monte Carlo {estimate} +- {sigma}"
    );
}

use proptest::prelude::*;

fn operand(kind: u8, at: DVec3, size: f64) -> Vec<Face> {
    match kind % 3 {
        0 => cuboid(at - DVec3::splat(size), at + DVec3::splat(size)),
        1 => faces(&parametric::sphere(10, 6), size, at),
        _ => faces(&parametric::cylinder(9, true), size, at),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    #[test]
    fn random_chains_stay_closed_with_the_right_volume(
        steps in proptest::collection::vec(
            (0u8..3, 0u8..3, -0.6f64..0.6, -0.6f64..0.6, -0.6f64..0.6, 0.4f64..0.9),
            2..6,
        ),
        seed in any::<u64>(),
    ) {
        let solids: Vec<Vec<Face>> = steps
            .iter()
            .map(|&(_, k, x, y, z, s)| operand(k, DVec3::new(x, y, z), s))
            .collect();
        let ops: Vec<Op> = steps[1..]
            .iter()
            .map(|&(o, ..)| [Op::Union, Op::Intersection, Op::Difference][o as usize])
            .collect();
        check_chain(&ops, &solids, 20_000, seed);
    }
}

#[test]
fn a_long_chain_of_unions_stays_closed() {
    // The hostile corpus failed at its 218th union; 80 overlapping
    // spheres and boxes along a helix show the same (each result is the
    // next operand).
    let solids: Vec<Vec<Face>> = (0..80)
        .map(|k| {
            let a = k as f64 * 0.45;
            let at = DVec3::new(1.2 * a.cos(), 1.2 * a.sin(), -1.5 + k as f64 * 0.04);
            operand(k as u8, at, 0.35)
        })
        .collect();
    let ops = vec![Op::Union; solids.len() - 1];
    check_chain(&ops, &solids, 20_000, 7);
}

mod hostile_support {
    use std::path::Path;
    use std::sync::mpsc;
    use std::time::Duration;

    use plytrace::Error;
    use plytrace::internal::budget::Budgets;
    use plytrace::internal::scene::{Interpreter, NoHost};

    /// Runs `body` as a scene file under `budgets` on another thread,
    /// failing the test past `secs` seconds.
    pub fn run(body: &str, budgets: Budgets, secs: u64) -> Result<Interpreter, Error> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("h.des");
        std::fs::write(&path, format!("ident\n{body}\n")).unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut i = Interpreter::new();
            i.set_budgets(budgets);
            let r = i
                .execute_file(Path::new(&path), true, &mut NoHost)
                .map(|_| i);
            let _ = tx.send(r);
            drop(dir);
        });
        match rx.recv_timeout(Duration::from_secs(secs)) {
            Ok(v) => v,
            Err(_) => panic!("still running after {secs} s, or panicked"),
        }
    }
}

use plytrace::internal::budget::Budgets;

#[test]
fn generators_past_the_model_memory_are_refused_before_building() {
    // 4 million steps: 4,000,002 polygons but 16 million vertices (2.4 GB
    // measured); refused in well under a second, naming the flag.
    let budgets = Budgets {
        polygons: 10_000_000,
        ..Budgets::default()
    };
    for cmd in [
        "cylinder 4000000",
        "sphere 2000 2000",
        "superquadric 1 1 3000 1000",
    ] {
        let e = hostile_support::run(&format!("defobj c\n{cmd}\nendobj"), budgets, 5)
            .err()
            .unwrap_or_else(|| panic!("{cmd}: built"));
        let m = e.to_string();
        assert!(m.contains("--max-model-memory"), "{cmd}: {m}");
        assert!(
            m.contains("h.des:3:1"),
            "{cmd}: located at the command: {m}"
        );
    }
    // Raised, a small one builds.
    hostile_support::run("defobj c\ncylinder 1000\nendobj", budgets, 5).unwrap();
}

#[test]
fn csg_past_the_pair_budget_is_a_located_error() {
    let body = "defobj a\nsphere 64 32\nendobj\ndefobj b\ntranslate 0.5 0 0\nsphere 64 32\nendobj\ndefobj r\nunion a b\nendobj";
    let small = Budgets {
        pair_tests: 1000,
        ..Budgets::default()
    };
    let m = hostile_support::run(body, small, 10)
        .err()
        .unwrap()
        .to_string();
    assert!(
        m.contains("--max-pair-tests") && m.contains("h.des:10:1"),
        "{m}"
    );
    hostile_support::run(body, Budgets::default(), 10).unwrap();
}

#[test]
fn big_lathe_and_extrude_outlines_are_checked_in_seconds() {
    // Smooth outlines of 40,000 points: 8e8 pairs for the old quadratic
    // check (tens of seconds), a sweep now.
    let n = 40_000;
    let circle: String = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            format!("{} {} ", a.cos(), a.sin())
        })
        .collect();
    let started = std::time::Instant::now();
    hostile_support::run(
        &format!("defobj e\nextrude 1 {circle}\nendobj"),
        Budgets::default(),
        30,
    )
    .unwrap();
    let profile: String = (0..n)
        .map(|i| {
            let a = std::f64::consts::PI * i as f64 / (n - 1) as f64;
            let r = if i == 0 || i == n - 1 { 0.0 } else { a.sin() };
            format!("{r} {} ", -a.cos())
        })
        .collect();
    hostile_support::run(
        &format!("defobj l\nlathe 4 {profile}\nendobj"),
        Budgets::default(),
        30,
    )
    .unwrap();
    assert!(
        started.elapsed().as_secs_f64() < 60.0,
        "{:?}",
        started.elapsed()
    );
    // A crossing is still found and reported.
    let e = hostile_support::run(
        "defobj e\nextrude 1 0 0 1 1 1 0 0 1\nendobj",
        Budgets::default(),
        5,
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("intersects itself"), "{e}");
}

#[test]
fn the_sweep_finds_the_same_first_crossing_as_all_pairs() {
    use plytrace::internal::modeling::sweep::self_intersection_within;
    let mut state = 12345u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f64 / (1u64 << 24) as f64
    };
    for case in 0..300 {
        let m = 3 + case % 9;
        // Coarse coordinates: collinear and touching cases are common.
        let pts: Vec<DVec2> = (0..m)
            .map(|_| DVec2::new((next() * 4.0).floor(), (next() * 4.0).floor()))
            .collect();
        let brute = brute_self_intersection(&pts);
        assert_eq!(
            self_intersection_within(&pts, u64::MAX),
            Ok(brute),
            "{pts:?}"
        );
    }
}

/// The all-pairs check the sweep replaced (the oracle).
fn brute_self_intersection(points: &[DVec2]) -> Option<(usize, usize)> {
    let orient = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let on = |a: DVec2, b: DVec2, p: DVec2| {
        p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
    };
    let meet = |a: DVec2, b: DVec2, c: DVec2, d: DVec2| {
        let (d1, d2, d3, d4) = (
            orient(c, d, a),
            orient(c, d, b),
            orient(a, b, c),
            orient(a, b, d),
        );
        (((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
            && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)))
            || (d1 == 0.0 && on(c, d, a))
            || (d2 == 0.0 && on(c, d, b))
            || (d3 == 0.0 && on(a, b, c))
            || (d4 == 0.0 && on(a, b, d))
    };
    let m = points.len();
    let edge = |i: usize| (points[i], points[(i + 1) % m]);
    for i in 0..m {
        for j in i + 1..m {
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            if j == i + 1 || (i == 0 && j == m - 1) {
                let (s, p, q) = if j == i + 1 { (b, a, d) } else { (a, b, c) };
                if orient(p, s, q) == 0.0 && (p - s).dot(q - s) > 0.0 {
                    return Some((i + 1, j + 1));
                }
            } else if meet(a, b, c, d) {
                return Some((i + 1, j + 1));
            }
        }
    }
    None
}

/// A fan of `n` triangles about a hub at (0, 0, 1).
fn fan(n: usize, jitter: bool) -> plytrace::internal::model::Mesh {
    let mut vertices = vec![DVec3::new(0.0, 0.0, 1.0)];
    for i in 0..n {
        let mut a = std::f64::consts::TAU * i as f64 / n as f64;
        if jitter {
            a += ((i * 7919) % 13) as f64 * 0.02 / n as f64;
        }
        vertices.push(DVec3::new(0.5 * a.cos(), 0.5 * a.sin(), 0.8));
    }
    let polygons = (0..n as u32).map(|i| [0, 1 + i, 1 + (i + 1) % n as u32]);
    plytrace::internal::model::Mesh::new(vertices, polygons)
}

#[test]
fn brown_check_of_a_wide_fan_is_fast_and_exact() {
    use plytrace::internal::modeling::geodesic::check_tessellation;
    // The hub's nonadjacent minimum against all pairs, on fans of degree
    // 17 to 60 (past the small-fan all-pairs path).
    for n in [17, 23, 40, 60] {
        let m = fan(n, true);
        let r = check_tessellation(&m, DVec3::ZERO).unwrap();
        let d = m.vertices[0].normalize();
        let t: Vec<DVec3> = m.vertices[1..]
            .iter()
            .map(|v| {
                let u = v.normalize();
                (u - d * u.dot(d)).normalize()
            })
            .collect();
        let mut best = f64::INFINITY;
        for i in 0..n {
            for j in i + 2..n {
                if !(i == 0 && j == n - 1) {
                    best = best.min(t[i].angle_between(t[j]));
                }
            }
        }
        // The rim vertices have degree 3 and add their own pairs only
        // when smaller; the hub's is the minimum here.
        assert!(r.min_nonadjacent_angle <= best + 1e-12, "{n}");
        assert!(
            (r.min_nonadjacent_angle - best).abs() < 1e-9 || r.min_nonadjacent_angle < best,
            "{n}"
        );
        assert_eq!(r.max_degree, n);
    }
    // 60,000 triangles round one vertex: 1.8e9 pairs before, now a sort.
    let started = std::time::Instant::now();
    let r = check_tessellation(&fan(60_000, false), DVec3::ZERO).unwrap();
    assert!(!r.angle_condition);
    assert!(
        started.elapsed().as_secs_f64() < 60.0,
        "{:?}",
        started.elapsed()
    );
}

#[test]
fn a_one_line_patch_file_reads_in_linear_time() {
    use plytrace::internal::modeling::patch::{self, Form};
    // 6,000 patches on one line: counting every column from the line's
    // start read 300,000 tokens in quadratic time.
    let mut text = String::from("6000");
    for p in 0..6000 {
        text += " 3 3";
        for i in 0..4 {
            for j in 0..4 {
                text += &format!(" {} {} 0", p as f64 + i as f64 / 3.0, j as f64 / 3.0);
            }
        }
    }
    let started = std::time::Instant::now();
    let set = patch::parse(&text, "one.bpt".as_ref(), Form::Bezier, |_| Ok(())).unwrap();
    assert_eq!(set.patches.len(), 6000);
    assert!(
        started.elapsed().as_secs_f64() < 60.0,
        "{:?}",
        started.elapsed()
    );
    // A bad token far along the line keeps its exact column.
    let bad = text.replacen(" 3 3", " 3 x", 5000);
    let e = patch::parse(&bad, "one.bpt".as_ref(), Form::Bezier, |_| Ok(())).unwrap_err();
    let col = bad.find(" 3 x").unwrap() + 4;
    assert!(e.to_string().contains(&format!("one.bpt:1:{col}")), "{e}");
    // Continuity: the strip's 5,999 shared edges found through the grid.
    let r = patch::continuity_within(&set, 1_000_000).unwrap();
    assert_eq!(r.joins.len(), 5999);
    // Patches piled on one edge stop at the pair budget.
    let pile = patch::PatchSet {
        patches: vec![set.patches[0]; 3000],
    };
    assert!(matches!(
        patch::continuity_within(&pile, 100_000),
        Err(patch::ContinuityStop::Pairs(_))
    ));
}

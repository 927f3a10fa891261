//! Hostile geometry: inputs whose cost used to grow with the square (or
//! worse) of their size, and the budgets that bound the rest. Each test
//! would hang (or fail) without its fix; none measures time: they check
//! counts and structure, on inputs large enough that a quadratic step
//! could not finish.

use glam::DVec3;
use plytrace::internal::geometry::polygon;
use plytrace::internal::scene::Scene;
use plytrace::internal::shading::Materials;

/// Writes `det/NAME.det` for each `(name, det text)` and `s.des` holding
/// `des` into a temporary directory, and loads the scene.
fn load(dets: &[(&str, String)], des: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    for (name, text) in dets {
        std::fs::write(dir.path().join(format!("det/{name}.det")), text).unwrap();
    }
    let path = dir.path().join("s.des");
    std::fs::write(&path, des).unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

/// A `.det` text of the given vertices and polygons (0-based indices).
fn det(vertices: &[DVec3], polygons: &[Vec<usize>]) -> String {
    use std::fmt::Write;
    let mut s = format!("title t\ndata\n{} {}\n", vertices.len(), polygons.len());
    for v in vertices {
        writeln!(s, "{} {} {}", v.x, v.y, v.z).unwrap();
    }
    for p in polygons {
        write!(s, "{}", p.len()).unwrap();
        for i in p {
            write!(s, " {}", i + 1).unwrap();
        }
        s.push('\n');
    }
    s
}

/// A 6 x 6 square in z = 0 facing +z.
fn floor_det() -> String {
    let v =
        [(-3.0, -3.0), (-3.0, 3.0), (3.0, 3.0), (3.0, -3.0)].map(|(x, y)| DVec3::new(x, y, 0.0));
    det(&v, &[vec![0, 1, 2, 3]])
}

/// `n` points on a circle of radius 1 in z = 0, clockwise seen from +z
/// (facing +z); every second one at radius `inner` (a star when < 1).
fn circle(n: usize, inner: f64) -> Vec<DVec3> {
    (0..n)
        .map(|k| {
            let a = -std::f64::consts::TAU * k as f64 / n as f64;
            let r = if k % 2 == 0 { 1.0 } else { inner };
            DVec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()
}

const HEAD: &str =
    "resolution 64 64\nperspective 45 1 0.1 100\npushmatrix\nident\npolarview 6 0 30 0\n";

// ---------------------------------------------------------------------
// Item 1: one polygon of 200,000 vertices.
// ---------------------------------------------------------------------

/// The plane of a 200,000-gon: its size and distinct-vertex count were
/// quadratic (2 * 10^10 distance computations each).
#[test]
fn plane_of_a_200000_vertex_polygon() {
    let c = circle(200_000, 1.0);
    let plane = polygon::outward_plane(&c).unwrap();
    assert!((plane.truncate() - DVec3::Z).length() < 1e-9);
    // 200,000 copies of two points: still too few vertices.
    let two: Vec<DVec3> = (0..200_000)
        .map(|k| if k % 2 == 0 { DVec3::ZERO } else { DVec3::X })
        .collect();
    assert_eq!(
        polygon::outward_plane(&two),
        Err(polygon::PolygonDefect::TooFewVertices(2))
    );
}

/// A star of 200,000 vertices (100,000 reflex) is cut into n - 2
/// triangles of the same total area and orientation; ear clipping that
/// tests every vertex against every candidate ear took the cube of n.
#[test]
fn triangulate_a_200000_vertex_star() {
    let n = 200_000;
    let star = circle(n, 0.8);
    assert!(!polygon::is_convex(&star));
    let tris = polygon::triangulate(&star);
    assert_eq!(tris.len(), n - 2);
    let normal = polygon::newell_vector(star.iter().copied());
    let total: f64 = tris
        .iter()
        .map(|t| polygon::newell_vector(t.iter().copied()).dot(normal) / normal.length() / 2.0)
        .sum();
    assert!((total - polygon::area(&star)).abs() < 1e-9 * polygon::area(&star));
    // No triangle reversed beyond rounding.
    for t in &tris {
        let a = polygon::newell_vector(t.iter().copied()).dot(normal) / normal.length() / 2.0;
        assert!(a > -1e-12, "{a}");
    }
}

/// The whole pipeline with one 200,000-gon: level 1, its mirror image at
/// level 2 and the shadows it casts.
#[test]
fn a_200000_vertex_polygon_goes_through_the_pipeline() {
    let mut big = circle(200_000, 1.0);
    for p in &mut big {
        // Nine digits, as a .det file often holds: convex only within
        // rounding.
        *p = (DVec3::new(p.x, p.y, 0.5) * 1e9).round() / 1e9;
    }
    let idx: Vec<usize> = (0..big.len()).collect();
    let scene = load(
        &[("big", det(&big, &[idx])), ("floor", floor_det())],
        &format!(
            "{HEAD}depth 2\nlight 2 2 5 1 1 1 100 Point\ndefobj floor\nreflectance 0.5\nendobj\n\
             defobj big\ntype open\nendobj\npopmatrix\n"
        ),
    );
    let r = plytrace::internal::render::render(
        &scene,
        &plytrace::internal::render::RenderOptions {
            shadows: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(r.stats.max_depth, 2);
    // The polygon is seen directly and in the mirror, and casts a shadow.
    let big_seen = r.polygons.iter().filter(|p| p.0 == 1).count();
    assert!(big_seen >= 2, "{big_seen}");
    assert!(r.shadows.iter().any(|s| s.is_some()));
    // With NNS the polygon is cut into triangles (it is not convex within
    // rounding), whose shades were each an average over all 200,000
    // vertices of their source polygon.
    let view = plytrace::internal::geometry::view::View::new(&scene, 64, 64).unwrap();
    let tree = plytrace::internal::image_tree::build(
        &Materials::new(&scene),
        &view,
        plytrace::internal::image_tree::TreeOptions {
            nns: true,
            ..Default::default()
        },
    );
    let pieces = tree.nodes.iter().filter(|f| f.object == 1).count();
    assert!(pieces > 1000, "{pieces}");
    let first = tree.nodes.iter().find(|f| f.object == 1).unwrap().shade;
    assert!(
        tree.nodes
            .iter()
            .filter(|f| f.object == 1)
            .all(|f| f.shade == first)
    );
}

// ---------------------------------------------------------------------
// Item 2: shadows over coincident casters.
// ---------------------------------------------------------------------

/// The tree of `scene` at 64 x 64 with shadows, level 1.
fn shadow_tree(scene: &Scene) -> plytrace::internal::image_tree::VirtualImageTree {
    let view = plytrace::internal::geometry::view::View::new(scene, 64, 64).unwrap();
    plytrace::internal::image_tree::build(
        &Materials::new(scene),
        &view,
        plytrace::internal::image_tree::TreeOptions {
            shadows: true,
            ..Default::default()
        },
    )
}

fn shadow_count(tree: &plytrace::internal::image_tree::VirtualImageTree) -> usize {
    tree.nodes
        .iter()
        .filter(|f| {
            matches!(
                f.kind,
                plytrace::internal::image_tree::FragmentKind::Shadow { .. }
            )
        })
        .count()
}

/// A triangle above the floor, facing +z.
fn triangle() -> [DVec3; 3] {
    [
        DVec3::new(-1.0, -1.0, 0.5),
        DVec3::new(-1.0, 1.0, 0.5),
        DVec3::new(1.0, 1.0, 0.5),
    ]
}

/// 65,535 copies of one triangle in one object over a floor, with a Point
/// light: every copy's shadow query found every other copy (and sorted
/// them), 4 * 10^9 steps. Identical casters are one caster now: the floor
/// gets one shadow, the triangles none.
#[test]
fn shadows_of_65535_identical_triangles() {
    let tris = vec![vec![0, 1, 2]; 65_535];
    let scene = load(
        &[("tris", det(&triangle(), &tris)), ("floor", floor_det())],
        &format!(
            "{HEAD}light 0.5 0.3 5 1 1 1 100 Point\ndefobj floor\nendobj\ndefobj tris\nendobj\npopmatrix\n"
        ),
    );
    let tree = shadow_tree(&scene);
    assert_eq!(tree.roots.len(), 65_536);
    assert_eq!(shadow_count(&tree), 1);
    let shadow = tree
        .nodes
        .iter()
        .find(|f| {
            matches!(
                f.kind,
                plytrace::internal::image_tree::FragmentKind::Shadow { .. }
            )
        })
        .unwrap();
    assert_eq!(shadow.object, 0, "the shadow falls on the floor");
}

/// The same triangle in 500 objects: every copy is coplanar with the
/// others (no shadow on one another), and they cast one shadow on the
/// floor instead of 500 coincident ones.
#[test]
fn identical_triangles_in_separate_objects() {
    let mut des = format!("{HEAD}light 0.5 0.3 5 1 1 1 100 Point\ndefobj floor\nendobj\n");
    for _ in 0..500 {
        des.push_str("defobj tri\nendobj\n");
    }
    des.push_str("popmatrix\n");
    let scene = load(
        &[
            ("tri", det(&triangle(), &[vec![0, 1, 2]])),
            ("floor", floor_det()),
        ],
        &des,
    );
    let tree = shadow_tree(&scene);
    assert_eq!(tree.roots.len(), 501);
    assert_eq!(shadow_count(&tree), 1);
}

// ---------------------------------------------------------------------
// Item 3: the cost per light.
// ---------------------------------------------------------------------

/// 20,000 dim Point lights over a cube on a floor: each shadow's shade is
/// the target's shade without its light, which was a new sum over the
/// other 19,999 lights per shadow (4 * 10^8 light terms on the floor
/// alone). Now the target's sum less the shadow's lights; the shades
/// agree with the sum over the others.
#[test]
fn twenty_thousand_point_lights() {
    let mut des = HEAD.to_string();
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..20_000 {
        des.push_str(&format!(
            "light {} {} {} 0.001 0.001 0.001 100 Point\n",
            next() * 8.0 - 4.0,
            next() * 8.0 - 4.0,
            next() * 3.0 + 3.0
        ));
    }
    let cube = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det"),
    )
    .unwrap();
    des.push_str(
        "defobj floor\nendobj\ndefobj cube\nscale 0.5 0.5 0.5\ntranslate 0 0 0.5\nendobj\npopmatrix\n",
    );
    let scene = load(&[("floor", floor_det()), ("cube", cube)], &des);
    assert_eq!(scene.lights.len(), 20_000);
    let tree = shadow_tree(&scene);
    let shadows: Vec<_> = tree
        .nodes
        .iter()
        .filter(|f| {
            matches!(
                f.kind,
                plytrace::internal::image_tree::FragmentKind::Shadow { .. }
            )
        })
        .collect();
    // Most lights cast the cube's shadow on the floor.
    assert!(shadows.len() > 10_000, "{}", shadows.len());
    for f in shadows.iter().step_by(2_000) {
        let others: Vec<_> = (0..scene.lights.len() as u32)
            .filter(|k| !f.shadowed_from().contains(k))
            .map(|k| scene.lights[k as usize])
            .collect();
        let want = plytrace::internal::shading::facet_shade_with(
            &Materials::new(&scene),
            tree.eye(f),
            f.object,
            f.polygon,
            f.back_facing,
            &others,
            None,
        );
        assert!((f.shade - want).length() < 1e-9, "{} {}", f.shade, want);
    }
}

// ---------------------------------------------------------------------
// Item 4: NNS worst cases.
// ---------------------------------------------------------------------

/// `n` random triangles of size about 1 in the cube [-1, 1]^3, most of
/// them interpenetrating others.
fn random_triangles(n: usize) -> String {
    let mut state = 7u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut vertices = Vec::new();
    let mut polygons = Vec::new();
    for i in 0..n {
        let c = DVec3::new(next(), next(), next());
        for _ in 0..3 {
            vertices.push(c + DVec3::new(next(), next(), next()) * 0.5);
        }
        polygons.push(vec![3 * i, 3 * i + 1, 3 * i + 2]);
    }
    det(&vertices, &polygons)
}

fn random_scene(n: usize) -> Scene {
    load(
        &[("rand", random_triangles(n))],
        &format!("{HEAD}setmode n on\ndefobj rand\ntype open\nendobj\npopmatrix\n"),
    )
}

/// 20,000 random interpenetrating triangles: NNS split and searched
/// without end. Within the default budgets the level is sorted (by NNS or,
/// past the budget, by the simple sort) and every face comes out.
#[test]
fn nns_on_20000_random_intersecting_triangles() {
    let scene = random_scene(20_000);
    let view = plytrace::internal::geometry::view::View::new(&scene, 64, 64).unwrap();
    let tree = plytrace::internal::image_tree::build(
        &Materials::new(&scene),
        &view,
        plytrace::internal::image_tree::TreeOptions {
            nns: true,
            ..Default::default()
        },
    );
    let nns = tree.nns.unwrap();
    let budgets = plytrace::internal::budget::Budgets::default();
    assert!(nns.splits <= budgets.splits);
    // The work is checked between searches: one search may overrun it by
    // what it visits.
    let max_work = budgets.splits * plytrace::internal::visibility::nns::WORK_PER_SPLIT;
    assert!(nns.work <= max_work + max_work / 10, "{}", nns.work);
    assert_eq!(tree.roots.len(), nns.faces_out);
    assert!(nns.faces_out >= nns.faces_in);
    assert_eq!(nns.fallbacks > 0, !tree.warnings.is_empty());
}

/// A small split budget: the sort stops, the level comes out in the
/// simple depth sort's order (unsplit, farthest first), and the tree
/// says so in a warning naming the flag.
#[test]
fn nns_falls_back_to_the_depth_sort_past_its_split_budget() {
    let scene = random_scene(2_000);
    let view = plytrace::internal::geometry::view::View::new(&scene, 64, 64).unwrap();
    let budgets = plytrace::internal::budget::Budgets {
        splits: 50,
        ..Default::default()
    };
    let tree = plytrace::internal::image_tree::build(
        &Materials::new(&scene),
        &view,
        plytrace::internal::image_tree::TreeOptions {
            nns: true,
            budgets,
            ..Default::default()
        },
    );
    let nns = tree.nns.unwrap();
    assert_eq!(nns.fallbacks, 1);
    assert!(nns.splits <= 50, "{}", nns.splits);
    assert_eq!(nns.faces_out, nns.faces_in);
    assert_eq!(tree.roots.len(), nns.faces_in);
    let zmax: Vec<f64> = tree
        .roots
        .iter()
        .map(|&r| {
            tree.nodes[r]
                .screen(&scene.objects, &view)
                .iter()
                .map(|p| p.z)
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect();
    assert!(zmax.windows(2).all(|w| w[0] >= w[1] - 1e-12));
    assert_eq!(tree.warnings.len(), 1);
    assert!(
        tree.warnings[0].contains("--max-splits"),
        "{}",
        tree.warnings[0]
    );
    assert!(
        tree.warnings[0].starts_with(&format!("NNS stopped after {} splits", nns.splits)),
        "{}",
        tree.warnings[0]
    );
    assert!(tree.warnings[0].contains("the simple depth sort ordered this level"));
}

// ---------------------------------------------------------------------
// Item 5: the node budget of the virtual image tree.
// ---------------------------------------------------------------------

/// 12 glass slabs (kr 0.4, kt 0.5) stacked under the eye at depth 14:
/// every fragment both reflects and refracts, so the tree doubles at every
/// level (killed past 1.5 GB before). With a budget it stops there,
/// pruning the lightest branches, and says how many.
fn glass_slabs() -> Scene {
    let mut des = "resolution 64 64\nperspective 45 1 0.1 100\ndepth 14\npushmatrix\nident\n\
                   polarview 8 0 20 0\nlight 2 2 6 1 1 1 100 Diffuse\ndefobj floor\nendobj\n"
        .to_string();
    for i in 0..12 {
        des.push_str(&format!(
            "defobj cube\nreflectance 0.4\ntransmittance 0.5\nscale 2 2 0.05\n\
             translate 0 0 {}\nendobj\n",
            0.3 + 0.25 * i as f64
        ));
    }
    des.push_str("popmatrix\n");
    let cube = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det"),
    )
    .unwrap();
    load(&[("floor", floor_det()), ("cube", cube)], &des)
}

fn glass_tree(budget: usize) -> plytrace::internal::image_tree::VirtualImageTree {
    let scene = glass_slabs();
    let view = plytrace::internal::geometry::view::View::new(&scene, 64, 64).unwrap();
    plytrace::internal::image_tree::build(
        &Materials::new(&scene),
        &view,
        plytrace::internal::image_tree::TreeOptions {
            max_level: scene.modes.max_level,
            threshold: scene.threshold,
            budgets: plytrace::internal::budget::Budgets {
                tree_nodes: budget,
                ..Default::default()
            },
            ..Default::default()
        },
    )
}

#[test]
fn twelve_glass_slabs_stay_within_the_node_budget() {
    let budget = 20_000;
    let tree = glass_tree(budget);
    assert!(tree.nodes.len() <= budget, "{}", tree.nodes.len());
    assert!(tree.pruned > 0);
    assert!(tree.max_depth > 2);
    assert!(tree.warnings.iter().any(|w| w.contains("--max-tree-nodes")));
    // The heaviest branches were kept: every pruned branch is at most as
    // heavy as the lightest fragment kept below level 1 ... (checked through
    // the weights of the deepest fragments: all kept fragments outweigh
    // 0.4^14).
    let lightest = tree
        .nodes
        .iter()
        .map(|f| f.weight)
        .fold(f64::INFINITY, f64::min);
    assert!(lightest > 0.4f64.powi(14));
    // The tree is whole: every child's parent is the node that lists it.
    for (i, f) in tree.nodes.iter().enumerate() {
        for c in f.children() {
            assert_eq!(tree.nodes[c].parent(), Some(i));
        }
    }
}

/// Overlapping shadows of many Point lights multiply (every subset of up
/// to 8 lights makes regions): office2 under 50 lights held more than
/// 5 GB. The node budget now bounds level 1's shadows too, and the
/// pruning is said.
#[test]
fn overlapping_shadows_of_many_lights_stay_within_the_node_budget() {
    let mut des = HEAD.to_string();
    for k in 0..12 {
        let a = k as f64 * std::f64::consts::TAU / 12.0;
        des.push_str(&format!(
            "light {} {} 4 0.05 0.05 0.05 100 Point\n",
            0.6 * a.cos(),
            0.6 * a.sin()
        ));
    }
    let cube = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det"),
    )
    .unwrap();
    des.push_str("defobj floor\nendobj\n");
    for (x, y) in [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)] {
        des.push_str(&format!(
            "defobj cube\nscale 0.3 0.3 0.3\ntranslate {x} {y} 1\nendobj\n"
        ));
    }
    des.push_str("popmatrix\n");
    let scene = load(&[("floor", floor_det()), ("cube", cube)], &des);
    let view = plytrace::internal::geometry::view::View::new(&scene, 64, 64).unwrap();
    let options = |tree_nodes| plytrace::internal::image_tree::TreeOptions {
        shadows: true,
        budgets: plytrace::internal::budget::Budgets {
            tree_nodes,
            ..Default::default()
        },
        ..Default::default()
    };
    let materials = Materials::new(&scene);
    let free = plytrace::internal::image_tree::build(&materials, &view, options(1 << 20));
    assert!(shadow_count(&free) > 300, "{}", shadow_count(&free));
    let budget = 200;
    let tree = plytrace::internal::image_tree::build(&materials, &view, options(budget));
    assert!(tree.nodes.len() <= budget, "{} nodes", tree.nodes.len());
    assert!(tree.pruned > 0);
    assert!(
        tree.warnings.iter().any(|w| w.contains("--max-tree-nodes")),
        "{:?}",
        tree.warnings
    );
}

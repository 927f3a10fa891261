//! End-to-end rendering: the manual's ccube checked at chosen pixels
//! against hand-worked shades, and the painted id image of several scenes
//! against the independent ray-cast oracle of `support`.

mod support;

use std::path::Path;

use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::{self, Scene};
use plytrace::internal::shading::Materials;

fn ccube() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ccube.des");
    scene::load(&path).expect("ccube loads").0
}

fn byte(v: f64) -> u8 {
    (v * 255.0).round() as u8
}

fn rgb(r: &plytrace::internal::render::Rendered, x: u32, y: u32) -> [u8; 3] {
    r.frame.pixel(x, y).map(|c| (c * 255.0).round() as u8)
}

#[test]
fn ccube_pixels_match_hand_worked_shades() {
    let scene = ccube();
    assert_eq!(scene.objects.len(), 2);
    assert_eq!((scene.point_count(), scene.polygon_count()), (18, 13));
    let r = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!((r.frame.width, r.frame.height), (512, 512));

    // Background (default black) above the horizon of the table.
    assert_eq!(rgb(&r, 5, 5), [0, 0, 0]);
    assert_eq!(r.polygon_at(5, 5), None);

    // Table top at the bottom centre: white, N = +z, centroid at the origin
    // of the scene frame (distances are the same in eye space).
    //   ka = 1 - 0.6 = 0.4
    //   light 1 at (-4,-2,6), range 100: |L| = sqrt 56, N.L = 6/sqrt 56,
    //     k = (1 - sqrt 56 / 100)^2, term = 0.8 * 0.6 * N.L * k
    //   light 2 at (0,-10,10), range 50: |L| = sqrt 200, N.L = 1/sqrt 2,
    //     k = (1 - sqrt 200 / 50)^2, term = 0.5 * 0.6 * N.L * k
    let l1 = 56f64.sqrt();
    let l2 = 200f64.sqrt();
    let table = 0.4
        + 0.8 * 0.6 * (6.0 / l1) * (1.0 - l1 / 100.0).powi(2)
        + 0.5 * 0.6 * (10.0 / l2) * (1.0 - l2 / 50.0).powi(2);
    assert_eq!(rgb(&r, 256, 500), [byte(table); 3]);
    assert_eq!(
        r.polygon_at(256, 500),
        Some((0, 0)),
        "the table's top (polygon 1 of cube.det)"
    );

    // The cut cube's face x = -1 (polygon 6 of cutcube.det) after
    // `rotate 30 z`, `translate 0 0 1.05`: normal (-cos 30, -sin 30, 0),
    // centroid (-cos 30, -sin 30, 1.05); green, lit by both lights.
    let (s, c) = 30f64.to_radians().sin_cos();
    let n = glam::DVec3::new(-c, -s, 0.0);
    let p = glam::DVec3::new(-c, -s, 1.05);
    let term = |light: glam::DVec3, intensity: f64, range: f64| {
        let v = light - p;
        let d = v.length();
        intensity * 0.6 * n.dot(v / d).max(0.0) * (1.0 - d / range).powi(2)
    };
    let green = 0.4
        + term(glam::DVec3::new(-4.0, -2.0, 6.0), 0.8, 100.0)
        + term(glam::DVec3::new(0.0, -10.0, 10.0), 0.5, 50.0);
    assert_eq!(r.polygon_at(175, 280), Some((1, 5)));
    assert_eq!(rgb(&r, 175, 280), [0, byte(green), 0]);

    // The cube stands in front of the table: its face at (300, 300) hides it.
    assert_eq!(r.polygon_at(300, 300).map(|p| p.0), Some(1));
}

fn assert_matches_oracle(scene: &Scene, size: u32) {
    let r = render(
        scene,
        &RenderOptions {
            size: Some((size, size)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let mut scene = scene.clone();
    scene.viewport = plytrace::internal::model::Viewport::of_size(size, size);
    let oracle = support::oracle_ids(&scene, size, size);
    let painted = support::painted_ids(&r);
    let (checked, bad) = support::mismatches(&oracle, &painted, size, size);
    assert!(
        checked > size as usize * size as usize / 2,
        "only {checked} pixels checked"
    );
    assert!(
        bad.is_empty(),
        "{} of {checked} pixels differ from the oracle, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

#[test]
fn ccube_agrees_with_ray_cast_oracle() {
    assert_matches_oracle(&ccube(), 160);
}

#[test]
fn mirror_scene_agrees_with_ray_cast_oracle() {
    let path = support::scene_fixture("mirror.des");
    // Level 1 only: reflections are checked in tests/reflection.rs.
    let mut scene = scene::load(&path).unwrap().0;
    scene.modes.max_level = 1;
    assert_matches_oracle(&scene, 128);
}

/// Two squares at different depths overlapping on the screen, with the
/// near one defined first: both orders paint the near one in front.
#[test]
fn front_to_back_and_back_to_front_agree_on_separated_polygons() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(
        dir.path().join("det/square.det"),
        "title square facing +z\ndata\n4 1\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n4 4 3 2 1\n",
    )
    .unwrap();
    let scene_path = dir.path().join("two.des");
    std::fs::write(
        &scene_path,
        "resolution 64 64\nperspective 60 1 0.1 100\npushmatrix\nident\ntranslate 0 0 -5\n\
         defobj square\ncolor 1 0 0\ntranslate 0.5 0 1\nendobj\n\
         defobj square\ncolor 0 0 1\ntranslate -0.5 0 -1\nendobj\npopmatrix\n",
    )
    .unwrap();
    let mut scene = scene::load(&scene_path).unwrap().0;
    let a = render(&scene, &RenderOptions::default()).unwrap();
    scene.sort_order = plytrace::internal::model::SortOrder::FrontToBack;
    let b = render(&scene, &RenderOptions::default()).unwrap();
    let (ia, ib) = (support::painted_ids(&a), support::painted_ids(&b));
    let differing = ia.iter().zip(&ib).filter(|(x, y)| x != y).count();
    assert_eq!(differing, 0);
    // The centre pixel shows the near (red) square, object 0.
    assert_eq!(a.polygon_at(32, 32), Some((0, 0)));
    assert!(a.frame.color == b.frame.color);
    let oracle = support::oracle_ids(&scene, 64, 64);
    let (_, bad) = support::mismatches(&oracle, &ia, 64, 64);
    assert_eq!(bad.len(), 0);
}

/// Gouraud shading (`setmode v on`) of a `type curved` geodesic sphere:
/// neighbouring pixels inside the sphere differ by far less than across the
/// facet edges of the faceted image.
#[test]
fn gouraud_shading_is_smooth_across_edges() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ball.des");
    std::fs::write(
        &path,
        "resolution 96 96\nperspective 40 1 0.1 100\npushmatrix\nident\npolarview 4 20 60 0\n\
         light 3 -4 5 1 1 1 100 Point\ndefobj ball\n type polygon curved\n color 0.9 0.6 0.2\n\
         geodesic 3 angle\nendobj\npopmatrix\n",
    )
    .unwrap();
    let mut scene = scene::load(&path).unwrap().0;
    let max_jump = |scene: &Scene| {
        let r = render(scene, &RenderOptions::default()).unwrap();
        let f = &r.frame;
        let mut worst = 0.0f32;
        for y in 4..f.height - 4 {
            for x in 4..f.width - 4 {
                // Away from the silhouette (where the surface folds over
                // itself): no background within 4 pixels.
                if (0..9).any(|i| (0..9).any(|j| f.id(x + i - 4, y + j - 4) == 0)) {
                    continue;
                }
                let c = f.pixel(x, y);
                for (nx, ny) in [(x + 1, y), (x, y + 1)] {
                    let d = f.pixel(nx, ny);
                    worst = worst.max((0..3).map(|i| (c[i] - d[i]).abs()).fold(0.0, f32::max));
                }
            }
        }
        worst
    };
    let faceted = max_jump(&scene);
    scene.modes.vertex_shades = true;
    let smooth = max_jump(&scene);
    assert!(smooth < 0.06, "Gouraud jump {smooth}, faceted {faceted}");
    assert!(
        faceted > 2.0 * smooth,
        "faceted {faceted} vs Gouraud {smooth}"
    );
}

/// Phong polygons (`setmode s on`, 004 section 4.8): a highlight in the
/// middle of one large polygon, far from its vertices, survives; Gouraud
/// shading loses it. Hand-worked: the light straight above the centre at
/// height 1 (range 100) and the eye above it too give N.H = 1 there, so the
/// highlight adds ks k = 0.6 (1 - 1/100)^2 to the interpolated shade.
#[test]
fn phong_keeps_a_highlight_inside_a_polygon() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(
        dir.path().join("det/square.det"),
        "title\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n",
    )
    .unwrap();
    let path = dir.path().join("hl.des");
    std::fs::write(
        &path,
        "resolution 65 65\nperspective 60 1 0.1 100\npushmatrix\nident\npolarview 6 0 0 0\n\
         light 0 0 1 1 1 1 100 Point\ndefobj square\n diffuse 0.5\n specular 0.6\n shininess 60\n\
         scale 2 2 1\nendobj\npopmatrix\nsetmode v on\n",
    )
    .unwrap();
    let mut scene = scene::load(&path).unwrap().0;
    let centre = |scene: &Scene| {
        render(scene, &RenderOptions::default())
            .unwrap()
            .frame
            .pixel(32, 32)[0]
    };
    let gouraud = centre(&scene);
    scene.modes.phong = true;
    let phong = centre(&scene);
    let highlight = 0.6 * (1.0f32 - 0.01).powi(2);
    assert!(
        (phong - (gouraud + highlight).min(1.0)).abs() < 0.03,
        "phong {phong}, gouraud {gouraud}"
    );
    assert!(phong > gouraud + 0.3);
}

/// 004 figure 4.16: a parent's shade under a child vertex is interpolated
/// along the two parent edges crossing the vertex's row, then across.
#[test]
fn parent_shade_interpolation_of_figure_4_16() {
    use glam::DVec3;
    use plytrace::internal::shading::interpolate_in_polygon;
    // A triangle with a linear value x + 2y: exact everywhere inside.
    let tri = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(4.0, 0.0, 0.0),
        DVec3::new(0.0, 4.0, 0.0),
    ];
    let f = |x: f64, y: f64| DVec3::splat(x + 2.0 * y);
    let vals: Vec<DVec3> = tri.iter().map(|p| f(p.x, p.y)).collect();
    for (x, y) in [(1.0, 1.0), (0.5, 2.5), (3.0, 0.5)] {
        assert!((interpolate_in_polygon(&tri, &vals, x, y) - f(x, y)).length() < 1e-12);
    }
    // A unit square with corner values a, b, c, d (counter-clockwise from
    // the origin): the centre gets the mean; (0.25, 0.5) gets the left
    // edge's midpoint value blended a quarter of the way to the right's.
    let sq = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];
    let (a, b, c, d) = (0.0, 1.0, 2.0, 3.0);
    let vals: Vec<DVec3> = [a, b, c, d].iter().map(|&v| DVec3::splat(v)).collect();
    assert!((interpolate_in_polygon(&sq, &vals, 0.5, 0.5).x - (a + b + c + d) / 4.0).abs() < 1e-12);
    let left = (a + d) / 2.0;
    let right = (b + c) / 2.0;
    assert!(
        (interpolate_in_polygon(&sq, &vals, 0.25, 0.5).x - (left + (right - left) * 0.25)).abs()
            < 1e-12
    );
}

/// Gouraud shading inside the tree writes Gouraud records.
#[test]
fn gouraud_tree_records() {
    let path = support::scene_fixture("mirror.des");
    let mut scene = scene::load(&path).unwrap().0;
    scene.modes.vertex_shades = true;
    scene.modes.output_tree = true;
    scene.modes.blend = true;
    let r = render(
        &scene,
        &RenderOptions {
            size: Some((64, 64)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let tree = r.tree.unwrap();
    let gouraud = tree
        .records
        .iter()
        .filter(|r| matches!(r.shades, plytrace::internal::tree::Shades::Gouraud(_)))
        .count();
    assert!(gouraud > 10 && tree.records.iter().any(|r| r.level == 2));
}

fn square_scene(extra_det: &[(&str, &str)], body: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(
        dir.path().join("det/square.det"),
        "title\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n",
    )
    .unwrap();
    for (name, text) in extra_det {
        std::fs::write(dir.path().join("det").join(name), text).unwrap();
    }
    let path = dir.path().join("s.des");
    std::fs::write(
        &path,
        format!("resolution 65 65\nperspective 60 1 0.1 100\npushmatrix\nident\npolarview 4 0 0 0\n{body}\npopmatrix\n"),
    )
    .unwrap();
    scene::load(&path).unwrap().0
}

/// `.vcl` vertex colours with `setmode v on`: with no lights and diffuse
/// 0 (so the ambient coefficient is 1), the square's centre shows the mean
/// of its four vertex colours (double-linear interpolation).
#[test]
fn vertex_colours_are_interpolated() {
    let vcl = "title\ndata 4\n1 0 0 0 0 0\n0 1 0 0 0 0\n0 0 1 0 0 0\n1 1 1 0 0 0\n";
    let mut scene = square_scene(
        &[("square.vcl", vcl)],
        "defobj square\n vcolors square\n scale 2 2 1\nendobj",
    );
    scene.modes.vertex_shades = true;
    let r = render(&scene, &RenderOptions::default()).unwrap();
    let c = r.frame.pixel(32, 32);
    let want = [0.5, 0.5, 0.5];
    for k in 0..3 {
        assert!((c[k] - want[k]).abs() < 0.03, "{c:?}");
    }
    // Near a corner, that corner's colour dominates: the vertex (-1,-1)
    // (red) is at the lower left of the image.
    let corner = r.frame.pixel(12, 52);
    assert!(corner[0] > 0.6 && corner[1] < 0.4, "{corner:?}");
}

/// Non-linear transparency per vertex (004 section 4.9): `k_t = k_trp
/// (E.N)^tpwr`; for the square facing the eye 4 away, a corner at distance
/// sqrt(2) off-axis has E.N = 4 / sqrt(18).
#[test]
fn transparency_per_vertex_follows_the_roll_off() {
    let scene = square_scene(&[], "defobj square\n transparency 0.8 2\nendobj");
    let view = plytrace::internal::geometry::view::View::new(&scene, 65, 65).unwrap();
    let o = &scene.objects[0];
    let world: Vec<glam::DVec3> = o.polygons[0]
        .indices
        .iter()
        .map(|&i| o.vertices[i as usize])
        .collect();
    let kt = plytrace::internal::shading::vertex_transparency(
        &Materials::new(&scene),
        view.eye,
        0,
        0,
        false,
        &world,
    )
    .unwrap();
    let cos = 4.0 / 18f64.sqrt();
    for k in kt {
        assert!((k as f64 - 0.8 * cos * cos).abs() < 1e-6, "{k}");
    }
    let centre = [world.iter().copied().sum::<glam::DVec3>() / 4.0];
    let kt = plytrace::internal::shading::vertex_transparency(
        &Materials::new(&scene),
        view.eye,
        0,
        0,
        false,
        &centre,
    )
    .unwrap();
    assert!((kt[0] - 0.8).abs() < 1e-6);
}

/// One pipeline (part 4): the kind of a light and `setmode o` change the
/// shading at most, never which polygon is seen where; with `sort ftb`
/// and the simple sort the picture used to differ in 29,679 pixels when
/// ccube's Point light became Diffuse.
#[test]
fn light_kinds_and_tree_output_do_not_change_the_picture() {
    let mut scene = ccube();
    scene.sort_order = plytrace::internal::model::SortOrder::FrontToBack;
    let options = RenderOptions {
        shadows: true,
        ..RenderOptions::default()
    };
    let point = render(&scene, &options).unwrap();
    let mut diffuse = scene.clone();
    for l in &mut diffuse.lights {
        l.kind = plytrace::internal::model::LightKind::Diffuse;
    }
    let diffuse = render(&diffuse, &options).unwrap();
    let (w, h) = (point.frame.width, point.frame.height);
    let differing = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| point.polygon_at(x, y) != diffuse.polygon_at(x, y))
        .count();
    assert_eq!(differing, 0, "pixels showing another polygon");
    let mut with_tree = scene.clone();
    with_tree.modes.output_tree = true;
    let tree = render(&with_tree, &options).unwrap();
    assert!(tree.tree.is_some());
    assert_eq!(
        tree.frame.color, point.frame.color,
        "-o on changed the picture"
    );
}

/// Nothing dropped silently (part 4): an image-space algorithm refuses a
/// scene whose tree it cannot render, naming what it cannot do.
#[test]
fn image_space_algorithms_refuse_the_tree_by_name() {
    let path = support::scene_fixture("mirror.des");
    let scene = plytrace::internal::scene::load(&path).unwrap().0;
    for algorithm in [
        plytrace::internal::visibility::Algorithm::ZBuffer,
        plytrace::internal::visibility::Algorithm::ScanLine,
        plytrace::internal::visibility::Algorithm::Warnock,
        plytrace::internal::visibility::Algorithm::RayCast,
    ] {
        let options = RenderOptions {
            visibility: Some(algorithm),
            shadows: true,
            ..RenderOptions::default()
        };
        let e = render(&scene, &options).unwrap_err().to_string();
        assert!(
            e.contains("mirrors") && e.contains("shadows") && e.contains(algorithm.name()),
            "{e}"
        );
    }
}

/// The picture's records are made while the tree's points are freed, run
/// by run (`emit::records_freeing`): they must be the records made from
/// the whole tree, in every order and blending, on office2 with shadows
/// and three more lights (some 60,000 fragments: several runs), and
/// without shadows (one run, the tree freed on another thread).
#[test]
fn records_made_while_freeing_the_tree_are_the_records_of_the_tree() {
    use plytrace::internal::image_tree::{self, TreeOptions};
    let office2 = support::scene_fixture("office2.des");
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink(office2.with_file_name("det"), dir.path().join("det")).unwrap();
    let mut text = std::fs::read_to_string(&office2).unwrap();
    let at = text.find("\nlight").unwrap();
    text.insert_str(
        at,
        "\nlight -1.5 3 2.9 0.3 0.3 0.3 30 Point\nlight 1.8 -1 2.9 0.3 0.3 0.3 30 Point\n\
         light 0 1 2.9 0.3 0.3 0.3 30 Point",
    );
    let des = dir.path().join("office2.des");
    std::fs::write(&des, text).unwrap();
    let scene = scene::load(&des).unwrap().0;
    let view = plytrace::internal::geometry::view::View::new(&scene, 64, 64).unwrap();
    let materials = Materials::new(&scene);
    for shadows in [true, false] {
        let options = TreeOptions {
            max_level: scene.modes.max_level,
            shadows,
            ..TreeOptions::default()
        };
        let tree = image_tree::build(&materials, &view, options);
        // Runs of 32768 fragments.
        if shadows {
            assert!(tree.nodes.len() > 40_000, "{}", tree.nodes.len());
        } else {
            assert!(tree.nodes.len() < 32_768, "{}", tree.nodes.len());
        }
        same_records_while_freeing(&materials, &tree, &view);
    }
}

fn same_records_while_freeing(
    materials: &Materials,
    tree: &plytrace::internal::image_tree::VirtualImageTree,
    view: &plytrace::internal::geometry::view::View,
) {
    use plytrace::internal::emit::{self, Emit};
    use plytrace::internal::model::SortOrder;
    for order in [SortOrder::FrontToBack, SortOrder::BackToFront] {
        for blended in [false, true] {
            let how = Emit {
                order,
                blended,
                width: 64,
                height: 64,
            };
            let whole = emit::records(materials, tree, how, view);
            let freeing = emit::records_freeing(materials, tree.clone(), how, view);
            assert!(whole == freeing, "{order:?}, blended {blended}");
        }
    }
}

//! Metamorphic tests: changes to a scene that must not change its image.
//!
//! - Rotating the whole scene (objects and lights) and the camera together
//!   by the same rotation leaves the eye's view as it was.
//! - Listing the objects in another order leaves the picture as it was, with
//!   the NNS sorter (`setmode n on`), which splits what it cannot order.
//!
//! Small scenes written in the test (det files in a temporary directory),
//! rendered at 64x64 with one sample per pixel (`Method::Point`), so that
//! the comparison can be exact: the id images must agree at every pixel
//! whose 3x3 neighbourhood sees one polygon in the ray-cast oracle, and the
//! colours there within one level of 255.

mod support;

use plytrace::internal::raster::scan::Method;
use plytrace::internal::render::{RenderOptions, Rendered, render};
use plytrace::internal::scene::Scene;

const SIZE: u32 = 64;

/// NNS (`setmode n on`) everywhere: the objects interpenetrate, which the
/// simple depth sort does not resolve, so its picture may depend on
/// rounding; NNS splits what it cannot order and matches the oracle.
const NNS: &str = "setmode n on\n";

const CUBE_DET: &str = "cube\ndata\n8 6\n-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n\
    -1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n\
    4 5 8 7 6\n4 1 2 3 4\n4 1 5 6 2\n4 4 3 7 8\n4 2 6 7 3\n4 1 4 8 5\n";
const SQUARE_DET: &str = "square facing +z\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n";

/// The objects of the test scene, each a `defobj` block with its number:
/// a floor that a green box pierces, a red cube, a blue slab across the
/// green box and a tilted yellow plate through the red cube.
const OBJECTS: [&str; 5] = [
    "defobj square 1\n color 0.9 0.9 0.9\n scale 3 3 1\n translate 0 0 -0.2\nendobj\n",
    "defobj cube 2\n color 0.1 0.8 0.2\n translate 0.6 -0.3 0\n rotate 25 z\n scale 0.5 0.7 0.6\nendobj\n",
    "defobj cube 3\n color 0.9 0.1 0.1\n translate -1 1 0.4\n scale 0.4 0.4 0.4\nendobj\n",
    "defobj cube 4\n color 0.2 0.3 0.9\n translate 0.3 -0.3 0.3\n rotate -40 z\n scale 1.2 0.15 0.15\nendobj\n",
    "defobj square 5\n color 0.9 0.8 0.1\n translate -1 1 0.4\n rotate 35 x\n scale 0.7 0.7 1\nendobj\n",
];

/// Loads a scene made of `camera` (statements that place the eye), then
/// `world` (statements applied to every object and light), a light and
/// `objects`, in a temporary directory with the det files.
fn scene(camera: &str, world: &str, objects: &[&str], extra: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    std::fs::write(dir.path().join("det/cube.det"), CUBE_DET).unwrap();
    std::fs::write(dir.path().join("det/square.det"), SQUARE_DET).unwrap();
    let path = dir.path().join("s.des");
    std::fs::write(
        &path,
        format!(
            "resolution {SIZE} {SIZE}\nperspective 40 1 0.1 100\n{extra}pushmatrix\nident\n\
             {camera}\n{world}\nlight -4 -2 6 0.8 0.8 0.8 100 Diffuse\n\
             light 3 -5 4 0.4 0.4 0.4 100 Diffuse\n{}popmatrix\n",
            objects.concat()
        ),
    )
    .unwrap();
    let (scene, warnings) = plytrace::internal::scene::load(&path).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(scene.objects.len(), objects.len());
    scene
}

fn rendered(scene: &Scene) -> Rendered {
    render(
        scene,
        &RenderOptions {
            size: Some((SIZE, SIZE)),
            aa: Some(Method::Point),
            ..RenderOptions::default()
        },
    )
    .unwrap()
}

/// Ids by object number (not by place in the list) and polygon.
fn ids_by_number(scene: &Scene, r: &Rendered) -> Vec<Option<(u32, u32)>> {
    support::painted_ids(r)
        .into_iter()
        .map(|id| id.map(|(o, p)| (scene.objects[o as usize].number, p)))
        .collect()
}

/// Compares two renders of the same view at the pixels where `oracle` is
/// unambiguous: same ids and colours within one level. Returns the number
/// of pixels compared.
fn assert_same_image(
    what: &str,
    oracle: &[Option<(u32, u32)>],
    (ids_a, a): (&[Option<(u32, u32)>], &Rendered),
    (ids_b, b): (&[Option<(u32, u32)>], &Rendered),
) -> usize {
    let (checked, _) = support::mismatches(oracle, oracle, SIZE, SIZE);
    // The first image is right, so that the comparison means something.
    let (_, wrong) = support::mismatches(oracle, ids_a, SIZE, SIZE);
    assert!(
        wrong.is_empty(),
        "{what}: the first image differs from the oracle at {wrong:?}"
    );
    let differing: Vec<(u32, u32)> = (0..SIZE)
        .flat_map(|y| (0..SIZE).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let i = (y * SIZE + x) as usize;
            uniform(oracle, x, y) && ids_a[i] != ids_b[i]
        })
        .collect();
    assert!(
        differing.is_empty(),
        "{what}: {} of {checked} pixels have other polygons, e.g. {:?}",
        differing.len(),
        &differing[..differing.len().min(8)]
    );
    let mut colour_differences = Vec::new();
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (ca, cb) = (a.frame.pixel(x, y), b.frame.pixel(x, y));
            let levels = (0..3)
                .map(|k| ((ca[k] - cb[k]).abs() * 255.0).round() as u32)
                .max()
                .unwrap();
            if levels > 1 && uniform(oracle, x, y) {
                colour_differences.push(((x, y), ca, cb));
            }
        }
    }
    assert!(
        colour_differences.is_empty(),
        "{what}: {} pixels differ by more than one level, e.g. {:?}",
        colour_differences.len(),
        &colour_differences[..colour_differences.len().min(4)]
    );
    checked
}

/// Whether the 3x3 neighbourhood of (x, y) holds one value in `oracle`.
fn uniform(oracle: &[Option<(u32, u32)>], x: u32, y: u32) -> bool {
    let here = oracle[(y * SIZE + x) as usize];
    (-1i64..=1).all(|dy| {
        (-1i64..=1).all(|dx| {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            nx < 0
                || ny < 0
                || nx >= SIZE as i64
                || ny >= SIZE as i64
                || oracle[(ny as u32 * SIZE + nx as u32) as usize] == here
        })
    })
}

/// The oracle with ids by object number.
fn oracle_by_number(scene: &Scene) -> Vec<Option<(u32, u32)>> {
    support::oracle_ids(scene, SIZE, SIZE)
        .into_iter()
        .map(|id| id.map(|(o, p)| (scene.objects[o as usize].number, p)))
        .collect()
}

/// The picture is worth comparing: most pixels are checked and several
/// polygons of every object are seen.
fn assert_rich(scene: &Scene, oracle: &[Option<(u32, u32)>], checked: usize) {
    assert!(
        checked > (SIZE * SIZE / 2) as usize,
        "only {checked} pixels compared"
    );
    for o in &scene.objects {
        assert!(
            oracle.iter().flatten().any(|&(n, _)| n == o.number),
            "object {} is not seen",
            o.number
        );
    }
}

/// Rotating the objects and lights about z by `angle` and moving the eye
/// round by the same angle (`polarview` azimuth) gives the same image.
#[test]
fn rotating_scene_and_camera_together_about_z_keeps_the_image() {
    let base = scene("polarview 7 30 55 0", "", &OBJECTS, NNS);
    let a = rendered(&base);
    let oracle = oracle_by_number(&base);
    let ids_a = ids_by_number(&base, &a);
    for angle in [37.0, 90.0, -123.5, 200.0] {
        let turned = scene(
            &format!("polarview 7 {} 55 0", 30.0 + angle),
            &format!("rotate {angle} z"),
            &OBJECTS,
            NNS,
        );
        let b = rendered(&turned);
        let checked = assert_same_image(
            &format!("rotated by {angle} degrees"),
            &oracle,
            (&ids_a, &a),
            (&ids_by_number(&turned, &b), &b),
        );
        assert_rich(&base, &oracle, checked);
    }
}

/// The same with `lookat`, whose up direction is +y: the scene, the eye
/// and the point looked at turn about y.
#[test]
fn rotating_scene_and_lookat_camera_together_keeps_the_image() {
    let (eye, at) = ([5.0f64, -4.0, 3.5], [0.2f64, 0.1, 0.0]);
    let camera = |angle: f64| {
        let (s, c) = angle.to_radians().sin_cos();
        let turn = |p: [f64; 3]| [c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2]];
        let (e, t) = (turn(eye), turn(at));
        format!(
            "lookat {} {} {} {} {} {} 0",
            e[0], e[1], e[2], t[0], t[1], t[2]
        )
    };
    let base = scene(&camera(0.0), "", &OBJECTS, NNS);
    let a = rendered(&base);
    let oracle = oracle_by_number(&base);
    let ids_a = ids_by_number(&base, &a);
    for angle in [15.0, 140.0, -75.0] {
        let turned = scene(&camera(angle), &format!("rotate {angle} y"), &OBJECTS, NNS);
        let b = rendered(&turned);
        let checked = assert_same_image(
            &format!("lookat rotated by {angle} degrees"),
            &oracle,
            (&ids_a, &a),
            (&ids_by_number(&turned, &b), &b),
        );
        assert_rich(&base, &oracle, checked);
    }
}

/// Re-ordering the objects gives the same image with NNS (`-n on`), ids
/// compared by object number.
#[test]
fn reordering_objects_keeps_the_image_with_nns() {
    let camera = "polarview 7 30 55 0";
    let base = scene(camera, "", &OBJECTS, NNS);
    assert!(base.modes.nns);
    let a = rendered(&base);
    let oracle = oracle_by_number(&base);
    let ids_a = ids_by_number(&base, &a);
    let orders: [[usize; 5]; 4] = [
        [4, 3, 2, 1, 0],
        [2, 0, 4, 1, 3],
        [1, 4, 0, 3, 2],
        [3, 1, 2, 0, 4],
    ];
    for order in orders {
        let objects: Vec<&str> = order.iter().map(|&i| OBJECTS[i]).collect();
        let shuffled = scene(camera, "", &objects, NNS);
        let b = rendered(&shuffled);
        let checked = assert_same_image(
            &format!("objects in the order {order:?}"),
            &oracle,
            (&ids_a, &a),
            (&ids_by_number(&shuffled, &b), &b),
        );
        assert_rich(&base, &oracle, checked);
    }
}

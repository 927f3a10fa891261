//! Every visible-surface algorithm against the ray-cast oracle: the painted
//! id image must equal the oracle's at every pixel whose 3x3 neighbourhood
//! holds a single polygon in the oracle (issue: part 2, "Done means").
//! Scenes: all of `tests/data/scenes` and generated ones (random
//! interpenetrating triangle soups, random boxes).

mod support;

use std::path::Path;

use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::Scene;
use plytrace::internal::visibility::Algorithm;
use plytrace::internal::visibility::ray_cast::RayCaster;

/// (pixels checked, pixels differing, first differing pixels).
fn compare(scene: &Scene, algorithm: Algorithm, size: u32) -> (usize, usize, Vec<(u32, u32)>) {
    compare_with(scene, Some(algorithm), size)
}

/// [`compare`] with the algorithm the scene and the defaults choose when
/// `algorithm` is `None`.
fn compare_with(
    scene: &Scene,
    algorithm: Option<Algorithm>,
    size: u32,
) -> (usize, usize, Vec<(u32, u32)>) {
    let options = RenderOptions {
        size: Some((size, size)),
        visibility: algorithm,
        ..RenderOptions::default()
    };
    let r = render(scene, &options).unwrap();
    let oracle: Vec<Option<(u32, u32)>> = RayCaster::new(scene)
        .id_image(size, size)
        .into_iter()
        .map(|h| h.map(|h| (h.object, h.polygon)))
        .collect();
    let painted = support::painted_ids(&r);
    let (checked, bad) = support::mismatches(&oracle, &painted, size, size);
    let first = bad.iter().take(5).copied().collect();
    (checked, bad.len(), first)
}

fn assert_agrees(name: &str, scene: &Scene, algorithm: Algorithm, size: u32) {
    let (checked, bad, first) = compare(scene, algorithm, size);
    assert!(checked > 0, "{name}: nothing checked");
    assert_eq!(
        bad, 0,
        "{name} with {algorithm}: {bad} of {checked} pixels differ from the oracle, e.g. {first:?}"
    );
}

/// A shared scene at level 1 only (reflections are checked against the
/// reflecting oracle in tests/reflection.rs).
fn shared(name: &str) -> Scene {
    let path = support::scene_fixture(name);
    let mut scene = plytrace::internal::scene::load(&path).unwrap().0;
    scene.modes.max_level = 1;
    // Visibility only: the image-space algorithms refuse transparency.
    for o in &mut scene.objects {
        o.surface.transparency = (0.0, 0.0);
    }
    scene
}

const SCENES: [&str; 8] = [
    "ccube.des",
    "mirror.des",
    "gallery.des",
    "office1.des",
    "office2.des",
    "intersect.des",
    "cycles.des",
    "underwater.des",
];

#[test]
fn library_ray_caster_equals_brute_force_oracle() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ccube.des");
    let mut scenes = vec![plytrace::internal::scene::load(&path).unwrap().0];
    scenes.extend(
        ["intersect.des", "cycles.des", "mirror.des"]
            .iter()
            .map(|n| shared(n)),
    );
    for scene in scenes {
        let size = 64;
        let mut s = scene.clone();
        s.viewport = plytrace::internal::model::Viewport::of_size(size, size);
        let brute = support::oracle_ids(&s, size, size);
        let bvh: Vec<Option<(u32, u32)>> = RayCaster::new(&scene)
            .id_image(size, size)
            .into_iter()
            .map(|h| h.map(|h| (h.object, h.polygon)))
            .collect();
        assert_eq!(brute.iter().zip(&bvh).filter(|(a, b)| a != b).count(), 0);
    }
}

#[test]
fn nns_agrees_with_the_oracle_on_every_shared_scene() {
    for name in SCENES {
        let scene = shared(name);
        assert_agrees(name, &scene, Algorithm::Nns, 160);
    }
}

/// What a user who just runs `plytrace scene.des` gets, in both orders.
#[test]
fn the_default_sort_agrees_with_the_oracle_on_every_shared_scene() {
    for name in SCENES {
        let mut scene = shared(name);
        for order in [
            plytrace::internal::model::SortOrder::BackToFront,
            plytrace::internal::model::SortOrder::FrontToBack,
        ] {
            scene.sort_order = order;
            let (checked, bad, first) = compare_with(&scene, None, 160);
            assert!(checked > 0, "{name}: nothing checked");
            assert_eq!(
                bad, 0,
                "{name} {order:?}: {bad} of {checked} pixels differ, e.g. {first:?}"
            );
        }
    }
}

#[test]
fn z_buffer_agrees_with_the_oracle_on_every_shared_scene() {
    for name in SCENES {
        let scene = shared(name);
        assert_agrees(name, &scene, Algorithm::ZBuffer, 160);
    }
}

#[test]
fn scan_line_agrees_with_the_oracle_on_every_shared_scene() {
    for name in SCENES {
        let scene = shared(name);
        assert_agrees(name, &scene, Algorithm::ScanLine, 160);
    }
}

#[test]
fn warnock_agrees_with_the_oracle_on_every_shared_scene() {
    for name in SCENES {
        let scene = shared(name);
        assert_agrees(name, &scene, Algorithm::Warnock, 160);
    }
}

#[test]
fn nns_front_to_back_agrees_too() {
    for name in ["intersect.des", "cycles.des", "office1.des"] {
        let mut scene = shared(name);
        scene.sort_order = plytrace::internal::model::SortOrder::FrontToBack;
        assert_agrees(name, &scene, Algorithm::Nns, 128);
    }
}

#[test]
fn simple_sort_fails_where_nns_is_needed() {
    // The reason for NNS: intersect.des and cycles.des defeat the simple sort.
    for name in ["intersect.des", "cycles.des"] {
        let scene = shared(name);
        let (_, bad, _) = compare(&scene, Algorithm::DepthSort, 160);
        assert!(
            bad > 0,
            "{name}: the simple sort was expected to be wrong somewhere"
        );
    }
}

#[test]
fn nns_splits_the_cycles_and_the_interpenetrations() {
    for name in ["intersect.des", "cycles.des"] {
        let scene = shared(name);
        let options = RenderOptions {
            size: Some((128, 128)),
            visibility: Some(Algorithm::Nns),
            ..RenderOptions::default()
        };
        let stats = render(&scene, &options).unwrap().stats.nns.unwrap();
        assert!(stats.splits > 0, "{name}: {stats:?}");
        assert_eq!(stats.unresolved, 0, "{name}: {stats:?}");
    }
}

/// A deterministic generator (64-bit LCG), so failures reproduce.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

fn scene_from(files: &[(&str, String)], des: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join("det").join(name), text).unwrap();
    }
    let path = dir.path().join("g.des");
    std::fs::write(&path, des).unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

/// Random triangles in a box, two-sided (`type open`), many of them
/// piercing each other.
fn triangle_soup(seed: u64, count: usize) -> Scene {
    let mut rng = Lcg(seed);
    let mut det = format!("title soup\ndata\n{} {}\n", 3 * count, count);
    for _ in 0..3 * count {
        det.push_str(&format!(
            "{} {} {}\n",
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0)
        ));
    }
    for k in 0..count {
        det.push_str(&format!("3 {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3));
    }
    let des = "resolution 128 128\nperspective 50 1 0.1 100\npushmatrix\nident\n\
               polarview 9 30 60 0\ntype polygon open\ngetobj soup\npopmatrix\n";
    scene_from(&[("soup.det", det)], des)
}

/// Random boxes, overlapping and interpenetrating.
fn random_boxes(seed: u64, count: usize) -> Scene {
    let mut rng = Lcg(seed);
    let cube = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/det/cube.det"),
    )
    .unwrap();
    let mut des = String::from(
        "resolution 128 128\nperspective 50 1 0.1 100\npushmatrix\nident\npolarview 12 20 55 0\n",
    );
    for _ in 0..count {
        des.push_str(&format!(
            "defobj cube\ncolor {} {} {}\ntranslate {} {} {}\nrotate {} z\nrotate {} x\nscale {} {} {}\nendobj\n",
            rng.next(),
            rng.next(),
            rng.next(),
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(-1.0, 1.0),
            rng.range(0.0, 360.0),
            rng.range(0.0, 360.0),
            rng.range(0.2, 2.0),
            rng.range(0.1, 0.6),
            rng.range(0.1, 1.0),
        ));
    }
    des.push_str("popmatrix\n");
    scene_from(&[("cube.det", cube)], &des)
}

#[test]
fn generated_triangle_soups() {
    for seed in 1..=6 {
        let scene = triangle_soup(seed, 40);
        for algorithm in [
            Algorithm::Nns,
            Algorithm::ZBuffer,
            Algorithm::ScanLine,
            Algorithm::Warnock,
        ] {
            assert_agrees(&format!("soup {seed}"), &scene, algorithm, 128);
        }
    }
}

#[test]
fn generated_random_boxes() {
    for seed in 1..=6 {
        let scene = random_boxes(seed, 14);
        for algorithm in [
            Algorithm::Nns,
            Algorithm::ZBuffer,
            Algorithm::ScanLine,
            Algorithm::Warnock,
        ] {
            assert_agrees(&format!("boxes {seed}"), &scene, algorithm, 128);
        }
    }
}

//! The tree builder leaves out the polygons of each level hidden at every
//! sample by that level's own polygons (`TreeOptions::cull_samples`).
//! That no picture changes is checked by `output_hashes` (every sampling
//! method, with culling on); here an independent ray caster checks that
//! nothing visible is left out, directly or in mirrors, and that the
//! culling happens at all.

mod support;

use std::collections::HashSet;

use plytrace::geometry::view::View;
use plytrace::image_tree::{TreeOptions, VirtualImageTree, build};
use plytrace::shading::Materials;
use plytrace::visibility::ray_cast::RayCaster;

const SIZE: u32 = 96;

fn office2() -> plytrace::model::Scene {
    plytrace::scene::load(&support::scene_fixture("office2.des"))
        .unwrap()
        .0
}

fn tree(scene: &plytrace::model::Scene, cull: Option<u32>) -> VirtualImageTree {
    let view = View::new(scene, SIZE, SIZE).unwrap();
    let options = TreeOptions {
        nns: true,
        cull_samples: cull,
        ..TreeOptions::default()
    };
    build(&Materials::new(scene), &view, options)
}

fn level_one(tree: &VirtualImageTree) -> HashSet<(u32, u32)> {
    tree.roots
        .iter()
        .map(|&k| (tree.nodes[k].object, tree.nodes[k].polygon))
        .collect()
}

/// Every polygon a ray through one of the 4 x 4 samples of a pixel hits
/// first is kept; a tenth or more of office2's front faces are not.
#[test]
fn no_polygon_seen_at_a_sample_is_left_out() {
    let scene = office2();
    let culled = tree(&scene, Some(4));
    let all = tree(&scene, None);
    let kept = level_one(&culled);
    assert_eq!(all.hidden, 0);
    assert!(
        culled.hidden * 10 >= all.roots.len(),
        "{} of {} left out",
        culled.hidden,
        all.roots.len()
    );
    assert!(kept.is_subset(&level_one(&all)));
    let seen: HashSet<(u32, u32)> = RayCaster::new(&scene)
        .id_image(SIZE * 4, SIZE * 4)
        .into_iter()
        .flatten()
        .map(|h| (h.object, h.polygon))
        .collect();
    let missing: Vec<_> = seen.difference(&kept).collect();
    assert!(missing.is_empty(), "seen but left out: {missing:?}");
}

fn mirror_tree(scene: &plytrace::model::Scene, cull: Option<u32>) -> VirtualImageTree {
    let view = View::new(scene, SIZE, SIZE).unwrap();
    let options = TreeOptions {
        max_level: scene.modes.max_level,
        threshold: scene.threshold,
        nns: true,
        cull_samples: cull,
        ..TreeOptions::default()
    };
    build(&Materials::new(scene), &view, options)
}

/// The (level, object, polygon) of every fragment below level 1.
fn below_level_one(tree: &VirtualImageTree) -> HashSet<(u32, u32, u32)> {
    tree.nodes
        .iter()
        .filter(|f| f.level > 1)
        .map(|f| (f.level, f.object, f.polygon))
        .collect()
}

/// In mirrors too: every polygon that a ray through one of the 4 x 4
/// samples of a pixel sees after one or more reflections (the ray caster
/// follows them) is kept at that level, and polygons hidden by others of
/// their own mirror's level are left out: gallery's facing mirrors (depth
/// 14) and office2's wall mirror and mirrored bookcase (depth 3).
#[test]
fn no_polygon_seen_in_a_mirror_is_left_out() {
    for name in ["gallery.des", "office2.des"] {
        let scene = plytrace::scene::load(&support::scene_fixture(name))
            .unwrap()
            .0;
        assert!(scene.modes.max_level >= 3, "{name}");
        let culled = mirror_tree(&scene, Some(4));
        let all = mirror_tree(&scene, None);
        let kept = below_level_one(&culled);
        assert!(kept.is_subset(&below_level_one(&all)), "{name}");
        let in_level_one = all.roots.len() - culled.roots.len();
        assert!(
            culled.hidden > in_level_one + 100,
            "{name}: {} left out, {in_level_one} of them at level 1",
            culled.hidden
        );
        let seen: HashSet<(u32, u32, u32)> = RayCaster::new(&scene)
            .traced_image(SIZE * 4, SIZE * 4, scene.modes.max_level, scene.threshold)
            .into_iter()
            .flatten()
            .filter(|(_, level)| *level > 1)
            .map(|(h, level)| (level, h.object, h.polygon))
            .collect();
        assert!(seen.len() > 100, "{name}: {} seen in mirrors", seen.len());
        let missing: Vec<_> = seen.difference(&kept).collect();
        assert!(missing.is_empty(), "{name}: seen but left out: {missing:?}");
    }
}

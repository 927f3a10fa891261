//! The tree builder leaves out the polygons of each level hidden at every
//! sample by that level's own polygons (`TreeOptions::cull_samples`):
//! every hidden polygon of a level that casts shadows, and in a level
//! without shadows the hidden polygons over those that branch (mirrors,
//! glasses), the only ones whose leaving out saves more than the cull
//! costs. That no picture changes is checked by `output_hashes` (every
//! sampling method, with culling on); here an independent ray caster
//! checks that nothing visible is left out, directly or in mirrors, and
//! that the culling happens where it should.

mod support;

use std::collections::HashSet;

use plytrace::internal::geometry::view::View;
use plytrace::internal::image_tree::{TreeOptions, VirtualImageTree, build};
use plytrace::internal::shading::Materials;
use plytrace::internal::visibility::ray_cast::RayCaster;

const SIZE: u32 = 96;

fn office2() -> plytrace::internal::model::Scene {
    plytrace::internal::scene::load(&support::scene_fixture("office2.des"))
        .unwrap()
        .0
}

/// Level 1 of `scene`, with its shadows (office2 has two Point lights).
fn tree(scene: &plytrace::internal::model::Scene, cull: Option<u32>) -> VirtualImageTree {
    let view = View::new(scene, SIZE, SIZE).unwrap();
    let options = TreeOptions {
        nns: true,
        shadows: true,
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

fn mirror_tree(
    scene: &plytrace::internal::model::Scene,
    cull: Option<u32>,
    shadows: bool,
) -> VirtualImageTree {
    let view = View::new(scene, SIZE, SIZE).unwrap();
    let options = TreeOptions {
        max_level: scene.modes.max_level,
        threshold: scene.threshold,
        nns: true,
        shadows,
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
/// follows them) is kept at that level, with shadows or without, and with
/// shadows polygons hidden by others of their own mirror's level are left
/// out: gallery's facing mirrors (depth 14) and office2's wall mirror and
/// mirrored bookcase (depth 3).
#[test]
fn no_polygon_seen_in_a_mirror_is_left_out() {
    for name in ["gallery.des", "office2.des"] {
        let scene = plytrace::internal::scene::load(&support::scene_fixture(name))
            .unwrap()
            .0;
        assert!(scene.modes.max_level >= 3, "{name}");
        let seen: HashSet<(u32, u32, u32)> = RayCaster::new(&scene)
            .traced_image(SIZE * 4, SIZE * 4, scene.modes.max_level, scene.threshold)
            .into_iter()
            .flatten()
            .filter(|(_, level)| *level > 1)
            .map(|(h, level)| (level, h.object, h.polygon))
            .collect();
        assert!(seen.len() > 100, "{name}: {} seen in mirrors", seen.len());
        for shadows in [true, false] {
            let culled = mirror_tree(&scene, Some(4), shadows);
            let all = mirror_tree(&scene, None, shadows);
            let kept = below_level_one(&culled);
            assert!(kept.is_subset(&below_level_one(&all)), "{name}");
            let in_level_one = all.roots.len() - culled.roots.len();
            assert!(
                !shadows || culled.hidden > in_level_one + 100,
                "{name}: {} left out, {in_level_one} of them at level 1",
                culled.hidden
            );
            let missing: Vec<_> = seen.difference(&kept).collect();
            assert!(
                missing.is_empty(),
                "{name}, shadows {shadows}: seen but left out: {missing:?}"
            );
        }
    }
}

/// Without shadows, a mirror hidden behind a wall is left out with its
/// branch, while the polygons nowhere near a mirror are not asked about
/// (leaving them out would save less than the cull costs); the mirror in
/// view is kept and traced. The same scene with one level (nothing
/// branches) culls nothing; with shadows, the polygons behind the wall
/// are left out too.
#[test]
fn without_shadows_only_what_lies_over_a_mirror_is_culled() {
    let dir = support::cube_and_square_dir();
    let des = dir.path().join("mirrors.des");
    std::fs::write(
        &des,
        "resolution 96 96\ndepth 3\nident\nperspective 40 1.0 0.01 1000.0\n\
         pushmatrix\nident\npolarview 14 0 70 0\nlight 3 -3 8 1 1 1 100 Point\n\
         defobj cube /* floor */\n color 0.6 0.6 0.6\n scale 6 6 0.1\nendobj\n\
         defobj cube /* wall */\n color 0.8 0.3 0.2\n translate 0 -1 1.5\n\
          scale 3 0.1 1.4\nendobj\n\
         defobj cube /* hidden mirror, left behind the wall */\n color 0.9 0.9 0.9\n\
          reflectance 0.8\n translate -1.5 1 0.6\n scale 0.5 0.5 0.5\nendobj\n\
         defobj cube /* block, right behind the wall */\n color 0.2 0.3 0.8\n\
          translate 1.5 2 0.6\n scale 0.5 0.5 0.5\nendobj\n\
         defobj cube /* mirror in view, in front of the wall */\n color 0.9 0.9 0.9\n\
          reflectance 0.8\n translate 3.8 -3 0.6\n scale 0.5 0.5 0.5\nendobj\n\
         popmatrix\n",
    )
    .unwrap();
    let scene = plytrace::internal::scene::load(&des).unwrap().0;
    let culled = mirror_tree(&scene, Some(4), false);
    let all = mirror_tree(&scene, None, false);
    let objects = |t: &VirtualImageTree| -> HashSet<u32> {
        level_one(t).into_iter().map(|(o, _)| o).collect()
    };
    let (hidden_mirror, block, in_view) = (2, 3, 4);
    assert!(
        objects(&all).contains(&hidden_mirror),
        "the hidden mirror is in level 1 uncullled"
    );
    assert!(
        !objects(&culled).contains(&hidden_mirror),
        "the hidden mirror is left out"
    );
    assert!(objects(&culled).contains(&in_view));
    let branches = |t: &VirtualImageTree| t.nodes.iter().filter(|f| f.level > 1).count();
    assert!(branches(&culled) > 0, "the mirror in view is traced");
    assert!(
        branches(&culled) < branches(&all),
        "the hidden mirror is not traced"
    );
    assert!(
        objects(&culled).contains(&block),
        "polygons away from the mirrors are not asked about without shadows"
    );
    let mut one_level = scene.clone();
    one_level.modes.max_level = 1;
    assert_eq!(mirror_tree(&one_level, Some(4), false).hidden, 0);
    let shadowed = mirror_tree(&scene, Some(4), true);
    assert!(
        !objects(&shadowed).contains(&block),
        "with shadows all that is hidden goes"
    );
}

//! The tree builder leaves out level-1 polygons hidden at every sample
//! (`TreeOptions::cull_samples`). That no picture changes is checked by
//! `output_hashes` (every sampling method, with culling on); here an
//! independent ray caster checks that nothing visible is left out, and
//! that the culling happens at all.

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

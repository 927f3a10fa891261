//! One thread or many: the virtual image tree (shadows are cast in
//! parallel, fragment by fragment) and the anti-aliased picture are the
//! same, bit for bit, whatever the number of threads (issue 10: "one
//! thread gives bit-identical output").

mod support;

use plytrace::internal::image_tree::{self, TreeOptions};
use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::shading::Materials;

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

/// The shared scenes with the most shadow work per fragment: office2's
/// 24,374 polygons under two lights with its mirrors, the gallery's
/// facing mirrors under four.
const SCENES: [&str; 2] = ["office2.des", "gallery.des"];

#[test]
fn the_tree_does_not_depend_on_the_thread_count() {
    for name in SCENES {
        let mut scene = plytrace::internal::scene::load(&support::scene_fixture(name))
            .unwrap()
            .0;
        scene.modes.max_level = scene.modes.max_level.min(4);
        let view = plytrace::internal::geometry::view::View::new(&scene, 48, 48).unwrap();
        let options = TreeOptions {
            max_level: scene.modes.max_level,
            shadows: true,
            ..TreeOptions::default()
        };
        let one = pool(1).install(|| image_tree::build(&Materials::new(&scene), &view, options));
        assert!(
            one.nodes
                .iter()
                .any(|f| matches!(f.kind, image_tree::FragmentKind::Shadow { .. })),
            "{name}: no shadows to compare"
        );
        for threads in [2, 3] {
            let many = pool(threads)
                .install(|| image_tree::build(&Materials::new(&scene), &view, options));
            assert_eq!(
                one.nodes.len(),
                many.nodes.len(),
                "{name}, {threads} threads"
            );
            for (k, (a, b)) in one.nodes.iter().zip(&many.nodes).enumerate() {
                assert!(a == b, "{name}, {threads} threads: fragment {k} differs");
            }
            assert_eq!(one.roots, many.roots);
        }
    }
}

#[test]
fn the_picture_does_not_depend_on_the_thread_count() {
    for name in SCENES {
        let scene = plytrace::internal::scene::load(&support::scene_fixture(name))
            .unwrap()
            .0;
        let options = |threads| RenderOptions {
            size: Some((40, 40)),
            shadows: true,
            threads,
            ..RenderOptions::default()
        };
        let one = render(&scene, &options(1)).unwrap();
        for threads in [2, 3] {
            let many = render(&scene, &options(threads)).unwrap();
            let bits = |r: &plytrace::internal::render::Rendered| {
                r.frame
                    .color
                    .iter()
                    .flat_map(|c| c.map(f32::to_bits))
                    .collect::<Vec<u32>>()
            };
            assert!(
                bits(&one) == bits(&many),
                "{name}, {threads} threads: pixels differ"
            );
            assert!(
                one.frame.ids == many.frame.ids,
                "{name}, {threads} threads: ids differ"
            );
            assert_eq!(one.polygons, many.polygons);
        }
    }
}

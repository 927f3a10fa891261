//! Shadows by projection (004 section 4.7) against a ray tracer's shadow
//! test: at every pixel where the oracle sees one polygon lit from the
//! viewer's side, and whose 3x3 neighbourhood agrees on the polygon and on
//! whether the light is blocked, the painted image shows a shadow polygon
//! exactly when a ray from the Point light to the visible point is blocked.
//! Also: shadow polygons lie in their target's plane and inside it.

mod support;

use glam::DVec3;
use plytrace::internal::geometry::view::View;
use plytrace::internal::image_tree::{self, FragmentKind, TreeOptions};
use plytrace::internal::model::LightKind;
use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::Scene;
use plytrace::internal::shading::Materials;
use plytrace::internal::visibility::ray_cast::RayCaster;

fn level_one(name: &str) -> Scene {
    let path = if name == "ccube.des" {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ccube.des")
    } else {
        support::scene_fixture(name)
    };
    let mut scene = plytrace::internal::scene::load(&path).unwrap().0;
    scene.modes.max_level = 1;
    scene.modes.nns = true;
    scene
}

/// The polygon seen at each pixel, and (where comparable) whether it is in
/// shadow there.
type ShadowMask = (Vec<Option<(u32, u32)>>, Vec<Option<bool>>);

/// Per pixel: `None` where not comparable, else whether it is in shadow.
fn oracle_shadow_mask(scene: &Scene, size: u32) -> ShadowMask {
    let caster = RayCaster::new(scene);
    let light = scene
        .lights
        .iter()
        .find(|l| l.kind == LightKind::Point)
        .unwrap()
        .position;
    let mut ids = Vec::new();
    let mut mask = Vec::new();
    for row in 0..size {
        for col in 0..size {
            let x = (col as f64 + 0.5) / size as f64 * 2.0 - 1.0;
            let y = 1.0 - (row as f64 + 0.5) / size as f64 * 2.0;
            let (o, d) = caster.ray(x, y).unwrap();
            let hit = caster.cast(o, d);
            ids.push(hit.map(|h| (h.object, h.polygon)));
            mask.push(hit.and_then(|h| {
                let object = &scene.objects[h.object as usize];
                let p = o + d * h.t;
                let n = object.polygons[h.polygon as usize].normal();
                // Lit from the viewer's side (the front, for a seen polygon).
                if n.dot(light - p) <= 0.0 {
                    return None;
                }
                let skip = (!object.surface_type.concave).then_some(h.object);
                Some(caster.occluded(light, p, (h.object, h.polygon), skip))
            }));
        }
    }
    (ids, mask)
}

fn assert_shadows_agree(name: &str, scene: &Scene, size: u32) {
    let r = render(
        scene,
        &RenderOptions {
            size: Some((size, size)),
            shadows: true,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let (ids, mask) = oracle_shadow_mask(scene, size);
    let painted_shadow: Vec<bool> = r
        .frame
        .ids
        .iter()
        .map(|&i| i > 0 && r.shadows[i as usize - 1].is_some())
        .collect();
    let (w, h) = (size as i64, size as i64);
    let (mut checked, mut shadowed, mut bad) = (0, 0, Vec::new());
    for y in 0..h {
        for x in 0..w {
            let k = (y * w + x) as usize;
            let Some(want) = mask[k] else { continue };
            let uniform = (-1..=1).all(|dy: i64| {
                (-1..=1).all(|dx: i64| {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w || ny >= h {
                        return true;
                    }
                    let j = (ny * w + nx) as usize;
                    ids[j] == ids[k] && mask[j] == mask[k]
                })
            });
            if !uniform {
                continue;
            }
            checked += 1;
            shadowed += want as usize;
            if painted_shadow[k] != want {
                bad.push((x, y, want));
            }
        }
    }
    assert!(checked > 1000, "{name}: {checked}");
    assert!(
        shadowed > 20,
        "{name}: only {shadowed} shadowed pixels: the test needs shadows"
    );
    assert!(
        bad.is_empty(),
        "{name}: {} of {checked} pixels differ, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(6)]
    );
}

#[test]
fn shadow_masks_agree_with_the_shadow_rays() {
    for name in ["ccube.des", "intersect.des", "cycles.des", "mirror.des"] {
        let scene = level_one(name);
        assert_shadows_agree(name, &scene, 160);
    }
}

#[test]
fn shadow_polygons_lie_in_their_target() {
    let scene = level_one("ccube.des");
    let view = View::new(&scene, 256, 256).unwrap();
    let tree = image_tree::build(
        &Materials::new(&scene),
        &view,
        TreeOptions {
            max_level: 1,
            threshold: 0.0,
            nns: true,
            shadows: true,
            explicit_shadow_shades: false,
            refraction: Default::default(),
            ..Default::default()
        },
    );
    let mut count = 0;
    for f in &tree.nodes {
        if let FragmentKind::Shadow { .. } = f.kind {
            count += 1;
            let parent = &tree.nodes[f.parent().unwrap()];
            let plane =
                scene.objects[parent.object as usize].polygons[parent.polygon as usize].plane;
            // In the target's plane.
            for p in f.points(&scene.objects).iter() {
                assert!((plane.truncate().dot(*p) + plane.w).abs() < 1e-9, "{p}");
            }
            // Inside the target (its convex outline, with a tolerance).
            let n = plane.truncate();
            let t = parent.points(&scene.objects);
            for p in f.points(&scene.objects).iter() {
                for i in 0..t.len() {
                    let (a, b) = (t[i], t[(i + 1) % t.len()]);
                    let side = (b - a).cross(*p - a).dot(n);
                    let orient = (t[1] - t[0]).cross(t[2] - t[1]).dot(n).signum();
                    assert!(
                        side * orient >= -1e-9,
                        "shadow vertex {p} outside its target"
                    );
                }
            }
            // Its shade is the target's without the light: darker.
            assert!(f.shade.length() < parent.shade.length());
        }
    }
    assert!(count > 0);
    let _ = DVec3::ZERO;
}

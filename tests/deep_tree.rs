//! The virtual image tree below level 1 against a ray caster that follows
//! mirrors (004 sections 4.4-4.7): at every pixel whose 3x3 neighbourhood
//! the oracle sees uniformly, the tree painted back to front (point in
//! polygon at the pixel centre, the last fragment hit wins: what the
//! painter of 004 section 4.10 shows) shows the polygon, at the level, that
//! the mirror-following ray hits; and a shadow polygon covers the pixel
//! exactly when that hit point is occluded from the Point light (004
//! section 4.7, shadows on reflected fragments). Scenes: a box on a floor
//! beside a perfect mirror (level 2), and between two facing mirrors
//! (levels 3 and deeper). The tree is checked directly, not through the
//! renderer.

mod support;

use glam::DVec3;
use plytrace::internal::geometry::view::View;
use plytrace::internal::image_tree::{self, FragmentKind, TreeOptions, VirtualImageTree};
use plytrace::internal::model::{LightKind, SortOrder};
use plytrace::internal::scene::Scene;
use plytrace::internal::shading::Materials;
use plytrace::internal::visibility::ray_cast::RayCaster;

/// The scene of `des` (without its header), with `cube.det` and a unit
/// `square.det` facing +z in a temporary `det` folder.
fn load(depth: u32, body: &str) -> Scene {
    let dir = support::cube_and_square_dir();
    let path = dir.path().join("s.des");
    let des = format!(
        "resolution 96 96\nperspective 45 1 0.1 100\ndepth {depth}\npushmatrix\nident\n{body}popmatrix\n"
    );
    std::fs::write(&path, des).unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

/// What a pixel shows: (object, polygon, level) and whether it is in the
/// shadow of the Point light (`None`: lit from behind, not compared).
type Seen = ((u32, u32, u32), Option<bool>);

/// The oracle: the ray through the pixel centre follows mirrors (kr > 0)
/// up to `max_level`; the last polygon hit is seen, and its hit point is
/// tested for occlusion from the first Point light.
fn oracle(scene: &Scene, size: u32, max_level: u32) -> Vec<Option<Seen>> {
    let caster = RayCaster::new(scene);
    let light = scene
        .lights
        .iter()
        .find(|l| l.kind == LightKind::Point)
        .expect("a Point light")
        .position;
    let mut out = Vec::new();
    for row in 0..size {
        for col in 0..size {
            let x = (col as f64 + 0.5) / size as f64 * 2.0 - 1.0;
            let y = 1.0 - (row as f64 + 0.5) / size as f64 * 2.0;
            let (o, d) = caster.ray(x, y).unwrap();
            let seen = follow(scene, &caster, o, d, max_level).map(|(id, p)| {
                let object = &scene.objects[id.0 as usize];
                let n = object.polygons[id.1 as usize].normal();
                let lit = n.dot(light - p) > 0.0;
                let skip = (!object.surface_type.concave).then_some(id.0);
                (
                    id,
                    lit.then(|| caster.occluded(light, p, (id.0, id.1), skip)),
                )
            });
            // The loop agrees with the ray caster's own mirror tracing.
            let traced = caster
                .trace(o, d, max_level, 0.0)
                .map(|(h, l)| (h.object, h.polygon, l));
            assert_eq!(seen.map(|s| s.0), traced);
            out.push(seen);
        }
    }
    out
}

/// The last polygon (object, polygon, level) hit by `o + t d` through
/// mirror reflections, and the world point hit.
fn follow(
    scene: &Scene,
    caster: &RayCaster,
    mut o: DVec3,
    mut d: DVec3,
    max_level: u32,
) -> Option<((u32, u32, u32), DVec3)> {
    let mut last = None;
    for level in 1..=max_level {
        let Some(hit) = caster.cast(o, d) else {
            return last;
        };
        let p = o + d * hit.t;
        last = Some(((hit.object, hit.polygon, level), p));
        let object = &scene.objects[hit.object as usize];
        let kr = object.material(hit.polygon as usize).reflectance;
        if kr <= 0.0 {
            break;
        }
        let n = object.polygons[hit.polygon as usize].normal();
        let rest = d * (1.0 - hit.t);
        d = rest - n * (2.0 * rest.dot(n));
        o = p;
    }
    last
}

/// Even-odd point in polygon on screen (x, y).
fn inside(screen: &[DVec3], x: f64, y: f64) -> bool {
    let mut odd = false;
    for i in 0..screen.len() {
        let (a, b) = (screen[i], screen[(i + 1) % screen.len()]);
        if (a.y > y) != (b.y > y) && x < a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y) {
            odd = !odd;
        }
    }
    odd
}

/// What the painter shows at a pixel: (object, polygon, level) of the
/// polygon, and whether a shadow polygon covers it.
type Painted = ((u32, u32, u32), bool);

/// The last fragment hit at each pixel centre (rows from the top) when
/// the tree is painted back to front.
fn painted_fragments(
    scene: &Scene,
    tree: &VirtualImageTree,
    view: &View,
    size: u32,
) -> Vec<Option<usize>> {
    let order = tree.output_order(SortOrder::BackToFront);
    let screens: Vec<Vec<DVec3>> = tree
        .nodes
        .iter()
        .map(|f| f.screen(&scene.objects, view))
        .collect();
    let mut out = Vec::new();
    for row in 0..size {
        for col in 0..size {
            let (x, y) = (col as f64 + 0.5, size as f64 - (row as f64 + 0.5));
            out.push(order.iter().copied().rfind(|&n| inside(&screens[n], x, y)));
        }
    }
    out
}

/// The tree painted back to front at each pixel centre (rows from the
/// top): the last fragment hit wins; a shadow polygon shows its target.
fn painted(scene: &Scene, tree: &VirtualImageTree, view: &View, size: u32) -> Vec<Option<Painted>> {
    painted_fragments(scene, tree, view, size)
        .into_iter()
        .map(|last| {
            last.map(|n| {
                let f = &tree.nodes[n];
                let shadow = matches!(f.kind, FragmentKind::Shadow { .. });
                let target = if shadow {
                    &tree.nodes[f.parent().unwrap()]
                } else {
                    f
                };
                ((target.object, target.polygon, target.level), shadow)
            })
        })
        .collect()
}

/// Pixels compared: all, at level 2 or deeper, at level 3 or deeper, and
/// of those in shadow; and the mismatches.
#[derive(Debug, Default)]
struct Counts {
    checked: usize,
    deep: usize,
    deeper: usize,
    deep_shadowed: usize,
    deeper_shadowed: usize,
    bad: Vec<(u32, u32, String)>,
}

fn compare(scene: &Scene, size: u32, max_level: u32) -> Counts {
    let view = View::new(scene, size, size).unwrap();
    let tree = image_tree::build(
        &Materials::new(scene),
        &view,
        TreeOptions {
            max_level,
            nns: true,
            shadows: true,
            ..Default::default()
        },
    );
    let want = oracle(scene, size, max_level);
    let got = painted(scene, &tree, &view, size);
    let mut c = Counts::default();
    let s = size as i64;
    for y in 0..s {
        for x in 0..s {
            let k = (y * s + x) as usize;
            let Some(w) = want[k] else { continue };
            let uniform = (-1..=1).all(|dy: i64| {
                (-1..=1).all(|dx: i64| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx < 0
                        || ny < 0
                        || nx >= s
                        || ny >= s
                        || want[(ny * s + nx) as usize] == want[k]
                })
            });
            if !uniform {
                continue;
            }
            c.checked += 1;
            let level = w.0.2;
            c.deep += (level >= 2) as usize;
            c.deeper += (level >= 3) as usize;
            c.deep_shadowed += (level >= 2 && w.1 == Some(true)) as usize;
            c.deeper_shadowed += (level >= 3 && w.1 == Some(true)) as usize;
            let g = got[k];
            let ok = g.is_some_and(|(id, shadow)| id == w.0 && w.1.is_none_or(|s| s == shadow));
            if !ok {
                c.bad
                    .push((x as u32, y as u32, format!("want {w:?} got {g:?}")));
            }
        }
    }
    c
}

fn assert_agrees(name: &str, c: &Counts) {
    assert!(
        c.bad.is_empty(),
        "{name}: {} of {} pixels differ from the oracle, e.g. {:?}",
        c.bad.len(),
        c.checked,
        &c.bad[..c.bad.len().min(6)]
    );
}

/// A floor, a box on it and a perfect mirror standing beside them, lit by
/// one Point light: the box's shadow on the floor is seen directly and in
/// the mirror.
fn box_beside_mirror() -> Scene {
    load(
        2,
        "polarview 14 30 55 0\n\
         light 4 -1 5 1 1 1 100 Point\n\
         defobj square\n scale 6 6 1\nendobj\n\
         defobj cube\n translate 0 0 1.01\nendobj\n\
         defobj square\n reflectance 1\n translate -4 0 2.5\n rotate 90 y\n scale 2.5 4 1\nendobj\n",
    )
}

#[test]
fn level_two_shadows_and_reflections_agree_with_the_oracle() {
    let c = compare(&box_beside_mirror(), 96, 2);
    assert_agrees("box beside a mirror", &c);
    // The test needs reflections, and shadows seen in the mirror.
    assert!(c.deep > 300 && c.deep_shadowed > 50, "{c:?}");
}

/// The box between two facing perfect mirrors (the near one seen from
/// behind, so culled): the box and its shadow are seen after up to three
/// reflections.
fn box_between_mirrors(depth: u32) -> Scene {
    load(
        depth,
        "polarview 12 60 65 0\n\
         light -2 1 4 1 1 1 100 Point\n\
         defobj square\n scale 6 6 1\nendobj\n\
         defobj cube\n translate 0 0 1.01\nendobj\n\
         defobj square\n reflectance 1\n translate -4 0 2.5\n rotate 90 y\n scale 2.5 4 1\nendobj\n\
         defobj square\n reflectance 1\n translate 5 0 2.5\n rotate -90 y\n scale 2.5 4 1\nendobj\n",
    )
}

#[test]
fn facing_mirrors_to_depth_four_agree_with_the_oracle() {
    let c = compare(&box_between_mirrors(4), 128, 4);
    assert_agrees("box between mirrors", &c);
    assert!(c.deeper > 200 && c.deeper_shadowed > 20, "{c:?}");
}

/// A box on a floor lit by two Point lights whose shadows overlap.
fn box_under_two_lights() -> Scene {
    load(
        1,
        "polarview 14 30 40 0\n\
         light 3 -1.5 5 0.6 0.6 0.6 100 Point\n\
         light 3 1.5 5 0.6 0.6 0.6 100 Point\n\
         defobj square\n scale 6 6 1\nendobj\n\
         defobj cube\n translate 0 0 1.01\nendobj\n",
    )
}

/// Overlapping shadows of two lights (beyond 004 section 4.10's limit):
/// the overlap is a region shaded without both lights, painted over the
/// single shadows back to front and before them front to back; and at
/// every uniform pixel the painter shows the region of exactly the lights
/// the shadow rays say are blocked.
#[test]
fn overlapping_shadows_of_two_lights() {
    let scene = box_under_two_lights();
    let size = 96;
    let view = View::new(&scene, size, size).unwrap();
    let materials = Materials::new(&scene);
    let tree = image_tree::build(
        &materials,
        &view,
        TreeOptions {
            nns: true,
            shadows: true,
            ..Default::default()
        },
    );
    let both: Vec<usize> = (0..tree.nodes.len())
        .filter(|&n| *tree.nodes[n].shadowed_from() == [0, 1])
        .collect();
    assert!(!both.is_empty(), "no overlap region");
    for &n in &both {
        let f = &tree.nodes[n];
        assert_eq!(f.kind, FragmentKind::Shadow { light: 0 });
        let without_both = plytrace::internal::shading::facet_shade_with(
            &materials,
            tree.eye(f),
            f.object,
            f.polygon,
            f.back_facing,
            &[],
            None,
        );
        assert!((f.shade - without_both).length() < 1e-12, "{}", f.shade);
        // Darker than the target without one light only.
        let without_one = plytrace::internal::shading::facet_shade_with(
            &materials,
            tree.eye(f),
            f.object,
            f.polygon,
            f.back_facing,
            &scene.lights[1..],
            None,
        );
        assert!(f.shade.length() < without_one.length());
    }
    assert_overlap_order(&tree, &both);
    assert_overlap_pixels(&scene, &tree, &view, size);
    // `setmode h on`: each region shaded at its own centroid, still without
    // both lights.
    let tree = image_tree::build(
        &materials,
        &view,
        TreeOptions {
            nns: true,
            shadows: true,
            explicit_shadow_shades: true,
            ..Default::default()
        },
    );
    let mut count = 0;
    for f in tree.nodes.iter().filter(|f| *f.shadowed_from() == [0, 1]) {
        count += 1;
        let points = f.points(&scene.objects);
        let at = points.iter().copied().sum::<DVec3>() / points.len() as f64;
        let want = plytrace::internal::shading::facet_shade_with(
            &materials,
            tree.eye(f),
            f.object,
            f.polygon,
            f.back_facing,
            &[],
            Some(at),
        );
        assert!((f.shade - want).length() < 1e-12);
    }
    assert!(count > 0);
}

/// Back to front every overlap region comes after the single shadows on its
/// target; front to back before them.
fn assert_overlap_order(tree: &VirtualImageTree, both: &[usize]) {
    for order in [SortOrder::BackToFront, SortOrder::FrontToBack] {
        let seq = tree.output_order(order);
        let at = |n: usize| seq.iter().position(|&m| m == n).unwrap();
        for &n in both {
            let parent = tree.nodes[n].parent();
            for (m, g) in tree.nodes.iter().enumerate() {
                if g.parent() == parent && g.shadowed_from().len() == 1 {
                    let after = at(n) > at(m);
                    assert_eq!(after, order == SortOrder::BackToFront, "{order:?}");
                }
            }
        }
    }
}

/// At uniform pixels on the floor, the painted shadow's light set is the
/// set of lights whose shadow rays are blocked.
fn assert_overlap_pixels(scene: &Scene, tree: &VirtualImageTree, view: &View, size: u32) {
    let caster = RayCaster::new(scene);
    let mut want = Vec::new();
    for row in 0..size {
        for col in 0..size {
            let x = (col as f64 + 0.5) / size as f64 * 2.0 - 1.0;
            let y = 1.0 - (row as f64 + 0.5) / size as f64 * 2.0;
            let (o, d) = caster.ray(x, y).unwrap();
            want.push(caster.cast(o, d).filter(|h| h.object == 0).map(|h| {
                let p = o + d * h.t;
                (0..2u32)
                    .filter(|&j| {
                        let light = scene.lights[j as usize].position;
                        caster.occluded(light, p, (0, 0), Some(0))
                    })
                    .collect::<Vec<u32>>()
            }));
        }
    }
    let got = painted_fragments(scene, tree, view, size);
    let s = size as i64;
    let (mut checked, mut overlap, mut bad) = (0, 0, Vec::new());
    for y in 0..s {
        for x in 0..s {
            let k = (y * s + x) as usize;
            let Some(w) = &want[k] else { continue };
            let uniform = (-1..=1).all(|dy: i64| {
                (-1..=1).all(|dx: i64| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx < 0
                        || ny < 0
                        || nx >= s
                        || ny >= s
                        || want[(ny * s + nx) as usize] == want[k]
                })
            });
            if !uniform {
                continue;
            }
            checked += 1;
            overlap += (w.len() == 2) as usize;
            let g = got[k].map(|n| tree.nodes[n].shadowed_from().to_vec());
            if g.as_ref() != Some(w) {
                bad.push((x, y, w.clone(), g));
            }
        }
    }
    assert!(checked > 1000 && overlap > 20, "{checked} {overlap}");
    assert!(
        bad.is_empty(),
        "{} of {checked}: {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

/// `TreeOptions::shading` selects the illumination model of every
/// fragment's shade, reflected ones and shadows included (Donovan 000
/// section 6 rules (1) and (2), or Garcia's 004 section 4.8).
#[test]
fn the_tree_shades_with_the_selected_model() {
    use plytrace::internal::shading::{ShadingModel, facet_shade_with_model};
    let scene = box_beside_mirror();
    let view = View::new(&scene, 64, 64).unwrap();
    let materials = Materials::new(&scene);
    let mut differ = 0;
    for model in [ShadingModel::Garcia, ShadingModel::Donovan] {
        let tree = image_tree::build(
            &materials,
            &view,
            TreeOptions {
                max_level: 2,
                nns: true,
                shadows: true,
                shading: model,
                ..Default::default()
            },
        );
        assert!(tree.nodes.iter().any(|f| f.level == 2));
        for f in &tree.nodes {
            let lights: Vec<_> = (0..scene.lights.len() as u32)
                .filter(|j| !f.shadowed_from().contains(j))
                .map(|j| scene.lights[j as usize])
                .collect();
            let shade = |m| {
                facet_shade_with_model(
                    &materials,
                    tree.eye(f),
                    f.object,
                    f.polygon,
                    f.back_facing,
                    &lights,
                    None,
                    m,
                )
            };
            assert!((f.shade - shade(model)).length() < 1e-12);
            let other = match model {
                ShadingModel::Garcia => ShadingModel::Donovan,
                ShadingModel::Donovan => ShadingModel::Garcia,
            };
            differ += ((shade(other) - f.shade).length() > 1e-6) as usize;
        }
    }
    assert!(differ > 10, "{differ}");
}

/// Two squares piercing each other, close to a Point light: the NNS sorter
/// must split them.
fn crossed_squares() -> Scene {
    load(
        1,
        "polarview 10 30 50 0\n\
         light 1 -1 2 1 1 1 6 Point\n\
         defobj square\n scale 3 3 1\nendobj\n\
         defobj square\n translate 0 0.5 0\n rotate 90 x\n scale 2 2 1\nendobj\n",
    )
}

/// Donovan (000 section 6): "if Gouraud's method is used, then the face
/// splitting routine, when it splits type D edges, should compute a correct
/// intensity value for the vertex it creates": the vertex shade at a vertex
/// made by the NNS splitter is the linear interpolation of the shades at
/// the ends of the original edge it lies on (so no seam appears along it).
#[test]
fn split_vertices_get_interpolated_gouraud_shades() {
    use plytrace::internal::shading::vertex_shades;
    use plytrace::internal::visibility::nns;
    let scene = crossed_squares();
    let view = View::new(&scene, 64, 64).unwrap();
    let faces: Vec<nns::NnsFace> = scene
        .objects
        .iter()
        .enumerate()
        .flat_map(|(oi, o)| {
            o.polygons
                .iter()
                .enumerate()
                .map(move |(pi, p)| nns::NnsFace {
                    object: oi as u32,
                    polygon: pi as u32,
                    world: p
                        .indices
                        .iter()
                        .map(|&i| o.vertices[i as usize])
                        .collect::<Vec<_>>()
                        .into(),
                })
        })
        .collect();
    let (sorted, _) = nns::sort(faces, &view, 1e-9);
    assert!(sorted.len() > 2, "nothing was split");
    let materials = Materials::new(&scene);
    let mut split = 0;
    for f in &sorted {
        let o = &scene.objects[f.object as usize];
        let idx = &o.polygons[f.polygon as usize].indices;
        let shade =
            |p: DVec3| vertex_shades(&materials, view.eye, f.object, f.polygon, false, &[p])[0];
        for &p in f.world.get(&scene.objects, f.object, f.polygon).iter() {
            for k in 0..idx.len() {
                let a = o.vertices[idx[k] as usize];
                let b = o.vertices[idx[(k + 1) % idx.len()] as usize];
                let t = (p - a).dot(b - a) / (b - a).length_squared();
                let on_edge = (a + (b - a) * t).distance(p) < 1e-9 && t > 1e-6 && t < 1.0 - 1e-6;
                if on_edge {
                    split += 1;
                    let lerp = shade(a) + (shade(b) - shade(a)) * t;
                    assert!((shade(p) - lerp).length() < 1e-9, "{} vs {lerp}", shade(p));
                }
            }
        }
    }
    assert!(split >= 2, "{split}");
}

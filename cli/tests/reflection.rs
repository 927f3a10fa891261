//! The virtual image tree against a ray caster that follows mirror
//! reflections: every pixel whose 3x3 neighbourhood sees one polygon (after
//! any number of reflections, up to the scene's depth) shows that polygon,
//! on mirror.des (depth 2), gallery.des (depth 14, facing mirrors) and
//! office1.des (depth 3). Also the output orders of 004 section 4.10 for a
//! cube on a mirror.

#[path = "../../tests/support/mod.rs"]
mod support;

use glam::DVec3;
use plytrace::internal::geometry::view::View;
use plytrace::internal::image_tree::{self, Branch, TreeOptions};
use plytrace::internal::model::SortOrder;
use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::Scene;
use plytrace::internal::shading::Materials;
use plytrace::internal::visibility::ray_cast::RayCaster;

fn traced_oracle(scene: &Scene, size: u32) -> Vec<Option<(u32, u32)>> {
    RayCaster::new(scene)
        .traced_image(size, size, scene.modes.max_level, scene.threshold)
        .into_iter()
        .map(|h| h.map(|(h, _)| (h.object, h.polygon)))
        .collect()
}

/// With the NNS sorter at every level (`setmode n on`), so that what is
/// checked is the tree, not the simple sort's known failures.
fn assert_tree_agrees(name: &str, scene: &Scene, size: u32) {
    let mut scene = scene.clone();
    scene.modes.nns = true;
    let scene = &scene;
    let r = render(
        scene,
        &RenderOptions {
            size: Some((size, size)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let oracle = traced_oracle(scene, size);
    let (checked, bad) = support::mismatches(&oracle, &support::painted_ids(&r), size, size);
    assert!(
        checked > size as usize * size as usize / 3,
        "{name}: only {checked} checked"
    );
    assert!(
        bad.is_empty(),
        "{name}: {} of {checked} pixels differ from the reflecting oracle, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

#[test]
fn mirror_scene_reflections_agree_with_the_oracle() {
    let path = support::scene_fixture("mirror.des");
    let scene = plytrace::internal::scene::load(&path).unwrap().0;
    assert_eq!(scene.modes.max_level, 2);
    assert_tree_agrees("mirror", &scene, 192);
}

#[test]
fn gallery_facing_mirrors_to_depth_14_agree_with_the_oracle() {
    let path = support::scene_fixture("gallery.des");
    let scene = plytrace::internal::scene::load(&path).unwrap().0;
    assert_eq!(scene.modes.max_level, 14);
    assert_tree_agrees("gallery", &scene, 192);
    let r = render(
        &scene,
        &RenderOptions {
            size: Some((192, 192)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    assert_eq!(r.stats.max_depth, 14);
}

#[test]
fn office1_reflections_agree_with_the_oracle() {
    let path = support::scene_fixture("office1.des");
    let scene = plytrace::internal::scene::load(&path).unwrap().0;
    assert_tree_agrees("office1", &scene, 192);
}

fn cube_on_mirror() -> Scene {
    cube_on_mirror_lit("")
}

/// The cube on a mirror of 004 figure 4.15, with `light` lines.
fn cube_on_mirror_lit(light: &str) -> Scene {
    let dir = support::cube_and_square_dir();
    let path = dir.path().join("m.des");
    std::fs::write(
        &path,
        format!("resolution 128 128\nperspective 45 1 0.1 100\ndepth 2\npushmatrix\nident\npolarview 9 30 60 0\n{light}\
         defobj square\n reflectance 0.5\n scale 4 4 1\nendobj\n\
         defobj cube\n translate 0 0 1.01\nendobj\npopmatrix\n"),
    )
    .unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

/// 004 section 4.10, figure 4.15: back to front `P11, P21, P22, P23, P12,
/// P13, P14`; front to back `P12, P13, P14, P21, P22, P23, P11`.
#[test]
fn cube_on_mirror_output_orders() {
    let scene = cube_on_mirror();
    let view = View::new(&scene, 128, 128).unwrap();
    let tree = image_tree::build(
        &Materials::new(&scene),
        &view,
        TreeOptions {
            max_level: 2,
            threshold: 0.0,
            nns: false,
            shadows: false,
            explicit_shadow_shades: false,
            refraction: Default::default(),
            ..Default::default()
        },
    );
    let label = |n: usize| {
        let f = &tree.nodes[n];
        (f.level, f.object)
    };
    let btf: Vec<(u32, u32)> = tree
        .output_order(SortOrder::BackToFront)
        .into_iter()
        .map(label)
        .collect();
    // The mirror (object 0) first, then the three reflected cube faces,
    // then the three visible cube faces.
    assert_eq!(
        btf,
        vec![(1, 0), (2, 1), (2, 1), (2, 1), (1, 1), (1, 1), (1, 1)]
    );
    let ftb: Vec<(u32, u32)> = tree
        .output_order(SortOrder::FrontToBack)
        .into_iter()
        .map(label)
        .collect();
    assert_eq!(
        ftb,
        vec![(1, 1), (1, 1), (1, 1), (2, 1), (2, 1), (2, 1), (1, 0)]
    );
    // The children are reflected, with shades pre-blended: I = I11 + kr I own.
    let mirror = tree.roots[0];
    let i11 = tree.nodes[mirror].shade;
    for c in tree.nodes[mirror].children() {
        let f = &tree.nodes[c];
        assert_eq!(f.branch, Branch::Reflected);
        assert!((f.blended - (i11 + f.shade * 0.5)).length() < 1e-12);
        assert_eq!(f.weight, 0.5);
    }
    // The mirror sees the cube's bottom face and the two side faces seen
    // directly; every reflected fragment lies beyond the mirror plane (in
    // virtual coordinates, the reflection of the scene), its corners are
    // exactly the mirror images of its cube face's corners (the cube lies
    // wholly inside the mirror's outline, so nothing is clipped off), and
    // on screen it lies inside the mirror's outline.
    let mut seen: Vec<u32> = tree
        .roots
        .iter()
        .map(|&n| &tree.nodes[n])
        .filter(|f| f.object == 1)
        .map(|f| f.polygon)
        .collect();
    seen.sort_unstable();
    let cube = &scene.objects[1];
    let (top, bottom) = (0u32, 1u32);
    // (In eye coordinates: the top faces the way the mirror does.)
    let up = scene.objects[0].polygons[0].normal().normalize();
    assert!(
        cube.polygons[top as usize].normal().normalize().dot(up) > 0.999
            && cube.polygons[bottom as usize].normal().normalize().dot(up) < -0.999
    );
    assert_eq!(seen.len(), 3, "level 1 sees three cube faces: {seen:?}");
    assert!(seen.contains(&top) && !seen.contains(&bottom));
    let mut want: Vec<u32> = seen
        .iter()
        .map(|&p| if p == top { bottom } else { p })
        .collect();
    want.sort_unstable();
    let mut reflected: Vec<u32> = tree.nodes[mirror]
        .children()
        .map(|c| tree.nodes[c].polygon)
        .collect();
    reflected.sort_unstable();
    assert_eq!(reflected, want, "the cube faces seen in the mirror");
    let plane = scene.objects[0].polygons[0].plane;
    let (n, d) = (plane.truncate(), plane.w);
    let side = |p: DVec3| (n.dot(p) + d) / n.length();
    let mirror_image = |p: DVec3| p - n * (2.0 * (n.dot(p) + d) / n.length_squared());
    let outline = &tree.nodes[mirror].screen(&scene.objects, &view);
    let turn = |a: DVec3, b: DVec3, p: DVec3| (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    let orientation = (0..outline.len())
        .map(|i| turn(outline[0], outline[i], outline[(i + 1) % outline.len()]))
        .sum::<f64>()
        .signum();
    for c in tree.nodes[mirror].children() {
        let f = &tree.nodes[c];
        let face = &cube.polygons[f.polygon as usize];
        let points = f.points(&scene.objects);
        assert_eq!(points.len(), face.indices.len());
        for &p in points.iter() {
            assert!(side(p) < -1e-3, "{p} is not beyond the mirror");
            let q = mirror_image(p);
            assert!(
                face.indices
                    .iter()
                    .any(|&i| (cube.vertices[i as usize] - q).length() < 1e-9),
                "the mirror image {q} of {p} is not a corner of cube face {}",
                f.polygon
            );
        }
        for &p in &f.screen(&scene.objects, &view) {
            for i in 0..outline.len() {
                let (a, b) = (outline[i], outline[(i + 1) % outline.len()]);
                assert!(
                    orientation * turn(a, b, p) >= -1e-6 * (b - a).length(),
                    "{p} is outside the mirror's outline"
                );
            }
        }
    }
    // The painted image agrees with the reflecting oracle.
    let r = render(&scene, &RenderOptions::default()).unwrap();
    let (checked, bad) = support::mismatches(
        &traced_oracle(&scene, 128),
        &support::painted_ids(&r),
        128,
        128,
    );
    assert!(
        checked > 5000 && bad.is_empty(),
        "{} of {checked}",
        bad.len()
    );
}

/// 004 section 5.9, figure 5.14, a cube on a partly diffuse mirror with a
/// Point light: front to back `P12, P13, P14, P21, P22, P23, S1, S2, S3,
/// P11` (the mirror's sub-tree, then its shadow polygons, then the
/// mirror); back to front the painter's `P11, S.., P21, .., P12, ..`.
#[test]
fn cube_on_partly_diffuse_mirror_orders_with_shadows() {
    let scene = cube_on_mirror_lit("light -4 -2 6 1 1 1 100 Point\n");
    let view = View::new(&scene, 128, 128).unwrap();
    let tree = image_tree::build(
        &Materials::new(&scene),
        &view,
        TreeOptions {
            max_level: 2,
            shadows: true,
            ..Default::default()
        },
    );
    // (level, object, is a shadow)
    let label = |n: usize| {
        let f = &tree.nodes[n];
        let shadow = matches!(f.kind, image_tree::FragmentKind::Shadow { .. });
        (f.level, f.object, shadow)
    };
    let shadows = tree
        .nodes
        .iter()
        .filter(|f| f.branch == Branch::Shadow)
        .count();
    assert!(shadows >= 1, "the cube casts a shadow on the mirror");
    let (p1, p2, s) = ((1, 1, false), (2, 1, false), (1, 0, true));
    let mut want_ftb = vec![p1, p1, p1, p2, p2, p2];
    want_ftb.extend(std::iter::repeat_n(s, shadows));
    want_ftb.push((1, 0, false));
    let ftb: Vec<_> = tree
        .output_order(SortOrder::FrontToBack)
        .into_iter()
        .map(label)
        .collect();
    assert_eq!(ftb, want_ftb);
    let mut want_btf = vec![(1, 0, false)];
    want_btf.extend(std::iter::repeat_n(s, shadows));
    want_btf.extend([p2, p2, p2, p1, p1, p1]);
    let btf: Vec<_> = tree
        .output_order(SortOrder::BackToFront)
        .into_iter()
        .map(label)
        .collect();
    assert_eq!(btf, want_btf);
}

/// `setmode o on`: the tree in the file form of 004 figure 4.14, read back
/// losslessly from both forms; levels follow the output order.
#[test]
fn tree_file_of_the_cube_on_a_mirror() {
    let mut scene = cube_on_mirror();
    scene.modes.output_tree = true;
    scene.modes.blend = true;
    let r = render(&scene, &RenderOptions::default()).unwrap();
    let tree = r.tree.expect("setmode o on gives the tree");
    let levels: Vec<u16> = tree.records.iter().map(|r| r.level).collect();
    assert_eq!(levels, vec![1, 2, 2, 2, 1, 1, 1]);
    assert!(tree.blended && !tree.front_to_back);
    let path = std::path::Path::new("m.out");
    assert_eq!(
        plytrace::internal::tree::RecordStream::from_bytes(&tree.to_bytes(), path).unwrap(),
        tree
    );
    assert_eq!(
        plytrace::internal::tree::RecordStream::from_text(&tree.to_text(), path).unwrap(),
        tree
    );
    // Normalized coordinates: each record's points are its fragment's
    // screen points (pixels from the lower left corner) over the image
    // size, in the tree's back-to-front order.
    let view = View::new(&scene, 128, 128).unwrap();
    let built = image_tree::build(
        &Materials::new(&scene),
        &view,
        TreeOptions {
            max_level: 2,
            ..Default::default()
        },
    );
    let order = built.output_order(SortOrder::BackToFront);
    assert_eq!(order.len(), tree.records.len());
    for (rec, &n) in tree.records.iter().zip(&order) {
        let screen = &built.nodes[n].screen(&scene.objects, &view);
        assert_eq!(rec.points.len(), screen.len());
        for (p, s) in rec.points.iter().zip(screen) {
            let want = [(s.x / 128.0) as f32, (s.y / 128.0) as f32];
            assert!(
                (p[0] - want[0]).abs() <= 1e-6 && (p[1] - want[1]).abs() <= 1e-6,
                "record point {p:?}, want {want:?} (screen {s})"
            );
        }
    }
}

/// Refraction through the water of underwater.des: the pool floor is seen
/// through the surface as a refracted branch, and the three matrices of
/// 004 sections 4.6 and 6.4.3 place it differently.
#[test]
fn refraction_models_map_the_pool_floor() {
    let path = support::scene_fixture("underwater.des");
    let scene = plytrace::internal::scene::load(&path).unwrap().0;
    let view = View::new(&scene, 128, 128).unwrap();
    let centroid_of_refracted = |model: image_tree::Refraction| {
        let tree = image_tree::build(
            &Materials::new(&scene),
            &view,
            TreeOptions {
                max_level: 2,
                threshold: 0.0,
                nns: true,
                shadows: false,
                explicit_shadow_shades: false,
                refraction: model,
                ..Default::default()
            },
        );
        let refracted: Vec<_> = tree
            .nodes
            .iter()
            .filter(|f| f.branch == Branch::Refracted)
            .collect();
        assert!(
            !refracted.is_empty(),
            "{model:?}: nothing seen through the water"
        );
        // The floor is seen through the water, and the water surface does
        // not see itself (regression: it mapped onto itself and hid all).
        let name = |f: &&image_tree::Fragment| scene.objects[f.object as usize].name.clone();
        assert!(
            refracted.iter().any(|f| name(f).starts_with("checker")),
            "{model:?}: no floor"
        );
        for f in &refracted {
            let parent = &tree.nodes[f.parent().unwrap()];
            assert!(
                (f.object, f.polygon) != (parent.object, parent.polygon),
                "{model:?}: the surface sees itself"
            );
        }
        let pts: Vec<DVec3> = refracted
            .iter()
            .flat_map(|f| f.screen(&scene.objects, &view))
            .collect();
        pts.iter().copied().sum::<DVec3>() / pts.len() as f64
    };
    // Each model sees something through the water.
    for model in [
        image_tree::Refraction::Linearized,
        image_tree::Refraction::Paraxial,
        image_tree::Refraction::Orthographic,
    ] {
        assert!(centroid_of_refracted(model).is_finite());
    }
    // And they show the checkerboard differently.
    let ids = |model| {
        let r = render(
            &scene,
            &RenderOptions {
                size: Some((128, 128)),
                refraction: model,
                ..RenderOptions::default()
            },
        )
        .unwrap();
        support::painted_ids(&r)
    };
    let (lin, par) = (
        ids(image_tree::Refraction::Linearized),
        ids(image_tree::Refraction::Paraxial),
    );
    let differing = lin.iter().zip(&par).filter(|(a, b)| a != b).count();
    assert!(differing > 50, "only {differing} pixels differ");
    // Seen in parallel projection, the orthographic matrix M_to is exact,
    // and so is the linearization (every ray has the direction of the one
    // through the centre): what each shows through the water is what a
    // ray refracted by Snell's law hits (the bent stick included), at every
    // pixel where that is unambiguous. (The water's reflection is turned off, so that what is
    // painted last over it is what is seen through it.)
    let mut parallel = scene.clone();
    parallel.projection = plytrace::internal::math::ortho(-3.2, 3.2, -3.2, 3.2, 0.01, 1000.0);
    let water = parallel
        .objects
        .iter()
        .position(|o| o.surface.transmittance > 0.0)
        .expect("the water");
    parallel.objects[water].surface.reflectance = 0.0;
    // NNS at every level, as above: the stick's foot nearly touches the
    // floor, which the simple depth sort need not get right.
    parallel.modes.nns = true;
    let size = 192;
    let oracle = snell_oracle(&parallel, size);
    let through_water = oracle
        .iter()
        .flatten()
        .filter(|&&(o, _)| o as usize != water)
        .count();
    for model in [
        image_tree::Refraction::Orthographic,
        image_tree::Refraction::Linearized,
    ] {
        let r = render(
            &parallel,
            &RenderOptions {
                size: Some((size, size)),
                refraction: model,
                aa: Some(plytrace::internal::raster::scan::Method::Point),
                ..RenderOptions::default()
            },
        )
        .unwrap();
        let (checked, bad) = support::mismatches(&oracle, &support::painted_ids(&r), size, size);
        assert!(
            checked > (size * size / 2) as usize && through_water > 4000,
            "{model:?}: {checked} checked, {through_water} seen through the water"
        );
        assert!(
            bad.is_empty(),
            "{model:?}: {} of {checked} pixels differ from Snell's law, e.g. {:?}",
            bad.len(),
            &bad[..bad.len().min(6)]
        );
    }
}

/// The nearest polygon hit by the ray `o + t d`, `t` in `(from, 1]`,
/// skipping polygons seen from behind (unless `type open`) and those in
/// the plane `skip`: (t, object, polygon).
fn nearest_hit(
    scene: &Scene,
    o: DVec3,
    d: DVec3,
    from: f64,
    skip: Option<glam::DVec4>,
) -> Option<(f64, u32, u32)> {
    let mut best: Option<(f64, u32, u32)> = None;
    for (oi, obj) in scene.objects.iter().enumerate() {
        if obj.surface_type.hidden {
            continue;
        }
        for (pi, poly) in obj.polygons.iter().enumerate() {
            if skip.is_some_and(|s| (s - poly.plane).length() < 1e-9) {
                continue;
            }
            let n = poly.normal();
            let denom = n.dot(d);
            if denom == 0.0 || (denom > 0.0 && !obj.surface_type.open) {
                continue;
            }
            let t = -(n.dot(o) + poly.plane.w) / denom;
            if t <= from || t > 1.0 || best.is_some_and(|b| b.0 <= t) {
                continue;
            }
            let pts: Vec<DVec3> = poly
                .indices
                .iter()
                .map(|&i| obj.vertices[i as usize])
                .collect();
            if support::inside(&pts, n, o + d * t) {
                best = Some((t, oi as u32, pi as u32));
            }
        }
    }
    best
}

/// At each pixel centre (rows from the top), what a ray shows when it is
/// refracted by Snell's law at a transparent polygon (one level, as at
/// depth 2): the polygon hit beyond it, or the transparent polygon itself
/// when the refracted ray hits nothing. Between the near and far planes.
fn snell_oracle(scene: &Scene, size: u32) -> Vec<Option<(u32, u32)>> {
    let inv = support::invert(&scene.projection).unwrap();
    let unproject = |x: f64, y: f64, z: f64| support::unproject(&inv, x, y, z);
    let mut out = Vec::new();
    for row in 0..size {
        for col in 0..size {
            let x = (col as f64 + 0.5) / size as f64 * 2.0 - 1.0;
            let y = 1.0 - (row as f64 + 0.5) / size as f64 * 2.0;
            let o = unproject(x, y, -1.0);
            let d = unproject(x, y, 1.0) - o;
            let Some((t, oi, pi)) = nearest_hit(scene, o, d, 0.0, None) else {
                out.push(None);
                continue;
            };
            let object = &scene.objects[oi as usize];
            if object.surface.transmittance <= 0.0 {
                out.push(Some((oi, pi)));
                continue;
            }
            let plane = object.polygons[pi as usize].plane;
            let n = plane.truncate().normalize();
            let dir = d.normalize();
            let eta = 1.0 / object.surface.index;
            let cos_i = -dir.dot(n);
            let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
            assert!(k > 0.0, "no total reflection entering the water");
            let refracted = eta * dir + (eta * cos_i - k.sqrt()) * n;
            // The rest of the ray's length, as the far plane bounds it.
            let hit = o + d * t;
            let rest = refracted * (d.length() * (1.0 - t));
            out.push(Some(
                nearest_hit(scene, hit, rest, 1e-12, Some(plane))
                    .map_or((oi, pi), |(_, o2, p2)| (o2, p2)),
            ));
        }
    }
    out
}

/// With `setmode s on`, specular polygons are written as Phong records
/// (type 3) with one highlight vector per vertex and light.
#[test]
fn phong_tree_records() {
    let path = support::scene_fixture("mirror.des");
    let mut scene = plytrace::internal::scene::load(&path).unwrap().0;
    scene.modes.phong = true;
    scene.modes.output_tree = true;
    let r = render(
        &scene,
        &RenderOptions {
            size: Some((64, 64)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let tree = r.tree.unwrap();
    let phong: Vec<_> = tree
        .records
        .iter()
        .filter_map(|r| match &r.shades {
            plytrace::internal::tree::Shades::Phong(p) => Some((r, p)),
            _ => None,
        })
        .collect();
    // The red ball has specular 0.3: it and its reflection are Phong.
    assert!(phong.len() > 5);
    for (rec, p) in &phong {
        assert_eq!(p.rgbt.len(), rec.points.len());
        assert!(p.normals.iter().all(|n| n.len() == scene.lights.len()));
        assert_eq!(p.shininess, 150.0);
    }
    let path = std::path::Path::new("m.out");
    assert_eq!(
        plytrace::internal::tree::RecordStream::from_bytes(&tree.to_bytes(), path).unwrap(),
        tree
    );
    assert_eq!(
        plytrace::internal::tree::RecordStream::from_text(&tree.to_text(), path).unwrap(),
        tree
    );
}

/// The records of a tree file (`FNAME.txt`): each one's level and the
/// area of its screen polygon.
fn tree_records(txt: &str) -> Vec<(u32, f64)> {
    txt.lines()
        .filter(|l| l.starts_with("faceted "))
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .map(|x| x.parse().unwrap())
                .collect();
            let (level, n) = (w[0] as u32, w[1] as usize);
            let xy = &w[5..5 + 2 * n];
            let area = (0..n)
                .map(|i| {
                    let j = (i + 1) % n;
                    xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1]
                })
                .sum::<f64>()
                .abs()
                / 2.0;
            (level, area)
        })
        .collect()
}

/// 004 figure 4.15 through the program, as a user of the thesis runs it
/// (`sort ftb`, `depth 2`, `setmode o on`): the front-to-back tree file
/// is `P12, P13, P14, P21, P22, P23, P11` (the cube's faces, the reflected
/// faces, then the mirror, the largest), the back-to-front one the
/// mirror first; and the two orders give one picture, with the default
/// sort and with the simple one (`-n off`).
#[test]
fn cube_on_mirror_both_orders_through_the_program() {
    let dir = support::cube_and_square_dir();
    let scene = |order: &str| {
        format!(
            "resolution 128 128\nperspective 45 1 0.1 100\ndepth 2\nsort {order}\n\
             setmode o on\nfname fig{order}\npushmatrix\nident\npolarview 9 30 60 0\n\
             light 0 -10 10 1 1 1 50 Diffuse\n\
             defobj square\n reflectance 0.5\n scale 4 4 1\nendobj\n\
             defobj cube\n translate 0 0 1.01\nendobj\npopmatrix\n"
        )
    };
    for sort in [&[][..], &["-n", "off"][..]] {
        let mut png = Vec::new();
        for order in ["ftb", "btf"] {
            std::fs::write(dir.path().join(format!("{order}.des")), scene(order)).unwrap();
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_plytrace"))
                .current_dir(dir.path())
                .args(sort)
                .args(["-q", &format!("{order}.des"), "-o", &format!("{order}.png")])
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            png.push(std::fs::read(dir.path().join(format!("{order}.png"))).unwrap());
            let txt = std::fs::read_to_string(dir.path().join(format!("fig{order}.txt"))).unwrap();
            let records = tree_records(&txt);
            let levels: Vec<u32> = records.iter().map(|r| r.0).collect();
            let largest = (0..records.len())
                .max_by(|&a, &b| records[a].1.total_cmp(&records[b].1))
                .unwrap();
            if order == "ftb" {
                assert_eq!(levels, [1, 1, 1, 2, 2, 2, 1], "{sort:?}");
                assert_eq!(largest, 6, "the mirror last: {records:?}");
            } else {
                assert_eq!(levels, [1, 2, 2, 2, 1, 1, 1], "{sort:?}");
                assert_eq!(largest, 0, "the mirror first: {records:?}");
            }
        }
        assert!(
            png[0] == png[1],
            "{sort:?}: sort ftb and sort btf draw two pictures"
        );
    }
}

//! Exact refraction (`--refraction exact`, `raytrace::exact`) and the ray
//! tracer's refraction, against hand-worked rays and against each other.
//!
//! - Hand-worked rays (independent oracle): a ray at 45 degrees through a
//!   glass slab (index 1.5, 1 thick) leaves it parallel to itself, shifted
//!   by `tan(asin(sin 45 / 1.5)) = 0.534522` along x; through a flat water
//!   surface (index 1.33) 1 above the floor it lands `tan(asin(sin 45 /
//!   1.33)) = 0.627722` past the entry point.
//! - Images: with the glass made fully transparent (`kt` 1, no diffuse,
//!   no reflection: the glass shows only what is behind it), the tree
//!   with exact refraction shows the ray tracer's colour (to 2/255: the
//!   tree's byte records) at >= 99% of the pixels away from edges (3x3
//!   neighbourhood seeing one object through the glass, by the tracer's
//!   refraction-following rays), and the linearized matrix does not (it
//!   is the model the exact one replaces, so the check can fail).

mod support;

use glam::DVec3;
use plytrace::internal::geometry::view::View;
use plytrace::internal::image_tree::Refraction;
use plytrace::internal::raster::scan::Method;
use plytrace::internal::raytrace::{self, RayTraceOptions, RayTracer};
use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::Scene;
use plytrace::internal::shading::ShadingModel;

fn scene_of(text: &str) -> Scene {
    let dir = support::cube_and_square_dir();
    let path = dir.path().join("s.des");
    std::fs::write(&path, text).unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

/// Where a ray from (0, 0, 10) going down at 45 degrees along +x meets
/// the floor (z = 0) when it follows refraction.
fn landing(scene: &Scene) -> DVec3 {
    let view = View::new(scene, 16, 16).unwrap();
    let tracer = RayTracer::new(scene, view, false, ShadingModel::Garcia);
    let mut ray = tracer.primary(8.0, 8.0).unwrap();
    ray.origin = DVec3::new(0.0, 0.0, 10.0);
    ray.dir = DVec3::new(100.0, 0.0, -100.0);
    let (hit, point) = tracer.seen_through(&ray).expect("the floor");
    assert_eq!(hit.object, 0, "the floor is object 0");
    point
}

/// No viewing transform: world coordinates are the scene's own.
const HEADER: &str = "resolution 16 16\nperspective 45 1 0.1 100\ndepth 2\npushmatrix\nident\n";

#[test]
fn hand_worked_ray_through_a_glass_slab() {
    let scene = scene_of(&format!(
        "{HEADER}defobj square\n scale 40 40 1\nendobj\n\
         defobj cube\n diffuse 0\n transmittance 1\n index 1.5\n translate 0 0 2\n scale 20 20 0.5\nendobj\n\
         popmatrix\n"
    ));
    // In at z = 2.5, x = 7.5; out at z = 1.5, x = 7.5 + 0.534522; down
    // at 45 degrees again to z = 0: x = 9.534522.
    let p = landing(&scene);
    assert!((p.x - 9.534_522).abs() < 1e-5 && p.y.abs() < 1e-9, "{p}");
    assert!(p.z.abs() < 1e-9, "{p}");
}

#[test]
fn hand_worked_ray_through_a_flat_water_surface() {
    let scene = scene_of(&format!(
        "{HEADER}defobj square\n scale 40 40 1\nendobj\n\
         defobj square\n diffuse 0\n transmittance 1\n index 1.33\n translate 0 0 1\n scale 20 20 1\nendobj\n\
         popmatrix\n"
    ));
    // In at z = 1, x = 9; sin(theta2) = 0.707107 / 1.33 = 0.531659,
    // tan(theta2) = 0.627722: the floor at x = 9.627722.
    let p = landing(&scene);
    assert!((p.x - 9.627_722).abs() < 1e-5, "{p}");
}

/// The share of non-edge pixels where the tree (with `model`) shows the
/// ray tracer's colour, and how many were compared.
fn agreement(scene: &Scene, size: u32, model: Refraction, aa: Method) -> (f64, usize) {
    let tree = render(
        scene,
        &RenderOptions {
            size: Some((size, size)),
            refraction: model,
            aa: Some(aa),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let (traced, _) = raytrace::render(
        scene,
        &RayTraceOptions {
            size: Some((size, size)),
            ..RayTraceOptions::default()
        },
    )
    .unwrap();
    let view = View::new(scene, size, size).unwrap();
    let tracer = RayTracer::new(scene, view, false, ShadingModel::Garcia);
    let seen: Vec<Option<(u32, u32)>> = (0..size * size)
        .map(|k| {
            let (x, y) = (k % size, k / size);
            let ray = tracer.primary(x as f64 + 0.5, size as f64 - y as f64 - 0.5)?;
            tracer
                .seen_through(&ray)
                .map(|(h, _)| (h.object, h.polygon))
        })
        .collect();
    let (mut checked, mut good) = (0, 0);
    for y in 1..size - 1 {
        for x in 1..size - 1 {
            let here = seen[(y * size + x) as usize];
            let uniform = (0..9).all(|k| {
                let (nx, ny) = (x + k % 3 - 1, y + k / 3 - 1);
                seen[(ny * size + nx) as usize] == here
            });
            if !uniform {
                continue;
            }
            checked += 1;
            let k = (y * size + x) as usize;
            let (a, b) = (tree.frame.color[k], traced.color[k]);
            if (0..3).all(|c| (a[c] - b[c]).abs() <= 2.0 / 255.0) {
                good += 1;
            }
        }
    }
    (good as f64 / checked.max(1) as f64, checked)
}

/// The pool of underwater.des with its water fully transparent.
fn clear_pool() -> Scene {
    let mut scene = plytrace::internal::scene::load(&support::scene_fixture("underwater.des"))
        .unwrap()
        .0;
    for o in &mut scene.objects {
        if o.surface.transmittance > 0.0 {
            o.surface.transmittance = 1.0;
            o.surface.reflectance = 0.0;
            o.surface.diffuse = 0.0;
        }
    }
    // NNS: the stick crossing the water needs splitting at level 1.
    scene.modes.nns = true;
    scene
}

/// Coloured letters (bars) on a floor under a thick glass slab, seen
/// obliquely from above.
fn slab_over_letters() -> Scene {
    slab_over_letters_with("", 2)
}

/// The same with more objects and another depth.
fn slab_over_letters_with(more: &str, depth: u32) -> Scene {
    let mut text = format!(
        "resolution 96 96\nperspective 45 1 0.1 100\ndepth {depth}\npushmatrix\nident\n\
         polarview 9 20 40 0\nlight 2 -3 8 1 1 1 100 Diffuse\n{more}\
         defobj square\n color 0.9 0.9 0.9\n diffuse 0.8\n scale 5 5 1\nendobj\n",
    );
    let colours = ["1 0 0", "0 1 0", "0 0 1", "1 1 0", "0 1 1", "1 0 1"];
    for (k, c) in colours.iter().enumerate() {
        let x = -2.5 + k as f64;
        text += &format!(
            "defobj square\n color {c}\n diffuse 0.8\n translate {x} 0 0.01\n scale 0.3 1.5 1\nendobj\n"
        );
    }
    text += "defobj cube\n diffuse 0\n transmittance 1\n index 1.5\n translate 0 0 1.2\n \
             scale 3.5 2.5 0.6\nendobj\npopmatrix\n";
    let mut scene = scene_of(&text);
    scene.modes.nns = true;
    scene
}

#[test]
fn exact_refraction_matches_the_ray_tracer_through_water() {
    let scene = clear_pool();
    for aa in [Method::Point, Method::Multilevel] {
        let (share, checked) = agreement(&scene, 96, Refraction::Exact, aa);
        assert!(checked > 4000, "{checked}");
        assert!(
            share >= 0.99,
            "pool, exact, {aa:?}: {:.2}% agree",
            share * 100.0
        );
    }
    let (share, _) = agreement(&scene, 96, Refraction::Linearized, Method::Point);
    assert!(
        share < 0.99,
        "pool, linearized: {:.2}% agree",
        share * 100.0
    );
}

#[test]
fn exact_refraction_matches_the_ray_tracer_through_a_slab() {
    let scene = slab_over_letters();
    for aa in [Method::Point, Method::Multilevel] {
        let (share, checked) = agreement(&scene, 96, Refraction::Exact, aa);
        assert!(checked > 3000, "{checked}");
        assert!(
            share >= 0.99,
            "slab, exact, {aa:?}: {:.2}% agree",
            share * 100.0
        );
    }
    let (share, _) = agreement(&scene, 96, Refraction::Linearized, Method::Point);
    assert!(
        share < 0.99,
        "slab, linearized: {:.2}% agree",
        share * 100.0
    );
}

#[test]
fn auto_picks_exact_when_the_linear_map_is_off_and_says_so() {
    let scene = clear_pool();
    let r = render(
        &scene,
        &RenderOptions {
            size: Some((64, 64)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let said = r.stats.refraction.expect("the scene refracts");
    assert!(said.starts_with("exact"), "{said}");
    assert!(r.stats.raytrace.is_some_and(|s| s.rays > 0));
    // Seen straight down in parallel projection the linear map is exact.
    let mut straight = scene.clone();
    straight.projection = plytrace::internal::math::ortho(-3.2, 3.2, -3.2, 3.2, 0.01, 1000.0);
    let r = render(
        &straight,
        &RenderOptions {
            size: Some((64, 64)),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let said = r.stats.refraction.expect("the scene refracts");
    assert!(said.starts_with("linearized"), "{said}");
}

/// The slab seen in a mirror standing behind it: the refracted branch
/// of a fragment at level 2, mapped back to world space by the mirror.
#[test]
fn exact_refraction_of_a_slab_seen_in_a_mirror() {
    let scene = slab_over_letters_with(
        "defobj square\n color 0.2 0.2 0.2\n diffuse 0.1\n reflectance 0.8\n \
         translate 0 4 1.5\n rotate 90 x\n scale 5 1.5 1\nendobj\n",
        3,
    );
    // Point sampled, post-blended (method 4) and pre-blended (method 2).
    for aa in [Method::Point, Method::Multilevel, Method::Mask] {
        let (share, checked) = agreement(&scene, 96, Refraction::Exact, aa);
        assert!(checked > 3000, "{checked}");
        let pct = share * 100.0;
        assert!(
            share >= 0.99,
            "slab in a mirror, exact, {aa:?}: {pct:.2}% agree"
        );
    }
}

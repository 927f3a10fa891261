//! What of a scene needs the virtual image tree (Garcia 1986, 004 chapter
//! 4: reflections and refractions below level 1, transparency, smooth
//! shading, shadows), for the algorithms that paint level 1 only, and the
//! bounding-box scene of `setmode p` (004 appendix, SETMODE COMMANDS).

use glam::DVec3;

use crate::error::{Error, Result};
use crate::model::Scene;
use crate::raster::scan::Method;
use crate::visibility::Algorithm;

use super::RenderOptions;

/// What of the scene needs the virtual image tree, in words; empty when
/// level 1 painted point by point shows all of it. Each item names the
/// objects concerned (the first few) and what about them needs the tree:
/// reflectance or transmittance traced below level 1, transparency, a
/// curved object smoothly shaded; and shadows, with how to go without.
pub fn tree_effects(scene: &Scene, options: &RenderOptions) -> Vec<String> {
    const NAMED: usize = 3;
    let mut what = Vec::new();
    let named = |o: &crate::model::Object| format!("object `{}` (#{})", o.name, o.number);
    let visible = || scene.objects.iter().filter(|o| !o.surface_type.hidden);
    let list = |items: Vec<String>| {
        let n = items.len();
        let mut shown: Vec<String> = items.into_iter().take(NAMED).collect();
        if n > NAMED {
            shown.push(format!("and {} more", n - NAMED));
        }
        shown.join(", ")
    };
    if needs_tree(scene) {
        let items: Vec<String> = visible()
            .filter_map(|o| {
                let (mut kr, mut kt) = (0.0f64, 0.0f64);
                for p in 0..o.polygons.len() {
                    let m = o.material(p);
                    kr = kr.max(m.reflectance);
                    kt = kt.max(m.transmittance);
                }
                let mut about = Vec::new();
                if kr > 0.0 {
                    about.push(format!("reflectance {kr}"));
                }
                if kt > 0.0 {
                    about.push(format!("transmittance {kt}"));
                }
                (!about.is_empty()).then(|| format!("{} with {}", named(o), about.join(" and ")))
            })
            .collect();
        what.push(format!(
            "mirrors and refracting surfaces traced to depth {} ({})",
            scene.modes.max_level,
            list(items)
        ));
    }
    let transparent: Vec<String> = visible()
        .filter(|o| o.surface.transparency.0 > 0.0)
        .map(|o| {
            format!(
                "{} with transparency {}",
                named(o),
                o.surface.transparency.0
            )
        })
        .collect();
    if !transparent.is_empty() {
        what.push(format!("transparency ({})", list(transparent)));
    }
    for (on, kind, mode) in [
        (scene.modes.vertex_shades, "Gouraud", "setmode v"),
        (scene.modes.phong, "Phong", "setmode s"),
    ] {
        if !on {
            continue;
        }
        let curved: Vec<String> = visible()
            .filter(|o| o.surface_type.curved)
            .map(|o| format!("{} is curved", named(o)))
            .collect();
        what.push(if curved.is_empty() {
            format!("{kind} polygons ({mode})")
        } else {
            format!("{kind} polygons ({mode}; {})", list(curved))
        });
    }
    if options.shadows && has_point_light(scene) {
        what.push(
            "shadows (`run y` with a Point light), which need the tree too: render without \
             them with `run n` (--no-shadows in immediate mode)"
                .into(),
        );
    }
    if options.aa.is_some_and(|m| m != Method::Point) {
        what.push("anti-aliasing (use --aa none)".into());
    }
    what
}

/// Refuses a scene that `algorithm` cannot render whole.
pub(super) fn refuse_tree_effects(
    scene: &Scene,
    options: &RenderOptions,
    algorithm: Algorithm,
) -> Result<()> {
    let what = tree_effects(scene, options);
    if what.is_empty() {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "--visibility {} paints level 1 only, point sampled, and cannot render {}; \
         use depth-sort or nns (the virtual image tree) for them",
        algorithm.name(),
        what.join("; ")
    )))
}

/// Whether the scene has a shadow-casting light.
pub fn has_point_light(scene: &Scene) -> bool {
    scene
        .lights
        .iter()
        .any(|l| l.kind == crate::model::LightKind::Point)
}

/// Whether the scene has anything to trace below level 1.
pub fn needs_tree(scene: &Scene) -> bool {
    scene.modes.max_level > 1
        && scene.objects.iter().any(|o| {
            !o.surface_type.hidden
                && (0..o.polygons.len()).any(|p| {
                    let m = o.material(p);
                    m.reflectance > 0.0 || m.transmittance > 0.0
                })
        })
}

/// The scene with every object replaced by its bounding box (the eight
/// transformed corners of its object-space box), in the object's colours.
pub fn bounding_box_scene(scene: &Scene) -> Scene {
    let mut out = scene.clone();
    for object in &mut out.objects {
        let corners = object.bbox_corners;
        let centre = corners.iter().copied().sum::<DVec3>() / 8.0;
        // Corner i has x, y, z from bits 0, 1, 2: the six faces.
        let faces: [[u32; 4]; 6] = [
            [0, 2, 6, 4],
            [1, 5, 7, 3],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 1, 3, 2],
            [4, 6, 7, 5],
        ];
        let polygons = faces
            .iter()
            .map(|f| {
                // Clockwise from outside: the Newell normal points inward.
                let pts: Vec<DVec3> = f.iter().map(|&i| corners[i as usize]).collect();
                let n = crate::geometry::polygon::newell_vector(pts.iter().copied());
                let fc = pts.iter().copied().sum::<DVec3>() / 4.0;
                if n.dot(fc - centre) > 0.0 {
                    f.iter().rev().copied().collect()
                } else {
                    crate::model::IndexList::from(*f)
                }
            })
            .collect();
        let parts = crate::scene::build::ObjectParts {
            number: object.number,
            name: object.name.clone(),
            mesh: std::sync::Arc::new(crate::model::Mesh {
                vertices: corners.to_vec(),
                polygons,
            }),
            polygon_colors: None,
            vertex_colors: None,
            transform: crate::math::Matrix4::IDENTITY,
            surface: object.surface,
            surface_type: object.surface_type,
        };
        if let Ok(b) = crate::scene::build::build_object(parts, &mut |_| {}) {
            *object = b;
        }
    }
    out
}

/// The size of the scene ([`Scene::size`]).
pub fn scene_scale(scene: &Scene) -> f64 {
    scene.size()
}

//! Brown's priority order (003) on geodesic spheres made in the scene
//! language and deformed by several radial functions, checked against the
//! ray-cast oracle; and the paper's main claim: the order computed once
//! stays correct under a perspective change and a radial deformation.

mod support;

use glam::{DVec2, DVec3};
use plytrace::internal::geometry::view::{self, GeometryStats, View};
use plytrace::internal::modeling::geodesic::{Division, Radial, geodesic};
use plytrace::internal::raster::frame_buffer::{FrameBuffer, PaintItem, PaintMode};
use plytrace::internal::render::{RenderOptions, render};
use plytrace::internal::scene::Scene;
use plytrace::internal::visibility::Algorithm;
use plytrace::internal::visibility::brown::priority_order;
use plytrace::internal::visibility::ray_cast::RayCaster;

fn load(des: &str, dets: &[(&str, String)]) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    for (name, text) in dets {
        std::fs::write(dir.path().join("det").join(name), text).unwrap();
    }
    let path = dir.path().join("b.des");
    std::fs::write(&path, des).unwrap();
    plytrace::internal::scene::load(&path).unwrap().0
}

fn sphere_scene(n: usize, division: &str, radial: &str, dist: f64) -> Scene {
    load(
        &format!(
            "resolution 128 128\nperspective 40 1 0.1 100\npushmatrix\nident\npolarview {dist} 25 65 0\n\
             defobj geo\n  geodesic {n} {division}\n  radial {radial}\nendobj\npopmatrix\n"
        ),
        &[],
    )
}

fn oracle(scene: &Scene, size: u32) -> Vec<Option<(u32, u32)>> {
    RayCaster::new(scene)
        .id_image(size, size)
        .into_iter()
        .map(|h| h.map(|h| (h.object, h.polygon)))
        .collect()
}

fn assert_brown_agrees(name: &str, scene: &Scene) {
    let r = render(
        scene,
        &RenderOptions {
            visibility: Some(Algorithm::Brown),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let (w, h) = (r.frame.width, r.frame.height);
    let (checked, bad) = support::mismatches(&oracle(scene, w), &support::painted_ids(&r), w, h);
    assert!(checked > 1000, "{name}: {checked}");
    assert!(
        bad.is_empty(),
        "{name}: {} of {checked} pixels differ, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

const RADIALS: [&str; 4] = [
    "sphere",
    "ellipsoid 1.6 1 0.7",
    "bumps 0.35 3",
    "lobes 0.4 4",
];

#[test]
fn opaque_geodesics_agree_with_the_oracle() {
    for division in ["equal", "angle"] {
        for n in [2, 4] {
            for radial in RADIALS {
                let scene = sphere_scene(n, division, radial, 5.0);
                assert_brown_agrees(&format!("{n} {division} {radial}"), &scene);
            }
        }
    }
}

/// A general (open) surface: the lower part of a deformed geodesic sphere,
/// a bowl whose inside and outside are both seen.
#[test]
fn general_surface_agrees_with_the_oracle() {
    let mesh = geodesic(4, Division::EqualAngle, Radial::Bumps(0.25, 2.0)).unwrap();
    let keep: Vec<plytrace::internal::model::IndexList> = mesh
        .polygons
        .iter()
        .filter(|p| p.iter().all(|&i| mesh.vertices[i as usize].z < 0.45))
        .cloned()
        .collect();
    let bowl = plytrace::internal::model::Mesh {
        vertices: mesh.vertices.clone(),
        polygons: keep,
    };
    let det = plytrace::internal::scene::object_file::write_det_ascii(&bowl, "bowl");
    for inc in [40.0, 70.0, 110.0] {
        let scene = load(
            &format!(
                "resolution 128 128\nperspective 40 1 0.1 100\npushmatrix\nident\npolarview 5 10 {inc} 0\n\
                 defobj bowl\n type polygon open\nendobj\npopmatrix\n"
            ),
            &[("bowl.det", det.clone())],
        );
        assert_brown_agrees(&format!("bowl seen from inc {inc}"), &scene);
    }
}

/// Brown's priority order of the first sphere view as a rank per polygon
/// (reversed if asked, to show that a wrong order is caught).
fn stored_rank(reverse: bool) -> Vec<usize> {
    let first = sphere_scene(4, "angle", "sphere", 6.0);
    let object = &first.objects[0];
    let faces: Vec<Vec<u32>> = object.polygons.iter().map(|p| p.indices.to_vec()).collect();
    let v = View::new(&first, 128, 128).unwrap();
    let centre = object.transform.transform_point(DVec3::ZERO);
    let axis = v.eye.truncate() / v.eye.w - centre;
    let mut order = priority_order(&object.vertices, &faces, centre, axis, false);
    if reverse {
        order.reverse();
    }
    let mut rank = vec![0; order.len()];
    for (r, &f) in order.iter().enumerate() {
        rank[f] = r;
    }
    rank
}

/// Paints `scene` (one object) in the stored order, without sorting again,
/// and returns the pixels checked and those that differ from the oracle.
fn paint_in_stored_order(scene: &Scene, rank: &[usize]) -> (usize, usize) {
    let size = 128;
    let view = View::new(scene, size, size).unwrap();
    let mut polys = Vec::new();
    view::expand_object(
        &scene.objects,
        0,
        &view,
        &mut polys,
        &mut GeometryStats::default(),
    );
    polys.sort_by_key(|p| rank[p.polygon as usize]);
    let items: Vec<PaintItem> = polys
        .iter()
        .map(|p| PaintItem {
            points: p.points.iter().map(|q| DVec2::new(q.x, q.y)).collect(),
            color: [1.0; 3],
            id: p.polygon + 1,
            transparency: 0.0,
            vertex_colors: None,
            vertex_transparency: None,
            phong: None,
        })
        .collect();
    let mut frame = FrameBuffer::new(size, size, [0.0; 3]);
    frame.paint(&items, PaintMode::Overwrite);
    let painted: Vec<Option<(u32, u32)>> = frame
        .ids
        .iter()
        .map(|&i| (i > 0).then(|| (0, i - 1)))
        .collect();
    let (checked, bad) = support::mismatches(&oracle(scene, size), &painted, size, size);
    (checked, bad.len())
}

/// Brown's claim: the order depends on the vertex directions and the
/// viewing axis only. Computed once for one view of one surface, it is
/// reused, without sorting again, for a nearer viewpoint on the same axis
/// (stronger perspective) and for a radially deformed surface.
#[test]
fn priority_order_is_reused_under_perspective_and_radial_change() {
    let rank = stored_rank(false);
    for (dist, radial) in [
        (6.0, "sphere"),
        (2.2, "sphere"),
        (6.0, "bumps 0.35 3"),
        (2.4, "lobes 0.4 4"),
    ] {
        let (checked, bad) = paint_in_stored_order(&sphere_scene(4, "angle", radial, dist), &rank);
        assert!(checked > 1000);
        assert_eq!(bad, 0, "dist {dist}, {radial}: {bad} of {checked} differ");
    }
}

/// The check above can fail: the same reuse with a wrong order (Brown's
/// reversed) paints the deformed, near view wrongly.
#[test]
fn a_wrong_order_fails_the_same_check() {
    let (_, bad) = paint_in_stored_order(
        &sphere_scene(4, "angle", "lobes 0.4 4", 2.4),
        &stored_rank(true),
    );
    assert!(bad > 0);
}

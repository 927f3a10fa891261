//! The geometry stage: clipping against the standard view box (results lie
//! inside, untouched polygons pass through, areas match an analytic
//! overlap) and back-face removal by the clockwise rule.

use glam::{DVec3, DVec4};
use plytrace::internal::geometry::clip::{ClipVertex, clip_polygon, outcode};
use plytrace::internal::geometry::polygon::area;
use plytrace::internal::render::{RenderOptions, render};
use proptest::prelude::*;

fn vertex(p: DVec3, w: f64) -> ClipVertex {
    ClipVertex {
        clip: (p * w).extend(w),
        world: p,
    }
}

fn inside_box(c: DVec4, eps: f64) -> bool {
    let lim = c.w * (1.0 + eps) + eps;
    c.x.abs() <= lim && c.y.abs() <= lim && c.z.abs() <= lim
}

proptest! {
    #[test]
    fn clipped_polygons_lie_in_the_box_and_lose_area(
        pts in prop::collection::vec((-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0), 3),
        w in 0.5f64..4.0,
    ) {
        let poly: Vec<ClipVertex> = pts.iter().map(|&(x, y, z)| vertex(DVec3::new(x, y, z), w)).collect();
        let clipped = clip_polygon(&poly, 1e-9);
        for v in &clipped {
            prop_assert!(inside_box(v.clip, 1e-9), "{:?}", v.clip);
            // The world point follows the clip point (affine here: clip = world * w).
            prop_assert!((v.clip.truncate() / v.clip.w - v.world).length() < 1e-9);
        }
        let before: Vec<DVec3> = poly.iter().map(|v| v.world).collect();
        let after: Vec<DVec3> = clipped.iter().map(|v| v.world).collect();
        prop_assert!(area(&after) <= area(&before) + 1e-9);
        if poly.iter().all(|v| outcode(v.clip) == 0) {
            prop_assert_eq!(clipped, poly);
        }
    }

    /// An axis-aligned rectangle in a plane z = c inside the box: the clipped
    /// area is the analytic overlap of two rectangles.
    #[test]
    fn clipped_rectangle_area_is_the_overlap(
        x0 in -3.0f64..3.0, dx in 0.01f64..4.0,
        y0 in -3.0f64..3.0, dy in 0.01f64..4.0,
        z in -0.99f64..0.99,
    ) {
        let (x1, y1) = (x0 + dx, y0 + dy);
        let rect = [
            DVec3::new(x0, y0, z), DVec3::new(x0, y1, z),
            DVec3::new(x1, y1, z), DVec3::new(x1, y0, z),
        ];
        let poly: Vec<ClipVertex> = rect.iter().map(|&p| vertex(p, 1.0)).collect();
        let clipped = clip_polygon(&poly, 1e-12);
        let after: Vec<DVec3> = clipped.iter().map(|v| v.world).collect();
        let overlap = |a: f64, b: f64| (b.min(1.0) - a.max(-1.0)).max(0.0);
        let expected = overlap(x0, x1) * overlap(y0, y1);
        prop_assert!((area(&after) - expected).abs() < 1e-9, "{} vs {}", area(&after), expected);
    }
}

#[test]
fn near_plane_clipping_keeps_w_positive() {
    // A triangle reaching behind the eye under a real perspective.
    let m = plytrace::internal::math::perspective(60.0, 1.0, 0.5, 50.0);
    let tri = [
        DVec3::new(0.0, 0.0, -10.0),
        DVec3::new(1.0, 0.0, 5.0),
        DVec3::new(-1.0, 0.5, 5.0),
    ];
    let poly: Vec<ClipVertex> = tri
        .iter()
        .map(|&p| ClipVertex {
            clip: m.transform_point4(p),
            world: p,
        })
        .collect();
    let clipped = clip_polygon(&poly, 1e-9);
    assert!(clipped.len() >= 3);
    for v in &clipped {
        assert!(v.clip.w > 0.0 && inside_box(v.clip, 1e-9));
        // The world point is in front of the near plane: z <= -near.
        assert!(v.world.z <= -0.5 + 1e-9, "{}", v.world);
        // And it still projects to its clip point.
        let again = m.transform_point4(v.world);
        assert!((again / again.w - v.clip / v.clip.w).length() < 1e-9);
    }
}

fn one_square(extra: &str) -> plytrace::internal::render::Rendered {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("det")).unwrap();
    // Clockwise seen from +z: it faces +z.
    std::fs::write(
        dir.path().join("det/square.det"),
        "title\ndata\n4 1\n-1 -1 0\n-1 1 0\n1 1 0\n1 -1 0\n4 1 2 3 4\n",
    )
    .unwrap();
    let path = dir.path().join("s.des");
    std::fs::write(
        &path,
        format!(
            "resolution 32 32\nperspective 60 1 0.1 100\npushmatrix\nident\ntranslate 0 0 -4\n\
             defobj square\n{extra}\nendobj\npopmatrix\n"
        ),
    )
    .unwrap();
    let scene = plytrace::internal::scene::load(&path).unwrap().0;
    render(&scene, &RenderOptions::default()).unwrap()
}

#[test]
fn back_faces_are_removed_by_the_clockwise_rule() {
    // Facing the eye (at the origin, the square at z = -4 facing +z).
    let front = one_square("");
    assert_eq!(front.polygon_at(16, 16), Some((0, 0)));
    // Turned around: seen from behind, removed.
    let back = one_square("rotate 180 y");
    assert_eq!(back.polygon_at(16, 16), None);
    assert_eq!(back.stats.geometry.back_faces, 1);
    // `type open` keeps it.
    let open = one_square("rotate 180 y\ntype polygon open");
    assert_eq!(open.polygon_at(16, 16), Some((0, 0)));
    // A mirroring scale keeps the polygon facing outward (towards +z here).
    let mirrored = one_square("scale -1 1 1");
    assert_eq!(mirrored.polygon_at(16, 16), Some((0, 0)));
}

#[test]
fn objects_behind_the_eye_and_around_it() {
    // Behind the eye: culled by its bounding box, nothing painted.
    let behind = one_square("translate 0 0 8\nrotate 180 y");
    assert!(behind.frame.ids.iter().all(|&i| i == 0));
    assert_eq!(behind.stats.geometry.objects_culled, 1);
    // Crossing the near plane and the sides: clipped, covering the image.
    let big = one_square("translate 0 0 3.5\nscale 50 50 1");
    assert!(big.frame.ids.iter().all(|&i| i == 1));
}

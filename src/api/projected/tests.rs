//! Tests of [`Projected`]: hand-worked pictures and the properties of
//! the paint order.

use super::*;

/// matplotlib's perspective (`Axes3D.get_proj()` at its default
/// view of the unit cube), rows of `M @ p`.
const MPL: [[f64; 4]; 4] = [
    [1.031, 0.5952, 0.0, -0.8131],
    [-0.2976, 0.5155, 0.7732, -0.4956],
    [0.0, 0.0, 0.0, -10.0],
    [-0.5155, 0.8929, -0.4464, 10.0345],
];

fn project(p: [f64; 3]) -> [f64; 3] {
    let r = |k: usize| MPL[k][0] * p[0] + MPL[k][1] * p[1] + MPL[k][2] * p[2] + MPL[k][3];
    let w = r(3);
    [r(0) / w, r(1) / w, r(2) / w]
}

/// Two wavy grids of `n` x `n` quads (not planar) crossing each other.
fn crossing_surfaces(n: usize) -> Vec<Vec<[f64; 3]>> {
    let mut polys = Vec::new();
    for s in 0..2 {
        let f = |x: f64, y: f64| {
            let wave = 0.15 * (6.0 * x).sin() * (5.0 * y).cos();
            if s == 0 {
                0.5 + wave
            } else {
                0.2 + 0.6 * x - wave
            }
        };
        for i in 0..n {
            for j in 0..n {
                let (x0, x1) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
                let (y0, y1) = (j as f64 / n as f64, (j + 1) as f64 / n as f64);
                polys.push(vec![
                    [x0, y0, f(x0, y0)],
                    [x1, y0, f(x1, y0)],
                    [x1, y1, f(x1, y1)],
                    [x0, y1, f(x0, y1)],
                ]);
            }
        }
    }
    polys
}

fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            c = !c;
        }
    }
    c
}

#[test]
fn painting_the_pieces_shows_the_nearest_surface_everywhere() {
    let polys = crossing_surfaces(12);
    let refs: Vec<&[[f64; 3]]> = polys.iter().map(|p| &p[..]).collect();
    let order = Projected::new(&refs, MPL).unwrap().paint_order().unwrap();
    assert!(order.splits > 0 && order.warning.is_none());
    // The oracle: the nearest of the quads' triangles (the diagonal
    // from the first corner, as the screen's ear clipping cuts these
    // convex outlines) at each sample.
    let tris: Vec<(usize, [[f64; 3]; 3])> = polys
        .iter()
        .enumerate()
        .flat_map(|(k, q)| {
            let q: Vec<[f64; 3]> = q.iter().map(|p| project(*p)).collect();
            [(k, [q[0], q[1], q[2]]), (k, [q[0], q[2], q[3]])]
        })
        .collect();
    let depth = |p: [f64; 2], t: &[[f64; 3]; 3]| {
        let (a, b, c) = (t[0], t[1], t[2]);
        let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        let u = ((p[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[1] - a[1])) / det;
        let v = ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) / det;
        (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then(|| a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]))
    };
    // Pieces of one surface filled together where the order allows:
    // the same picture in fewer patches.
    let keys: Vec<u32> = (0..polys.len()).map(|k| (k / 144) as u32).collect();
    let merged = Projected::new(&refs, MPL)
        .unwrap()
        .paint_order_by(Some(&keys))
        .unwrap();
    assert!(
        merged.patches.len() * 4 < order.patches.len(),
        "{} patches",
        merged.patches.len()
    );
    for order in [order, merged] {
        let (mut checked, mut wrong) = (0, 0);
        for i in 0..150 {
            for j in 0..150 {
                let p = [
                    -0.09 + 0.18 * i as f64 / 150.0,
                    -0.07 + 0.14 * j as f64 / 150.0,
                ];
                let mut hits: Vec<(f64, usize)> = tris
                    .iter()
                    .filter_map(|(k, t)| depth(p, t).map(|z| (z, *k)))
                    .collect();
                hits.sort_by(|a, b| a.0.total_cmp(&b.0));
                let Some(&(z, want)) = hits.first() else {
                    continue;
                };
                // Not where two surfaces meet (within rounding of depth).
                if hits
                    .iter()
                    .any(|h| h.1 / 144 != want / 144 && h.0 - z < 1e-6)
                {
                    continue;
                }
                let painted = order
                    .patches
                    .iter()
                    .rev()
                    .find_map(|patch| patch.rings.iter().find(|r| inside(p, &r.points)));
                checked += 1;
                if painted.map(|ring| ring.source / 144) != Some(want / 144) {
                    wrong += 1;
                }
            }
        }
        assert!(checked > 5000, "{checked}");
        assert!(
            wrong * 1000 <= checked,
            "{wrong} of {checked} samples show the far surface"
        );
    }
}

#[test]
fn unsplit_polygons_come_back_whole() {
    let polys = crossing_surfaces(6);
    let refs: Vec<&[[f64; 3]]> = polys.iter().map(|p| &p[..]).collect();
    let order = Projected::new(&refs[..36], MPL)
        .unwrap()
        .paint_order()
        .unwrap();
    // One surface alone: every quad (two triangles each) whole, once.
    assert_eq!(order.patches.len(), 36);
    let mut seen: Vec<usize> = order.patches.iter().map(|p| p.source()).collect();
    seen.sort();
    assert_eq!(seen, (0..36).collect::<Vec<_>>());
    for p in &order.patches {
        assert!(p.rings.len() == 1 && p.rings[0].whole && p.rings[0].points.len() == 4);
        let q = project(polys[p.source()][0]);
        assert!((p.rings[0].points[0][0] - q[0]).abs() < 1e-12);
    }
    // One key for all: the surface does not fold over itself here,
    // so one patch holds every quad, whole.
    let one = Projected::new(&refs[..36], MPL)
        .unwrap()
        .paint_order_by(Some(&[0; 36]))
        .unwrap();
    assert_eq!(one.patches.len(), 1);
    assert_eq!(one.patches[0].rings.len(), 36);
    assert!(one.patches[0].rings.iter().all(|r| r.whole));
}

#[test]
fn segments_are_cut_where_a_polygon_hides_them() {
    // A square at depth 0 and a segment piercing it from behind
    // (depth 1 at the left) to in front (depth -1 at the right).
    let m = [
        [1., 0., 0., 0.],
        [0., 1., 0., 0.],
        [0., 0., 1., 0.],
        [0., 0., 0., 1.],
    ];
    let square: Vec<[f64; 3]> = vec![[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]];
    let seen = Projected::new(&[&square[..]], m).unwrap();
    let pieces = seen
        .visible_segments(&[[[-2., 0., 1.], [2., 0., -1.]]])
        .unwrap();
    assert_eq!(pieces.len(), 2, "{pieces:?}");
    let x: Vec<[f64; 2]> = pieces
        .iter()
        .map(|p| [p.points[0][0], p.points[1][0]])
        .collect();
    assert!(
        (x[0][0] + 2.0).abs() < 1e-9 && (x[0][1] + 1.0).abs() < 1e-6,
        "{x:?}"
    );
    assert!(
        x[1][0].abs() < 1e-5 && (x[1][1] - 2.0).abs() < 1e-9,
        "{x:?}"
    );
    // A segment on the square stays; a point behind it goes.
    let on = seen
        .visible_segments(&[[[-0.5, 0.5, 0.], [0.5, 0.5, 0.]]])
        .unwrap();
    assert_eq!(on.len(), 1);
    let behind = seen
        .visible_segments(&[[[0.2, 0.2, 0.5], [0.2, 0.2, 0.5]]])
        .unwrap();
    assert!(behind.is_empty());
    let front = seen
        .visible_segments(&[[[0.2, 0.2, -0.5], [0.2, 0.2, -0.5]]])
        .unwrap();
    assert_eq!(front.len(), 1);
}

#[test]
fn projected_input_is_checked_and_clipped_in_front_of_the_eye() {
    let m = [
        [1., 0., 0., 0.],
        [0., 1., 0., 0.],
        [0., 0., 1., 0.],
        [0., 0., 0., 1.],
    ];
    let nan: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., f64::NAN, 0.], [1., 1., 0.]];
    let e = Projected::new(&[&nan[..]], m).unwrap_err().to_string();
    assert!(e.contains("polygon 0, point 1 is not finite"), "{e}");
    let two: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., 0., 0.]];
    let e = Projected::new(&[&two[..]], m).unwrap_err().to_string();
    assert!(e.contains("polygon 0 has 2 points"), "{e}");
    let mut bad = m;
    bad[1][2] = f64::INFINITY;
    assert!(Projected::new(&[], bad).is_err());
    assert!(
        Projected::new(&[], m)
            .unwrap()
            .paint_order()
            .unwrap()
            .patches
            .is_empty()
    );
    // W = 1 + z: the part of a quad at z <= -1 is behind the eye.
    let persp = [
        [1., 0., 0., 0.],
        [0., 1., 0., 0.],
        [0., 0., 1., 0.],
        [0., 0., 1., 1.],
    ];
    let through: Vec<[f64; 3]> = vec![[-1., 0., -2.], [1., 0., -2.], [1., 1., 1.], [-1., 1., 1.]];
    let order = Projected::new(&[&through[..]], persp)
        .unwrap()
        .paint_order()
        .unwrap();
    assert_eq!(order.patches.len(), 1);
    assert!(!order.patches[0].rings[0].whole);
    assert!(
        order.patches[0]
            .rings
            .iter()
            .flat_map(|r| &r.points)
            .all(|p| p.iter().all(|v| v.is_finite()))
    );
}

//! An object's outline as a Point light sees it, cast whole (the light's
//! side of 004 section 4.7, after Atherton, Weiler and Greenberg 1978).
//!
//! The edges of an object's polygons that face the light, less every edge
//! that two of them share (one each way round), are closed loops around
//! what those polygons cover: around a point, the loops wind once for
//! each polygon over it. A polygon whose shadow volume holds the whole
//! object takes the loops, projected from the light, in place of one
//! piece per polygon: the same region under the non-zero rule, in the
//! outline's points rather than every polygon's, and without the shared
//! edges the union would only have removed. A mesh of a million
//! triangles over a floor casts a few thousand points there instead of
//! half a million pieces.

use glam::DVec3;

use crate::model::Object;

/// The loops of an object's outline as one light sees it, as indices of
/// the object's vertices, each loop turning as the polygons do.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Outline {
    /// Every loop's vertices, one loop after another.
    points: Vec<u32>,
    /// Where each loop ends in `points`.
    ends: Vec<u32>,
}

/// An edge `a -> b` as one number, `a` in the high half, so that edges
/// sort by the vertex they leave.
fn edge(a: u32, b: u32) -> u64 {
    (u64::from(a) << 32) | u64::from(b)
}

fn ends(e: u64) -> (u32, u32) {
    ((e >> 32) as u32, e as u32)
}

impl Outline {
    /// The outline of the polygons of `object` that face `light` (those
    /// whose plane has the light strictly in front, as the casters that
    /// face it). The edges are sorted, not hashed: a mesh of ten million
    /// triangles has fifteen million edges facing the light.
    ///
    /// It is made inside casts, once per object and light, so on the
    /// calling thread alone (see [`super::CasterIndex::warm_faces`]).
    pub fn new(object: &Object, light: DVec3) -> Outline {
        let mut edges: Vec<u64> = Vec::new();
        for p in &object.polygons {
            if p.plane.truncate().dot(light) + p.plane.w <= 0.0 {
                continue;
            }
            let ix = &p.indices;
            for k in 0..ix.len() {
                edges.push(edge(ix[k], ix[(k + 1) % ix.len()]));
            }
        }
        edges.sort_unstable();
        let count = |e: u64| {
            let at = edges.partition_point(|&x| x < e);
            edges[at..].iter().take_while(|&&x| x == e).count()
        };
        // Each edge the other way round cancels one of its copies.
        let left: Vec<u64> = edges
            .chunk_by(|a, b| a == b)
            .flat_map(|run| {
                let (a, b) = ends(run[0]);
                let back = count(edge(b, a));
                std::iter::repeat_n(run[0], run.len().saturating_sub(back))
            })
            .collect();
        drop(edges);
        Outline::chained(&left)
    }

    /// `left` (sorted edges, as many out of each vertex as into it)
    /// chained into loops: from each vertex in turn, its edges are
    /// followed until the walk comes back.
    fn chained(left: &[u64]) -> Outline {
        // The next unused edge out of each vertex, by its first edge's place.
        let mut next: Vec<usize> = Vec::with_capacity(left.len());
        let mut first = 0;
        for (k, &e) in left.iter().enumerate() {
            if k > 0 && ends(left[k - 1]).0 != ends(e).0 {
                first = k;
            }
            next.push(first);
        }
        let mut out = Outline::default();
        let take = |next: &mut Vec<usize>, v: u32| -> Option<u32> {
            let start = left.partition_point(|&x| ends(x).0 < v);
            let k = *next.get(start)?;
            let (a, b) = ends(*left.get(k)?);
            (a == v).then(|| {
                next[start] = k + 1;
                b
            })
        };
        for &e in left {
            let a = ends(e).0;
            while let Some(mut b) = take(&mut next, a) {
                out.points.push(a);
                while b != a {
                    out.points.push(b);
                    match take(&mut next, b) {
                        Some(c) => b = c,
                        None => break,
                    }
                }
                out.ends.push(out.points.len() as u32);
            }
        }
        out
    }

    /// How many points its loops have in all.
    pub fn point_count(&self) -> usize {
        self.points.len()
    }

    /// The loops, as slices of vertex indices.
    pub fn loops(&self) -> impl Iterator<Item = &[u32]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts
            .zip(self.ends.iter().copied())
            .map(|(s, e)| &self.points[s as usize..e as usize])
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use std::fmt::Write;

    /// The scene of `des` with the object files `dets` (name, text), read
    /// from a temporary folder.
    pub fn scene(des: &str, dets: &[(&str, String)]) -> crate::model::Scene {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("det")).unwrap();
        for (name, text) in dets {
            std::fs::write(dir.path().join("det").join(format!("{name}.det")), text).unwrap();
        }
        let path = dir.path().join("scene.des");
        std::fs::write(&path, format!("ident\n{des}")).unwrap();
        crate::scene::load(&path).expect("the test scene").0
    }

    /// A flat square ring at height `z` facing up: the cells of an
    /// `n x n` grid over -1..1 less those within 0.5 of the middle, each a
    /// quadrilateral (clockwise seen from above, as object files are).
    pub fn ring_det(n: usize, z: f64) -> String {
        let at = |i: usize| -1.0 + 2.0 * i as f64 / n as f64;
        let mut text = String::new();
        let cells: Vec<(usize, usize)> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let c = |k: usize| 0.5 * (at(k) + at(k + 1));
                c(i).abs() > 0.5 || c(j).abs() > 0.5
            })
            .collect();
        writeln!(
            text,
            "title ring\ndata\n{} {}",
            (n + 1) * (n + 1),
            cells.len()
        )
        .unwrap();
        for j in 0..=n {
            for i in 0..=n {
                writeln!(text, "{} {} {z}", at(i), at(j)).unwrap();
            }
        }
        let v = |i: usize, j: usize| j * (n + 1) + i + 1;
        for (i, j) in cells {
            writeln!(
                text,
                "4 {} {} {} {}",
                v(i, j),
                v(i, j + 1),
                v(i + 1, j + 1),
                v(i + 1, j)
            )
            .unwrap();
        }
        text
    }

    /// Twice the signed area of a loop of `object`'s points seen from
    /// above.
    fn twice_area(object: &Object, ring: &[u32]) -> f64 {
        let p = |k: usize| object.vertices[ring[k % ring.len()] as usize];
        (0..ring.len())
            .map(|k| p(k).x * p(k + 1).y - p(k).y * p(k + 1).x)
            .sum()
    }

    /// A cube seen from beyond a corner shows three faces; their outline
    /// is one hexagon through the six corners not nearest or farthest.
    #[test]
    fn a_cube_seen_from_a_corner_is_a_hexagon() {
        let cube = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/det/cube.det"),
        )
        .unwrap();
        let s = scene("defobj cube\nendobj\n", &[("cube", cube)]);
        let outline = Outline::new(&s.objects[0], DVec3::new(3.0, 4.0, 5.0));
        let loops: Vec<&[u32]> = outline.loops().collect();
        assert_eq!(loops.len(), 1, "{outline:?}");
        let mut corners: Vec<DVec3> = loops[0]
            .iter()
            .map(|&i| s.objects[0].vertices[i as usize])
            .collect();
        assert_eq!(corners.len(), 6);
        corners.retain(|c| c.x + c.y + c.z != 3.0 && c.x + c.y + c.z != -3.0);
        assert_eq!(
            corners.len(),
            6,
            "the nearest and farthest corners are inside"
        );
    }

    /// A ring's cells facing the light share their inner edges: the
    /// outline is the ring's outer square and its inner one, turning
    /// opposite ways, so the region they wind around has the hole. From
    /// below, no cell faces the light: no outline.
    #[test]
    fn a_ring_is_two_loops_turning_opposite_ways() {
        let s = scene("defobj ring\nendobj\n", &[("ring", ring_det(8, 1.0))]);
        let ring = &s.objects[0];
        let outline = Outline::new(ring, DVec3::new(0.2, 0.1, 5.0));
        let areas: Vec<f64> = outline.loops().map(|l| twice_area(ring, l)).collect();
        assert_eq!(areas.len(), 2, "{outline:?}");
        let (mut outer, mut inner) = (areas[0], areas[1]);
        if outer.abs() < inner.abs() {
            std::mem::swap(&mut outer, &mut inner);
        }
        assert!((outer.abs() - 8.0).abs() < 1e-9, "{areas:?}");
        assert!((inner.abs() - 2.0).abs() < 1e-9, "{areas:?}");
        assert!(outer * inner < 0.0, "{areas:?}");
        assert_eq!(
            Outline::new(ring, DVec3::new(0.0, 0.0, -5.0)),
            Outline::default()
        );
    }
}

//! Properties of polygon meshes as solids: enclosed volume (divergence
//! theorem), closedness (every edge shared by exactly two faces, in
//! opposite directions) and outward orientation. Polygons are clockwise
//! seen from outside (Firebaugh 001, figure 8.20; Garcia 004 section 4.3),
//! so a closed, outward mesh has a positive [`signed_volume`].

use std::collections::HashMap;

use glam::DVec3;

use crate::model::Mesh;

/// The volume enclosed by `polygons` over `vertices`, positive when they
/// are clockwise seen from outside. Exact for closed meshes of planar
/// polygons (any fan of a planar polygon has its area vector).
pub fn signed_volume<P: AsRef<[u32]>>(vertices: &[DVec3], polygons: &[P]) -> f64 {
    let mut six = 0.0;
    for p in polygons {
        let p = p.as_ref();
        if p.len() < 3 {
            continue;
        }
        let a = vertices[p[0] as usize];
        for k in 1..p.len() - 1 {
            let (b, c) = (vertices[p[k] as usize], vertices[p[k + 1] as usize]);
            // Clockwise from outside: the reversed triangle (a, c, b) is
            // counter-clockwise.
            six += a.dot(c.cross(b));
        }
    }
    six / 6.0
}

/// [`signed_volume`] of a mesh.
pub fn mesh_volume(mesh: &Mesh) -> f64 {
    signed_volume(&mesh.vertices, &mesh.polygons)
}

/// Vertex ids that identify copies of one point: equal ids for bitwise
/// equal coordinates (a crease's repeated vertices).
pub fn weld_exact(vertices: &[DVec3]) -> Vec<u32> {
    let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(vertices.len());
    vertices
        .iter()
        .map(|v| {
            let key = [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            let next = seen.len() as u32;
            *seen.entry(key).or_insert(next)
        })
        .collect()
}

/// Why a mesh is not a closed, consistently oriented surface.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NotClosed {
    /// An edge (welded vertex ids) used by one face only: a hole.
    Border(u32, u32),
    /// An edge used twice in the same direction, or more than twice.
    Inconsistent(u32, u32),
}

impl std::fmt::Display for NotClosed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotClosed::Border(a, b) => write!(
                f,
                "the edge between its points {} and {} belongs to one face only (a hole)",
                a + 1,
                b + 1
            ),
            NotClosed::Inconsistent(a, b) => write!(
                f,
                "the edge between its points {} and {} is not shared by exactly two faces in opposite directions",
                a + 1,
                b + 1
            ),
        }
    }
}

/// Checks that every edge of `polygons` (vertices identified by `ids`) is
/// shared by exactly two faces, in opposite directions.
pub fn check_closed<P: AsRef<[u32]>>(ids: &[u32], polygons: &[P]) -> Result<(), NotClosed> {
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for p in polygons {
        let p = p.as_ref();
        let m = p.len();
        for k in 0..m {
            let (a, b) = (ids[p[k] as usize], ids[p[(k + 1) % m] as usize]);
            if a == b {
                continue;
            }
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    let mut bad: Vec<NotClosed> = Vec::new();
    for (&(a, b), &n) in &edges {
        let back = edges.get(&(b, a)).copied().unwrap_or(0);
        if n != 1 || back != 1 {
            bad.push(if back == 0 {
                NotClosed::Border(a, b)
            } else {
                NotClosed::Inconsistent(a.min(b), a.max(b))
            });
        }
    }
    // The first defect in a stable order.
    bad.sort_by_key(|d| match *d {
        NotClosed::Border(a, b) | NotClosed::Inconsistent(a, b) => (a, b),
    });
    bad.into_iter().next().map_or(Ok(()), Err)
}

/// Whether a mesh is closed, its copies of one point identified.
pub fn is_closed(mesh: &Mesh) -> bool {
    check_closed(&weld_exact(&mesh.vertices), &mesh.polygons).is_ok()
}

/// Reverses every polygon (and negates the normals) when the enclosed
/// volume is negative, so that a closed mesh is outward.
pub fn orient_outward(mesh: &mut Mesh, normals: Option<&mut Vec<DVec3>>) {
    if mesh_volume(mesh) < 0.0 {
        for p in &mut mesh.polygons {
            p.reverse();
        }
        if let Some(n) = normals {
            for v in n.iter_mut() {
                *v = -*v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Mesh {
        let mut vertices = Vec::new();
        for i in 0..8 {
            vertices.push(DVec3::new(
                (i & 1) as f64,
                ((i >> 1) & 1) as f64,
                ((i >> 2) & 1) as f64,
            ));
        }
        // Clockwise from outside.
        let polygons = vec![
            vec![0, 1, 3, 2],
            vec![4, 6, 7, 5],
            vec![0, 4, 5, 1],
            vec![2, 3, 7, 6],
            vec![0, 2, 6, 4],
            vec![1, 5, 7, 3],
        ];
        Mesh::new(vertices, polygons)
    }

    #[test]
    fn unit_cube_has_volume_one_and_is_closed() {
        let mut m = cube();
        assert!((mesh_volume(&m) - 1.0).abs() < 1e-15);
        assert!(is_closed(&m));
        m.polygons.pop();
        assert!(matches!(
            check_closed(&weld_exact(&m.vertices), &m.polygons),
            Err(NotClosed::Border(..))
        ));
        let mut m = cube();
        m.polygons[0].reverse();
        assert!(!is_closed(&m));
        let mut m = cube();
        for p in &mut m.polygons {
            p.reverse();
        }
        orient_outward(&mut m, None);
        assert!((mesh_volume(&m) - 1.0).abs() < 1e-15);
    }
}

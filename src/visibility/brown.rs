//! C. M. Brown's priority order for well-tesselated surfaces (*Fast
//! Display of Well-Tesselated Surfaces*, 1978, 003 section 3 and appendix
//! section 3): faces of a surface that is a function on a sphere are
//! painted in decreasing order of `maxphi`, the largest angle at the
//! sphere's centre between a face vertex and the viewing direction.
//!
//! * PaintOpaquePolyhedron: back faces (those meeting the Interior Test)
//!   are discarded, the rest sorted by `maxphi`, ties in any order.
//! * PaintGeneralSurface: no face is discarded; faces with equal `maxphi`
//!   are handed to PaintAPhi, which classifies edge neighbours as prior or
//!   posterior by the Priority Test (the plane through the centre and their
//!   shared edge: the neighbour on the viewpoint's side is prior) and paints
//!   posterior faces, then prior ones, isolated ones at any time.
//!
//! The order depends on the vertex directions and the viewing axis only,
//! not on the radial distances of the vertices nor on the viewpoint's
//! distance along the axis: computed once, it stays correct under
//! perspective changes and radial deformation ([`priority_order`] takes
//! no eye distance). Back faces of an opaque polyhedron are removed per
//! view by the geometry stage.
//!
//! Animation frames ([`PriorityCache`]): an object whose vertex
//! directions, faces, centre and viewing axis are those of the previous
//! frame keeps its order, with no re-sort. That is the case of Brown's
//! approximate rotation (003 section 2; `radial rotate`) and of a
//! perspective change along the axis (Theorem IV): only the radii change.
//!
//! Preconditions: the faces are triangles of a well-tesselated surface
//! about `centre` (Angle Condition met, see
//! [`crate::modeling::geodesic::check_tessellation`]); the viewpoint lies on
//! the axis through `centre`.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use glam::DVec3;

/// Largest angle (radians, as a chord of the unit sphere) by which a
/// vertex direction may differ from the stored frame's and still count as
/// the same direction: rounding in `d r / |d r|`, not a real change.
pub const SAME_DIRECTION: f64 = 1e-9;

/// How many priority orders a render sorted and how many it reused.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BrownStats {
    /// Objects whose faces were sorted.
    pub sorted: usize,
    /// Objects whose order of the previous frame was reused, with no
    /// re-sort.
    pub reused: usize,
}

impl std::fmt::Display for BrownStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.sorted, self.reused) {
            (0, r) => write!(f, "priority order reused (no re-sort) for {r} object(s)"),
            (s, 0) => write!(f, "priority order sorted for {s} object(s)"),
            (s, r) => write!(
                f,
                "priority order sorted for {s} object(s), reused (no re-sort) for {r}"
            ),
        }
    }
}

/// One object's order and what it was computed from.
#[derive(Debug)]
struct Stored {
    dirs: Vec<DVec3>,
    faces: Vec<Vec<u32>>,
    centre: DVec3,
    axis: DVec3,
    general: bool,
    order: Arc<Vec<usize>>,
}

impl Stored {
    /// Whether the order stored holds for this frame: same faces, centre,
    /// axis, and vertex directions.
    fn holds(
        &self,
        dirs: &[DVec3],
        faces: &[Vec<u32>],
        centre: DVec3,
        axis: DVec3,
        general: bool,
    ) -> bool {
        let scale = 1.0 + centre.abs().max_element();
        self.general == general
            && self.centre.distance(centre) <= SAME_DIRECTION * scale
            && self.axis.distance(axis) <= SAME_DIRECTION
            && self.faces == faces
            && self.dirs.len() == dirs.len()
            && self
                .dirs
                .iter()
                .zip(dirs)
                .all(|(a, b)| a.distance(*b) <= SAME_DIRECTION)
    }
}

/// The priority orders of the previous frame, per object number, for
/// animations: [`PriorityCache::order`] reuses an order whose vertex
/// directions, faces, centre and axis are unchanged. Shared by reference
/// between threads (`Send + Sync`).
#[derive(Debug, Default)]
pub struct PriorityCache {
    slots: Mutex<HashMap<u32, Stored>>,
}

impl PriorityCache {
    /// An empty cache: every object will be sorted.
    pub fn new() -> PriorityCache {
        PriorityCache::default()
    }

    /// Brown's order of object `key`'s faces ([`priority_order`]), reused
    /// from the previous call for `key` when it still holds; the flag says
    /// whether it was reused.
    pub fn order(
        &self,
        key: u32,
        vertices: &[DVec3],
        faces: &[Vec<u32>],
        centre: DVec3,
        axis: DVec3,
        general: bool,
    ) -> (Arc<Vec<usize>>, bool) {
        let axis = axis.normalize_or_zero();
        let dirs: Vec<DVec3> = vertices
            .iter()
            .map(|v| (*v - centre).normalize_or_zero())
            .collect();
        let mut slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(s) = slots.get(&key)
            && s.holds(&dirs, faces, centre, axis, general)
        {
            return (Arc::clone(&s.order), true);
        }
        let order = Arc::new(priority_order(vertices, faces, centre, axis, general));
        slots.insert(
            key,
            Stored {
                dirs,
                faces: faces.to_vec(),
                centre,
                axis,
                general,
                order: Arc::clone(&order),
            },
        );
        (order, false)
    }
}

/// Faces (as vertex index lists into `vertices`) in Brown's painting order:
/// indices into `faces`. `axis` points from `centre` towards the viewpoint.
/// With `general` false (an opaque polyhedron) faces are sorted by `maxphi`
/// only; back faces must be removed by the caller, per view. With
/// `general` true ties are broken by PaintAPhi.
pub fn priority_order(
    vertices: &[DVec3],
    faces: &[Vec<u32>],
    centre: DVec3,
    axis: DVec3,
    general: bool,
) -> Vec<usize> {
    let axis = axis.normalize_or_zero();
    let phi = |i: u32| {
        (vertices[i as usize] - centre)
            .normalize_or_zero()
            .dot(axis)
            .clamp(-1.0, 1.0)
            .acos()
    };
    let maxphi: Vec<f64> = faces
        .iter()
        .map(|f| f.iter().map(|&i| phi(i)).fold(f64::NEG_INFINITY, f64::max))
        .collect();
    let mut order: Vec<usize> = (0..faces.len()).collect();
    // Descending maxphi; equal values keep input order (deterministic).
    order.sort_by(|&a, &b| maxphi[b].total_cmp(&maxphi[a]));
    if !general {
        return order;
    }
    let mut out = Vec::with_capacity(order.len());
    for group in order.chunk_by(|&a, &b| (maxphi[a] - maxphi[b]).abs() <= 1e-12) {
        out.extend(paint_a_phi(vertices, faces, centre, axis, group));
    }
    out
}

/// A shared edge, as its two vertex indices in increasing order.
type Edge = (u32, u32);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Class {
    Unclassified,
    Isolated,
    Prior,
    Posterior,
}

/// Subroutine PaintAPhi: orders faces of identical `maxphi`.
fn paint_a_phi(
    vertices: &[DVec3],
    faces: &[Vec<u32>],
    centre: DVec3,
    axis: DVec3,
    group: &[usize],
) -> Vec<usize> {
    if group.len() == 1 {
        return group.to_vec();
    }
    // Edge neighbours within the group.
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for &f in group {
        let v = &faces[f];
        for k in 0..v.len() {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(f);
        }
    }
    let mut nbrs: HashMap<usize, Vec<(usize, Edge)>> = HashMap::new();
    for (edge, fs) in &by_edge {
        if let [f, g] = fs[..] {
            nbrs.entry(f).or_default().push((g, *edge));
            nbrs.entry(g).or_default().push((f, *edge));
        }
    }
    // The Priority Test: is `f` on the viewpoint's side of the plane
    // through the centre and the shared edge?
    let prior = |f: usize, (a, b): (u32, u32)| -> Option<bool> {
        let n = (vertices[a as usize] - centre).cross(vertices[b as usize] - centre);
        let viewpoint = n.dot(axis);
        let third = faces[f].iter().find(|&&i| i != a && i != b)?;
        let side = n.dot(vertices[*third as usize] - centre);
        (viewpoint != 0.0 && side != 0.0).then_some((viewpoint > 0.0) == (side > 0.0))
    };
    let mut class: HashMap<usize, Class> =
        group.iter().map(|&f| (f, Class::Unclassified)).collect();
    let opposite = |c: Class| {
        if c == Class::Prior {
            Class::Posterior
        } else {
            Class::Prior
        }
    };
    for &f in group {
        if class[&f] != Class::Unclassified {
            continue;
        }
        let ns = nbrs.get(&f).cloned().unwrap_or_default();
        if ns.is_empty() {
            class.insert(f, Class::Isolated);
            continue;
        }
        // b. A neighbour already prior or posterior decides.
        if let Some(&(g, _)) = ns
            .iter()
            .find(|(g, _)| matches!(class[g], Class::Prior | Class::Posterior))
        {
            let c = opposite(class[&g]);
            class.insert(f, c);
            for &(h, _) in &ns {
                if class[&h] == Class::Unclassified {
                    class.insert(h, opposite(c));
                }
            }
            continue;
        }
        // c. The Priority Test with a neighbour.
        if let Some(is_prior) = ns.iter().find_map(|&(_, e)| prior(f, e)) {
            let c = if is_prior {
                Class::Prior
            } else {
                Class::Posterior
            };
            class.insert(f, c);
            for &(h, _) in &ns {
                if class[&h] == Class::Unclassified {
                    class.insert(h, opposite(c));
                }
            }
            continue;
        }
        // d.
        class.insert(f, Class::Isolated);
    }
    let mut out = Vec::with_capacity(group.len());
    for c in [Class::Posterior, Class::Prior, Class::Isolated] {
        out.extend(group.iter().copied().filter(|f| class[f] == c));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cache_reuses_an_order_only_for_the_same_directions() {
        let v = vec![DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z];
        let faces = vec![vec![0, 1, 2], vec![0, 3, 1]];
        let cache = PriorityCache::new();
        let first = cache.order(7, &v, &faces, DVec3::ZERO, DVec3::Z, false);
        assert!(!first.1);
        // Radii changed, directions kept: reused.
        let scaled: Vec<DVec3> = v
            .iter()
            .zip([2.0, 0.5, 3.0, 1.5])
            .map(|(p, r)| *p * r)
            .collect();
        let again = cache.order(7, &scaled, &faces, DVec3::ZERO, DVec3::Z * 4.0, false);
        assert!(again.1);
        assert_eq!(again.0, first.0);
        // Another object number, another direction or axis: sorted.
        assert!(!cache.order(8, &v, &faces, DVec3::ZERO, DVec3::Z, false).1);
        let mut moved = v.clone();
        moved[2] = DVec3::new(0.1, 0.0, 1.0);
        assert!(
            !cache
                .order(7, &moved, &faces, DVec3::ZERO, DVec3::Z, false)
                .1
        );
        assert!(
            !cache
                .order(7, &moved, &faces, DVec3::ZERO, DVec3::Y, false)
                .1
        );
    }

    #[test]
    fn far_side_first() {
        // Two faces of a unit sphere's inscribed octahedron, viewed from +z:
        // the one towards -z (larger angle) is painted first.
        let v = vec![DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z];
        let faces = vec![vec![0, 1, 2], vec![0, 3, 1]];
        assert_eq!(
            priority_order(&v, &faces, DVec3::ZERO, DVec3::Z, false),
            vec![1, 0]
        );
    }

    #[test]
    fn priority_test_paints_the_posterior_neighbour_first() {
        // Two faces sharing the edge (0, 1) with equal maxphi (both reach
        // their maximum at vertex 0); the plane through the centre and the
        // edge is y = 0, with one face on each side.
        let v = vec![
            DVec3::new(0.0, 0.0, -1.0),  // 0: largest angle from +z
            DVec3::new(1.0, 0.0, 0.0),   // 1: the edge (0, 1) is in y = 0
            DVec3::new(0.5, 0.5, -0.5),  // 2: y > 0
            DVec3::new(0.5, -0.5, -0.5), // 3: y < 0
        ];
        let faces = vec![vec![0, 1, 2], vec![1, 0, 3]];
        // Axis tilted towards +y: face 0 (with vertex 2, y > 0) is prior.
        let axis = DVec3::new(0.0, 0.2, 1.0);
        let order = priority_order(&v, &faces, DVec3::ZERO, axis, true);
        assert_eq!(order, vec![1, 0]);
        let axis = DVec3::new(0.0, -0.2, 1.0);
        assert_eq!(
            priority_order(&v, &faces, DVec3::ZERO, axis, true),
            vec![0, 1]
        );
    }
}

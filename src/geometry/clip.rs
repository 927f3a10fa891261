//! Clipping in homogeneous coordinates against the standard view box
//! `-w <= x, y, z <= w` (Garcia 1986, 004 section 4.5; Firebaugh, 001, 3D
//! clipping with 6-bit Cohen-Sutherland outcodes), by Sutherland and
//! Hodgman's re-entrant polygon clipper (004 reference \[46\]).
//!
//! Preconditions: points are homogeneous clip coordinates (`P * CTM`).
//! Polygons may be non-convex; Sutherland-Hodgman then can leave
//! zero-width bridges along the boundary, which cover no pixel centres.
//! Each vertex carries its world position, interpolated with the same
//! parameter, for world-space shading (004 section 4.8).

use glam::{DVec3, DVec4};

/// A vertex being clipped: clip-space position and world position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipVertex {
    /// Homogeneous clip coordinates.
    pub clip: DVec4,
    /// World coordinates.
    pub world: DVec3,
}

/// Outcode bits: which limits of the view box a point violates.
pub mod outcode_bits {
    /// x < -w
    pub const LEFT: u8 = 1;
    /// x > w
    pub const RIGHT: u8 = 2;
    /// y < -w
    pub const BOTTOM: u8 = 4;
    /// y > w
    pub const TOP: u8 = 8;
    /// z < -w (nearer than the near plane)
    pub const NEAR: u8 = 16;
    /// z > w (beyond the far plane)
    pub const FAR: u8 = 32;
}

/// The 6-bit outcode of a homogeneous point.
pub fn outcode(p: DVec4) -> u8 {
    use outcode_bits::*;
    let mut code = 0;
    if p.x < -p.w {
        code |= LEFT;
    }
    if p.x > p.w {
        code |= RIGHT;
    }
    if p.y < -p.w {
        code |= BOTTOM;
    }
    if p.y > p.w {
        code |= TOP;
    }
    if p.z < -p.w {
        code |= NEAR;
    }
    if p.z > p.w {
        code |= FAR;
    }
    code
}

/// How a set of points lies with respect to the view box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Containment {
    /// All inside: nothing to clip.
    Inside,
    /// All outside one and the same plane: nothing visible.
    Outside,
    /// Neither: clip.
    Crossing,
}

/// Trivial accept/reject from the outcodes of a set of points.
pub fn classify(codes: impl IntoIterator<Item = u8>) -> Containment {
    let (mut and, mut or) = (0x3f, 0);
    for c in codes {
        and &= c;
        or |= c;
    }
    if or == 0 {
        Containment::Inside
    } else if and != 0 {
        Containment::Outside
    } else {
        Containment::Crossing
    }
}

/// Signed distance-like value of `p` to clip plane `k` (0..6): inside when
/// non-negative.
fn boundary(p: DVec4, k: usize) -> f64 {
    match k {
        0 => p.w + p.x,
        1 => p.w - p.x,
        2 => p.w + p.y,
        3 => p.w - p.y,
        4 => p.w + p.z,
        _ => p.w - p.z,
    }
}

/// Clips a polygon to the view box. Points within `epsilon * |w|` of a
/// boundary count as inside, so that no sliver thinner than that is made.
/// Returns the clipped loop (empty if nothing is left, or fewer than three
/// vertices). The intersection of an edge with a plane is computed from its
/// endpoints in a canonical order, so that two polygons sharing the edge get
/// bit-identical new vertices.
pub fn clip_polygon(points: &[ClipVertex], epsilon: f64) -> Vec<ClipVertex> {
    let mut current: Vec<ClipVertex> = points.to_vec();
    let mut next = Vec::with_capacity(points.len() + 6);
    let mask = points.iter().fold(0u8, |m, p| m | outcode(p.clip));
    for k in 0..6 {
        if mask & (1 << k) == 0 {
            continue;
        }
        next.clear();
        let n = current.len();
        for i in 0..n {
            let a = current[i];
            let b = current[(i + 1) % n];
            let da = boundary(a.clip, k);
            let db = boundary(b.clip, k);
            let a_in = da >= -epsilon * a.clip.w.abs();
            let b_in = db >= -epsilon * b.clip.w.abs();
            if a_in {
                next.push(a);
            }
            if a_in != b_in {
                next.push(intersect(a, b, k));
            }
        }
        std::mem::swap(&mut current, &mut next);
        if current.len() < 3 {
            return Vec::new();
        }
    }
    current
}

fn intersect(a: ClipVertex, b: ClipVertex, k: usize) -> ClipVertex {
    // Canonical order: the same edge from either polygon gives the same point.
    let (p, q) = if key(a.clip) <= key(b.clip) {
        (a, b)
    } else {
        (b, a)
    };
    let dp = boundary(p.clip, k);
    let dq = boundary(q.clip, k);
    let t = dp / (dp - dq);
    ClipVertex {
        clip: p.clip + (q.clip - p.clip) * t,
        world: p.world + (q.world - p.world) * t,
    }
}

fn key(p: DVec4) -> [u64; 4] {
    // Total order on bit patterns; only consistency matters.
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits(), p.w.to_bits()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon::area;

    fn v(x: f64, y: f64, z: f64) -> ClipVertex {
        ClipVertex {
            clip: DVec4::new(x, y, z, 1.0),
            world: DVec3::new(x, y, z),
        }
    }

    #[test]
    fn outcodes() {
        assert_eq!(outcode(DVec4::new(0.0, 0.0, 0.0, 1.0)), 0);
        assert_eq!(outcode(DVec4::new(-2.0, 3.0, 0.0, 1.0)), 1 | 8);
        assert_eq!(outcode(DVec4::new(0.0, 0.0, 2.0, 1.0)), 32);
        // Behind the eye (w < 0) nothing can be inside.
        assert_ne!(outcode(DVec4::new(0.0, 0.0, 0.0, -1.0)), 0);
    }

    #[test]
    fn inside_polygon_is_untouched() {
        let p = [v(0.0, 0.0, 0.0), v(0.5, 0.0, 0.0), v(0.5, 0.5, 0.0)];
        assert_eq!(clip_polygon(&p, 1e-7), p.to_vec());
    }

    #[test]
    fn square_clipped_to_box_has_box_area() {
        // A square from -2 to 2 in the z = 0 plane clips to -1..1: area 4.
        let p = [
            v(-2.0, -2.0, 0.0),
            v(-2.0, 2.0, 0.0),
            v(2.0, 2.0, 0.0),
            v(2.0, -2.0, 0.0),
        ];
        let c = clip_polygon(&p, 1e-7);
        let pts: Vec<DVec3> = c.iter().map(|q| q.world).collect();
        assert!((area(&pts) - 4.0).abs() < 1e-12);
        for q in &c {
            assert_eq!(outcode(q.clip), 0);
        }
    }

    #[test]
    fn outside_polygon_vanishes() {
        let p = [v(2.0, 0.0, 0.0), v(3.0, 0.0, 0.0), v(3.0, 1.0, 0.0)];
        assert!(clip_polygon(&p, 1e-7).is_empty());
        assert_eq!(
            classify(p.iter().map(|q| outcode(q.clip))),
            Containment::Outside
        );
    }
}

//! Shadow pieces that share an edge, joined into one polygon. A polygon's
//! shadow from one light (004 section 4.7) is one piece per caster, and
//! the casters of a tessellated object are neighbours: their projections
//! share edges, point for point, since the same points are projected from
//! the same light. Two convex pieces of the same orientation that share an
//! edge, walked in opposite directions, lie on either side of it; when
//! their union is convex it replaces them. The region is the same (no
//! point is moved or made), the pieces fewer: fewer fragments in the tree,
//! records to scan convert and pairs for the overlaps of several lights.

use glam::DVec3;

use crate::geometry::polygon::newell_vector;

/// The most points a joined piece may have: joining is linear in the
/// points of the two pieces, so without a bound a large flat region
/// would be joined at a cost quadratic in its pieces.
const MAX_JOINED: usize = 24;

/// Directed edges by [`key`], to the piece each came from.
type Edges = std::collections::HashMap<u64, u32, std::hash::BuildHasherDefault<KeyHasher>>;

/// The hasher of keys that are hashes already.
#[derive(Default)]
struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x517c_c1b7_2722_0a95);
        }
    }

    fn write_u64(&mut self, k: u64) {
        self.0 = k;
    }
}

/// A directed edge by a hash of the bits of its end points; a match is
/// confirmed point for point.
fn key(a: DVec3, b: DVec3) -> u64 {
    a.to_array()
        .into_iter()
        .chain(b.to_array())
        .fold(0u64, |h, x| {
            (h.rotate_left(5) ^ x.to_bits()).wrapping_mul(0x517c_c1b7_2722_0a95)
        })
}

/// `pieces` (polygons in one plane whose normal is `normal`) with every
/// pair of convex ones that shares an edge in opposite directions, has
/// the same orientation and makes a convex union joined, repeatedly; in
/// the order of each result's first piece.
pub fn merge_adjacent(pieces: Vec<Vec<DVec3>>, normal: DVec3) -> Vec<Vec<DVec3>> {
    if pieces.len() < 2 {
        return pieces;
    }
    let pieces: Vec<Vec<DVec3>> = pieces.into_iter().map(without_repeats).collect();
    // The side each piece faces; 0 (never joined) for a piece that is
    // not convex, as the splitter leaves of a concave caster.
    let side: Vec<f64> = pieces
        .iter()
        .map(|p| {
            let s = newell_vector(p.iter().copied()).dot(normal).signum();
            if is_convex(p, normal * s) { s } else { 0.0 }
        })
        .collect();
    // Every directed edge with the piece it came from, by key (the first
    // piece, where two have the same edge the same way round). A joined
    // piece's edges are those of its parts, less the one they shared, so
    // the map never changes: `owner` says which piece holds each part.
    let mut edges = Edges::with_capacity_and_hasher(pieces.len() * 4, Default::default());
    for (i, p) in pieces.iter().enumerate() {
        if side[i] != 0.0 {
            for (a, b) in ring(p) {
                edges.entry(key(a, b)).or_insert(i as u32);
            }
        }
    }
    let mut owner: Vec<u32> = (0..pieces.len() as u32).collect();
    let mut alive: Vec<Option<Vec<DVec3>>> = pieces.into_iter().map(Some).collect();
    for i in 0..alive.len() {
        while let Some((j, merged)) = partner(&alive, &edges, &mut owner, &side, i, normal) {
            alive[i] = Some(merged);
            alive[j] = None;
            owner[j] = i as u32;
        }
    }
    alive.into_iter().flatten().collect()
}

/// The piece holding part `k` (a union-find root, paths halved).
fn holder(owner: &mut [u32], mut k: u32) -> u32 {
    while owner[k as usize] != k {
        let up = owner[owner[k as usize] as usize];
        owner[k as usize] = up;
        k = up;
    }
    k
}

/// The first piece that piece `i` can be joined with, and the union.
fn partner(
    alive: &[Option<Vec<DVec3>>],
    edges: &Edges,
    owner: &mut [u32],
    side: &[f64],
    i: usize,
    normal: DVec3,
) -> Option<(usize, Vec<DVec3>)> {
    let p = alive[i].as_deref()?;
    if side[i] == 0.0 {
        return None;
    }
    for (k, (a, b)) in ring(p).enumerate() {
        if let Some(&part) = edges.get(&key(b, a)) {
            let j = holder(owner, part) as usize;
            let Some(q) = alive[j].as_deref().filter(|_| j != i && side[j] == side[i]) else {
                continue;
            };
            if p.len() + q.len() - 2 > MAX_JOINED {
                continue;
            }
            let Some(m) = ring(q).position(|(c, d)| c == b && d == a) else {
                continue;
            };
            if joins_convex(p, k, q, m, normal * side[i]) {
                return Some((j, join(p, k, q, m)));
            }
        }
    }
    None
}

/// `p` without points equal to the one before (round the ring).
fn without_repeats(mut p: Vec<DVec3>) -> Vec<DVec3> {
    p.dedup();
    while p.len() > 1 && p.first() == p.last() {
        p.pop();
    }
    p
}

/// The edges of a ring, `(p[k], p[k + 1])`.
fn ring(p: &[DVec3]) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
    (0..p.len()).map(move |k| (p[k], p[(k + 1) % p.len()]))
}

/// Whether convex `p` and `q`, joined along `p`'s edge `k` (from `a` to
/// `b`), which is `q`'s edge `m` (from `b` to `a`), make a convex ring:
/// every other corner is one of theirs, so only the two new corners, at
/// `a` and at `b`, need to turn left.
fn joins_convex(p: &[DVec3], k: usize, q: &[DVec3], m: usize, up: DVec3) -> bool {
    let (np, nq) = (p.len(), q.len());
    let (a, b) = (p[k], p[(k + 1) % np]);
    let before_a = p[(k + np - 1) % np];
    let after_b = p[(k + 2) % np];
    let after_a = q[(m + 2) % nq];
    let before_b = q[(m + nq - 1) % nq];
    left_turn(before_a, a, after_a, up) && left_turn(before_b, b, after_b, up)
}

/// `p` and `q` joined along `p`'s edge `k` (from `a` to `b`), which is
/// `q`'s edge `m` (from `b` to `a`): `b` round `p` to `a`, then on round
/// `q` to the point before `b`.
fn join(p: &[DVec3], k: usize, q: &[DVec3], m: usize) -> Vec<DVec3> {
    let (np, nq) = (p.len(), q.len());
    let mut out = Vec::with_capacity(np + nq - 2);
    out.extend((1..=np).map(|s| p[(k + s) % np]));
    out.extend((2..nq).map(|s| q[(m + s) % nq]));
    without_repeats(out)
}

/// Whether ring `p` never turns right (nor back) about `up`. Two convex pieces
/// joined along an edge turn round exactly once (their corners' turns
/// add up to two full turns, less a half turn at each end of the shared
/// edge), so for them this is convexity.
fn turns_left(p: &[DVec3], up: DVec3) -> bool {
    let n = p.len();
    n >= 3 && (0..n).all(|k| left_turn(p[k], p[(k + 1) % n], p[(k + 2) % n], up))
}

/// Whether the path `a`, `b`, `c` turns left about `up` or goes straight
/// on at `b` (not back).
fn left_turn(a: DVec3, b: DVec3, c: DVec3, up: DVec3) -> bool {
    let (u, v) = (b - a, c - b);
    let cross = u.cross(v).dot(up);
    cross > 0.0 || (cross == 0.0 && u.dot(v) >= 0.0)
}

/// Whether ring `p` is convex about `up`: it never turns right and turns
/// round once. A ring of four points or fewer that never turns right
/// turns round at most once.
fn is_convex(p: &[DVec3], up: DVec3) -> bool {
    if !turns_left(p, up) || up == DVec3::ZERO {
        return false;
    }
    if p.len() <= 4 {
        return true;
    }
    let n = p.len();
    let turned: f64 = (0..n)
        .map(|k| {
            let (a, b, c) = (p[k], p[(k + 1) % n], p[(k + 2) % n]);
            let (u, v) = (b - a, c - b);
            u.cross(v).dot(up).atan2(u.dot(v))
        })
        .sum();
    (turned - std::f64::consts::TAU).abs() < 1e-6
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use proptest::prelude::*;

    fn flat(points: &[(f64, f64)]) -> Vec<DVec3> {
        points.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect()
    }

    fn area(p: &[DVec3]) -> f64 {
        newell_vector(p.iter().copied()).z / 2.0
    }

    #[test]
    fn two_triangles_of_a_square_become_one_quad() {
        let a = flat(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]);
        let b = flat(&[(0.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        let out = merge_adjacent(vec![a, b], DVec3::Z);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].len(), 4);
        assert!((area(&out[0]) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_concave_union_overlaps_and_mixed_orientations_stay_apart() {
        let n = DVec3::Z;
        let a = flat(&[(0.0, 0.0), (2.0, 0.0), (1.0, 1.0)]);
        // Shares (2,0)-(1,1) with `a`: the union has a reflex corner at (1,1).
        let b = flat(&[(1.0, 1.0), (2.0, 0.0), (2.0, 3.0)]);
        assert_eq!(merge_adjacent(vec![a.clone(), b], n).len(), 2);
        // The same triangle twice: the same edges in the same direction.
        assert_eq!(merge_adjacent(vec![a.clone(), a.clone()], n).len(), 2);
        // A neighbour walked the other way round (clockwise).
        let below = flat(&[(0.0, 0.0), (1.0, -1.0), (2.0, 0.0)]);
        assert_eq!(merge_adjacent(vec![a.clone(), below.clone()], n).len(), 1);
        let cw: Vec<DVec3> = below.iter().rev().copied().collect();
        assert_eq!(merge_adjacent(vec![a.clone(), cw], n).len(), 2);
        // A concave piece is never joined, even where the union is convex.
        let notched = flat(&[(0.0, 0.0), (1.0, -1.0), (2.0, 0.0), (1.0, -0.5)]);
        let fill = flat(&[(0.0, 0.0), (1.0, -0.5), (2.0, 0.0), (1.0, 1.0)]);
        assert_eq!(merge_adjacent(vec![notched, fill], n).len(), 2);
    }

    /// A convex polygon cut into a fan of triangles, in any order and
    /// from any start, comes back as one polygon of the same area.
    #[test]
    fn a_fan_comes_back_whole() {
        let hexagon: Vec<(f64, f64)> = (0..6)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 6.0;
                (t.cos() * 3.0 + 0.1, t.sin() * 2.0)
            })
            .collect();
        let h = flat(&hexagon);
        let mut fan: Vec<Vec<DVec3>> = (1..5).map(|k| vec![h[0], h[k], h[k + 1]]).collect();
        fan.swap(0, 3);
        let out = merge_adjacent(fan, DVec3::Z);
        assert_eq!(out.len(), 1, "{out:?}");
        assert!((area(&out[0]) - area(&h)).abs() < 1e-9);
    }

    /// A fan of a 60-gon is joined into pieces of at most
    /// [`MAX_JOINED`] points, the area kept.
    #[test]
    fn joined_pieces_stay_small() {
        let ring: Vec<DVec3> = (0..60)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 60.0;
                DVec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let fan: Vec<Vec<DVec3>> = (1..59)
            .map(|k| vec![ring[0], ring[k], ring[k + 1]])
            .collect();
        let out = merge_adjacent(fan, DVec3::Z);
        assert!((3..=10).contains(&out.len()), "{}", out.len());
        assert!(out.iter().all(|p| p.len() <= MAX_JOINED));
        let total: f64 = out.iter().map(|p| area(p)).sum();
        assert!((total - area(&ring)).abs() < 1e-12);
    }

    fn inside_any(pieces: &[Vec<DVec3>], s: DVec2) -> bool {
        pieces.iter().any(|p| {
            let n = p.len();
            let side = |k: usize| {
                let (a, b) = (p[k].truncate(), p[(k + 1) % n].truncate());
                (b - a).perp_dot(s - a)
            };
            (0..n).all(|k| side(k) > 1e-9) || (0..n).all(|k| side(k) < -1e-9)
        })
    }

    proptest! {
        /// Triangles of a grid (some left out, some turned over): the
        /// same points inside, the same total area, every result convex.
        #[test]
        fn the_region_is_unchanged(
            keep in prop::collection::vec(0u8..4, 32),
            jitter in prop::collection::vec(-0.3..0.3f64, 25),
        ) {
            let grid = |i: usize, j: usize| {
                let k = i * 5 + j;
                DVec3::new(i as f64 + jitter[k] * 0.5, j as f64 + jitter[(k + 7) % 25] * 0.5, 0.0)
            };
            let mut tris = Vec::new();
            for i in 0..4 {
                for j in 0..4 {
                    let (a, b, c, d) = (grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1));
                    for (t, tri) in [[a, b, c], [a, c, d]].into_iter().enumerate() {
                        match keep[(i * 4 + j) * 2 % 32 + t] {
                            0 => {}
                            3 => tris.push(vec![tri[2], tri[1], tri[0]]),
                            _ => tris.push(tri.to_vec()),
                        }
                    }
                }
            }
            let before: f64 = tris.iter().map(|t| area(t).abs()).sum();
            let out = merge_adjacent(tris.clone(), DVec3::Z);
            prop_assert!(out.len() <= tris.len());
            let after: f64 = out.iter().map(|t| area(t).abs()).sum();
            prop_assert!((before - after).abs() < 1e-9);
            for p in &out {
                let up = DVec3::Z * area(p).signum();
                prop_assert!(is_convex(p, up), "{p:?}");
            }
            for x in 0..40 {
                for y in 0..40 {
                    let s = DVec2::new(x as f64 * 0.1 + 0.013, y as f64 * 0.1 + 0.029);
                    prop_assert_eq!(inside_any(&tris, s), inside_any(&out, s), "{}", s);
                }
            }
        }
    }
}

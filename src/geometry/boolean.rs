//! Boolean operations on polygons of a plane, in two coordinates, by a
//! robust engine (`i_overlay`, on its 64-bit integer grid at its full 61
//! bits: its 32-bit grid was seen to multiply the vertices of nearly
//! collinear edges a thousandfold, and the 64-bit grid at 56 bits or
//! fewer did not finish uniting office2's floor, splitting its crossings
//! again and again). Used to unite the shadow pieces of one light (004
//! section 4.7), to intersect the shadows of several lights, and to clip
//! the vector painter's shadow patches.
//!
//! The engine gives regions as outlines with holes. Every polygon of the
//! tree is simple and has no hole, so [`without_holes`] cuts a region with
//! holes into horizontal strips, one cut through the middle of each hole:
//! every hole then meets the side of its strip and becomes a notch. The
//! strips share their cut lines exactly (every strip's overlay has the
//! outline's box, so the same integer grid), and the scan converter's
//! half-open sampling owns every sample on a shared edge once.

use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::core::solver::{Precision, Solver, Strategy};
use i_overlay::float::overlay::{FloatOverlay, OverlayOptions};
use i_overlay::float::simplify::SimplifyShape;

/// A point in two coordinates.
pub type Flat = [f64; 2];

/// A region as the engine gives it: outlines (counter-clockwise), each
/// followed by its holes (clockwise).
pub type Shapes = Vec<Vec<Vec<Flat>>>;

/// The engine's solver. Where rounded crossings meet new ones, it snaps
/// them to endpoints within a radius it widens each round until none is
/// left: its default widens the squared radius twofold, and 22 shadow
/// pieces of a book in office2, sharing long edges and crossing at
/// grazing angles, took 55 s to unite so; fourfold, 17 ms. The first
/// round is the same (a squared radius of 1), and office2's 3,147 unions
/// come out the same, point for point.
const SOLVER: Solver = Solver {
    precision: Precision::MEDIUM,
    ..Solver::AUTO
};

/// The solver for unions of up to [`LIST_SEGMENTS`] edges: the engine's
/// split by lists of segments, which its automatic choice leaves at 2,000
/// segments for its tree. Office2's 3,147 unions come out the same point
/// for point, one after another in 34.1 ms against 36.3 ms (its floor's
/// 3,195 edges in 4.8 ms against 6.1 ms).
const LIST_SOLVER: Solver = Solver {
    strategy: Strategy::List,
    ..SOLVER
};

/// The most edges a union splits by lists; past them the engine chooses
/// its split, as before (on fields of overlapping quads the two splits
/// took the same time from 500 to 8,000 edges).
const LIST_SEGMENTS: usize = 4096;

/// Twice the signed area of a ring (positive counter-clockwise).
pub fn twice_area(c: &[Flat]) -> f64 {
    let n = c.len();
    (0..n)
        .map(|k| {
            let (a, b) = (c[k], c[(k + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

/// `ring` counter-clockwise.
pub fn counter_clockwise(mut ring: Vec<Flat>) -> Vec<Flat> {
    if twice_area(&ring) < 0.0 {
        ring.reverse();
    }
    ring
}

/// The union of counter-clockwise rings (the non-zero rule).
pub fn union(rings: &[Vec<Flat>]) -> Shapes {
    let edges: usize = rings.iter().map(Vec::len).sum();
    let solver = if edges <= LIST_SEGMENTS {
        LIST_SOLVER
    } else {
        SOLVER
    };
    rings.simplify_shape_custom_as::<i64>(FillRule::NonZero, OverlayOptions::default(), solver)
}

/// The intersection of two regions, each given as counter-clockwise rings
/// (holes clockwise) under the non-zero rule.
/// Two convex rings are clipped one by the other (Sutherland-Hodgman),
/// without the engine: most shadows of two lights on a polygon are one
/// convex outline each.
pub fn intersection(a: &[Vec<Flat>], b: &[Vec<Flat>]) -> Shapes {
    let convex_ccw = |r: &[Flat]| r.len() >= 3 && turns(r).all(|t| t >= 0.0);
    if let ([a], [b]) = (a, b)
        && convex_ccw(a)
        && convex_ccw(b)
    {
        let ring = clip_convex(a, b);
        return if ring.len() >= 3 && twice_area(&ring) > 0.0 {
            vec![vec![ring]]
        } else {
            Vec::new()
        };
    }
    FloatOverlay::<Flat, i64>::from_subj_and_clip_custom(&a, &b, OverlayOptions::default(), SOLVER)
        .overlay(OverlayRule::Intersect, FillRule::NonZero)
}

/// Whether a ring of at least three points never turns both ways (a
/// convex ring, either way round).
pub fn is_convex(ring: &[Flat]) -> bool {
    ring.len() >= 3 && (turns(ring).all(|t| t >= 0.0) || turns(ring).all(|t| t <= 0.0))
}

/// The turn at each point of a ring: positive to the left.
fn turns(ring: &[Flat]) -> impl Iterator<Item = f64> + '_ {
    let n = ring.len();
    (0..n).map(move |k| cross(ring[k], ring[(k + 1) % n], ring[(k + 2) % n]))
}

/// `(b - a) x (c - a)`: positive when `c` is left of the line `a b`.
fn cross(a: Flat, b: Flat, c: Flat) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The ring `subject` (either way round) clipped to the left of every
/// edge of the counter-clockwise convex ring `clip` (Sutherland-Hodgman).
pub fn clip_convex(subject: &[Flat], clip: &[Flat]) -> Vec<Flat> {
    let mut ring = subject.to_vec();
    let mut next = Vec::with_capacity(ring.len() + clip.len());
    for k in 0..clip.len() {
        let (a, b) = (clip[k], clip[(k + 1) % clip.len()]);
        next.clear();
        for i in 0..ring.len() {
            let (p, q) = (ring[i], ring[(i + 1) % ring.len()]);
            let (dp, dq) = (cross(a, b, p), cross(a, b, q));
            if dp >= 0.0 {
                next.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                let t = dp / (dp - dq);
                next.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        std::mem::swap(&mut ring, &mut next);
        if ring.is_empty() {
            break;
        }
    }
    ring
}

/// The region `shapes` as simple rings without holes
/// (counter-clockwise), or `None` if a strip kept a hole (only a
/// degenerate one could).
pub fn without_holes(shapes: Shapes) -> Option<Vec<Vec<Flat>>> {
    let mut out = Vec::new();
    for shape in shapes {
        strips(shape, &mut out)?;
    }
    Some(out)
}

/// One region cut into strips, added to `out`.
fn strips(mut shape: Vec<Vec<Flat>>, out: &mut Vec<Vec<Flat>>) -> Option<()> {
    if shape.len() == 1 {
        out.extend(shape.pop());
        return Some(());
    }
    let (lo, hi) = bounds(&shape[0]);
    let mut cuts: Vec<f64> = shape[1..]
        .iter()
        .map(|h| {
            let (l, h) = bounds(h);
            0.5 * (l[1] + h[1])
        })
        .collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let edges: Vec<f64> = std::iter::once(lo[1])
        .chain(cuts)
        .chain(std::iter::once(hi[1]))
        .collect();
    for w in edges.windows(2) {
        if w[1] <= w[0] {
            continue;
        }
        let strip = vec![vec![
            [lo[0], w[0]],
            [hi[0], w[0]],
            [hi[0], w[1]],
            [lo[0], w[1]],
        ]];
        for mut piece in intersection(&shape, &strip) {
            if piece.len() != 1 {
                return None;
            }
            out.extend(piece.pop());
        }
    }
    Some(())
}

/// The box of a ring.
fn bounds(c: &[Flat]) -> (Flat, Flat) {
    c.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use i_overlay::float::single::SingleFloatOverlay;
    use proptest::prelude::*;

    /// Whether `p` is inside `ring` (any turning) by its winding number.
    fn winds_around(ring: &[Flat], p: Flat) -> bool {
        let mut winding = 0;
        for k in 0..ring.len() {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            if a[1] <= p[1] && b[1] > p[1] && cross(a, b, p) > 0.0 {
                winding += 1;
            } else if a[1] > p[1] && b[1] <= p[1] && cross(a, b, p) < 0.0 {
                winding -= 1;
            }
        }
        winding != 0
    }

    /// The 22 shadow pieces of a face of a book in office2 (hidden in
    /// every view): long shared edges and crossings at grazing angles,
    /// which the engine's default solver took 55 s to unite. The union
    /// covers, on a grid of points, what the pieces cover, once.
    #[test]
    fn the_pieces_that_once_took_a_minute_unite() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/unions/book_face.json");
        let text = std::fs::read_to_string(&path).expect("the fixture of 22 pieces");
        let pieces: Vec<Vec<Flat>> = serde_json::from_str(&text).unwrap();
        assert_eq!(pieces.len(), 22);
        let rings = without_holes(union(&pieces)).expect("no degenerate hole");
        let (lo, hi) = pieces.iter().map(|r| bounds(r)).fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), (l, h)| {
                (
                    [lo[0].min(l[0]), lo[1].min(l[1])],
                    [hi[0].max(h[0]), hi[1].max(h[1])],
                )
            },
        );
        let mut checked = 0;
        for i in 0..=40 {
            for j in 0..=40 {
                let p = [
                    lo[0] + (hi[0] - lo[0]) * (i as f64 + 0.31) / 41.0,
                    lo[1] + (hi[1] - lo[1]) * (j as f64 + 0.47) / 41.0,
                ];
                let by_pieces = pieces.iter().any(|r| winds_around(r, p));
                let by_union = rings.iter().filter(|r| winds_around(r, p)).count();
                assert_eq!(by_union, usize::from(by_pieces), "at {p:?}");
                checked += usize::from(by_pieces);
            }
        }
        assert!(checked > 500, "only {checked} covered points");
    }

    fn convex(c: Flat, r: f64, k: usize, turn: f64) -> Vec<Flat> {
        (0..k)
            .map(|i| {
                let a = turn + std::f64::consts::TAU * i as f64 / k as f64;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            })
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// Two convex rings: the clipped ring has the area the engine
        /// finds for their intersection.
        #[test]
        fn convex_clipping_agrees_with_the_engine(
            a in (0.0f64..4.0, 0.0f64..4.0, 0.1f64..3.0, 3usize..9, 0.0f64..6.3),
            b in (0.0f64..4.0, 0.0f64..4.0, 0.1f64..3.0, 3usize..9, 0.0f64..6.3),
        ) {
            let a = convex([a.0, a.1], a.2, a.3, a.4);
            let b = convex([b.0, b.1], b.2, b.3, b.4);
            let fast: f64 = intersection(std::slice::from_ref(&a), std::slice::from_ref(&b))
                .iter()
                .map(|s| twice_area(&s[0]))
                .sum();
            let engine: f64 = [a]
                .overlay_as::<i64>(&[b], OverlayRule::Intersect, FillRule::NonZero)
                .iter()
                .flat_map(|s| s.iter().map(|c| twice_area(c)))
                .sum();
            prop_assert!((fast - engine).abs() < 1e-9, "{fast} against {engine}");
        }
    }
}

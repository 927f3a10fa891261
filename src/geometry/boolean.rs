//! Boolean operations on polygons of a plane, in two coordinates, by a
//! robust engine (`i_overlay`, on its 64-bit integer grid: its 32-bit grid
//! was seen to multiply the vertices of nearly collinear edges a
//! thousandfold). Used to unite the shadow pieces of one light (004
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
use i_overlay::float::simplify::SimplifyShape;
use i_overlay::float::single::SingleFloatOverlay;

/// A point in two coordinates.
pub type Flat = [f64; 2];

/// A region as the engine gives it: outlines (counter-clockwise), each
/// followed by its holes (clockwise).
pub type Shapes = Vec<Vec<Vec<Flat>>>;

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
    rings.simplify_shape_as::<i64>(FillRule::NonZero)
}

/// The intersection of two regions, each given as counter-clockwise rings
/// (holes clockwise) under the non-zero rule.
pub fn intersection(a: &[Vec<Flat>], b: &[Vec<Flat>]) -> Shapes {
    a.overlay_as::<i64>(&b, OverlayRule::Intersect, FillRule::NonZero)
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

//! Gouraud triangles as flat pieces, for SVG and TikZ, which have no
//! free-form triangle shadings (PDF has: type 4, see [`super::pdf`]).
//!
//! Over a triangle the shade is linear (004 section 4.8: interpolated
//! along the edges, then across, which is linear on a triangle). Cut
//! into `n x n` similar sub-triangles, with `n` the largest difference
//! between two vertices in any channel (in 8-bit levels), neighbouring
//! pieces' centroid shades differ by at most `2/3` of a level before
//! rounding, so no step exceeds one level. Each piece is filled with its
//! centroid's shade and stroked 1 unit wide in the same colour: a stroke
//! reaches half a unit over the neighbouring pieces, whose colour is
//! within a level, and covers the crack a viewer's anti-aliasing leaves
//! between abutting pieces (the only dilation in the vector output; it
//! moves a Gouraud surface's outline out by half a unit, 1/1024 of a
//! 512-unit frame; PDF needs none).

use super::Pt;

/// Largest subdivision per triangle side (65,536 pieces).
pub const MAX_STEPS: usize = 256;

/// The flat pieces of a Gouraud triangle: sub-triangles and their shades.
pub fn flat_pieces(t: &[(Pt, [u8; 3]); 3]) -> Vec<([Pt; 3], [u8; 3])> {
    let range = (0..3)
        .map(|c| {
            let v = t.map(|(_, col)| col[c] as i32);
            v.iter().max().unwrap_or(&0) - v.iter().min().unwrap_or(&0)
        })
        .max()
        .unwrap_or(0);
    let n = (range.max(1) as usize).min(MAX_STEPS);
    let (a, b, c) = (t[0].0, t[1].0, t[2].0);
    let point = |i: usize, j: usize| -> Pt {
        let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
        [
            a[0] + (b[0] - a[0]) * u + (c[0] - a[0]) * v,
            a[1] + (b[1] - a[1]) * u + (c[1] - a[1]) * v,
        ]
    };
    // Shade at barycentric (1 - u - v, u, v), u, v in units of 1/(3n).
    let shade = |u3: usize, v3: usize| -> [u8; 3] {
        let (u, v) = (u3 as f64 / (3 * n) as f64, v3 as f64 / (3 * n) as f64);
        std::array::from_fn(|ch| {
            let s =
                t[0].1[ch] as f64 * (1.0 - u - v) + t[1].1[ch] as f64 * u + t[2].1[ch] as f64 * v;
            s.round().clamp(0.0, 255.0) as u8
        })
    };
    let mut out = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n - i {
            out.push((
                [point(i, j), point(i + 1, j), point(i, j + 1)],
                shade(3 * i + 1, 3 * j + 1),
            ));
            if i + j + 1 < n {
                out.push((
                    [point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)],
                    shade(3 * i + 2, 3 * j + 2),
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_tile_the_triangle_with_steps_of_at_most_one_level() {
        let t = [
            ([0.0, 0.0], [0, 10, 200]),
            ([100.0, 0.0], [40, 10, 100]),
            ([0.0, 100.0], [20, 90, 150]),
        ];
        let pieces = flat_pieces(&t);
        let n = 100;
        assert_eq!(pieces.len(), n * n);
        let area: f64 = pieces
            .iter()
            .map(|(p, _)| super::super::signed_area(p).abs() / 2.0)
            .sum();
        assert!((area - 5000.0).abs() < 1e-6, "{area}");
        // Pieces sharing an edge (same two corners) differ by <= 1 level.
        let key = |p: Pt| {
            (
                (p[0] * 1000.0).round() as i64,
                (p[1] * 1000.0).round() as i64,
            )
        };
        let mut edges = std::collections::HashMap::new();
        for (tri, c) in &pieces {
            for k in 0..3 {
                let (a, b) = (key(tri[k]), key(tri[(k + 1) % 3]));
                let e = if a < b { (a, b) } else { (b, a) };
                edges.entry(e).or_insert_with(Vec::new).push(*c);
            }
        }
        let mut shared = 0;
        for cs in edges.values().filter(|cs| cs.len() == 2) {
            shared += 1;
            for ch in 0..3 {
                assert!((cs[0][ch] as i32 - cs[1][ch] as i32).abs() <= 1, "{cs:?}");
            }
        }
        assert!(shared > 10_000);
    }
}

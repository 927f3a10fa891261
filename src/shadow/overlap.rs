//! Overlapped shadows of several lights on one target (004 section 4.7,
//! extended past the limit of section 4.10 on "overlapped shadow regions
//! caused by multiple light sources"): the shadow pieces of each light on a
//! target's plane are intersected with those of the other lights, so that a
//! region shadowed from two lights can be shaded darker than either.
//!
//! A floor under a detailed object may carry thousands of pieces per
//! light, so the pieces of each light are indexed by a uniform grid over
//! their boxes in the target's plane (`PieceGrid`): a region is tested
//! only against the pieces whose cells it meets, in their original order,
//! so the regions made are the same as testing every pair.

use glam::{DVec2, DVec3, DVec4};

use crate::geometry::plane_clip::{self, ClipScratch, Clipped};
use crate::geometry::polygon;

/// A region of a target's plane and the lights it is shadowed from.
pub type ShadowRegion = (Vec<DVec3>, Vec<u32>);

/// The shadow regions on one target plane (unit normal `normal`) from the
/// shadow pieces of several lights (`(light, pieces)`, lights in increasing
/// order, pieces in the plane): first every piece alone, then the
/// intersections of two pieces of different lights, then of three, and so
/// on, each carrying its light set (increasing). The painter, back to
/// front, lets the regions of more lights overwrite those of fewer. Two
/// pieces are intersected with the splitter, clipping one to the planes
/// through the edges of the other (triangulated when not convex)
/// perpendicular to the target plane.
///
/// Past `cap` regions of two or more lights, no more intersections are
/// made: the remaining overlaps show the shade of a smaller light set (too
/// bright there), never a wrong outline.
///
/// The regions are made once, in the list returned: each layer of
/// intersections refers to the previous one by index, so a floor with
/// thousands of pieces holds no copies of them.
pub fn overlap_regions(
    per_light: Vec<(u32, Vec<Vec<DVec3>>)>,
    normal: DVec3,
    eps: f64,
    cap: usize,
) -> Vec<ShadowRegion> {
    let lights: Vec<u32> = per_light.iter().map(|(j, _)| *j).collect();
    // Every piece's box and clipping planes, once, and a grid per light.
    let prepared: Vec<Vec<InPlane>> = if lights.len() < 2 {
        Vec::new()
    } else {
        per_light
            .iter()
            .map(|(_, pieces)| pieces.iter().map(|p| InPlane::new(p, normal)).collect())
            .collect()
    };
    let grids: Vec<PieceGrid> = prepared
        .iter()
        .map(|pieces| PieceGrid::new(pieces, normal))
        .collect();
    // The pieces alone, and the layer to intersect next: (index of the
    // region in `out`, index of its last light in `lights`).
    let mut out: Vec<ShadowRegion> = Vec::new();
    let mut layer: Vec<(usize, usize)> = Vec::new();
    for (k, (j, pieces)) in per_light.into_iter().enumerate() {
        for p in pieces {
            layer.push((out.len(), k));
            out.push((p, vec![j]));
        }
    }
    if lights.len() < 2 {
        return out;
    }
    let mut scratch = ClipScratch::default();
    let mut many = Vec::new();
    let mut made = 0;
    let mut found = Vec::new();
    let mut near = Vec::new();
    while !layer.is_empty() && made < cap {
        let mut next = Vec::new();
        let mut next_last = Vec::new();
        'regions: for &(at, last) in &layer {
            let (points, set) = &out[at];
            let bounds = super::bounds(points);
            for (k, j) in lights.iter().enumerate().skip(last + 1) {
                grids[k].near(bounds, eps, &mut near);
                for &i in &near {
                    found.clear();
                    prepared[k][i as usize].clip(
                        points,
                        bounds,
                        eps,
                        &mut scratch,
                        &mut many,
                        &mut found,
                    );
                    for region in found.drain(..) {
                        if made >= cap {
                            break 'regions;
                        }
                        made += 1;
                        let mut set = set.clone();
                        set.push(*j);
                        next.push((region, set));
                        next_last.push(k);
                    }
                }
            }
        }
        let start = out.len();
        out.extend(next);
        layer = next_last
            .into_iter()
            .enumerate()
            .map(|(n, k)| (start + n, k))
            .collect();
    }
    out
}

/// The pieces of one light bucketed by the grid cells their boxes meet,
/// in the two coordinates the target's plane shows best (the normal's
/// largest component dropped). About one cell per piece, at most 256 a
/// side; each cell lists its pieces in increasing order.
struct PieceGrid {
    axes: [usize; 2],
    lo: DVec2,
    inv_cell: DVec2,
    side: [usize; 2],
    /// Cell `c`'s pieces are `items[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    items: Vec<u32>,
    pieces: usize,
}

impl PieceGrid {
    fn new(pieces: &[InPlane], normal: DVec3) -> PieceGrid {
        let a = normal.abs();
        let axes = if a.x >= a.y && a.x >= a.z {
            [1, 2]
        } else if a.y >= a.z {
            [0, 2]
        } else {
            [0, 1]
        };
        let flat = |v: DVec3| DVec2::new(v[axes[0]], v[axes[1]]);
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in pieces {
            lo = lo.min(flat(p.bounds.0));
            hi = hi.max(flat(p.bounds.1));
        }
        let n = ((pieces.len() as f64).sqrt().ceil() as usize).clamp(1, 256);
        let extent = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let inv_cell = DVec2::splat(n as f64) / extent;
        let mut grid = PieceGrid {
            axes,
            lo: if lo.is_finite() { lo } else { DVec2::ZERO },
            inv_cell: if inv_cell.is_finite() {
                inv_cell
            } else {
                DVec2::ZERO
            },
            side: [n, n],
            starts: vec![0; n * n + 1],
            items: Vec::new(),
            pieces: pieces.len(),
        };
        // Counts, then offsets, then the lists (pieces in order).
        let ranges: Vec<_> = pieces.iter().map(|p| grid.cells(p.bounds, 0.0)).collect();
        for r in &ranges {
            for c in Self::indices(n, r) {
                grid.starts[c + 1] += 1;
            }
        }
        for c in 0..n * n {
            grid.starts[c + 1] += grid.starts[c];
        }
        let mut next = grid.starts.clone();
        grid.items = vec![0; grid.starts[n * n] as usize];
        for (i, r) in ranges.iter().enumerate() {
            for c in Self::indices(n, r) {
                grid.items[next[c] as usize] = i as u32;
                next[c] += 1;
            }
        }
        grid
    }

    /// The cell columns and rows a box (grown by `eps`) meets.
    fn cells(&self, (lo, hi): (DVec3, DVec3), eps: f64) -> [std::ops::RangeInclusive<usize>; 2] {
        let at = |v: DVec3, k: usize, grow: f64| {
            let x = (v[self.axes[k]] + grow - self.lo[k]) * self.inv_cell[k];
            // NaN and negatives to 0, past the end to the last cell.
            (x.max(0.0) as usize).min(self.side[k] - 1)
        };
        [
            at(lo, 0, -eps)..=at(hi, 0, eps),
            at(lo, 1, -eps)..=at(hi, 1, eps),
        ]
    }

    /// The cells of the columns and rows `r`, row by row, in a grid `n`
    /// cells wide.
    fn indices(
        n: usize,
        r: &[std::ops::RangeInclusive<usize>; 2],
    ) -> impl Iterator<Item = usize> + use<> {
        let cols = r[0].clone();
        r[1].clone()
            .flat_map(move |row| cols.clone().map(move |col| row * n + col))
    }

    /// The pieces whose cells a box (grown by `eps`) meets, in increasing
    /// order, into `out`: every piece whose box meets it, and some more.
    fn near(&self, bounds: (DVec3, DVec3), eps: f64, out: &mut Vec<u32>) {
        out.clear();
        let r = self.cells(bounds, eps);
        if (r[0].end() - r[0].start() + 1) * (r[1].end() - r[1].start() + 1)
            >= self.side[0] * self.side[1]
        {
            out.extend(0..self.pieces as u32);
            return;
        }
        for c in Self::indices(self.side[0], &r) {
            out.extend_from_slice(
                &self.items[self.starts[c] as usize..self.starts[c + 1] as usize],
            );
        }
        out.sort_unstable();
        out.dedup();
    }
}

/// A polygon in a plane, ready to clip others to it: its box and, per
/// convex part, the planes perpendicular to the plane through its edges.
struct InPlane {
    bounds: (DVec3, DVec3),
    parts: Vec<Vec<DVec4>>,
}

impl InPlane {
    fn new(b: &[DVec3], normal: DVec3) -> InPlane {
        let parts = polygon::triangulate_if_needed(b)
            .into_iter()
            .map(|part| {
                let centre = part.iter().copied().sum::<DVec3>() / part.len() as f64;
                (0..part.len())
                    .filter_map(|i| {
                        let (p, q) = (part[i], part[(i + 1) % part.len()]);
                        let n = (q - p).cross(normal).try_normalize()?;
                        let pl = n.extend(-n.dot(p));
                        Some(if pl.truncate().dot(centre) + pl.w < 0.0 {
                            -pl
                        } else {
                            pl
                        })
                    })
                    .collect()
            })
            .collect();
        InPlane {
            bounds: super::bounds(b),
            parts,
        }
    }

    /// The pieces of `a` (box `a_bounds`) inside this polygon, into `out`;
    /// pieces of no area are dropped.
    fn clip(
        &self,
        a: &[DVec3],
        a_bounds: (DVec3, DVec3),
        eps: f64,
        scratch: &mut ClipScratch,
        many: &mut Vec<Vec<DVec3>>,
        out: &mut Vec<Vec<DVec3>>,
    ) {
        let ((alo, ahi), (blo, bhi)) = (a_bounds, self.bounds);
        if (alo - DVec3::splat(eps)).cmpgt(bhi).any() || (blo - DVec3::splat(eps)).cmpgt(ahi).any()
        {
            return;
        }
        let keep = |p: &[DVec3]| polygon::newell_vector(p.iter().copied()).length() > eps * eps;
        for planes in &self.parts {
            match plane_clip::clip_to_planes(a, planes, eps, scratch, many) {
                Ok(Clipped::One) if keep(scratch.piece()) => out.push(scratch.piece().to_vec()),
                Ok(Clipped::Many) => out.extend(many.drain(..).filter(|p| keep(p))),
                _ => {}
            }
        }
    }
}

/// The intersection of two polygons lying in one plane (unit normal
/// `normal`): `a` clipped to the planes perpendicular to it through the
/// edges of each convex part of `b`. Pieces of no area are dropped.
pub fn intersect_in_plane(a: &[DVec3], b: &[DVec3], normal: DVec3, eps: f64) -> Vec<Vec<DVec3>> {
    let mut out = Vec::new();
    InPlane::new(b, normal).clip(
        a,
        super::bounds(a),
        eps,
        &mut ClipScratch::default(),
        &mut Vec::new(),
        &mut out,
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small pseudo-random generator, so the test needs no seed crate.
    fn lcg(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Triangles and quads scattered over a plane through the origin with
    /// normal `normal`, of sizes from tiny to a third of the field.
    fn pieces(seed: u64, n: usize, normal: DVec3) -> Vec<Vec<DVec3>> {
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let mut s = seed;
        (0..n)
            .map(|_| {
                let c = DVec2::new(lcg(&mut s) * 10.0, lcg(&mut s) * 10.0);
                let r = 0.05 + lcg(&mut s).powi(3) * 3.0;
                let k = 3 + (lcg(&mut s) * 2.0) as usize;
                (0..k)
                    .map(|i| {
                        let a = std::f64::consts::TAU * i as f64 / k as f64;
                        let p = c + r * DVec2::new(a.cos(), a.sin());
                        u * p.x + v * p.y
                    })
                    .collect()
            })
            .collect()
    }

    /// With two lights the regions are the pieces alone, then each piece
    /// of the first light intersected with every piece of the second, in
    /// order: the grid must find exactly the pairs testing all pairs finds.
    #[test]
    fn the_grid_finds_the_regions_all_pairs_find() {
        for (seed, normal) in [
            (1, DVec3::Z),
            (2, DVec3::new(0.3, -0.9, 0.2).normalize()),
            (3, DVec3::new(-1.0, 0.1, 0.05).normalize()),
        ] {
            let (a, b) = (pieces(seed, 150, normal), pieces(seed + 100, 170, normal));
            let per_light = [(0, a.clone()), (3, b.clone())];
            let got = overlap_regions(per_light.to_vec(), normal, 1e-9, usize::MAX);
            let mut want: Vec<ShadowRegion> = a
                .iter()
                .map(|p| (p.clone(), vec![0]))
                .chain(b.iter().map(|p| (p.clone(), vec![3])))
                .collect();
            for p in &a {
                for q in &b {
                    for r in intersect_in_plane(p, q, normal, 1e-9) {
                        want.push((r, vec![0, 3]));
                    }
                }
            }
            assert!(
                want.len() > a.len() + b.len() + 100,
                "too few overlaps to test"
            );
            assert_eq!(got, want, "seed {seed}");
        }
    }
}

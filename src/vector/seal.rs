//! Sealing abutting faces whatever their colours: vertex caps.
//!
//! A viewer anti-aliases every path on its own and composites it over
//! what is there. Where a shared edge crosses a pixel, the face painted
//! first covers `c` of it and the one painted after covers `1 - c`: the
//! pixel gets `B (1 - c) + (A c + G (1 - c)) c`, where `G` is what was
//! under both (the background), so `c (1 - c)` of `G`, up to a quarter,
//! shows: the crack. Near a vertex where faces covering `c_i` meet,
//! `prod (1 - c_i)` shows. Merging same-coloured pieces into one path
//! ([`super::merge`]) removes this only where the colours agree.
//!
//! A pixel shows nothing of what is under it as soon as *one* path
//! painted before the others covers it entirely. So each vertex `V` gets
//! a *cap*: the union of the faces around `V`, added to the path of the
//! first of them painted, `F` (filled with `F`, in `F`'s colour). Every
//! other face around `V` is opaque and painted later, so the cap is hidden
//! wherever those faces cover a pixel entirely: it shows only through
//! their anti-aliased edges, where it stands in for the background with
//! the colour of a face next to them. A pixel within the faces around
//! one vertex (its ring) is covered entirely by `F`'s path; the faces
//! painted after it blend their own colours over it, and no background
//! is left. Faces a few pixels wide or more have each pixel of their
//! shared edges and corners inside some vertex's ring.
//!
//! The cap is one closed subpath: the faces around `V` in angular order,
//! each from the end of its edge leaving `V` to the start of its edge
//! arriving at `V`, joined directly where the next face starts along the
//! same ray and through `V` where it does not. As a chain this is the sum
//! of the faces' boundaries, so the nonzero rule fills exactly their
//! union, whatever gaps or overlaps there are around `V`: never more than
//! faces painted later, so a cap never moves a silhouette and never
//! shows over a face painted earlier. Only opaque faces (flat or Gouraud)
//! are in caps, and only flat ones own caps: a translucent face would
//! show the cap through it.
//!
//! **Silhouettes.** Where a cap's edge lies on a silhouette of the faces
//! (against the background, or over a face that is not a neighbour), the
//! cap's anti-aliased edge and the face's own add up: coverage `c`
//! becomes `1 - (1 - c)^2`, a quarter pixel more at worst, and more where
//! several caps share the edge. So a face of a ring that has a *free*
//! edge within [`INSET`] of it (an edge along which no face runs the
//! other way: a silhouette, or a fold, where both faces lie on one side)
//! enters the cap without the band [`INSET`] wide inside that edge, as
//! separate subpaths. An edge met by pieces of a neighbour split at a
//! T-junction is not free. The measured growth of the outline is 0.01 to
//! 0.05 pixel on average, 0.26 at most (`tests/vector_cracks.rs`).
//!
//! **Cost.** A face with many free edges near it (shadows and reflections
//! painted over it, sub-pixel detail) is left out of the caps, which
//! bounds the work (see [`MAX_NEAR`], [`MAX_SCAN`], [`MAX_PIECES`]); so
//! is a record through a vertex twice.

use rayon::prelude::*;

use super::{Pt, clip_half_plane as clip};

/// A cap: a closed subpath, and the pieces of some records, whose
/// nonzero fill lies within the union of `ring`, records painted after
/// the cap's owner.
#[derive(Debug, Clone, PartialEq)]
pub struct Cap {
    /// The records whose union the cap fills, in increasing order.
    pub ring: Vec<usize>,
    /// One closed subpath around the vertex over the faces of the ring
    /// with no free edge near (empty if none).
    pub path: Vec<Pt>,
    /// The faces of the ring with free edges near: their
    /// [`Seal::pieces`] belong to the cap.
    pub cut: Vec<usize>,
}

/// What seals a picture's records.
#[derive(Debug, Clone, Default)]
pub struct Seal {
    /// The caps each record owns.
    pub caps: Vec<Vec<Cap>>,
    /// Per record with free edges near: the record without the bands
    /// [`INSET`] wide inside them (closed subpaths), as caps take it.
    pub pieces: Vec<Vec<Vec<Pt>>>,
}

/// How a record enters the caps.
#[derive(Debug, Clone, PartialEq)]
enum Entry {
    /// Whole: no free edge near.
    Whole,
    /// As its pieces, without the bands inside the free edges near it.
    Cut(Vec<Vec<Pt>>),
    /// Not at all.
    Out,
}

/// The caps of the records. `points[k]` is record `k`'s polygon (with
/// positive [`super::signed_area`]), `opaque[k]` says whether it covers
/// what is under it, and `owners[k]` whether it is painted as a filled
/// path that can carry caps (an opaque one).
pub fn caps(points: &[Option<Vec<Pt>>], opaque: &[bool], owners: &[bool]) -> Seal {
    let paths: Vec<Option<&[Pt]>> = points
        .iter()
        .zip(opaque)
        .map(|(p, &o)| p.as_deref().filter(|_| o))
        .collect();
    let paths = &paths[..];
    // Every corner by its point: records sharing a vertex share its
    // coordinates' bits (they come from the same float). Key, record,
    // corner, packed so that they sort together.
    let mut corners: Vec<u128> = Vec::new();
    for (k, path) in paths.iter().enumerate() {
        if let Some(path) = path {
            for (i, &p) in path.iter().enumerate() {
                corners.push((key(p) as u128) << 64 | (k as u128) << 32 | i as u128);
            }
        }
    }
    corners.par_sort_unstable();
    let edges = Silhouettes::of(paths, &corners);
    let record = |c: u128| (c >> 32) as u32 as usize;
    let corner = |c: u128| c as u32 as usize;
    // Per shared vertex: its first owner (the faces before it are not
    // covered) and the faces after it, `(record, corner)` in `members`.
    let mut plans: Vec<((usize, usize), std::ops::Range<usize>)> = Vec::new();
    let mut members: Vec<(usize, usize)> = Vec::new();
    let mut involved = vec![false; paths.len()];
    for group in corners.chunk_by(|a, b| a >> 64 == b >> 64) {
        if group.len() < 2 {
            continue;
        }
        let Some(first) = group.iter().position(|&c| owners[record(c)]) else {
            continue;
        };
        let owner = record(group[first]);
        let start = members.len();
        for (j, &c) in group.iter().enumerate().skip(first + 1) {
            let k = record(c);
            // A record through the vertex twice is left out.
            let again = |d: &u128| record(*d) == k;
            if k == owner || again(&group[j - 1]) || group.get(j + 1).is_some_and(again) {
                continue;
            }
            members.push((k, corner(c)));
            involved[k] = true;
        }
        if members.len() > start {
            involved[owner] = true;
            plans.push(((owner, corner(group[first])), start..members.len()));
        }
    }
    // How each record in a cap enters it: whole, or without the bands
    // inside the free edges within [`INSET`] of it.
    let entries: Vec<Option<Entry>> = paths
        .par_iter()
        .zip(&involved)
        .map(|(p, &i)| i.then(|| entry(p.unwrap(), edges.near(p.unwrap()))))
        .collect();
    let caps: Vec<Option<Cap>> = plans
        .par_iter()
        .map_init(Scratch::default, |scratch, (owner, range)| {
            cap_at(*owner, &members[range.clone()], paths, &entries, scratch)
        })
        .collect();
    let mut seal = Seal {
        caps: vec![Vec::new(); paths.len()],
        pieces: vec![Vec::new(); paths.len()],
    };
    for (((owner, _), _), cap) in plans.iter().zip(caps) {
        if let Some(cap) = cap {
            seal.caps[*owner].push(cap);
        }
    }
    for (k, e) in entries.into_iter().enumerate() {
        if let Some(Entry::Cut(pieces)) = e {
            seal.pieces[k] = pieces;
        }
    }
    seal
}

/// How `poly` enters caps, with the free edges `near` it.
fn entry(poly: &[Pt], near: Near) -> Entry {
    let Some(free) = near else {
        return Entry::Out;
    };
    if free.is_empty() {
        return Entry::Whole;
    }
    let n = poly.len();
    let own = |&(a, b): &(Pt, Pt)| (0..n).any(|i| poly[i] == a && poly[(i + 1) % n] == b);
    if convex(poly) && free.iter().all(own) {
        // Its own edges: the band inside each is all of the polygon
        // within INSET of the edge's line.
        let piece = free.iter().fold(poly.to_vec(), |p, &(a, b)| {
            let (_, inward, _) = frame(a, b);
            clip(&p, |q| inward(q) - INSET)
        });
        return Entry::Cut(tidy(vec![piece]));
    }
    let mut pieces = vec![poly.to_vec()];
    let mut cut = false;
    for &(a, b) in &free {
        if pieces.iter().all(|p| area(&band(p, a, b)) <= 1e-9) {
            continue;
        }
        cut = true;
        pieces = pieces
            .iter()
            .flat_map(|p| outside_band(p, a, b))
            .filter(|p| area(p) > 1e-6)
            .collect();
        if pieces.len() > MAX_PIECES {
            return Entry::Out;
        }
    }
    if cut {
        Entry::Cut(tidy(pieces))
    } else {
        Entry::Whole
    }
}

/// `pieces` without repeated points and without slivers (area under a
/// thousandth of a unit times the perimeter).
fn tidy(pieces: Vec<Vec<Pt>>) -> Vec<Vec<Pt>> {
    pieces
        .into_iter()
        .map(|mut p| {
            p.dedup();
            while p.len() > 1 && p.first() == p.last() {
                p.pop();
            }
            p
        })
        .filter(|p| p.len() >= 3 && area(p) > 1e-3 * perimeter(p))
        .collect()
}

fn perimeter(p: &[Pt]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum()
}

/// Whether `p` turns one way only (positive orientation).
fn convex(p: &[Pt]) -> bool {
    let n = p.len();
    (0..n).all(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) >= 0.0
    })
}

/// A point's key: the bits of its coordinates as `f32` (points within a
/// float's rounding of each other count as one).
fn key(p: Pt) -> u64 {
    ((p[0] as f32 + 0.0).to_bits() as u64) << 32 | (p[1] as f32 + 0.0).to_bits() as u64
}

/// How far inside a free edge a cap stays (user units): its anti-aliased
/// edge then adds little to the face's own there. Less leaves more of
/// the cap's edge on the silhouette (it grows); more leaves more of the
/// pixels next to it unsealed (the test's figures: 0.3 grows the outline
/// by 0.08 pixel on average, 0.6 leaves 0.06 % of the surface's pixels
/// cracked).
pub const INSET: f64 = 0.4;

/// A face with more free edges than this within [`INSET`] of it is left
/// out of the caps (cutting the bands out would cost too much).
pub const MAX_NEAR: usize = 16;

/// A face cut into more pieces than this by the bands is left out of
/// the caps.
pub const MAX_PIECES: usize = 64;

/// A face whose neighbourhood (the grid cells along its edges) holds
/// more free edges than this is left out of the caps without a search:
/// sub-pixel detail crowded with silhouettes.
pub const MAX_SCAN: usize = 256;

/// The free edges near a record, or `None` when it is left out.
type Near = Option<Vec<(Pt, Pt)>>;

/// The free edges of the opaque records: those along which no other
/// record runs the other way (a silhouette against the background or
/// against a face that is not a neighbour, or a fold, where both faces
/// lie on one side), with a grid to find them.
struct Silhouettes {
    edges: Vec<(Pt, Pt)>,
    grid: Grid,
}

/// Segments by the grid cells they cross. The cells are about as many
/// as the segments (from 2 to 8 units a side).
struct Grid {
    cell: f64,
    columns: usize,
    rows: usize,
    cells: Vec<Vec<u32>>,
    /// Summed segment counts: entry `(r, c)` of a `(rows + 1) x (columns
    /// + 1)` table counts the cells above and left of cell `(r, c)`.
    sums: Vec<u32>,
}

impl Grid {
    fn new(segments: &[(Pt, Pt)]) -> Grid {
        let extent = segments
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .fold([1.0f64; 2], |m, p| [m[0].max(p[0]), m[1].max(p[1])]);
        let cell = (extent[0] * extent[1] / segments.len().max(1) as f64)
            .sqrt()
            .clamp(2.0, 8.0);
        let size = |v: f64| ((v / cell).ceil().max(1.0) as usize).min(4096);
        let (columns, rows) = (size(extent[0]), size(extent[1]));
        let mut grid = Grid {
            cell,
            columns,
            rows,
            cells: vec![Vec::new(); columns * rows],
            sums: vec![0; (columns + 1) * (rows + 1)],
        };
        let mut crossed = Vec::new();
        for (k, &(a, b)) in segments.iter().enumerate() {
            crossed.clear();
            grid.crossed(a, b, |c| crossed.push(c));
            for &c in &crossed {
                grid.cells[c].push(k as u32);
            }
        }
        let w = columns + 1;
        for r in 0..rows {
            for c in 0..columns {
                grid.sums[(r + 1) * w + c + 1] = grid.cells[r * columns + c].len() as u32
                    + grid.sums[r * w + c + 1]
                    + grid.sums[(r + 1) * w + c]
                    - grid.sums[r * w + c];
            }
        }
        grid
    }

    /// Whether no segment is in a cell that box `b` (grown by a cell)
    /// meets.
    fn empty_near(&self, b: [f64; 4]) -> bool {
        let (c0, c1) = (
            self.column(b[0] - self.cell),
            self.column(b[2] + self.cell) + 1,
        );
        let (r0, r1) = (self.row(b[1] - self.cell), self.row(b[3] + self.cell) + 1);
        let w = self.columns + 1;
        let s = |r: usize, c: usize| self.sums[r * w + c];
        s(r1, c1) + s(r0, c0) == s(r0, c1) + s(r1, c0)
    }

    fn column(&self, x: f64) -> usize {
        ((x / self.cell).floor().max(0.0) as usize).min(self.columns - 1)
    }

    fn row(&self, y: f64) -> usize {
        ((y / self.cell).floor().max(0.0) as usize).min(self.rows - 1)
    }

    /// Calls `f` with each cell segment `a`-`b` crosses: per row of
    /// cells, the columns between where it enters and leaves the row.
    fn crossed(&self, a: Pt, b: Pt, mut f: impl FnMut(usize)) {
        let (lo, hi) = if a[1] <= b[1] { (a, b) } else { (b, a) };
        let flat = hi[1] - lo[1] <= 0.0;
        let x_at =
            |y: f64| lo[0] + (hi[0] - lo[0]) * ((y - lo[1]) / (hi[1] - lo[1])).clamp(0.0, 1.0);
        for r in self.row(lo[1])..=self.row(hi[1]) {
            let (x0, x1) = if flat {
                (lo[0], hi[0])
            } else {
                let y0 = (r as f64 * self.cell).max(lo[1]);
                let y1 = ((r + 1) as f64 * self.cell).min(hi[1]);
                (x_at(y0), x_at(y1))
            };
            for c in self.column(x0.min(x1))..=self.column(x0.max(x1)) {
                f(r * self.columns + c);
            }
        }
    }
}

/// `[x0, y0, x1, y1]` of `points`, grown by `margin`.
fn bounds(points: &[Pt], margin: f64) -> [f64; 4] {
    let b = points
        .iter()
        .fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        });
    [b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin]
}

impl Silhouettes {
    /// The free edges of `paths`, whose corners are `corners` (packed
    /// and sorted as in [`caps`]).
    fn of(paths: &[Option<&[Pt]>], corners: &[u128]) -> Silhouettes {
        // Edges without a reverse twin: at a vertex, an edge leaving to
        // `b` has one when an edge arrives from `b`.
        let mut loose: Vec<(Pt, Pt)> = Vec::new();
        let mut arrivals: Vec<u64> = Vec::new();
        for group in corners.chunk_by(|a, b| a >> 64 == b >> 64) {
            let at = |c: u128| {
                let path = paths[(c >> 32) as u32 as usize].unwrap();
                let i = c as u32 as usize;
                (path, i, path.len())
            };
            arrivals.clear();
            arrivals.extend(group.iter().map(|&c| {
                let (path, i, n) = at(c);
                key(path[(i + n - 1) % n])
            }));
            for &c in group {
                let (path, i, n) = at(c);
                let (a, b) = (path[i], path[(i + 1) % n]);
                let kb = key(b);
                if kb != (c >> 64) as u64 && !arrivals.contains(&kb) {
                    loose.push((a, b));
                }
            }
        }
        // ... are shared all the same when another runs the other way
        // along part of them from one of their ends: a T-junction, where
        // a neighbour was split and this face was not. By end point and
        // direction: each edge leaving its start and arriving at its end
        // (the direction back along it), packed as point key, angle (as
        // ordered bits), arriving flag and edge, sorted.
        let angle = |p: Pt, q: Pt| (q[1] - p[1]).atan2(q[0] - p[0]) as f32;
        let pack = |k: u64, t: f32, arriving: bool, j: usize| {
            (k as u128) << 64 | (ordered(t) as u128) << 32 | (arriving as u128) << 31 | j as u128
        };
        let mut ends: Vec<u128> = Vec::with_capacity(2 * loose.len());
        for (j, &(a, b)) in loose.iter().enumerate() {
            ends.push(pack(key(a), angle(a, b), false, j));
            ends.push(pack(key(b), angle(b, a), true, j));
        }
        ends.par_sort_unstable();
        // Edge `j` leaving `b` towards `a` meets edge `e` arriving at `b`
        // from `a`: both are entries at `b` with the angle of `a`, one
        // leaving and one arriving. So, per point, each entry looks for
        // entries of the other kind within 0.05 radian.
        const ANGLE: f32 = 0.05;
        let mut shared = vec![false; loose.len()];
        let loose_ref = &loose;
        let found: Vec<usize> = ends
            .par_chunk_by(|a, b| a >> 64 == b >> 64)
            .filter(|group| group.len() >= 2)
            .flat_map_iter(|group| {
                let angle_of = |e: u128| e >> 32 & 0xffff_ffff;
                group.iter().filter_map(move |&e| {
                    let (j, arriving) = (e as u32 as usize & 0x7fff_ffff, e >> 31 & 1 == 1);
                    let t = f32::from_bits(unordered((e >> 32) as u32));
                    let range = |from: f32, to: f32| {
                        let (lo, hi) = (ordered(from) as u128, ordered(to) as u128);
                        let i = group.partition_point(|&x| angle_of(x) < lo);
                        let k = group.partition_point(|&x| angle_of(x) <= hi).max(i);
                        group[i..k].iter().any(|&x| {
                            let other = x as u32 as usize & 0x7fff_ffff;
                            (x >> 31 & 1 == 1) != arriving
                                && overlaps_reversed(loose_ref[j], loose_ref[other])
                        })
                    };
                    let pi = std::f32::consts::PI;
                    (range(t - ANGLE, t + ANGLE)
                        || (t + ANGLE > pi && range(-pi, t + ANGLE - 2.0 * pi))
                        || (t - ANGLE < -pi && range(t - ANGLE + 2.0 * pi, pi)))
                    .then_some(j)
                })
            })
            .collect();
        for j in found {
            shared[j] = true;
        }
        let edges: Vec<(Pt, Pt)> = loose
            .into_iter()
            .zip(shared)
            .filter_map(|(e, s)| (!s).then_some(e))
            .collect();
        let grid = Grid::new(&edges);
        Silhouettes { edges, grid }
    }

    /// The free edges within [`INSET`] of `poly`'s edges, in order;
    /// `None` when there are more than [`MAX_NEAR`], or more than
    /// [`MAX_SCAN`] to look at.
    fn near(&self, poly: &[Pt]) -> Near {
        let g = &self.grid;
        let b = bounds(poly, INSET);
        if g.empty_near(b) {
            return Some(Vec::new());
        }
        // Points within INSET of an edge lie in the cells it crosses or
        // their neighbours (a cell is wider than INSET); for a small face,
        // in the cells its box meets.
        let mut cells: Vec<usize> = Vec::new();
        let (c0, c1) = (g.column(b[0]), g.column(b[2]));
        let (r0, r1) = (g.row(b[1]), g.row(b[3]));
        if (c1 - c0 + 1) * (r1 - r0 + 1) <= 16 {
            cells.extend((r0..=r1).flat_map(|r| (c0..=c1).map(move |c| r * g.columns + c)));
        } else {
            for i in 0..poly.len() {
                g.crossed(poly[i], poly[(i + 1) % poly.len()], |c| {
                    let (r, col) = (c / g.columns, c % g.columns);
                    for rr in r.saturating_sub(1)..=(r + 1).min(g.rows - 1) {
                        for cc in col.saturating_sub(1)..=(col + 1).min(g.columns - 1) {
                            cells.push(rr * g.columns + cc);
                        }
                    }
                });
            }
            cells.sort_unstable();
            cells.dedup();
        }
        if cells.iter().map(|&c| g.cells[c].len()).sum::<usize>() > MAX_SCAN {
            return None;
        }
        let mut found: Vec<u32> = Vec::new();
        for j in cells.into_iter().flat_map(|c| g.cells[c].iter().copied()) {
            let e = self.edges[j as usize];
            let outside = e.0[0].max(e.1[0]) < b[0]
                || e.0[0].min(e.1[0]) > b[2]
                || e.0[1].max(e.1[1]) < b[1]
                || e.0[1].min(e.1[1]) > b[3];
            // (An edge in several cells is measured once per cell.)
            if outside || found.contains(&j) {
                continue;
            }
            if (0..poly.len()).any(|i| within(e, (poly[i], poly[(i + 1) % poly.len()]), INSET)) {
                if found.len() == MAX_NEAR {
                    return None;
                }
                found.push(j);
            }
        }
        found.sort_unstable();
        Some(found.into_iter().map(|j| self.edges[j as usize]).collect())
    }
}

/// `t`'s bits, ordered as the numbers are.
fn ordered(t: f32) -> u32 {
    let b = t.to_bits();
    if b >> 31 == 1 { !b } else { b | 1 << 31 }
}

/// The number of `ordered` bits `b`.
fn unordered(b: u32) -> u32 {
    if b >> 31 == 1 { b & !(1 << 31) } else { !b }
}

/// Whether `f` runs along part of `e` the other way (to 1e-3 units).
fn overlaps_reversed(e: (Pt, Pt), f: (Pt, Pt)) -> bool {
    const TOL: f64 = 1e-3;
    let (a, b) = e;
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let len = (ux * ux + uy * uy).sqrt();
    if len <= TOL {
        return false;
    }
    let off = |p: Pt| ((p[1] - a[1]) * ux - (p[0] - a[0]) * uy) / len;
    let along = |p: Pt| ((p[0] - a[0]) * ux + (p[1] - a[1]) * uy) / len;
    let (s, t) = (along(f.0), along(f.1));
    off(f.0).abs() <= TOL && off(f.1).abs() <= TOL && t < s && s.min(len) - t.max(0.0) > TOL
}

/// Whether two segments come closer than `d`.
fn within(e: (Pt, Pt), f: (Pt, Pt), d: f64) -> bool {
    // Boxes first.
    if e.0[0].min(e.1[0]) > f.0[0].max(f.1[0]) + d
        || f.0[0].min(f.1[0]) > e.0[0].max(e.1[0]) + d
        || e.0[1].min(e.1[1]) > f.0[1].max(f.1[1]) + d
        || f.0[1].min(f.1[1]) > e.0[1].max(e.1[1]) + d
    {
        return false;
    }
    let cross = |o: Pt, p: Pt, q: Pt| (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    let (d1, d2) = (cross(f.0, f.1, e.0), cross(f.0, f.1, e.1));
    let (d3, d4) = (cross(e.0, e.1, f.0), cross(e.0, e.1, f.1));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    // Squared distance from a point to a segment.
    let to = |p: Pt, s: (Pt, Pt)| {
        let (dx, dy) = (s.1[0] - s.0[0], s.1[1] - s.0[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((p[0] - s.0[0]) * dx + (p[1] - s.0[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (x, y) = (p[0] - s.0[0] - dx * t, p[1] - s.0[1] - dy * t);
        x * x + y * y
    };
    let d2 = d * d;
    to(e.0, f) < d2 || to(e.1, f) < d2 || to(f.0, e) < d2 || to(f.1, e) < d2
}

/// The cap of `owner` (record, corner index) over `members`: one loop
/// over the faces that enter whole (the owner's own face included when
/// it would: it is in the owner's path anyway, and the loop need not go
/// round it through the vertex), and the members that enter cut.
fn cap_at(
    owner: (usize, usize),
    members: &[(usize, usize)],
    paths: &[Option<&[Pt]>],
    entries: &[Option<Entry>],
    scratch: &mut Scratch,
) -> Option<Cap> {
    let v = paths[owner.0].unwrap()[owner.1];
    // Per face: its points from the end of the edge leaving `v` to the
    // start of the edge arriving at `v` (a range of `scratch.points`),
    // and the first one's direction.
    let Scratch { points, faces } = scratch;
    points.clear();
    faces.clear();
    let mut cut: Vec<usize> = Vec::new();
    let mut whole = 0;
    for &(k, i) in std::iter::once(&owner).chain(members) {
        let path = paths[k].unwrap();
        let n = path.len();
        match &entries[k] {
            Some(Entry::Whole) => {}
            Some(Entry::Cut(_)) if k != owner.0 => {
                cut.push(k);
                continue;
            }
            _ => continue,
        }
        whole += (k != owner.0) as usize;
        // Points equal to `v` (repeated corners) are dropped.
        let start = points.len();
        points.extend((1..n).map(|d| path[(i + d) % n]).filter(|p| *p != v));
        if points.len() > start {
            let p = points[start];
            faces.push((pseudo_angle(p[0] - v[0], p[1] - v[1]), start, points.len()));
        }
    }
    faces.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut path: Vec<Pt> = Vec::new();
    let m = faces.len();
    for j in 0..m {
        let chain = &points[faces[j].1..faces[j].2];
        for &p in chain {
            if path.last() != Some(&p) {
                path.push(p);
            }
        }
        // Into the next face: along the ray when it starts where this
        // one ends, else through `v`.
        let (last, next) = (chain[chain.len() - 1], points[faces[(j + 1) % m].1]);
        if last != next && !same_ray(v, last, next) {
            path.push(v);
        }
    }
    if path.len() > 1 && path.first() == path.last() {
        path.pop();
    }
    if path.len() < 3 || whole == 0 {
        path.clear();
    }
    if path.is_empty() && cut.is_empty() {
        return None;
    }
    let mut ring: Vec<usize> = members.iter().map(|m| m.0).collect();
    ring.sort_unstable();
    Some(Cap { ring, path, cut })
}

/// Buffers [`cap_at`] reuses.
#[derive(Default)]
struct Scratch {
    points: Vec<Pt>,
    faces: Vec<(f64, usize, usize)>,
}

/// A number that grows with the angle of direction `(x, y)` from 0 to
/// a full turn (no trigonometry).
fn pseudo_angle(x: f64, y: f64) -> f64 {
    let p = x / (x.abs() + y.abs());
    if y < 0.0 { 3.0 + p } else { 1.0 - p }
}

/// Along edge `a`-`b` of a positively oriented polygon: the distance
/// from `a` along the edge and the distance to its inner side.
fn frame(a: Pt, b: Pt) -> (impl Fn(Pt) -> f64, impl Fn(Pt) -> f64, f64) {
    let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let (ux, uy) = ((b[0] - a[0]) / len, (b[1] - a[1]) / len);
    let along = move |p: Pt| (p[0] - a[0]) * ux + (p[1] - a[1]) * uy;
    let inward = move |p: Pt| ux * (p[1] - a[1]) - uy * (p[0] - a[0]);
    (along, inward, len)
}

/// The part of `poly` in the band [`INSET`] wide inside edge `a`-`b`.
fn band(poly: &[Pt], a: Pt, b: Pt) -> Vec<Pt> {
    let (along, inward, len) = frame(a, b);
    let p = clip(poly, &inward);
    let p = clip(&p, |q| INSET - inward(q));
    let p = clip(&p, &along);
    clip(&p, |q| len - along(q))
}

/// `poly` without the band [`INSET`] wide inside edge `a`-`b`, as
/// pieces: beyond the band, on the edge's outer side, and before and
/// after the band's ends.
fn outside_band(poly: &[Pt], a: Pt, b: Pt) -> Vec<Vec<Pt>> {
    let (along, inward, len) = frame(a, b);
    let within = clip(&clip(poly, &inward), |q| INSET - inward(q));
    [
        clip(poly, |q| inward(q) - INSET),
        clip(poly, |q| -inward(q)),
        clip(&within, |q| -along(q)),
        clip(&within, |q| along(q) - len),
    ]
    .into_iter()
    .filter(|p| p.len() >= 3)
    .collect()
}

/// The area of a polygon (nonzero winding, positive orientation).
fn area(p: &[Pt]) -> f64 {
    if p.len() < 3 {
        return 0.0;
    }
    super::signed_area(p) / 2.0
}

/// Whether `a` and `b` lie on one ray from `v` (to 1e-9 of the angle).
fn same_ray(v: Pt, a: Pt, b: Pt) -> bool {
    let (u, w) = ([a[0] - v[0], a[1] - v[1]], [b[0] - v[0], b[1] - v[1]]);
    let cross = u[0] * w[1] - u[1] * w[0];
    let dot = u[0] * w[0] + u[1] * w[1];
    let len = (u[0] * u[0] + u[1] * u[1]).sqrt() * (w[0] * w[0] + w[1] * w[1]).sqrt();
    dot > 0.0 && cross.abs() <= 1e-9 * len
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Winding number of `p` about the cap's subpaths together: its
    /// path and the pieces of the records it cuts.
    fn winding((seal, cap): (&Seal, &Cap), p: Pt) -> i32 {
        let pieces = cap.cut.iter().flat_map(|&r| &seal.pieces[r]);
        let mut w = 0;
        for path in std::iter::once(&cap.path).chain(pieces) {
            for k in 0..path.len() {
                let (a, b) = (path[k], path[(k + 1) % path.len()]);
                let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
                if a[1] <= p[1] && b[1] > p[1] && cross > 0.0 {
                    w += 1;
                } else if a[1] > p[1] && b[1] <= p[1] && cross < 0.0 {
                    w -= 1;
                }
            }
        }
        w
    }

    fn at(r: f64, k: f64) -> Pt {
        let a = std::f64::consts::TAU * (k % 6.0) / 6.0;
        [r * a.cos(), r * a.sin()]
    }

    /// Six triangles around the origin (records 0 to 5, `skip` left out)
    /// and a ring of six quadrilaterals around them (records 6 to 11),
    /// all positively oriented.
    fn fan(skip: Option<usize>) -> Vec<Option<Vec<Pt>>> {
        let inner = (0..6).map(|k| {
            let f = k as f64;
            (Some(k) != skip).then(|| vec![[0.0, 0.0], at(10.0, f), at(10.0, f + 1.0)])
        });
        let outer = (0..6).map(|k| {
            let f = k as f64;
            Some(vec![
                at(10.0, f),
                at(20.0, f),
                at(20.0, f + 1.0),
                at(10.0, f + 1.0),
            ])
        });
        inner.chain(outer).collect()
    }

    /// The cap at the origin, with the seal it belongs to.
    fn centre(seal: &Seal, owner: usize) -> (&Seal, &Cap) {
        let cap = seal.caps[owner]
            .iter()
            .find(|c| c.ring.iter().all(|&r| r < 6))
            .expect("a cap at the centre");
        (seal, cap)
    }

    #[test]
    fn the_cap_of_an_interior_vertex_is_its_ring_in_one_loop() {
        let paths = fan(None);
        let caps = caps(&paths, &[true; 12], &[true; 12]);
        let cap = centre(&caps, 0);
        assert_eq!(cap.1.ring, vec![1, 2, 3, 4, 5]);
        // One loop, the hexagon: the owner's face is in it.
        assert!(cap.1.cut.is_empty());
        assert_eq!(cap.1.path.len(), 6);
        assert!((0..6).all(|k| cap.1.path.contains(&at(10.0, k as f64))));
        for k in 0..6 {
            assert_eq!(winding(cap, at(5.0, k as f64 + 0.5)), 1);
        }
        assert_eq!(winding(cap, at(15.0, 0.5)), 0);
    }

    #[test]
    fn a_cap_at_a_silhouette_vertex_does_not_cross_the_gap_or_touch_its_edges() {
        // Face 3 missing: a wedge of background at the origin.
        let paths = fan(Some(3));
        let caps = caps(&paths, &[true; 12], &[true; 12]);
        let cap = centre(&caps, 0);
        assert_eq!(cap.1.ring, vec![1, 2, 4, 5]);
        assert_eq!(winding(cap, at(5.0, 3.5)), 0);
        // (The owner's own face, 0, is in its path; near the free edges
        // through the origin it is left out of the cap.)
        for k in [1.5, 2.5, 4.5, 5.5] {
            assert_eq!(winding(cap, at(5.0, k)), 1, "{k}");
        }
        // Faces 2 and 4 border the gap: the cap stays INSET inside their
        // edges there. `d` from the edge at 6 units from the origin:
        let off = |edge: f64, towards: f64, d: f64| {
            let (p, q) = (at(6.0, edge), at(6.0, towards));
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            // The distance from the edge grows as sin 30 along p-q.
            let t = d / ((dx * dx + dy * dy).sqrt() * 0.5);
            [p[0] + dx * t, p[1] + dy * t]
        };
        assert_eq!(winding(cap, off(3.0, 2.5, 0.5 * INSET)), 0);
        assert_eq!(winding(cap, off(3.0, 2.5, 2.0 * INSET)), 1);
        assert_eq!(winding(cap, off(4.0, 4.5, 0.5 * INSET)), 0);
        assert_eq!(winding(cap, off(4.0, 4.5, 2.0 * INSET)), 1);
    }

    #[test]
    fn only_owners_own_and_earlier_faces_are_not_covered() {
        let paths = fan(None);
        let mut owners = [true; 12];
        owners[0] = false;
        let caps = caps(&paths, &[true; 12], &owners);
        assert!(caps.caps[0].is_empty());
        let cap = centre(&caps, 1);
        assert_eq!(cap.1.ring, vec![2, 3, 4, 5]);
        assert_eq!(winding(cap, at(5.0, 0.5)), 0);
        assert_eq!(winding(cap, at(5.0, 1.5)), 1);
    }

    #[test]
    fn a_t_junction_is_no_silhouette() {
        // A square split in two on the left, one piece on the right.
        let squares: [&[Pt]; 3] = [
            &[[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]],
            &[[0.0, 5.0], [10.0, 5.0], [10.0, 10.0], [0.0, 10.0]],
            &[[10.0, 0.0], [20.0, 0.0], [20.0, 10.0], [10.0, 10.0]],
        ];
        let paths: Vec<Option<&[Pt]>> = squares.into_iter().map(Some).collect();
        let mut corners: Vec<u128> = Vec::new();
        for (k, path) in paths.iter().enumerate() {
            for (i, &p) in path.unwrap().iter().enumerate() {
                corners.push((key(p) as u128) << 64 | (k as u128) << 32 | i as u128);
            }
        }
        corners.sort_unstable();
        let edges = Silhouettes::of(&paths, &corners);
        assert!(
            edges
                .edges
                .iter()
                .all(|&(a, b)| a[0] != 10.0 || b[0] != 10.0)
        );
        assert_eq!(edges.edges.len(), 7);
    }
}

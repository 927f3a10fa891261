//! Records to paint items, with abutting pieces of one colour merged into
//! one path (no seams; the SVG/PDF "conflation" problem), and each flat
//! record's path carrying the caps that seal it to its neighbours of
//! other colours ([`super::seal`]).
//!
//! A viewer anti-aliases each path on its own: where two abutting
//! polygons of one colour each cover half of a pixel, the pixel gets
//! `C (1 - 1/4) + behind / 4`, a visible crack. One path whose subpaths
//! share the edge is rasterized as a whole (nonzero winding summed per
//! sample), so the shared edge does not show. Painting opaque polygons
//! of one colour one after the other equals painting their union, so
//! records of one colour go into one path as long as no record of
//! another colour painted between them overlaps them (the pieces of one
//! polygon split by NNS, 004 section 4.4; the faces of one flat-shaded
//! surface). Overlap is judged on a 64 x 64 grid of screen cells covered
//! by the records' bounding boxes (a record's caps included):
//! conservative, so the painting order is never changed where it
//! matters. Open groups are pairwise disjoint, so the order in which they
//! are closed does not matter either. A cap over records that all ended
//! up in its owner's group is left out: the group is one path already.
//!
//! Gouraud (and Phong) records that follow one another form one
//! [`Item::Gouraud`] run: one type-4 shading in PDF (clipped to the union
//! of their outlines), flat pieces dilated by a stroke in SVG and TikZ
//! ([`super::gouraud`]).

use super::seal::{self, Cap};
use super::{Item, Pt, user_points, vertex_paint};
use crate::tree::{Record, Shades};

/// Cells per side of the overlap grid.
const CELLS: usize = 64;
/// Most groups kept open at once (the oldest is closed first).
const MAX_OPEN: usize = 32;

/// The covered cells: one row of 64 columns per `u64`.
#[derive(Debug, Clone)]
struct Cells {
    rows: Box<[u64; CELLS]>,
    /// Row range with bits, for a quick reject.
    r0: usize,
    r1: usize,
    any: u64,
}

impl Cells {
    fn empty() -> Cells {
        Cells {
            rows: Box::new([0; CELLS]),
            r0: CELLS,
            r1: 0,
            any: 0,
        }
    }

    /// Empties the cells for reuse: only the rows with bits are cleared.
    fn clear(&mut self) {
        if self.r0 <= self.r1 {
            self.rows[self.r0..=self.r1].fill(0);
        }
        self.r0 = CELLS;
        self.r1 = 0;
        self.any = 0;
    }
}

/// A record's footprint: rows `r0..=r1`, column mask.
#[derive(Debug, Clone, Copy)]
struct Footprint {
    r0: usize,
    r1: usize,
    mask: u64,
}

impl Footprint {
    fn of<'a>(points: impl IntoIterator<Item = &'a Pt>, w: f64, h: f64) -> Footprint {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in points {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
            y0 = y0.min(p[1]);
            y1 = y1.max(p[1]);
        }
        // One unit of margin: anti-aliasing reaches half a pixel beyond.
        let cell = |v: f64, size: f64| {
            ((v / size * CELLS as f64).floor().max(0.0) as usize).min(CELLS - 1)
        };
        let (c0, c1) = (cell(x0 - 1.0, w), cell(x1 + 1.0, w));
        let (r0, r1) = (cell(y0 - 1.0, h), cell(y1 + 1.0, h));
        let mask = if c1 - c0 == 63 {
            u64::MAX
        } else {
            ((1u64 << (c1 - c0 + 1)) - 1) << c0
        };
        Footprint { r0, r1, mask }
    }

    fn hits(&self, c: &Cells) -> bool {
        if c.any & self.mask == 0 || self.r1 < c.r0 || self.r0 > c.r1 {
            return false;
        }
        (self.r0..=self.r1).any(|r| c.rows[r] & self.mask != 0)
    }

    fn add_to(&self, c: &mut Cells) {
        for r in self.r0..=self.r1 {
            c.rows[r] |= self.mask;
        }
        c.any |= self.mask;
        c.r0 = c.r0.min(self.r0);
        c.r1 = c.r1.max(self.r1);
    }
}

/// An open group of one colour.
struct Group {
    color: [u8; 3],
    paths: Vec<Vec<Pt>>,
    cells: Cells,
    /// The records in the group, in increasing order.
    members: Vec<usize>,
    /// The caps of its records ([`super::seal`]).
    caps: Vec<Cap>,
}

/// The sealing pieces of the records ([`seal::Seal::pieces`]).
type Pieces<'a> = &'a [Vec<Vec<Pt>>];

/// A run of Gouraud records.
struct Run {
    outline: Vec<Vec<Pt>>,
    triangles: Vec<[(Pt, [u8; 3]); 3]>,
}

struct Merger<'a> {
    open: Vec<Group>,
    run: Option<Run>,
    items: Vec<Item>,
    /// The cells of closed groups, cleared, for the next groups (a group
    /// per record is common: a curved surface's shades all differ).
    spare: Vec<Cells>,
    /// The pieces the caps take of records with free edges near.
    pieces: Pieces<'a>,
}

impl Merger<'_> {
    /// Closes (emits) every open group of another colour that `f` hits.
    fn close_hit(&mut self, f: &Footprint, keep: Option<[u8; 3]>) {
        let mut k = 0;
        while k < self.open.len() {
            if Some(self.open[k].color) != keep && f.hits(&self.open[k].cells) {
                let g = self.open.remove(k);
                self.emit(g);
            } else {
                k += 1;
            }
        }
    }

    fn emit(&mut self, g: Group) {
        let mut paths = g.paths;
        let member = |r: &usize| g.members.binary_search(r).is_ok();
        // A cap over records of the group itself adds nothing: the group
        // is one path. The pieces of a record go in once.
        let mut cut: Vec<usize> = Vec::new();
        for cap in g.caps {
            if !cap.ring.iter().all(member) {
                if !cap.path.is_empty() {
                    paths.push(cap.path);
                }
                cut.extend(cap.cut.into_iter().filter(|r| !member(r)));
            }
        }
        cut.sort_unstable();
        cut.dedup();
        for r in cut {
            paths.extend(self.pieces[r].iter().cloned());
        }
        self.items.push(Item::Fill {
            paths,
            color: g.color,
            opacity: 1.0,
        });
        let mut cells = g.cells;
        cells.clear();
        self.spare.push(cells);
    }

    fn flush_run(&mut self) {
        if let Some(run) = self.run.take() {
            self.items.push(Item::Gouraud {
                outline: run.outline,
                triangles: run.triangles,
            });
        }
    }

    /// Record `k`, filled in one colour, with its caps.
    fn flat(&mut self, k: usize, pts: Vec<Pt>, caps: Vec<Cap>, color: [u8; 3], f: Footprint) {
        self.flush_run();
        self.close_hit(&f, Some(color));
        if let Some(g) = self.open.iter_mut().find(|g| g.color == color) {
            f.add_to(&mut g.cells);
            g.paths.push(pts);
            g.members.push(k);
            g.caps.extend(caps);
            return;
        }
        if self.open.len() >= MAX_OPEN {
            let g = self.open.remove(0);
            self.emit(g);
        }
        let mut cells = self.spare.pop().unwrap_or_else(Cells::empty);
        f.add_to(&mut cells);
        self.open.push(Group {
            color,
            paths: vec![pts],
            cells,
            members: vec![k],
            caps,
        });
    }

    fn translucent(&mut self, pts: Vec<Pt>, color: [u8; 3], opacity: f32, f: Footprint) {
        self.flush_run();
        self.close_hit(&f, None);
        self.items.push(Item::Fill {
            paths: vec![pts],
            color,
            opacity,
        });
    }

    fn gouraud(&mut self, pts: Vec<Pt>, colors: Vec<[u8; 3]>, f: Footprint) {
        self.close_hit(&f, None);
        let run = self.run.get_or_insert_with(|| Run {
            outline: Vec::new(),
            triangles: Vec::new(),
        });
        // A fan from vertex 0 (the stream's polygons are convex pieces
        // of planar polygons; a non-convex one is triangulated).
        for t in fan(&pts) {
            run.triangles
                .push(t.map(|k| (pts[k], colors[k % colors.len()])));
        }
        run.outline.push(pts);
    }
}

/// Triangles of a polygon as vertex indices: a fan when convex, else ear
/// clipping.
fn fan(pts: &[Pt]) -> Vec<[usize; 3]> {
    let n = pts.len();
    if n < 3 {
        return Vec::new();
    }
    let convex = (0..n).all(|i| {
        let (a, b, c) = (pts[i], pts[(i + 1) % n], pts[(i + 2) % n]);
        (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) >= -1e-9
    });
    if convex {
        return (1..n - 1).map(|k| [0, k, k + 1]).collect();
    }
    let p3: Vec<glam::DVec3> = pts
        .iter()
        .map(|p| glam::DVec3::new(p[0], p[1], 0.0))
        .collect();
    let tris = crate::geometry::polygon::triangulate_if_needed(&p3);
    let index = |q: glam::DVec3| {
        pts.iter()
            .position(|p| p[0] == q.x && p[1] == q.y)
            .unwrap_or(0)
    };
    tris.iter()
        .filter(|t| t.len() == 3)
        .map(|t| [index(t[0]), index(t[1]), index(t[2])])
        .collect()
}

/// How a record is painted.
enum Paint {
    /// Nothing (special, or fewer than three points).
    Skip,
    /// Filled in one opaque colour.
    Flat([u8; 3]),
    /// Filled in one colour with an opacity below 1.
    Translucent([u8; 3], f32),
    /// Gouraud: a colour per point (in the order of the user points).
    Gouraud(Vec<[u8; 3]>),
}

fn paint_of(r: &Record, w: f64, h: f64) -> Paint {
    if r.points.len() < 3 {
        return Paint::Skip;
    }
    if let Shades::Faceted(color) = r.shades {
        // One opaque colour: the common case, without a colour list.
        return Paint::Flat(color);
    }
    let Some((colors, opacity)) = vertex_paint(r) else {
        return Paint::Skip;
    };
    if opacity < 1.0 {
        let n = colors.len() as u32;
        let mean = std::array::from_fn(|c| {
            (colors.iter().map(|v| v[c] as u32).sum::<u32>() / n.max(1)) as u8
        });
        Paint::Translucent(mean, opacity)
    } else if colors.iter().all(|c| *c == colors[0]) {
        Paint::Flat(colors[0])
    } else {
        // Orientation may have been reversed: keep colours with points.
        Paint::Gouraud(oriented_colors(r, &colors, w, h))
    }
}

/// The paint items of a back-to-front, pre-blended stream, in a frame of
/// `w x h` user units.
pub fn paint_items(records: &[Record], w: f64, h: f64) -> Vec<Item> {
    let paints: Vec<Paint> = records.iter().map(|r| paint_of(r, w, h)).collect();
    let mut points: Vec<Option<Vec<Pt>>> = records
        .iter()
        .zip(&paints)
        .map(|(r, p)| (!matches!(p, Paint::Skip)).then(|| user_points_with(r, w, h)))
        .collect();
    // The caps that seal abutting faces: over opaque records, owned by
    // flat ones.
    let opaque: Vec<bool> = paints
        .iter()
        .map(|p| matches!(p, Paint::Flat(_) | Paint::Gouraud(_)))
        .collect();
    let owners: Vec<bool> = paints.iter().map(|p| matches!(p, Paint::Flat(_))).collect();
    let seal::Seal { mut caps, pieces } = seal::caps(&points, &opaque, &owners);
    let mut m = Merger {
        open: Vec::new(),
        run: None,
        items: Vec::new(),
        spare: Vec::new(),
        pieces: &pieces,
    };
    for (k, paint) in paints.into_iter().enumerate() {
        // A stop request ends the painting early; the caller reports it
        // and writes nothing.
        if k % 1024 == 0 && crate::cancel::requested() {
            break;
        }
        let Some(pts) = points[k].take() else {
            continue;
        };
        match paint {
            Paint::Skip => {}
            Paint::Flat(color) => {
                let caps = std::mem::take(&mut caps[k]);
                let cut = caps.iter().flat_map(|c| &c.cut).flat_map(|&r| &pieces[r]);
                let f = Footprint::of(
                    pts.iter()
                        .chain(caps.iter().flat_map(|c| &c.path))
                        .chain(cut.flatten()),
                    w,
                    h,
                );
                m.flat(k, pts, caps, color, f);
            }
            Paint::Translucent(color, opacity) => {
                let f = Footprint::of(&pts, w, h);
                m.translucent(pts, color, opacity, f);
            }
            Paint::Gouraud(colors) => {
                let f = Footprint::of(&pts, w, h);
                m.gouraud(pts, colors, f);
            }
        }
    }
    m.flush_run();
    let open = std::mem::take(&mut m.open);
    for g in open {
        m.emit(g);
    }
    m.items
}

fn user_points_with(r: &Record, w: f64, h: f64) -> Vec<Pt> {
    user_points(r, w, h)
}

/// The vertex colours in the order [`user_points`] gives the points.
fn oriented_colors(r: &Record, colors: &[[u8; 3]], w: f64, h: f64) -> Vec<[u8; 3]> {
    let raw: Vec<Pt> = r
        .points
        .iter()
        .map(|p| [p[0] as f64 * w, (1.0 - p[1] as f64) * h])
        .collect();
    let mut c: Vec<[u8; 3]> = (0..raw.len()).map(|k| colors[k % colors.len()]).collect();
    if super::signed_area(&raw) < 0.0 {
        c.reverse();
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tree::Shades;

    fn rec(points: &[[f32; 2]], c: [u8; 3]) -> Record {
        Record {
            level: 1,
            points: points.to_vec(),
            shades: Shades::Faceted(c),
        }
    }

    #[test]
    fn abutting_pieces_of_one_colour_merge() {
        let red = [200, 0, 0];
        let a = rec(&[[0.1, 0.1], [0.5, 0.1], [0.5, 0.5]], red);
        let b = rec(&[[0.1, 0.1], [0.5, 0.5], [0.1, 0.5]], red);
        let items = paint_items(&[a, b], 512.0, 512.0);
        assert_eq!(items.len(), 1);
        let Item::Fill { paths, .. } = &items[0] else {
            panic!()
        };
        assert_eq!(paths.len(), 2);
    }

    #[test]
    fn an_overlapping_record_between_keeps_the_order() {
        let (red, blue) = ([200, 0, 0], [0, 0, 200]);
        let a = rec(&[[0.1, 0.1], [0.5, 0.1], [0.5, 0.5]], red);
        let b = rec(&[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6]], blue);
        let c = rec(&[[0.1, 0.1], [0.5, 0.5], [0.1, 0.5]], red);
        let items = paint_items(&[a, b, c], 512.0, 512.0);
        let colors: Vec<[u8; 3]> = items
            .iter()
            .map(|i| match i {
                Item::Fill { color, .. } => *color,
                _ => panic!(),
            })
            .collect();
        assert_eq!(colors, vec![red, blue, red]);
    }

    #[test]
    fn a_disjoint_record_between_does_not_split_the_group() {
        let (red, blue) = ([200, 0, 0], [0, 0, 200]);
        let a = rec(&[[0.1, 0.1], [0.3, 0.1], [0.3, 0.3]], red);
        let b = rec(&[[0.7, 0.7], [0.9, 0.7], [0.9, 0.9]], blue);
        let c = rec(&[[0.1, 0.1], [0.3, 0.3], [0.1, 0.3]], red);
        let items = paint_items(&[a, b, c], 512.0, 512.0);
        assert_eq!(items.len(), 2);
    }
}

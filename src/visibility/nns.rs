//! The Newell-Newell-Sancha sorter with face splitting, made deterministic
//! as W. Donovan's "special sorter" (Donovan 1973, 000 section 3; Garcia
//! 1986, 004 section 4.4; the refined painter's algorithm of Firebaugh, 001).
//!
//! The list is ordered back to front by the farthest depth of each face. A
//! candidate `P` (at first the farthest face) is compared with every face
//! `Q` that could overlap it; the question is "may P occult Q?", answered
//! by tests of increasing cost that each can prove "P does not occult Q":
//!
//! 1. the screen extents do not overlap;
//! 2. `P` lies wholly beyond `Q` in depth;
//! 3. `P` lies wholly behind the plane of `Q`, or `Q` wholly in front of the
//!    plane of `P` (half-spaces as seen from the eye);
//! 4. where the projections of `P` and `Q` overlap (their convex
//!    intersection, which is where Donovan's edge-crossing test looks), `P`
//!    is nowhere nearer than `Q`: depths are compared along the eye's rays
//!    through the corners of the overlap, exactly, in world coordinates.
//!
//! If `P` may occult `Q`, `Q` must be painted first: `P` is marked and `Q`
//! becomes the candidate. When `Q` may occult `P` as well (a cycle of
//! length 2: the faces interpenetrate) `Q` is split by the plane of `P`.
//! When `Q` was already marked (a longer cycle; marked faces are examined
//! first, so it is the smallest cycle through `Q`), `Q` is split by the
//! planes through the edges of `P` and the eye (Donovan's figures 9 and
//! 10: the part of `Q` behind `P` is cut out). A face that occults nothing
//! is output. Splitting uses [`crate::geometry::face_splitter`].
//!
//! Candidates for comparison come from a screen-space grid and the depth
//! extents, so typical scenes are far from the quadratic worst case. In
//! an animation the faces given are put in depth order starting from the
//! last frame's order ([`PriorOrder`]), with the same result.
//!
//! Preconditions: faces are planar and convex (non-convex faces are cut
//! into triangles first by [`crate::geometry::polygon::triangulate`]) and
//! lie inside the view volume (clipped). Faces seen edge-on cover no area
//! and are output as they come. A cycle that cannot be split numerically is
//! output as is and counted in [`NnsStats::unresolved`]. A budget bounds
//! the splits and the work ([`sort_budgeted`]); past it the level is
//! ordered by the simple depth sort instead, and the fact is reported.
//!
//! # Design notes
//!
//! - NNS: candidates from a screen grid plus depth extents; the exact test
//!   (overlap polygon and eye-ray depths) runs only for pairs that survive
//!   the cheap tests. office2: 20 ms on one thread.
//! - The NNS grid has about two faces a cell, up to 1024 x 1024 cells and no
//!   finer than a pixel. NNS sorts the faces given once (farthest first) and
//!   keeps only split pieces in its heap; the neighbour search walks compact
//!   lists of extents and alive flags, not the faces.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec2, DVec3, DVec4};

use crate::geometry::face_splitter::{self, Split};
use crate::geometry::view::View;
use crate::model::{Object, Points, PointsRef};

mod prior;

pub use prior::PriorOrder;
use prior::cold_order;

/// A face to sort: world points and what it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct NnsFace {
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// World coordinates, inside the view volume: the scene polygon's
    /// own (read from the objects given to [`sort_in_scene`]) or a list.
    pub world: Points,
}

/// Figures of one sort.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NnsStats {
    /// Faces given.
    pub faces_in: usize,
    /// Faces output (pieces included).
    pub faces_out: usize,
    /// Splits made (each replaces one face by its pieces).
    pub splits: usize,
    /// Cycles of length 2 found (interpenetrating faces).
    pub cycles_of_two: usize,
    /// Longer cycles found.
    pub longer_cycles: usize,
    /// Occlusion tests that needed the exact overlap test (test 4).
    pub exact_tests: usize,
    /// Cycles left unbroken (numerically unsplittable).
    pub unresolved: usize,
    /// Work done: faces visited as neighbour candidates plus occlusion
    /// tests; bounded by [`WORK_PER_SPLIT`] times the split budget.
    pub work: usize,
    /// Sorts that stopped at the split (or work) budget and were ordered
    /// by the simple depth sort instead (see [`sort_budgeted`]).
    pub fallbacks: usize,
}

/// The work an NNS sort may do per split of its budget before it falls
/// back: random interpenetrating faces can make every face a neighbour of
/// every other without splitting much.
pub const WORK_PER_SPLIT: usize = 5000;

/// The warning of sorts that fell back: `splits` made by the first of
/// them, `levels` of them in all. It names the flag that raises the
/// budget (the work allowed grows with it).
pub fn fallback_warning(splits: usize, levels: usize) -> String {
    format!(
        "NNS stopped after {splits} splits (--max-splits raises it); the simple depth sort \
         ordered {}: the image may be wrong where polygons interpenetrate",
        if levels == 1 {
            "this level".to_string()
        } else {
            format!("{levels} levels")
        }
    )
}

struct Face {
    source: NnsFace,
    /// World plane, oriented so that the eye is on its positive side;
    /// `None` when seen edge-on.
    plane: Option<DVec4>,
}

/// A face's screen extent and depth range, kept apart from its points in
/// one compact list that the neighbour search walks.
#[derive(Clone, Copy)]
struct Bounds {
    lo: DVec2,
    hi: DVec2,
    zmin: f64,
    zmax: f64,
}

#[derive(PartialEq)]
struct HeapKey(f64, usize);

impl Eq for HeapKey {}

impl PartialOrd for HeapKey {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for HeapKey {
    /// Farthest first; among equals, the earlier face first.
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(other.1.cmp(&self.1))
    }
}

struct Sorter<'v> {
    view: &'v View,
    /// The scene whose polygons the faces held as [`Points::Scene`] are.
    objects: &'v [Object],
    eps: f64,
    faces: Vec<Face>,
    bounds: Vec<Bounds>,
    /// Not yet output nor replaced by its pieces.
    alive: Vec<bool>,
    /// The faces given, farthest first ([`HeapKey`] order), and how many
    /// of them were taken; the pieces of splits go to `heap`. The head of
    /// the list is the greater of the two.
    given: Vec<usize>,
    next_given: usize,
    heap: BinaryHeap<HeapKey>,
    grid: Grid,
    stamp: Vec<u32>,
    epoch: u32,
    stats: NnsStats,
    max_splits: usize,
    max_work: usize,
    /// Set when a budget ran out: the sort gives up.
    stopped: bool,
    /// The neighbour list of [`Sorter::neighbours`], kept between calls
    /// so that the search allocates nothing per face.
    found: Vec<usize>,
}

/// The most cells of the screen grid along a side.
const MAX_GRID: usize = 1024;

/// Grid entries allowed per face (and a floor) when choosing the grid:
/// faces that each cover much of the screen make the grid coarser instead
/// of filling the memory.
const ENTRIES_PER_FACE: usize = 16;

/// Faces by screen cell. Each cell lists its faces farthest first (by the
/// far end of their depth range), from `start` on: the faces before it
/// were output. A search for the faces whose depth ranges reach past a
/// face's near end stops at the first that does not, so faces at one
/// depth (identical or coplanar faces facing the eye) cost nothing.
struct Grid {
    cells: Vec<Cell>,
    n: usize,
    cell_w: f64,
    cell_h: f64,
}

#[derive(Clone, Default)]
struct Cell {
    start: usize,
    faces: Vec<u32>,
}

impl Grid {
    fn new(bounds: &[Bounds], width: f64, height: f64) -> Grid {
        // About two faces per cell, so that the neighbours of a face stay
        // few as the scene grows (the sort stays near n log n to 10^6
        // faces); no finer than a pixel, where cells stop separating
        // faces, and at most MAX_GRID^2 cells.
        let faces = bounds.len();
        let finest = width.max(height).ceil().max(1.0) as usize;
        let mut n = ((faces as f64 / 2.0).sqrt() as usize).clamp(1, MAX_GRID.min(finest));
        let cap = faces.saturating_mul(ENTRIES_PER_FACE).max(1 << 20);
        loop {
            let g = Grid {
                cells: Vec::new(),
                n,
                cell_w: width / n as f64,
                cell_h: height / n as f64,
            };
            let total: usize = bounds
                .iter()
                .map(|b| {
                    let (x0, x1, y0, y1) = g.range(b.lo, b.hi);
                    (x1 - x0 + 1) * (y1 - y0 + 1)
                })
                .fold(0, usize::saturating_add);
            if total <= cap || n == 1 {
                return Grid {
                    cells: vec![Cell::default(); n * n],
                    ..g
                };
            }
            n /= 2;
        }
    }

    fn range(&self, lo: DVec2, hi: DVec2) -> (usize, usize, usize, usize) {
        let clamp = |v: f64, size: f64| {
            let c = (v / size).floor();
            if c.is_nan() || c < 0.0 {
                0
            } else {
                (c as usize).min(self.n - 1)
            }
        };
        (
            clamp(lo.x, self.cell_w),
            clamp(hi.x, self.cell_w),
            clamp(lo.y, self.cell_h),
            clamp(hi.y, self.cell_h),
        )
    }

    /// Adds face `id` to its cells, in place by `zmax` (farthest first).
    fn insert(&mut self, id: u32, lo: DVec2, hi: DVec2, bounds: &[Bounds]) {
        let (x0, x1, y0, y1) = self.range(lo, hi);
        let z = bounds[id as usize].zmax;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let cell = &mut self.cells[y * self.n + x];
                let at = cell.start
                    + cell.faces[cell.start..].partition_point(|&q| bounds[q as usize].zmax >= z);
                cell.faces.insert(at, id);
            }
        }
    }
}

/// Sorts `faces` back to front, splitting where needed, within the
/// default split budget ([`crate::budget::Budgets::splits`]). `epsilon` is
/// the absolute world distance under which points count as on a plane.
pub fn sort(faces: Vec<NnsFace>, view: &View, epsilon: f64) -> (Vec<NnsFace>, NnsStats) {
    sort_budgeted(
        faces,
        view,
        epsilon,
        crate::budget::Budgets::default().splits,
    )
}

/// [`sort`] with at most `max_splits` splits and `WORK_PER_SPLIT *
/// max_splits` units of work. Past either, the sort stops and the faces
/// (unsplit) are ordered by the simple depth sort (farthest vertex first,
/// 004 section 4.4), which is correct wherever faces do not overlap in
/// depth and on the screen; [`NnsStats::fallbacks`] is then 1.
pub fn sort_budgeted(
    faces: Vec<NnsFace>,
    view: &View,
    epsilon: f64,
    max_splits: usize,
) -> (Vec<NnsFace>, NnsStats) {
    assert!(
        faces.iter().all(|f| matches!(f.world, Points::Own(_))),
        "sort_budgeted: a face held as Points::Scene needs its objects (sort_in_scene)"
    );
    sort_in_scene(&[], faces, view, epsilon, max_splits, None)
}

/// [`sort_budgeted`] of faces some of which are whole polygons of the
/// scene of `objects`, held as [`Points::Scene`] (every face of
/// [`sort_budgeted`] holds its points), the faces given ordered starting
/// from the order `prior` kept from the last frame's sort (and kept there
/// for the next). The result is the same with any `prior` or none: only
/// the work of ordering the faces given changes.
pub fn sort_in_scene(
    objects: &[Object],
    faces: Vec<NnsFace>,
    view: &View,
    epsilon: f64,
    max_splits: usize,
    prior: Option<&PriorOrder>,
) -> (Vec<NnsFace>, NnsStats) {
    let n = faces.len();
    let mut s = Sorter::new(objects, view, epsilon, max_splits, n);
    // Measuring is a function of each face alone: in parallel, in order.
    let measured: Vec<(Bounds, Option<DVec4>)> = {
        use rayon::prelude::*;
        faces
            .par_iter()
            .with_min_len(1024)
            .map(|f| measure(view, &f.world.get(objects, f.object, f.polygon)))
            .collect()
    };
    let sources: Vec<(u32, u32)> = match prior {
        Some(_) => faces.iter().map(|f| (f.object, f.polygon)).collect(),
        None => Vec::new(),
    };
    for (f, (bounds, plane)) in faces.into_iter().zip(measured) {
        s.insert(f, bounds, plane);
    }
    // The faces given are ordered once; only pieces go through the heap.
    let zmax: Vec<f64> = s.bounds.iter().map(|b| b.zmax).collect();
    s.given = match prior {
        Some(prior) => prior.order(sources, &zmax),
        None => cold_order(&zmax),
    };
    // The grid, filled farthest first: each cell is in order.
    s.grid = Grid::new(&s.bounds, view.width, view.height);
    for &id in &s.given {
        let b = s.bounds[id];
        let (x0, x1, y0, y1) = s.grid.range(b.lo, b.hi);
        for y in y0..=y1 {
            for x in x0..=x1 {
                s.grid.cells[y * s.grid.n + x].faces.push(id as u32);
            }
        }
    }
    // The faces output, by index: a face split or output keeps its
    // points, so the first `n` are the faces given (for the fallback).
    let mut order = Vec::with_capacity(n);
    while let Some(head) = s.head() {
        let p = s.find_minimum(head);
        if s.stopped {
            break;
        }
        s.alive[p] = false;
        order.push(p);
    }
    let mut take = |k: usize| {
        std::mem::replace(
            &mut s.faces[k].source,
            NnsFace {
                object: 0,
                polygon: 0,
                world: Points::Scene,
            },
        )
    };
    let out: Vec<NnsFace>;
    if !s.stopped {
        out = order.into_iter().map(take).collect();
    } else {
        let originals: Vec<NnsFace> = (0..n).map(&mut take).collect();
        out = fallback_order(objects, view, originals);
        s.stats.fallbacks = 1;
    }
    s.stats.faces_out = out.len();
    (out, s.stats)
}

impl<'a> Sorter<'a> {
    /// An empty sorter for `n` faces.
    fn new(
        objects: &'a [Object],
        view: &'a View,
        epsilon: f64,
        max_splits: usize,
        n: usize,
    ) -> Self {
        Sorter {
            view,
            objects,
            eps: epsilon,
            faces: Vec::with_capacity(n),
            bounds: Vec::with_capacity(n),
            alive: Vec::with_capacity(n),
            given: (0..n).collect(),
            next_given: 0,
            heap: BinaryHeap::new(),
            grid: Grid {
                cells: Vec::new(),
                n: 1,
                cell_w: 1.0,
                cell_h: 1.0,
            },
            stamp: Vec::new(),
            epoch: 0,
            stats: NnsStats {
                faces_in: n,
                ..NnsStats::default()
            },
            max_splits,
            max_work: max_splits.saturating_mul(WORK_PER_SPLIT),
            stopped: false,
            found: Vec::new(),
        }
    }
}

/// The fallback when the sort stopped: the faces given, in
/// `depth_sort`'s order of their nearest-to-the-eye depth (`zmax`).
fn fallback_order(objects: &[Object], view: &View, originals: Vec<NnsFace>) -> Vec<NnsFace> {
    let keys: Vec<f64> = originals
        .iter()
        .map(|f| {
            let zmax = f
                .world
                .get(objects, f.object, f.polygon)
                .iter()
                .map(|p| view.project(*p).z)
                .fold(f64::NEG_INFINITY, f64::max);
            crate::visibility::depth_sort::sort_key(zmax)
        })
        .collect();
    let mut slots: Vec<Option<NnsFace>> = originals.into_iter().map(Some).collect();
    crate::visibility::depth_sort::sorted_order(&keys)
        .into_iter()
        .map(|k| slots[k].take().expect("a permutation"))
        .collect()
}

impl<'v> Sorter<'v> {
    /// The points of face `id`.
    fn points(&self, id: usize) -> PointsRef<'_> {
        let f = &self.faces[id].source;
        f.world.get(self.objects, f.object, f.polygon)
    }

    fn add(&mut self, source: NnsFace) -> usize {
        let (bounds, plane) = measure(
            self.view,
            &source
                .world
                .get(self.objects, source.object, source.polygon),
        );
        self.insert(source, bounds, plane)
    }

    /// Adds a face measured by [`measure`].
    fn insert(&mut self, source: NnsFace, bounds: Bounds, plane: Option<DVec4>) -> usize {
        let Bounds { lo, hi, zmin, zmax } = bounds;
        let id = self.faces.len();
        self.faces.push(Face { source, plane });
        self.bounds.push(Bounds { lo, hi, zmin, zmax });
        self.alive.push(true);
        self.stamp.push(0);
        if id >= self.given.len() {
            // A piece of a split (the faces given are put in the grid
            // once they are all measured and ordered).
            self.heap.push(HeapKey(zmax, id));
            self.grid.insert(id as u32, lo, hi, &self.bounds);
        }
        id
    }

    /// The farthest face still in the list.
    fn head(&mut self) -> Option<usize> {
        while self
            .given
            .get(self.next_given)
            .is_some_and(|&id| !self.alive[id])
        {
            self.next_given += 1;
        }
        while let Some(HeapKey(_, id)) = self.heap.peek() {
            if self.alive[*id] {
                break;
            }
            self.heap.pop();
        }
        let given = self.given.get(self.next_given).copied();
        match (given, self.heap.peek()) {
            (Some(g), Some(h)) => Some(if HeapKey(self.bounds[g].zmax, g) > *h {
                g
            } else {
                h.1
            }),
            (Some(g), None) => Some(g),
            (None, h) => h.map(|h| h.1),
        }
    }

    /// Donovan's search for a minimum face, splitting cycles on the way.
    fn find_minimum(&mut self, start: usize) -> usize {
        let mut p = start;
        let mut chain: Vec<usize> = Vec::new();
        loop {
            // A stop request ends the sort as a budget does (the caller
            // then reports the cancellation).
            if self.stats.work >= self.max_work || crate::cancel::requested() {
                self.stopped = true;
                return p;
            }
            let Some(q) = self.first_occulted(p, &chain) else {
                return p;
            };
            let mutual = self.may_occult(q, p);
            let marked = chain.contains(&q);
            if !mutual && !marked {
                chain.push(p);
                p = q;
                continue;
            }
            if self.stats.splits >= self.max_splits || self.stats.work >= self.max_work {
                self.stopped = true;
                return p;
            }
            let split = if mutual {
                self.stats.cycles_of_two += 1;
                self.split_by_plane(q, p) || self.split_by_plane(p, q)
            } else {
                self.stats.longer_cycles += 1;
                self.split_by_edges(q, p) || self.split_by_edges(p, q)
            };
            if !split {
                // Numerically unsplittable: paint P now.
                self.stats.unresolved += 1;
                return p;
            }
            // Start again from the (possibly new) farthest face.
            chain.clear();
            p = self.head().expect("the pieces are alive");
        }
    }

    /// The first face that `p` may occult: marked faces first (in marking
    /// order), then the others by index.
    fn first_occulted(&mut self, p: usize, chain: &[usize]) -> Option<usize> {
        for &q in chain {
            if q != p && self.alive[q] && self.may_occult(p, q) {
                return Some(q);
            }
        }
        let candidates = self.neighbours(p);
        let found = candidates
            .iter()
            .copied()
            .find(|&q| !chain.contains(&q) && self.may_occult(p, q));
        self.found = candidates;
        found
    }

    /// Alive faces whose screen extents and depth ranges overlap `p`'s.
    fn neighbours(&mut self, p: usize) -> Vec<usize> {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.epoch = 1;
        }
        let f = self.bounds[p];
        let (x0, x1, y0, y1) = self.grid.range(f.lo, f.hi);
        let mut out = std::mem::take(&mut self.found);
        out.clear();
        for y in y0..=y1 {
            for x in x0..=x1 {
                let cell = &mut self.grid.cells[y * self.grid.n + x];
                // Drop faces already output at the head, lazily.
                while cell
                    .faces
                    .get(cell.start)
                    .is_some_and(|&q| !self.alive[q as usize])
                {
                    cell.start += 1;
                }
                if cell.start > 64 && cell.start * 2 > cell.faces.len() {
                    cell.faces.drain(..cell.start);
                    cell.start = 0;
                }
                for &q in &cell.faces[cell.start..] {
                    self.stats.work += 1;
                    let q = q as usize;
                    let g = &self.bounds[q];
                    if g.zmax <= f.zmin {
                        // Farthest first: no later face reaches nearer.
                        break;
                    }
                    if q == p || !self.alive[q] || self.stamp[q] == self.epoch {
                        continue;
                    }
                    self.stamp[q] = self.epoch;
                    if g.lo.x < f.hi.x && f.lo.x < g.hi.x && g.lo.y < f.hi.y && f.lo.y < g.hi.y {
                        out.push(q);
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }

    /// Whether `a` may be nearer the eye than `b` somewhere both cover
    /// (tests 1 to 4 of the module comment).
    fn may_occult(&mut self, a: usize, b: usize) -> bool {
        self.stats.work += 1;
        let (ba, bb) = (&self.bounds[a], &self.bounds[b]);
        // Test 1: screen extents.
        if ba.hi.x <= bb.lo.x || bb.hi.x <= ba.lo.x || ba.hi.y <= bb.lo.y || bb.hi.y <= ba.lo.y {
            return false;
        }
        // Test 2: depth extents.
        if ba.zmin >= bb.zmax {
            return false;
        }
        let (Some(pa), Some(pb)) = (self.faces[a].plane, self.faces[b].plane) else {
            return false;
        };
        let exact = self.nearer_somewhere(a, b, pa, pb);
        self.stats.exact_tests += usize::from(exact.is_some());
        exact.unwrap_or(false)
    }

    /// Tests 3 and 4 of [`Self::may_occult`] for faces `a` and `b` of
    /// planes `pa` and `pb`: `None` when the half-spaces tell (`a` does
    /// not occult `b`), else the exact test's answer.
    fn nearer_somewhere(&self, a: usize, b: usize, pa: DVec4, pb: DVec4) -> Option<bool> {
        let (wa, wb) = (self.points(a), self.points(b));
        // Test 3: half-spaces.
        let eps = self.eps;
        if wa.iter().all(|p| pb.truncate().dot(*p) + pb.w <= eps) {
            return None;
        }
        if wb.iter().all(|p| pa.truncate().dot(*p) + pa.w >= -eps) {
            return None;
        }
        // Test 4: depths along the rays through the overlap's corners.
        let screen = |w: &[DVec3]| -> Vec<DVec2> {
            w.iter().map(|p| self.view.project(*p).truncate()).collect()
        };
        let overlap = convex_overlap(&screen(&wa), &screen(&wb));
        if overlap.len() < 3 || signed_area(&overlap).abs() < 1e-9 {
            return Some(false);
        }
        Some(overlap.iter().any(|v| {
            let Some((o, d)) = self.view.ray(v.x, v.y) else {
                return false;
            };
            let (Some(ta), Some(tb)) = (ray_plane(pa, o, d), ray_plane(pb, o, d)) else {
                return false;
            };
            (tb - ta) * d.length() > eps
        }))
    }

    /// Splits face `q` by the plane of face `p`; false if it does not cut.
    fn split_by_plane(&mut self, q: usize, p: usize) -> bool {
        let Some(plane) = self.faces[p].plane else {
            return false;
        };
        self.replace(q, &[plane])
    }

    /// Splits face `q` by the planes through each edge of `p` and the eye.
    fn split_by_edges(&mut self, q: usize, p: usize) -> bool {
        let eye = self.view.eye;
        let pts = self.points(p);
        let planes: Vec<DVec4> = (0..pts.len())
            .filter_map(|i| {
                let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                let towards_eye = crate::geometry::view::towards_eye(eye, a);
                let n = (b - a).cross(towards_eye).try_normalize()?;
                Some(n.extend(-n.dot(a)))
            })
            .collect();
        drop(pts);
        self.replace(q, &planes)
    }

    /// Cuts face `q` by each of `planes` in turn; if anything was cut, the
    /// pieces replace it.
    fn replace(&mut self, q: usize, planes: &[DVec4]) -> bool {
        let mut pieces = vec![self.points(q).to_vec()];
        let mut cut = false;
        for &plane in planes {
            let mut next = Vec::new();
            for piece in pieces {
                match face_splitter::split(&piece, plane, self.eps) {
                    Ok(Split::Both { front, back }) => {
                        cut = true;
                        next.extend(front);
                        next.extend(back);
                    }
                    _ => next.push(piece),
                }
            }
            pieces = next;
        }
        if !cut || pieces.len() < 2 {
            return false;
        }
        self.stats.splits += 1;
        self.alive[q] = false;
        let (object, polygon) = (self.faces[q].source.object, self.faces[q].source.polygon);
        for world in pieces {
            self.add(NnsFace {
                object,
                polygon,
                world: world.into(),
            });
        }
        true
    }
}

/// A face's screen extent, depth range and world plane (oriented so that
/// the eye is on its positive side; `None` when seen edge-on).
fn measure(view: &View, world: &[DVec3]) -> (Bounds, Option<DVec4>) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in world {
        let q = view.project(*p);
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let bounds = Bounds {
        lo: lo.truncate(),
        hi: hi.truncate(),
        zmin: lo.z,
        zmax: hi.z,
    };
    let plane = world_plane(world).and_then(|pl| {
        let side = pl.dot(view.eye);
        let scale = view.eye.truncate().length() + view.eye.w.abs() * pl.w.abs().max(1.0);
        (side.abs() > 1e-12 * scale.max(1e-300)).then(|| if side > 0.0 { pl } else { -pl })
    });
    (bounds, plane)
}

/// The plane of a planar polygon (unit normal, any orientation).
fn world_plane(points: &[DVec3]) -> Option<DVec4> {
    let n = crate::geometry::polygon::newell_vector(points.iter().copied()).try_normalize()?;
    let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    Some(n.extend(-n.dot(c)))
}

fn ray_plane(plane: DVec4, o: DVec3, d: DVec3) -> Option<f64> {
    let n = plane.truncate();
    let denom = n.dot(d);
    (denom != 0.0).then(|| -(n.dot(o) + plane.w) / denom)
}

fn signed_area(p: &[DVec2]) -> f64 {
    let n = p.len();
    (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum::<f64>() / 2.0
}

/// The intersection of two convex polygons (either orientation), by
/// clipping `a` with each edge of `b`.
pub fn convex_overlap(a: &[DVec2], b: &[DVec2]) -> Vec<DVec2> {
    let orient = signed_area(b).signum();
    if orient == 0.0 {
        return Vec::new();
    }
    let mut out = a.to_vec();
    for i in 0..b.len() {
        let (e0, e1) = (b[i], b[(i + 1) % b.len()]);
        let edge = e1 - e0;
        let side = |p: DVec2| orient * edge.perp_dot(p - e0);
        let input = std::mem::take(&mut out);
        let m = input.len();
        for k in 0..m {
            let (p, q) = (input[k], input[(k + 1) % m]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        if out.len() < 3 {
            return Vec::new();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_of_two_squares() {
        let a = [
            DVec2::new(0.0, 0.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(2.0, 0.0),
        ];
        let b: Vec<DVec2> = a.iter().map(|p| *p + DVec2::new(1.0, 1.0)).rev().collect();
        let o = convex_overlap(&a, &b);
        assert!((signed_area(&o).abs() - 1.0).abs() < 1e-12);
        let far: Vec<DVec2> = a.iter().map(|p| *p + DVec2::new(5.0, 0.0)).collect();
        assert!(convex_overlap(&a, &far).is_empty());
    }
}

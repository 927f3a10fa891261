//! The NNS sort's pieces grouped into patches: pieces of one key painted
//! together where no piece painted between them overlaps them on the
//! screen ([`Screen`]).

use glam::DVec3;

/// The pieces of an NNS sort back to front, and the patches they are
/// painted in (indices into `pieces`, in painting order).
pub(super) struct Sorted {
    pub(super) pieces: Vec<Piece>,
    pub(super) groups: Vec<Vec<usize>>,
    pub(super) splits: usize,
    pub(super) warning: Option<String>,
}

/// A piece of a face from the NNS sort.
pub(super) struct Piece {
    pub(super) source: u32,
    /// The face as given (not split).
    pub(super) whole: bool,
    pub(super) points: Vec<DVec3>,
}

/// Groups the pieces of a back-to-front order into patches: a piece
/// joins the last patch of its key when no piece painted after that
/// patch overlaps it on the screen, so the picture is the same. Returns
/// the members of each patch, in painting order.
///
/// A piece of a later patch was added after that patch's first member,
/// and each cell lists its pieces in the order they were added: the
/// search of a cell runs back from its newest entry and stops at that
/// first member.
pub(super) fn group_pieces(pieces: &[Piece], key: &dyn Fn(u32) -> u32) -> Vec<Vec<usize>> {
    /// Entries per cell searched before a piece is given its own patch.
    const MAX_SCAN: usize = 256;
    let n = ((pieces.len() as f64 / 2.0).sqrt() as usize).clamp(1, 512);
    let cell = |v: f64| (((v + 1.0) / 2.0 * n as f64).floor().max(0.0) as usize).min(n - 1);
    let screen = Screen::new(pieces);
    let mut cells: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n * n];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut last: rustc_hash::FxHashMap<u32, usize> = rustc_hash::FxHashMap::default();
    for (k, piece) in pieces.iter().enumerate() {
        let (lo, hi) = screen.bounds[k];
        let (x0, x1, y0, y1) = (cell(lo.x), cell(hi.x), cell(lo.y), cell(hi.y));
        let range = || (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| y * n + x));
        let kk = key(piece.source);
        let joins = last.get(&kk).copied().filter(|&g| {
            let first = groups[g][0];
            range().all(|c| cells[c].len() <= MAX_SCAN)
                && !range().any(|c| {
                    cells[c]
                        .iter()
                        .rev()
                        .take_while(|&&(other, _)| other as usize > first)
                        .any(|&(other, group)| {
                            group as usize > g && screen.overlap(k, other as usize)
                        })
                })
        });
        let g = joins.unwrap_or_else(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(k);
        last.insert(kk, g);
        for c in range() {
            cells[c].push((k as u32, g as u32));
        }
    }
    groups
}

/// The pieces' screen outlines (one after the other), with their bounds
/// and twice their signed areas.
pub(super) struct Screen {
    pub(super) flat: Vec<glam::DVec2>,
    pub(super) starts: Vec<usize>,
    pub(super) bounds: Vec<(glam::DVec2, glam::DVec2)>,
    pub(super) areas: Vec<f64>,
}

impl Screen {
    pub(super) fn new(pieces: &[Piece]) -> Screen {
        let mut flat = Vec::with_capacity(pieces.len() * 4);
        let mut starts = Vec::with_capacity(pieces.len() + 1);
        for p in pieces {
            starts.push(flat.len());
            flat.extend(p.points.iter().map(|q| q.truncate()));
        }
        starts.push(flat.len());
        let outline = |k: usize| &flat[starts[k]..starts[k + 1]];
        let bounds = (0..pieces.len()).map(|k| bounds2(outline(k))).collect();
        let areas = (0..pieces.len()).map(|k| twice_area(outline(k))).collect();
        Screen {
            flat,
            starts,
            bounds,
            areas,
        }
    }

    pub(super) fn outline(&self, k: usize) -> &[glam::DVec2] {
        &self.flat[self.starts[k]..self.starts[k + 1]]
    }

    /// Whether convex pieces `a` and `b` share more than a boundary on
    /// the screen: no edge of either separates them (the separating axis
    /// theorem), to within a width whose overlap could not reach an area
    /// of 1e-12.
    pub(super) fn overlap(&self, a: usize, b: usize) -> bool {
        boxes_overlap(self.bounds[a], self.bounds[b])
            && !separates_by(self.outline(a), self.areas[a], self.outline(b))
            && !separates_by(self.outline(b), self.areas[b], self.outline(a))
    }
}

pub(super) fn bounds2(pts: &[glam::DVec2]) -> (glam::DVec2, glam::DVec2) {
    use glam::DVec2;
    pts.iter()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        })
}

pub(super) fn boxes_overlap(a: (glam::DVec2, glam::DVec2), b: (glam::DVec2, glam::DVec2)) -> bool {
    a.1.x > b.0.x && b.1.x > a.0.x && a.1.y > b.0.y && b.1.y > a.0.y
}

/// Twice the signed area of a polygon (positive counter-clockwise).
pub(super) fn twice_area(a: &[glam::DVec2]) -> f64 {
    let n = a.len();
    (0..n).map(|i| a[i].perp_dot(a[(i + 1) % n])).sum()
}

/// Whether an edge of convex `a` (of `twice_area`) has all of `b` on
/// its outer side or on it (or `a` has no area).
pub(super) fn separates_by(a: &[glam::DVec2], twice_area: f64, b: &[glam::DVec2]) -> bool {
    /// The width (normalized units, the screen being 1.8 across) under
    /// which polygons count as touching.
    const TOUCH: f64 = 1e-13;
    if twice_area.abs() <= 2e-12 {
        return true;
    }
    let side = twice_area.signum();
    let n = a.len();
    (0..n).any(|i| {
        let (p, q) = (a[i], a[(i + 1) % n]);
        let e = q - p;
        let len = e.length();
        len > 0.0 && b.iter().all(|v| side * e.perp_dot(*v - p) <= TOUCH * len)
    })
}

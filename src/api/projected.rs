//! [`Projected`]: 3-D polygons and segments seen through another
//! program's 4 x 4 projection matrix, their visible pieces from the NNS
//! sort (Donovan 1973, 000 sections 3-4), for the matplotlib bridge of
//! the Python package.

use glam::{DVec3, DVec4};

use super::invalid;
use crate::error::Result;
use crate::math::Matrix4;

mod layers;

pub use layers::{Layered, PlacedSegment};

/// 3-D polygons seen through another program's 4 x 4 projection matrix
/// (a plotting library's camera), for hidden-surface removal in that
/// program's own picture: [`Projected::paint_order`] gives the visible
/// pieces of the polygons back to front, split by the NNS sort where they
/// interpenetrate or overlap in a cycle (Donovan 1973, 000 sections 3-4),
/// and [`Projected::visible_segments`] the visible pieces of 3-D line
/// segments.
///
/// The matrix maps a column `[x, y, z, 1]` to `[X, Y, Z, W]` (the
/// convention of OpenGL and of matplotlib's `Axes3D.get_proj()`: `M @ p`).
/// A point is drawn at `(X/W, Y/W)` and its depth is `Z/W`, smaller
/// nearer; only points with `W > 0` are in front of the eye, and polygons
/// and segments are clipped to them. Results are in the same 2-D
/// coordinates `(X/W, Y/W)`.
///
/// A projective map takes planes to planes and keeps the order of points
/// along each ray from the eye, so visibility is decided in the projected
/// space `(X/W, Y/W, Z/W)` (scaled into the unit cube), seen
/// orthographically. A polygon that is not planar (to 1e-9 of its size)
/// is taken as the fan of triangles from its first vertex, and a planar
/// one that is not convex is cut into triangles by ear clipping; the
/// pieces of each keep its index.
///
/// ```
/// use plytrace::api::Projected;
///
/// // Two unit squares crossing at right angles through the x axis, seen
/// // from above: the matrix keeps x and y and makes depth -z (nearer
/// // is higher up).
/// let flat: Vec<[f64; 3]> = vec![[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]];
/// let tilted: Vec<[f64; 3]> = vec![[-1., -1., -1.], [1., -1., -1.], [1., 1., 1.], [-1., 1., 1.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let polygons = [&flat[..], &tilted[..]];
/// let seen = Projected::new(&polygons, m)?;
/// let order = seen.paint_order()?;
/// // The flat square is cut along the x axis: its half under the upper
/// // half of the tilted one is painted first, its other half last.
/// let sources: Vec<usize> = order.patches.iter().map(|p| p.source()).collect();
/// assert_eq!(sources, [0, 1, 0]);
/// assert!(order.patches[0].rings[0].points.iter().all(|p| p[1] >= -1e-9));
/// assert!(order.patches[2].rings[0].points.iter().all(|p| p[1] <= 1e-9));
/// assert!(order.patches[1].rings[0].whole && !order.patches[0].rings[0].whole);
/// // A segment along the y axis below the flat square shows only where it
/// // leaves the square's outline (y beyond 1).
/// let pieces = seen.visible_segments(&[[[0., -2., -0.5], [0., 2., -0.5]]])?;
/// assert_eq!(pieces.len(), 2);
/// # Ok::<(), plytrace::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Projected {
    /// Normalized = (projected - centre) * scale, inside the unit cube.
    centre: DVec3,
    scale: DVec3,
    /// Distances under which points count as on a plane (normalized).
    eps: f64,
    /// The convex planar faces the sources are made of (normalized).
    faces: Vec<ProjectedFace>,
    sources: Vec<ProjectedSource>,
    /// The matrix, rows of `M` in `M @ p`.
    matrix: [[f64; 4]; 4],
    /// The least `W` kept (clipping in front of the eye).
    w_min: f64,
}

#[derive(Debug, Clone)]
struct ProjectedFace {
    source: u32,
    points: Vec<DVec3>,
}

#[derive(Debug, Clone, Default)]
struct ProjectedSource {
    /// The outline after clipping to `W > 0`, normalized.
    outline: Vec<DVec3>,
    /// Per edge of the outline: not made by clipping.
    original: Vec<bool>,
    /// Its faces: `faces[first..first + count]`.
    first: usize,
    count: usize,
    /// Whether clipping changed it.
    clipped: bool,
}

/// What [`Projected::paint_order`] gives.
///
/// ```
/// use plytrace::api::Projected;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// // Two squares, the second above and overlapping the first, seen from above.
/// let low: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
/// let high: Vec<[f64; 3]> = vec![[1., 1., 1.], [3., 1., 1.], [3., 3., 1.], [1., 3., 1.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let order = Projected::new(&[&low[..], &high[..]], m)?.paint_order()?;
/// assert_eq!(order.patches.len(), 2);
/// assert_eq!((order.splits, order.warning), (0, None), "no cycle, nothing split");
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PaintOrder {
    /// The visible pieces, to paint in this order.
    pub patches: Vec<Patch>,
    /// Faces the NNS sort split.
    pub splits: usize,
    /// Set when the sort stopped at its split budget and ordered the
    /// polygons by the simple depth sort instead.
    pub warning: Option<String>,
}

/// Pieces painted together, as one fill of their rings (which do not
/// overlap): the pieces of one source polygon, or with
/// [`Projected::paint_order_by`] of sources that share a key.
///
/// ```
/// use plytrace::api::Projected;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// // Two squares side by side at different heights, drawn as one fill.
/// let a: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
/// let b: Vec<[f64; 3]> = vec![[2., 0., 1.], [3., 0., 1.], [3., 1., 1.], [2., 1., 1.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let order = Projected::new(&[&a[..], &b[..]], m)?.paint_order_by(Some(&[7, 7]))?;
/// assert_eq!(order.patches.len(), 1);
/// assert_eq!(order.patches[0].rings.len(), 2);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// The rings, each a closed outline in the projected 2-D coordinates.
    pub rings: Vec<Ring>,
}

impl Patch {
    /// The source polygon of the first ring.
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let low: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
    /// let high: Vec<[f64; 3]> = vec![[1., 1., 1.], [3., 1., 1.], [3., 3., 1.], [1., 3., 1.]];
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// // Given nearest first, painted farthest first.
    /// let order = Projected::new(&[&high[..], &low[..]], m)?.paint_order()?;
    /// let sources: Vec<usize> = order.patches.iter().map(|p| p.source()).collect();
    /// assert_eq!(sources, [1, 0]);
    /// # Ok(())
    /// # }
    /// ```
    pub fn source(&self) -> usize {
        self.rings[0].source
    }
}

/// A closed outline of a [`Patch`].
///
/// ```
/// use plytrace::api::Projected;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let order = Projected::new(&[&square[..]], m)?.paint_order()?;
/// let ring = &order.patches[0].rings[0];
/// assert!(ring.whole && ring.source == 0);
/// assert_eq!(ring.points, [[0., 0.], [2., 0.], [2., 2.], [0., 2.]]);
/// assert_eq!(ring.edges, [true; 4]);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Ring {
    /// Index of the source polygon.
    pub source: usize,
    /// The source polygon whole, unsplit and unclipped: `points` is then
    /// its own outline, every vertex in the order given.
    pub whole: bool,
    /// The outline, in the projected 2-D coordinates.
    pub points: Vec<[f64; 2]>,
    /// Per edge (`k` joins points `k` and `k + 1`): whether it lies on an
    /// edge of the source polygon (not made by splitting, triangulating
    /// or clipping), for drawing the polygon's outline.
    pub edges: Vec<bool>,
}

/// A visible piece of a segment given to [`Projected::visible_segments`].
///
/// ```
/// use plytrace::api::Projected;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
/// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
/// let seen = Projected::new(&[&square[..]], m)?;
/// // Segment 1 passes above the square; segment 0 lies under it.
/// let pieces = seen.visible_segments(&[[[0.5, 1., -1.], [1.5, 1., -1.]], [[0.5, 1., 1.], [1.5, 1., 1.]]])?;
/// assert_eq!(pieces.len(), 1);
/// assert_eq!(pieces[0].segment, 1);
/// assert_eq!(pieces[0].points, [[0.5, 1.], [1.5, 1.]]);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentPiece {
    /// Index of the segment.
    pub segment: usize,
    /// Its ends, in the projected 2-D coordinates.
    pub points: [[f64; 2]; 2],
}

/// The screen of the NNS sort, in its pixels (the grid and the overlap
/// tolerances are in them): the unit cube's x and y map onto it.
const PROJECTED_SCREEN: f64 = 4096.0;

/// Half the side of the cube the projected points are scaled into.
const PROJECTED_HALF: f64 = 0.9;

impl Projected {
    /// Projects `polygons` (each three or more points) with `matrix`
    /// (rows of `M` in `M @ [x, y, z, 1]`). Refuses non-finite input and
    /// polygons of fewer than three points.
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// let triangle: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]];
    /// assert!(Projected::new(&[&triangle[..]], m).is_ok());
    /// let error = Projected::new(&[&triangle[..2]], m).unwrap_err().to_string();
    /// assert!(error.contains("polygon 0 has 2 points"), "{error}");
    /// let mut bad = m;
    /// bad[3][3] = f64::NAN;
    /// assert!(Projected::new(&[&triangle[..]], bad).is_err());
    /// ```
    pub fn new(polygons: &[&[[f64; 3]]], matrix: [[f64; 4]; 4]) -> Result<Projected> {
        Projected::new_with_open(polygons, matrix, &[])
    }

    /// [`Projected::new`], with `open[i]` (when given) saying that
    /// polygon `i` is open: its closing edge, from its last point back to
    /// its first, is not one of its edges (matplotlib's `closed=False`),
    /// so [`Ring::edges`] never marks it.
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
    /// let order = Projected::new_with_open(&[&square[..]], m, &[true])?.paint_order()?;
    /// assert_eq!(order.patches[0].rings[0].edges, [true, true, true, false]);
    /// # Ok(())
    /// # }
    /// ```
    pub fn new_with_open(
        polygons: &[&[[f64; 3]]],
        matrix: [[f64; 4]; 4],
        open: &[bool],
    ) -> Result<Projected> {
        if !open.is_empty() && open.len() != polygons.len() {
            return Err(invalid(&format!(
                "{} open flags for {} polygons",
                open.len(),
                polygons.len()
            )));
        }
        if matrix.iter().flatten().any(|v| !v.is_finite()) {
            return Err(invalid("the projection matrix is not finite"));
        }
        let project = |p: [f64; 3]| -> DVec4 {
            let r = |k: usize| {
                matrix[k][0] * p[0] + matrix[k][1] * p[1] + matrix[k][2] * p[2] + matrix[k][3]
            };
            DVec4::new(r(0), r(1), r(2), r(3))
        };
        let mut homogeneous: Vec<Vec<DVec4>> = Vec::with_capacity(polygons.len());
        for (i, poly) in polygons.iter().enumerate() {
            if poly.len() < 3 {
                return Err(invalid(&format!(
                    "polygon {i} has {} points; a polygon needs 3",
                    poly.len()
                )));
            }
            if let Some(j) = poly.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
                return Err(invalid(&format!(
                    "polygon {i}, point {j} is not finite: {:?}",
                    poly[j]
                )));
            }
            homogeneous.push(poly.iter().map(|p| project(*p)).collect());
        }
        let w_max = homogeneous
            .iter()
            .flatten()
            .map(|h| h.w)
            .fold(0.0f64, f64::max);
        let w_min = if w_max > 0.0 {
            w_max * 1e-9
        } else {
            f64::MIN_POSITIVE
        };
        // Clip to W >= w_min and divide.
        let mut sources: Vec<ProjectedSource> = Vec::with_capacity(polygons.len());
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (i, h) in homogeneous.iter().enumerate() {
            let mut edges = vec![true; h.len()];
            if open.get(i).copied().unwrap_or(false) {
                edges[h.len() - 1] = false;
            }
            let (points, original, clipped) = clip_in_front(h, &edges, w_min);
            let outline: Vec<DVec3> = points.iter().map(|p| p.truncate() / p.w).collect();
            for p in &outline {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
            sources.push(ProjectedSource {
                outline,
                original,
                clipped,
                ..ProjectedSource::default()
            });
        }
        let (centre, scale) = if lo.x.is_finite() {
            let extent = hi - lo;
            let s = |e: f64| {
                if e > 0.0 && (2.0 * PROJECTED_HALF / e).is_finite() {
                    2.0 * PROJECTED_HALF / e
                } else {
                    1.0
                }
            };
            (
                (lo + hi) / 2.0,
                DVec3::new(s(extent.x), s(extent.y), s(extent.z)),
            )
        } else {
            (DVec3::ZERO, DVec3::ONE)
        };
        let mut faces = Vec::new();
        for (i, src) in sources.iter_mut().enumerate() {
            for p in &mut src.outline {
                *p = (*p - centre) * scale;
            }
            src.first = faces.len();
            if src.outline.len() >= 3 {
                for points in convex_pieces(&src.outline) {
                    faces.push(ProjectedFace {
                        source: i as u32,
                        points,
                    });
                }
            }
            src.count = faces.len() - src.first;
        }
        let size = 2.0 * PROJECTED_HALF * 3f64.sqrt();
        Ok(Projected {
            centre,
            scale,
            eps: crate::precision::DEFAULT_CLIP_EPSILON * size,
            faces,
            sources,
            matrix,
            w_min,
        })
    }

    /// A normalized point in the projected 2-D coordinates.
    fn to_2d(&self, p: DVec3) -> [f64; 2] {
        [
            p.x / self.scale.x + self.centre.x,
            p.y / self.scale.y + self.centre.y,
        ]
    }

    /// The visible pieces of the polygons, back to front, from the NNS
    /// sort with face splitting. Pieces of one polygon that can be painted
    /// at the same moment are one [`Patch`] (no seam between them), and a
    /// polygon nothing cuts comes back whole, as given. Edge-on polygons
    /// are kept. Gives up with [`crate::Error::Cancelled`] on a stop request
    /// ([`crate::cancel`]).
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// // Two triangles piercing each other (each is above the other at one end):
    /// // neither can be painted whole first, so one is split.
    /// let a: Vec<[f64; 3]> = vec![[0., 0., -1.], [4., 0., 1.], [4., 2., 1.]];
    /// let b: Vec<[f64; 3]> = vec![[0., 2., 1.], [4., 1., -1.], [0., 0., 1.]];
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// let order = Projected::new(&[&a[..], &b[..]], m)?.paint_order()?;
    /// assert!(order.splits > 0 && order.patches.len() > 2, "{order:?}");
    /// # Ok(())
    /// # }
    /// ```
    pub fn paint_order(&self) -> Result<PaintOrder> {
        self.paint_order_by(None)
    }

    /// [`Projected::paint_order`], with the pieces of every source of one
    /// key (`keys[source]`) filled together where the order allows: for
    /// polygons of one opaque colour, so that fewer paths are drawn and
    /// no seam shows between them. Pieces of one key must not need to be
    /// told apart where they overlap (overlapping pieces of a patch are
    /// filled once).
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let a: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    /// let b: Vec<[f64; 3]> = vec![[2., 0., 0.], [3., 0., 0.], [3., 1., 0.], [2., 1., 0.]];
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// let seen = Projected::new(&[&a[..], &b[..]], m)?;
    /// assert_eq!(seen.paint_order_by(Some(&[0, 1]))?.patches.len(), 2);
    /// assert_eq!(seen.paint_order_by(Some(&[5, 5]))?.patches.len(), 1, "one key, one fill");
    /// assert!(seen.paint_order_by(Some(&[0])).is_err(), "one key per polygon");
    /// # Ok(())
    /// # }
    /// ```
    pub fn paint_order_by(&self, keys: Option<&[u32]>) -> Result<PaintOrder> {
        let sorted = self.sorted(keys)?;
        Ok(self.order_of(&sorted))
    }

    /// The patches of a sort, with its counts.
    fn order_of(&self, sorted: &Sorted) -> PaintOrder {
        PaintOrder {
            patches: sorted
                .groups
                .iter()
                .map(|members| self.patch(&sorted.pieces, members))
                .collect(),
            splits: sorted.splits,
            warning: sorted.warning.clone(),
        }
    }

    /// The NNS sort's pieces back to front, grouped into patches by
    /// `keys` (see [`Projected::paint_order_by`]).
    fn sorted(&self, keys: Option<&[u32]>) -> Result<Sorted> {
        use crate::visibility::nns;
        if let Some(k) = keys
            && k.len() != self.sources.len()
        {
            return Err(invalid(&format!(
                "{} keys for {} polygons",
                k.len(),
                self.sources.len()
            )));
        }
        let view = crate::geometry::view::View {
            projection: Matrix4::IDENTITY,
            eye: DVec4::new(0.0, 0.0, -1.0, 0.0),
            width: PROJECTED_SCREEN,
            height: PROJECTED_SCREEN,
            epsilon: self.eps,
            min_detail: 0.0,
            inverse: Some(Matrix4::IDENTITY),
        };
        let faces: Vec<nns::NnsFace> = self
            .faces
            .iter()
            .enumerate()
            .map(|(k, f)| nns::NnsFace {
                object: 0,
                polygon: k as u32,
                world: f.points.clone().into(),
            })
            .collect();
        let budget = crate::budget::Budgets::default().splits;
        let (sorted, stats) = nns::sort_budgeted(faces, &view, self.eps, budget);
        crate::cancel::check()?;
        let warning = (stats.fallbacks > 0).then(|| nns::fallback_warning(stats.splits, 1));
        let pieces: Vec<Piece> = sorted
            .into_iter()
            .map(|f| {
                let face = &self.faces[f.polygon as usize];
                // Every face given holds its points.
                let points = f.world.into_vec(&[], f.object, f.polygon);
                Piece {
                    source: face.source,
                    whole: points == face.points,
                    points,
                }
            })
            .collect();
        let key = |source: u32| keys.map_or(source, |k| k[source as usize]);
        let groups = group_pieces(&pieces, &key);
        Ok(Sorted {
            pieces,
            groups,
            splits: stats.splits,
            warning,
        })
    }

    /// The patch of pieces `members`: a source all of whose faces are
    /// among them, each whole, is given as its own outline.
    fn patch(&self, pieces: &[Piece], members: &[usize]) -> Patch {
        let mut count: rustc_hash::FxHashMap<u32, (usize, bool)> = rustc_hash::FxHashMap::default();
        for &k in members {
            let e = count.entry(pieces[k].source).or_insert((0, true));
            e.0 += 1;
            e.1 &= pieces[k].whole;
        }
        let whole = |source: u32| {
            let src = &self.sources[source as usize];
            let (n, all_whole) = count[&source];
            !src.clipped && n == src.count && all_whole
        };
        let mut rings = Vec::with_capacity(members.len());
        let mut done = rustc_hash::FxHashSet::default();
        for &k in members {
            let piece = &pieces[k];
            let source = piece.source as usize;
            let src = &self.sources[source];
            if whole(piece.source) {
                if done.insert(piece.source) {
                    rings.push(Ring {
                        source,
                        whole: true,
                        points: src.outline.iter().map(|p| self.to_2d(*p)).collect(),
                        edges: src.original.clone(),
                    });
                }
                continue;
            }
            let size = crate::geometry::polygon::extent(&src.outline).max(1e-300);
            let tol = 1e-9 * size;
            let n = src.outline.len();
            let on_edge = |a: DVec3, b: DVec3| {
                (0..n).any(|k| {
                    src.original[k] && {
                        let (p, q) = (src.outline[k], src.outline[(k + 1) % n]);
                        distance_to_segment(a, p, q) <= tol && distance_to_segment(b, p, q) <= tol
                    }
                })
            };
            let pts = &piece.points;
            let m = pts.len();
            rings.push(Ring {
                source,
                whole: false,
                points: pts.iter().map(|p| self.to_2d(*p)).collect(),
                edges: (0..m).map(|i| on_edge(pts[i], pts[(i + 1) % m])).collect(),
            });
        }
        Patch { rings }
    }

    /// The visible pieces of `segments` (3-D ends): where no polygon is
    /// nearer the eye. A segment lying on a polygon (to the tolerance of
    /// the sort) stays visible; a segment of zero length is a point, kept
    /// whole or dropped. Pieces come in the order of the segments, along
    /// each from its first end.
    ///
    /// ```
    /// use plytrace::api::Projected;
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let square: Vec<[f64; 3]> = vec![[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];
    /// let m = [[1., 0., 0., 0.], [0., 1., 0., 0.], [0., 0., -1., 0.], [0., 0., 0., 1.]];
    /// let seen = Projected::new(&[&square[..]], m)?;
    /// // Under the square from x = -1 to x = 3: only the ends outside it show.
    /// let pieces = seen.visible_segments(&[[[-1., 1., -1.], [3., 1., -1.]]])?;
    /// assert_eq!(pieces.len(), 2);
    /// assert!((pieces[0].points[1][0] - 0.).abs() < 1e-6 && (pieces[1].points[0][0] - 2.).abs() < 1e-6);
    /// # Ok(())
    /// # }
    /// ```
    pub fn visible_segments(&self, segments: &[[[f64; 3]; 2]]) -> Result<Vec<SegmentPiece>> {
        if let Some(i) = segments
            .iter()
            .position(|s| s.iter().flatten().any(|c| !c.is_finite()))
        {
            return Err(invalid(&format!(
                "segment {i} is not finite: {:?}",
                segments[i]
            )));
        }
        let occluders = Occluders::new(self.faces.iter().map(|f| (&f.points[..], 0)));
        let mut out = Vec::new();
        self.visible_parts(&occluders, segments, &mut |segment, a, b| {
            out.push(SegmentPiece {
                segment,
                points: [self.to_2d(a), self.to_2d(b)],
            })
        })?;
        Ok(out)
    }

    /// The parts of `segments` that no face of `occluders` hides, as
    /// normalized ends given to `part` with the segment's index, in the
    /// order of the segments and along each from its first end.
    fn visible_parts(
        &self,
        occluders: &Occluders,
        segments: &[[[f64; 3]; 2]],
        part: &mut dyn FnMut(usize, DVec3, DVec3),
    ) -> Result<()> {
        let mut stamp = vec![0u32; occluders.faces.len()];
        let mut hidden: Vec<(f64, f64, u32)> = Vec::new();
        for (i, seg) in segments.iter().enumerate() {
            if i % 4096 == 0 {
                crate::cancel::check()?;
            }
            let Some((a, b)) = self.normalized_segment(seg) else {
                continue;
            };
            hidden.clear();
            let epoch = (i as u32).wrapping_add(1);
            occluders.hiding(a, b, self.eps, epoch, &mut stamp, &mut hidden);
            if a.truncate() == b.truncate() {
                if hidden.is_empty() {
                    part(i, a, b);
                }
                continue;
            }
            hidden.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut t = 0.0;
            for &(h0, h1, _) in hidden.iter() {
                if h0 > t {
                    sub_segment(a, b, t, h0, &mut |p, q| part(i, p, q));
                }
                t = t.max(h1);
            }
            sub_segment(a, b, t, 1.0, &mut |p, q| part(i, p, q));
        }
        Ok(())
    }

    /// `p` through the matrix, normalized; `None` behind the eye.
    fn normalized_point(&self, p: [f64; 3]) -> Option<DVec3> {
        let h = self.homogeneous(p);
        (h.w >= self.w_min).then(|| (h.truncate() / h.w - self.centre) * self.scale)
    }

    fn homogeneous(&self, p: [f64; 3]) -> DVec4 {
        let r = |k: usize| {
            self.matrix[k][0] * p[0]
                + self.matrix[k][1] * p[1]
                + self.matrix[k][2] * p[2]
                + self.matrix[k][3]
        };
        DVec4::new(r(0), r(1), r(2), r(3))
    }

    /// `seg` through the matrix, clipped to `W >= w_min`, normalized;
    /// `None` when it lies wholly behind the eye.
    fn normalized_segment(&self, seg: &[[f64; 3]; 2]) -> Option<(DVec3, DVec3)> {
        let (mut a, mut b) = (self.homogeneous(seg[0]), self.homogeneous(seg[1]));
        let (ina, inb) = (a.w >= self.w_min, b.w >= self.w_min);
        match (ina, inb) {
            (false, false) => return None,
            (true, false) => b = a + (b - a) * ((a.w - self.w_min) / (a.w - b.w)),
            (false, true) => a = b + (a - b) * ((b.w - self.w_min) / (b.w - a.w)),
            (true, true) => {}
        }
        let norm = |h: DVec4| (h.truncate() / h.w - self.centre) * self.scale;
        Some((norm(a), norm(b)))
    }
}

/// The part of `a`-`b` from `t0` to `t1` given to `part`, unless it is
/// shorter than rounding (a stroke's cap would show it as a dot). The
/// ends themselves at 0 and 1, so that the pieces of a polyline meet
/// exactly.
fn sub_segment(a: DVec3, b: DVec3, t0: f64, t1: f64, part: &mut dyn FnMut(DVec3, DVec3)) {
    let shortest = 1e-9 / (b - a).truncate().length().max(1e-300);
    if t1 - t0 <= shortest {
        return;
    }
    let at = |t: f64| match t {
        0.0 => a,
        1.0 => b,
        _ => a + (b - a) * t,
    };
    part(at(t0), at(t1));
}

/// `h` clipped to `W >= w_min` (Sutherland-Hodgman), with per edge of
/// the result whether it is part of an edge of `h` that `edges` marks
/// (edge `k` from point `k` to `k + 1`; the cut is none), and whether
/// anything was cut.
fn clip_in_front(h: &[DVec4], edges: &[bool], w_min: f64) -> (Vec<DVec4>, Vec<bool>, bool) {
    if h.iter().all(|p| p.w >= w_min) {
        return (h.to_vec(), edges.to_vec(), false);
    }
    let n = h.len();
    let mut out = Vec::with_capacity(n + 2);
    let mut original = Vec::with_capacity(n + 2);
    for k in 0..n {
        let (p, q) = (h[k], h[(k + 1) % n]);
        let (pin, qin) = (p.w >= w_min, q.w >= w_min);
        if pin {
            out.push(p);
            original.push(edges[k]);
        }
        if pin != qin {
            let t = (p.w - w_min) / (p.w - q.w);
            out.push(p + (q - p) * t);
            // Leaving: the edge from here runs along the cut.
            original.push((!pin || qin) && edges[k]);
        }
    }
    (out, original, true)
}

/// `outline` (normalized, three or more points) as convex planar faces:
/// itself when it is one; a fan of triangles from its first vertex when
/// it is not planar; else (planar, not convex) triangles by ear clipping.
fn convex_pieces(outline: &[DVec3]) -> Vec<Vec<DVec3>> {
    use crate::geometry::polygon;
    if outline.len() == 3 {
        return vec![outline.to_vec()];
    }
    let normal = polygon::newell_vector(outline.iter().copied());
    let Some(unit) = normal.try_normalize() else {
        // No area: seen edge-on or degenerate; the sort passes it through.
        return vec![outline.to_vec()];
    };
    let c = outline.iter().copied().sum::<DVec3>() / outline.len() as f64;
    let size = polygon::extent(outline);
    let planar = outline
        .iter()
        .all(|p| unit.dot(*p - c).abs() <= 1e-9 * size);
    if !planar {
        // A fan of flat triangles from the first vertex.
        return (1..outline.len() - 1)
            .map(|k| vec![outline[0], outline[k], outline[k + 1]])
            .collect();
    }
    if polygon::is_convex(outline) {
        return vec![outline.to_vec()];
    }
    polygon::triangulate(outline)
        .into_iter()
        .map(|t| t.to_vec())
        .collect()
}

/// The pieces of an NNS sort back to front, and the patches they are
/// painted in (indices into `pieces`, in painting order).
struct Sorted {
    pieces: Vec<Piece>,
    groups: Vec<Vec<usize>>,
    splits: usize,
    warning: Option<String>,
}

/// A piece of a face from the NNS sort.
struct Piece {
    source: u32,
    /// The face as given (not split).
    whole: bool,
    points: Vec<DVec3>,
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
fn group_pieces(pieces: &[Piece], key: &dyn Fn(u32) -> u32) -> Vec<Vec<usize>> {
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
struct Screen {
    flat: Vec<glam::DVec2>,
    starts: Vec<usize>,
    bounds: Vec<(glam::DVec2, glam::DVec2)>,
    areas: Vec<f64>,
}

impl Screen {
    fn new(pieces: &[Piece]) -> Screen {
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

    fn outline(&self, k: usize) -> &[glam::DVec2] {
        &self.flat[self.starts[k]..self.starts[k + 1]]
    }

    /// Whether convex pieces `a` and `b` share more than a boundary on
    /// the screen: no edge of either separates them (the separating axis
    /// theorem), to within a width whose overlap could not reach an area
    /// of 1e-12.
    fn overlap(&self, a: usize, b: usize) -> bool {
        boxes_overlap(self.bounds[a], self.bounds[b])
            && !separates_by(self.outline(a), self.areas[a], self.outline(b))
            && !separates_by(self.outline(b), self.areas[b], self.outline(a))
    }
}

fn bounds2(pts: &[glam::DVec2]) -> (glam::DVec2, glam::DVec2) {
    use glam::DVec2;
    pts.iter()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        })
}

fn boxes_overlap(a: (glam::DVec2, glam::DVec2), b: (glam::DVec2, glam::DVec2)) -> bool {
    a.1.x > b.0.x && b.1.x > a.0.x && a.1.y > b.0.y && b.1.y > a.0.y
}

/// Twice the signed area of a polygon (positive counter-clockwise).
fn twice_area(a: &[glam::DVec2]) -> f64 {
    let n = a.len();
    (0..n).map(|i| a[i].perp_dot(a[(i + 1) % n])).sum()
}

/// Whether an edge of convex `a` (of `twice_area`) has all of `b` on
/// its outer side or on it (or `a` has no area).
fn separates_by(a: &[glam::DVec2], twice_area: f64, b: &[glam::DVec2]) -> bool {
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

/// The faces that may hide segments, by screen cell, each with a tag.
struct Occluders {
    /// Screen outline (counter-clockwise), plane `z = a x + b y + c`.
    faces: Vec<(Vec<glam::DVec2>, [f64; 3])>,
    tags: Vec<u32>,
    cells: Vec<Vec<u32>>,
    n: usize,
}

impl Occluders {
    /// The faces (convex, normalized) with their tags; edge-on ones hide
    /// nothing and are left out.
    fn new<'a>(faces: impl Iterator<Item = (&'a [DVec3], u32)>) -> Occluders {
        use glam::DVec2;
        let mut list = Vec::new();
        let mut tags = Vec::new();
        for (points, tag) in faces {
            let Some(unit) =
                crate::geometry::polygon::newell_vector(points.iter().copied()).try_normalize()
            else {
                continue;
            };
            if unit.z.abs() < 1e-9 {
                continue; // edge-on
            }
            let c = points[0];
            // unit . (p - c) = 0  =>  z = c.z - (ux (x - cx) + uy (y - cy)) / uz
            let (a, b) = (-unit.x / unit.z, -unit.y / unit.z);
            let plane = [a, b, c.z - a * c.x - b * c.y];
            let mut pts: Vec<DVec2> = points.iter().map(|p| p.truncate()).collect();
            if unit.z > 0.0 {
                // Newell z > 0: counter-clockwise already.
            } else {
                pts.reverse();
            }
            list.push((pts, plane));
            tags.push(tag);
        }
        let n = ((list.len() as f64 / 2.0).sqrt() as usize).clamp(1, 512);
        let mut cells = vec![Vec::new(); n * n];
        let cell = |v: f64| (((v + 1.0) / 2.0 * n as f64).floor().max(0.0) as usize).min(n - 1);
        for (k, (pts, _)) in list.iter().enumerate() {
            let (lo, hi) = pts
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                });
            for y in cell(lo.y)..=cell(hi.y) {
                for x in cell(lo.x)..=cell(hi.x) {
                    cells[y * n + x].push(k as u32);
                }
            }
        }
        Occluders {
            faces: list,
            tags,
            cells,
            n,
        }
    }

    /// Appends the parameter intervals of segment `a`-`b` (normalized)
    /// that faces hide, each with the face's tag: inside a face's
    /// outline and farther than its plane by more than `eps`.
    fn hiding(
        &self,
        a: DVec3,
        b: DVec3,
        eps: f64,
        epoch: u32,
        stamp: &mut [u32],
        hidden: &mut Vec<(f64, f64, u32)>,
    ) {
        let n = self.n;
        let cell = |v: f64| (((v + 1.0) / 2.0 * n as f64).floor().max(0.0) as usize).min(n - 1);
        let (lo, hi) = (a.min(b), a.max(b));
        if hi.x < -1.0 || lo.x > 1.0 || hi.y < -1.0 || lo.y > 1.0 {
            return;
        }
        let d = b - a;
        for y in cell(lo.y)..=cell(hi.y) {
            for x in cell(lo.x)..=cell(hi.x) {
                // Only the cells the segment's line passes near.
                let (cx0, cy0) = (
                    x as f64 / n as f64 * 2.0 - 1.0,
                    y as f64 / n as f64 * 2.0 - 1.0,
                );
                let w = 2.0 / n as f64;
                let corners = [
                    (cx0, cy0),
                    (cx0 + w, cy0),
                    (cx0, cy0 + w),
                    (cx0 + w, cy0 + w),
                ];
                let side = |(px, py): (f64, f64)| d.x * (py - a.y) - d.y * (px - a.x);
                let s: Vec<f64> = corners.iter().map(|c| side(*c)).collect();
                if s.iter().all(|v| *v > 0.0) || s.iter().all(|v| *v < 0.0) {
                    continue;
                }
                for &k in &self.cells[y * n + x] {
                    let k = k as usize;
                    if stamp[k] == epoch {
                        continue;
                    }
                    stamp[k] = epoch;
                    let (pts, [pa, pb, pc]) = &self.faces[k];
                    // Inside the outline, or on it to rounding (so that
                    // adjacent faces leave no gap between them).
                    let (mut t0, mut t1) = (0.0f64, 1.0f64);
                    let m = pts.len();
                    let mut empty = false;
                    for i in 0..m {
                        let (e0, e1) = (pts[i], pts[(i + 1) % m]);
                        let e = e1 - e0;
                        let tol = 1e-9 * e.length();
                        let f0 = e.perp_dot(a.truncate() - e0) + tol;
                        let f1 = e.perp_dot(b.truncate() - e0) + tol;
                        if !clip_interval(f0, f1, &mut t0, &mut t1) {
                            empty = true;
                            break;
                        }
                    }
                    if empty {
                        continue;
                    }
                    // Behind the plane by more than eps.
                    let g = |p: DVec3| p.z - (pa * p.x + pb * p.y + pc) - eps;
                    if !clip_interval(g(a), g(b), &mut t0, &mut t1) {
                        continue;
                    }
                    if a.truncate() == b.truncate() || t1 > t0 {
                        hidden.push((t0, t1, self.tags[k]));
                    }
                }
            }
        }
    }
}

/// Narrows `[t0, t1]` to where `f0 + t (f1 - f0) > 0`; false if nothing
/// is left.
fn clip_interval(f0: f64, f1: f64, t0: &mut f64, t1: &mut f64) -> bool {
    if f0 <= 0.0 && f1 <= 0.0 {
        return false;
    }
    if f0 > 0.0 && f1 > 0.0 {
        return *t0 <= *t1;
    }
    let t = f0 / (f0 - f1);
    if f0 > 0.0 {
        *t1 = t1.min(t);
    } else {
        *t0 = t0.max(t);
    }
    *t0 <= *t1
}

fn distance_to_segment(x: DVec3, p: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((x - p).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x - (p + d * t)).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// matplotlib's perspective (`Axes3D.get_proj()` at its default
    /// view of the unit cube), rows of `M @ p`.
    const MPL: [[f64; 4]; 4] = [
        [1.031, 0.5952, 0.0, -0.8131],
        [-0.2976, 0.5155, 0.7732, -0.4956],
        [0.0, 0.0, 0.0, -10.0],
        [-0.5155, 0.8929, -0.4464, 10.0345],
    ];

    fn project(p: [f64; 3]) -> [f64; 3] {
        let r = |k: usize| MPL[k][0] * p[0] + MPL[k][1] * p[1] + MPL[k][2] * p[2] + MPL[k][3];
        let w = r(3);
        [r(0) / w, r(1) / w, r(2) / w]
    }

    /// Two wavy grids of `n` x `n` quads (not planar) crossing each other.
    fn crossing_surfaces(n: usize) -> Vec<Vec<[f64; 3]>> {
        let mut polys = Vec::new();
        for s in 0..2 {
            let f = |x: f64, y: f64| {
                let wave = 0.15 * (6.0 * x).sin() * (5.0 * y).cos();
                if s == 0 {
                    0.5 + wave
                } else {
                    0.2 + 0.6 * x - wave
                }
            };
            for i in 0..n {
                for j in 0..n {
                    let (x0, x1) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
                    let (y0, y1) = (j as f64 / n as f64, (j + 1) as f64 / n as f64);
                    polys.push(vec![
                        [x0, y0, f(x0, y0)],
                        [x1, y0, f(x1, y0)],
                        [x1, y1, f(x1, y1)],
                        [x0, y1, f(x0, y1)],
                    ]);
                }
            }
        }
        polys
    }

    fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
        let mut c = false;
        let n = poly.len();
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            if (a[1] > p[1]) != (b[1] > p[1])
                && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
            {
                c = !c;
            }
        }
        c
    }

    #[test]
    fn painting_the_pieces_shows_the_nearest_surface_everywhere() {
        let polys = crossing_surfaces(12);
        let refs: Vec<&[[f64; 3]]> = polys.iter().map(|p| &p[..]).collect();
        let order = Projected::new(&refs, MPL).unwrap().paint_order().unwrap();
        assert!(order.splits > 0 && order.warning.is_none());
        // The oracle: the nearest of the quads' triangles (the diagonal
        // from the first corner, as the screen's ear clipping cuts these
        // convex outlines) at each sample.
        let tris: Vec<(usize, [[f64; 3]; 3])> = polys
            .iter()
            .enumerate()
            .flat_map(|(k, q)| {
                let q: Vec<[f64; 3]> = q.iter().map(|p| project(*p)).collect();
                [(k, [q[0], q[1], q[2]]), (k, [q[0], q[2], q[3]])]
            })
            .collect();
        let depth = |p: [f64; 2], t: &[[f64; 3]; 3]| {
            let (a, b, c) = (t[0], t[1], t[2]);
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            let u = ((p[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[1] - a[1])) / det;
            let v = ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) / det;
            (u >= 0.0 && v >= 0.0 && u + v <= 1.0)
                .then(|| a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]))
        };
        // Pieces of one surface filled together where the order allows:
        // the same picture in fewer patches.
        let keys: Vec<u32> = (0..polys.len()).map(|k| (k / 144) as u32).collect();
        let merged = Projected::new(&refs, MPL)
            .unwrap()
            .paint_order_by(Some(&keys))
            .unwrap();
        assert!(
            merged.patches.len() * 4 < order.patches.len(),
            "{} patches",
            merged.patches.len()
        );
        for order in [order, merged] {
            let (mut checked, mut wrong) = (0, 0);
            for i in 0..150 {
                for j in 0..150 {
                    let p = [
                        -0.09 + 0.18 * i as f64 / 150.0,
                        -0.07 + 0.14 * j as f64 / 150.0,
                    ];
                    let mut hits: Vec<(f64, usize)> = tris
                        .iter()
                        .filter_map(|(k, t)| depth(p, t).map(|z| (z, *k)))
                        .collect();
                    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let Some(&(z, want)) = hits.first() else {
                        continue;
                    };
                    // Not where two surfaces meet (within rounding of depth).
                    if hits
                        .iter()
                        .any(|h| h.1 / 144 != want / 144 && h.0 - z < 1e-6)
                    {
                        continue;
                    }
                    let painted = order
                        .patches
                        .iter()
                        .rev()
                        .find_map(|patch| patch.rings.iter().find(|r| inside(p, &r.points)));
                    checked += 1;
                    if painted.map(|ring| ring.source / 144) != Some(want / 144) {
                        wrong += 1;
                    }
                }
            }
            assert!(checked > 5000, "{checked}");
            assert!(
                wrong * 1000 <= checked,
                "{wrong} of {checked} samples show the far surface"
            );
        }
    }

    #[test]
    fn unsplit_polygons_come_back_whole() {
        let polys = crossing_surfaces(6);
        let refs: Vec<&[[f64; 3]]> = polys.iter().map(|p| &p[..]).collect();
        let order = Projected::new(&refs[..36], MPL)
            .unwrap()
            .paint_order()
            .unwrap();
        // One surface alone: every quad (two triangles each) whole, once.
        assert_eq!(order.patches.len(), 36);
        let mut seen: Vec<usize> = order.patches.iter().map(|p| p.source()).collect();
        seen.sort();
        assert_eq!(seen, (0..36).collect::<Vec<_>>());
        for p in &order.patches {
            assert!(p.rings.len() == 1 && p.rings[0].whole && p.rings[0].points.len() == 4);
            let q = project(polys[p.source()][0]);
            assert!((p.rings[0].points[0][0] - q[0]).abs() < 1e-12);
        }
        // One key for all: the surface does not fold over itself here,
        // so one patch holds every quad, whole.
        let one = Projected::new(&refs[..36], MPL)
            .unwrap()
            .paint_order_by(Some(&[0; 36]))
            .unwrap();
        assert_eq!(one.patches.len(), 1);
        assert_eq!(one.patches[0].rings.len(), 36);
        assert!(one.patches[0].rings.iter().all(|r| r.whole));
    }

    #[test]
    fn segments_are_cut_where_a_polygon_hides_them() {
        // A square at depth 0 and a segment piercing it from behind
        // (depth 1 at the left) to in front (depth -1 at the right).
        let m = [
            [1., 0., 0., 0.],
            [0., 1., 0., 0.],
            [0., 0., 1., 0.],
            [0., 0., 0., 1.],
        ];
        let square: Vec<[f64; 3]> =
            vec![[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]];
        let seen = Projected::new(&[&square[..]], m).unwrap();
        let pieces = seen
            .visible_segments(&[[[-2., 0., 1.], [2., 0., -1.]]])
            .unwrap();
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        let x: Vec<[f64; 2]> = pieces
            .iter()
            .map(|p| [p.points[0][0], p.points[1][0]])
            .collect();
        assert!(
            (x[0][0] + 2.0).abs() < 1e-9 && (x[0][1] + 1.0).abs() < 1e-6,
            "{x:?}"
        );
        assert!(
            x[1][0].abs() < 1e-5 && (x[1][1] - 2.0).abs() < 1e-9,
            "{x:?}"
        );
        // A segment on the square stays; a point behind it goes.
        let on = seen
            .visible_segments(&[[[-0.5, 0.5, 0.], [0.5, 0.5, 0.]]])
            .unwrap();
        assert_eq!(on.len(), 1);
        let behind = seen
            .visible_segments(&[[[0.2, 0.2, 0.5], [0.2, 0.2, 0.5]]])
            .unwrap();
        assert!(behind.is_empty());
        let front = seen
            .visible_segments(&[[[0.2, 0.2, -0.5], [0.2, 0.2, -0.5]]])
            .unwrap();
        assert_eq!(front.len(), 1);
    }

    #[test]
    fn projected_input_is_checked_and_clipped_in_front_of_the_eye() {
        let m = [
            [1., 0., 0., 0.],
            [0., 1., 0., 0.],
            [0., 0., 1., 0.],
            [0., 0., 0., 1.],
        ];
        let nan: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., f64::NAN, 0.], [1., 1., 0.]];
        let e = Projected::new(&[&nan[..]], m).unwrap_err().to_string();
        assert!(e.contains("polygon 0, point 1 is not finite"), "{e}");
        let two: Vec<[f64; 3]> = vec![[0., 0., 0.], [1., 0., 0.]];
        let e = Projected::new(&[&two[..]], m).unwrap_err().to_string();
        assert!(e.contains("polygon 0 has 2 points"), "{e}");
        let mut bad = m;
        bad[1][2] = f64::INFINITY;
        assert!(Projected::new(&[], bad).is_err());
        assert!(
            Projected::new(&[], m)
                .unwrap()
                .paint_order()
                .unwrap()
                .patches
                .is_empty()
        );
        // W = 1 + z: the part of a quad at z <= -1 is behind the eye.
        let persp = [
            [1., 0., 0., 0.],
            [0., 1., 0., 0.],
            [0., 0., 1., 0.],
            [0., 0., 1., 1.],
        ];
        let through: Vec<[f64; 3]> =
            vec![[-1., 0., -2.], [1., 0., -2.], [1., 1., 1.], [-1., 1., 1.]];
        let order = Projected::new(&[&through[..]], persp)
            .unwrap()
            .paint_order()
            .unwrap();
        assert_eq!(order.patches.len(), 1);
        assert!(!order.patches[0].rings[0].whole);
        assert!(
            order.patches[0]
                .rings
                .iter()
                .flat_map(|r| &r.points)
                .all(|p| p.iter().all(|v| v.is_finite()))
        );
    }
}

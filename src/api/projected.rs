//! [`Projected`]: 3-D polygons and segments seen through another
//! program's 4 x 4 projection matrix, their visible pieces from the NNS
//! sort (Donovan 1973, 000 sections 3-4), for the matplotlib bridge of
//! the Python package.

use glam::{DVec3, DVec4};

use super::invalid;
use crate::error::Result;
use crate::math::Matrix4;

mod grouping;
mod layers;
mod outline;
mod segments;
#[cfg(test)]
mod tests;

use grouping::{Piece, Sorted, group_pieces};
pub use layers::{Layered, PlacedSegment};
use outline::{checked_homogeneous, clipped_sources, convex_faces, normalization};
pub use segments::SegmentPiece;
use segments::distance_to_segment;

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
        let homogeneous = checked_homogeneous(polygons, &matrix)?;
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
        let (mut sources, lo, hi) = clipped_sources(&homogeneous, open, w_min);
        let (centre, scale) = normalization(lo, hi);
        let faces = convex_faces(&mut sources, centre, scale);
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
}

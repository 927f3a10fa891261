//! The matplotlib bridge's one call per draw: the polygons' paint order
//! with the places in it of the lines' visible parts and of the points
//! (markers, labels), as arrays (`plytrace::api::Projected::layered`).

use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use plytrace::api::{Layered, PaintOrder};

use crate::{LINETO, MOVETO, PaintArrays, Paths};

/// The line runs as arrays: xy, line, slot, starts.
type RunArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
);

/// What `Projection.layered` returns: the paint arrays, the line runs
/// and the points' slots.
pub(crate) type LayeredArrays<'py> = (PaintArrays<'py>, RunArrays<'py>, Bound<'py, PyAny>);

/// Segments (pairs of 3-D ends), and the first segment of each polyline.
type Segments = (Vec<[[f64; 3]; 2]>, Vec<usize>);

/// The segments of polylines given as points one after the other and
/// the points of each, with the first segment of each polyline.
pub(crate) fn polyline_segments(points: &[[f64; 3]], sizes: &[i64]) -> PyResult<Segments> {
    let mut segments = Vec::with_capacity(points.len());
    let mut first = Vec::with_capacity(sizes.len());
    let mut at = 0usize;
    for &n in sizes {
        let n = usize::try_from(n).map_err(|_| PyValueError::new_err("negative size"))?;
        if at + n > points.len() {
            return Err(PyValueError::new_err("polyline sizes exceed the points"));
        }
        first.push(segments.len());
        for k in at..(at + n).saturating_sub(1) {
            segments.push([points[k], points[k + 1]]);
        }
        at += n;
    }
    if at != points.len() {
        return Err(PyValueError::new_err(
            "polyline sizes do not add up to the points",
        ));
    }
    Ok((segments, first))
}

/// The arrays of a layered draw.
pub(crate) fn arrays<'py>(
    py: Python<'py>,
    layered: &Layered,
    grow: Option<(f64, f64)>,
    grown: Option<&[bool]>,
    first_segment: &[usize],
) -> PyResult<LayeredArrays<'py>> {
    let paint = paint_arrays(py, &layered.order, grow, grown)?;
    let runs = line_runs(py, layered, first_segment)?;
    let slots: Vec<i64> = layered
        .points
        .iter()
        .map(|s| s.map_or(-1, |k| k as i64))
        .collect();
    Ok((paint, runs, PyArray1::from_vec(py, slots).into_any()))
}

/// The patches as paths: see `Projection.paint_order`. A whole ring of
/// an open polygon is an open path (filled as if closed, its closing
/// edge not stroked).
fn paint_arrays<'py>(
    py: Python<'py>,
    order: &PaintOrder,
    grow: Option<(f64, f64)>,
    grown: Option<&[bool]>,
) -> PyResult<PaintArrays<'py>> {
    let (mut fills, mut edges) = (Paths::default(), Paths::default());
    let mut sources = Vec::with_capacity(order.patches.len());
    let mut whole = Vec::with_capacity(order.patches.len());
    for patch in &order.patches {
        sources.push(patch.source() as i64);
        whole.push(patch.rings.iter().all(|r| r.whole));
        fills.start();
        edges.start();
        for ring in &patch.rings {
            let grows = grow.filter(|_| grown.is_none_or(|g| g.get(ring.source) == Some(&true)));
            match grows {
                Some(g) => fills.grown_ring(&ring.points, g),
                None if ring.whole && ring.edges.iter().any(|e| !*e) => {
                    fills.open_ring(&ring.points)
                }
                None => fills.ring(&ring.points),
            }
            if !ring.whole {
                edges.edges(&ring.points, &ring.edges);
            }
        }
    }
    Ok((
        PyArray1::from_vec(py, sources).into_any(),
        PyArray1::from_vec(py, whole).into_any(),
        fills.finish(py)?,
        edges.finish(py)?,
        order.splits,
        order.warning.clone(),
    ))
}

impl Paths {
    /// `ring` as an open subpath, in its own order.
    fn open_ring(&mut self, ring: &[[f64; 2]]) {
        for (k, p) in ring.iter().enumerate() {
            self.push(*p, if k == 0 { MOVETO } else { LINETO });
        }
    }
}

/// The placed parts of the polylines in runs: consecutive parts of one
/// polyline with one place, as rows of xy with NaN rows where parts do
/// not join. Returns (xy (k, 2), line (r,), slot (r,), starts (r + 1,)).
fn line_runs<'py>(
    py: Python<'py>,
    layered: &Layered,
    first_segment: &[usize],
) -> PyResult<RunArrays<'py>> {
    let mut xy: Vec<f64> = Vec::new();
    let (mut lines, mut slots, mut starts) = (Vec::new(), Vec::new(), Vec::new());
    let mut last: Option<(usize, usize, [f64; 2])> = None;
    for part in &layered.segments {
        // The polyline of the segment: the last whose first segment is
        // at or before it.
        let line = first_segment.partition_point(|&f| f <= part.segment) - 1;
        let [a, b] = part.points;
        match last {
            Some((l, s, end)) if l == line && s == part.before => {
                if end != a {
                    xy.extend_from_slice(&[f64::NAN, f64::NAN]);
                    xy.extend_from_slice(&a);
                }
            }
            _ => {
                starts.push((xy.len() / 2) as i64);
                lines.push(line as i64);
                slots.push(part.before as i64);
                xy.extend_from_slice(&a);
            }
        }
        xy.extend_from_slice(&b);
        last = Some((line, part.before, b));
    }
    starts.push((xy.len() / 2) as i64);
    let k = xy.len() / 2;
    let xy =
        Array2::from_shape_vec((k, 2), xy).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((
        PyArray2::from_owned_array(py, xy).into_any(),
        PyArray1::from_vec(py, lines).into_any(),
        PyArray1::from_vec(py, slots).into_any(),
        PyArray1::from_vec(py, starts).into_any(),
    ))
}

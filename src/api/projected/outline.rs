//! From the polygons given to the convex faces the sort takes: the
//! projection (checked), the clip in front of the eye, the normalization
//! into the unit cube and the cut into convex planar faces.

use glam::{DVec3, DVec4};

use super::{PROJECTED_HALF, ProjectedFace, ProjectedSource, invalid};
use crate::error::Result;

/// `polygons` through `matrix` (homogeneous), refusing polygons of fewer
/// than three points and points that are not finite.
pub(super) fn checked_homogeneous(
    polygons: &[&[[f64; 3]]],
    matrix: &[[f64; 4]; 4],
) -> Result<Vec<Vec<DVec4>>> {
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
    Ok(homogeneous)
}

/// The polygons clipped to `W >= w_min` and divided (not yet
/// normalized), with the least and greatest corner of their points.
pub(super) fn clipped_sources(
    homogeneous: &[Vec<DVec4>],
    open: &[bool],
    w_min: f64,
) -> (Vec<ProjectedSource>, DVec3, DVec3) {
    let mut sources: Vec<ProjectedSource> = Vec::with_capacity(homogeneous.len());
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
    (sources, lo, hi)
}

/// The centre and per-axis scale that put the box `lo`..`hi` inside
/// the unit cube (`PROJECTED_HALF` of it).
pub(super) fn normalization(lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
    if !lo.x.is_finite() {
        return (DVec3::ZERO, DVec3::ONE);
    }
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
}

/// Normalizes the sources' outlines and cuts each into its convex
/// faces (recording which faces are whose).
pub(super) fn convex_faces(
    sources: &mut [ProjectedSource],
    centre: DVec3,
    scale: DVec3,
) -> Vec<ProjectedFace> {
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
    faces
}

/// `h` clipped to `W >= w_min` (Sutherland-Hodgman), with per edge of
/// the result whether it is part of an edge of `h` that `edges` marks
/// (edge `k` from point `k` to `k + 1`; the cut is none), and whether
/// anything was cut.
pub(super) fn clip_in_front(
    h: &[DVec4],
    edges: &[bool],
    w_min: f64,
) -> (Vec<DVec4>, Vec<bool>, bool) {
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
pub(super) fn convex_pieces(outline: &[DVec3]) -> Vec<Vec<DVec3>> {
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

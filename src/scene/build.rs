//! An object placed in the world at `endobj` (Garcia 1986, 004 section
//! 4.3: "a data structure is created containing the object's
//! three-dimensional bounding-box description, an array of points ... and
//! a list of all polygons"): its vertices transformed by the CTM, each
//! polygon's plane, degenerate polygons skipped and non-planar ones split,
//! with warnings.

use std::sync::Arc;

use glam::{DVec3, DVec4};

use crate::error::{MAX_SHOWN_TOKEN, printable};
use crate::geometry::polygon::{self, PolygonDefect};
use crate::math::Matrix4;
use crate::model::{ColorEntry, IndexList, Mesh};
use crate::model::{Object, Polygon, Surface, SurfaceType};

/// What `endobj` needs to build an [`Object`].
pub struct ObjectParts {
    /// Object number.
    pub number: u32,
    /// Name.
    pub name: String,
    /// Geometry in object coordinates.
    pub mesh: Arc<Mesh>,
    /// Polygon colours.
    pub polygon_colors: Option<Arc<Vec<ColorEntry>>>,
    /// Vertex colours.
    pub vertex_colors: Option<Arc<Vec<ColorEntry>>>,
    /// Object to world.
    pub transform: Matrix4,
    /// Surface attributes.
    pub surface: Surface,
    /// Type attributes.
    pub surface_type: SurfaceType,
}

/// Transforms an object to world coordinates and computes its planes
/// (004 section 4.3). Degenerate polygons (fewer than three distinct
/// vertices, zero area) are skipped and non-planar ones split into a
/// triangle fan, each with a warning through `warn`. A transform with a
/// negative determinant (a mirror image) reverses the vertex order so that
/// polygons stay clockwise from outside. Fails on non-finite coordinates.
pub fn build_object(parts: ObjectParts, warn: &mut dyn FnMut(String)) -> Result<Object, String> {
    let ObjectParts {
        number,
        name,
        mesh,
        polygon_colors,
        vertex_colors,
        transform,
        surface,
        surface_type,
    } = parts;
    let vertices: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|v| transform.transform_point(*v))
        .collect();
    // The name as messages show it.
    let shown = printable(&name, MAX_SHOWN_TOKEN);
    if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
        return Err(format!(
            "object `{shown}`: vertex {} is not finite after transformation by the CTM (a projection is still on the CTM, or a number overflowed; scenes usually `pushmatrix` and `ident` before defining objects)",
            i + 1
        ));
    }
    let mirrored = transform.linear_determinant() < 0.0;
    let oriented = orient(&mesh, &vertices, mirrored);
    let (polygons, source_polygon) = planes(oriented, &vertices, &shown, warn)?;
    let vertex_normals = surface_type.curved.then(|| {
        let faces: Vec<(Vec<u32>, DVec3)> = polygons
            .iter()
            .map(|p| (p.indices.to_vec(), p.normal()))
            .collect();
        polygon::vertex_normals(vertices.len(), &faces)
    });
    let bbox_corners = bbox_corners(&mesh, &transform);
    Ok(Object {
        number,
        name,
        mesh,
        polygon_colors,
        vertex_colors,
        transform,
        vertices,
        polygons,
        source_polygon,
        vertex_normals,
        bbox_corners,
        surface,
        surface_type,
    })
}

/// A polygon's vertex list (reversed when mirrored) and its plane or
/// defect; `None` when an index is beyond the vertices.
type Oriented = Option<(IndexList, std::result::Result<DVec4, PolygonDefect>)>;

/// Each polygon of `mesh` oriented and its plane computed, in parallel (a
/// pure function of the polygon).
fn orient(mesh: &Mesh, vertices: &[DVec3], mirrored: bool) -> Vec<Oriented> {
    use rayon::prelude::*;
    mesh.polygons
        .par_iter()
        .with_min_len(1024)
        .map_init(Vec::new, |points: &mut Vec<DVec3>, indices| {
            points.clear();
            for &i in indices {
                points.push(*vertices.get(i as usize)?);
            }
            let mut indices = IndexList::from(indices.as_slice());
            if mirrored {
                points.reverse();
                indices.reverse();
            }
            Some((indices, polygon::outward_plane(points)))
        })
        .collect()
}

/// The polygons kept, in order, with the index of the mesh polygon each
/// came from; a warning for each defect. Fails on a vertex index beyond
/// the vertices.
fn planes(
    oriented: Vec<Oriented>,
    vertices: &[DVec3],
    shown: &str,
    warn: &mut dyn FnMut(String),
) -> Result<(Vec<Polygon>, Vec<u32>), String> {
    let mut polygons = Vec::with_capacity(oriented.len());
    let mut source_polygon = Vec::with_capacity(oriented.len());
    for (pi, oriented) in oriented.into_iter().enumerate() {
        let Some((indices, plane)) = oriented else {
            return Err(format!(
                "object `{shown}` polygon {}: a vertex index is beyond the {} vertices",
                pi + 1,
                vertices.len()
            ));
        };
        let n = pi + 1;
        match plane {
            Ok(plane) => {
                polygons.push(Polygon { indices, plane });
                source_polygon.push(pi as u32);
            }
            Err(PolygonDefect::TooFewVertices(k)) => warn(format!(
                "warning: object `{shown}` polygon {n}: only {k} distinct vertices; skipped"
            )),
            Err(PolygonDefect::ZeroArea) => warn(format!(
                "warning: object `{shown}` polygon {n}: zero area; skipped"
            )),
            Err(PolygonDefect::NonPlanar(off)) => {
                warn(format!(
                    "warning: object `{shown}` polygon {n}: not planar (off by {off:.2e} of its size); split into triangles"
                ));
                for triangle in fan(&indices, vertices) {
                    polygons.push(triangle);
                    source_polygon.push(pi as u32);
                }
            }
        }
    }
    Ok((polygons, source_polygon))
}

/// A non-planar polygon split into the triangles of a fan, those with a
/// plane.
fn fan(indices: &[u32], vertices: &[DVec3]) -> Vec<Polygon> {
    (1..indices.len() - 1)
        .filter_map(|k| {
            let tri = IndexList::from([indices[0], indices[k], indices[k + 1]]);
            let pts: Vec<DVec3> = tri
                .iter()
                .filter_map(|&i| vertices.get(i as usize).copied())
                .collect();
            let plane = polygon::outward_plane(&pts).ok()?;
            Some(Polygon {
                indices: tri,
                plane,
            })
        })
        .collect()
}

/// The object-space bounding box's corners in world coordinates.
fn bbox_corners(mesh: &Mesh, transform: &Matrix4) -> [DVec3; 8] {
    let (lo, hi) = crate::math::bounds(mesh.vertices.iter().copied());
    let (lo, hi) = if mesh.vertices.is_empty() {
        (DVec3::ZERO, DVec3::ZERO)
    } else {
        (lo, hi)
    };
    std::array::from_fn(|i| {
        let p = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        transform.transform_point(p)
    })
}

/// The kind of a warning of [`build_object`], for counting.
pub(super) fn warning_kind(message: &str) -> &'static str {
    if message.contains("not planar") {
        "non-planar polygon"
    } else if message.contains("distinct vertices") || message.contains("zero area") {
        "degenerate polygon"
    } else {
        "object"
    }
}

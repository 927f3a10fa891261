//! Modeling primitives that generate object geometry in the scene language
//! instead of reading it from a file: the geodesic constructions of Brown
//! 1978 (003 section 4) with a radial spherical function to deform them,
//! and the primitives of Firebaugh's chapter 8 (001): parametric sphere and
//! cylinder and superquadrics ([`parametric`], eqs. 8.2-8.3, 8.19-8.23),
//! bicubic Bezier and Hermite patches ([`patch`], eqs. 8.6, 8.16-8.18),
//! lathing and extrusion ([`sweep`]) and constructive solid geometry
//! ([`csg`], figs. 8.12-8.15). [`solid`] holds the properties of closed
//! meshes (volume, closedness, orientation) they share.
//!
//! # Design notes
//!
//! `modeling::{parametric, patch, sweep}` make a `modeling::Generated`: a
//! `Mesh` in object coordinates (clockwise from outside), exact vertex
//! normals for curved surfaces (vertices on creases repeated, one copy per
//! side) and an `open` flag. `modeling::Primitive::face_count` is computed
//! from the parameters alone, so the polygon budget refuses before anything
//! is allocated (patch files: from their first line). `scene::parse` reads
//! their commands like every other, and `scene::interpreter::generators` records
//! them in the active object and at `endobj` builds the object with the
//! ordinary `build_object`, then replaces the averaged vertex normals by the
//! exact ones transformed by the inverse transpose.
//!
//! CSG (`modeling::csg`) takes the operands' world polygons (they are already
//! placed), triangulates non-convex faces, builds one BSP tree per operand in
//! an arena (iteratively: a convex solid makes a chain as deep as its face
//! count) and runs the classic clip/invert sequences. Splits interpolate the
//! per-corner normals. The fragments are welded (tolerance 1e-9 of the
//! operands' size, on a hash grid) and points lying on unmatched edges are
//! inserted into them, so the result is a closed mesh. It becomes an object
//! whose mesh is in world coordinates and whose transform is
//! `C0^-1 * CTM_endobj` (only the block's own transforms), with per-face
//! polygon colours from the operands. `modeling::solid` holds the shared
//! checks: signed volume, closedness by edge pairing, outward orientation.

pub mod csg;
pub mod geodesic;
pub mod parametric;
pub mod patch;
pub mod solid;
pub mod sweep;

use glam::DVec3;

use crate::model::Mesh;

/// Bytes a scene holds per vertex of a generated object (position,
/// exact normal, their transformed copies, and the renderer's per-vertex
/// data), measured on `plytrace --check` of spheres and cylinders.
pub const BYTES_PER_VERTEX: u64 = 112;
/// Bytes per polygon (its record, plane, colour and index list header).
pub const BYTES_PER_POLYGON: u64 = 176;
/// Bytes per polygon corner (a vertex index and its share of the rest).
pub const BYTES_PER_CORNER: u64 = 8;

/// The memory a generated object of `vertices`, `polygons` and `corners`
/// will hold, saturating.
pub fn model_bytes(vertices: usize, polygons: usize, corners: usize) -> u64 {
    (vertices as u64)
        .saturating_mul(BYTES_PER_VERTEX)
        .saturating_add((polygons as u64).saturating_mul(BYTES_PER_POLYGON))
        .saturating_add((corners as u64).saturating_mul(BYTES_PER_CORNER))
}

/// What a generator makes: polygons clockwise from outside, and for curved
/// surfaces the exact unit normal at every vertex (vertices on a crease
/// are repeated, one copy per side).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Generated {
    /// Vertices and polygons in object coordinates.
    pub mesh: Mesh,
    /// Exact outward unit normals, one per vertex (curved surfaces).
    pub normals: Option<Vec<DVec3>>,
    /// The surface does not close: both sides are seen (`type open`).
    pub open: bool,
}

impl Generated {
    /// Whether the object is `curved` (it carries vertex normals).
    pub fn curved(&self) -> bool {
        self.normals.is_some()
    }
}

use glam::DVec2;

use parametric::Superquadric;
use sweep::Profile;

/// A generator command of the scene language with checked parameters
/// (the patch generators, which read a file, are handled apart).
#[derive(Debug, Clone, PartialEq)]
pub enum Primitive {
    /// `sphere NU NV`.
    Sphere {
        /// Steps of longitude.
        nu: usize,
        /// Steps of latitude.
        nv: usize,
    },
    /// `cylinder NU [capped|open]`.
    Cylinder {
        /// Steps about z.
        nu: usize,
        /// With end discs.
        capped: bool,
    },
    /// `superquadric E1 E2 NU NV [AX AY AZ]`.
    Superquadric {
        /// Exponents and scale factors.
        q: Superquadric,
        /// Steps of longitude.
        nu: usize,
        /// Steps of latitude.
        nv: usize,
    },
    /// `lathe N r1 z1 ...`.
    Lathe {
        /// The profile.
        profile: Profile,
        /// Steps about z.
        n: usize,
    },
    /// `extrude DEPTH x1 y1 ...`.
    Extrude {
        /// The outline, counter-clockwise.
        outline: Vec<DVec2>,
        /// Depth along z.
        depth: f64,
    },
}

impl Primitive {
    /// The number of polygons it will make, computed before anything is
    /// built (`None` on overflow), so that a budget can refuse it.
    pub fn face_count(&self) -> Option<usize> {
        match self {
            Primitive::Sphere { nu, nv } => parametric::grid_face_count(*nu, *nv, true),
            Primitive::Cylinder { nu, capped } => parametric::cylinder_face_count(*nu, *capped),
            Primitive::Superquadric { nu, nv, .. } => parametric::superquadric_face_count(*nu, *nv),
            Primitive::Lathe { profile, n } => profile.face_count(*n),
            Primitive::Extrude { outline, .. } => sweep::extrude_face_count(outline.len()),
        }
    }

    /// The vertices and the polygon corners it will make (upper bounds,
    /// `None` on overflow), computed before anything is built.
    pub fn vertex_and_corner_counts(&self) -> Option<(usize, usize)> {
        let faces = self.face_count()?;
        match self {
            Primitive::Sphere { nu, nv } | Primitive::Superquadric { nu, nv, .. } => {
                let v = nu.checked_mul(nv.checked_sub(1)?)?.checked_add(2)?;
                Some((v, faces.checked_mul(4)?))
            }
            Primitive::Cylinder { nu, .. } => Some((nu.checked_mul(4)?, nu.checked_mul(6)?)),
            Primitive::Lathe { profile, n } => {
                let k = profile.points().len().checked_add(2)?;
                Some((
                    k.checked_mul(*n)?,
                    faces.checked_add(2 * n)?.checked_mul(4)?,
                ))
            }
            Primitive::Extrude { outline, .. } => {
                let k = outline.len();
                Some((k.checked_mul(2)?, k.checked_mul(6)?))
            }
        }
    }

    /// Generates the polygons.
    pub fn build(&self) -> Generated {
        match self {
            Primitive::Sphere { nu, nv } => parametric::sphere(*nu, *nv),
            Primitive::Cylinder { nu, capped } => parametric::cylinder(*nu, *capped),
            Primitive::Superquadric { q, nu, nv } => parametric::superquadric(q, *nu, *nv),
            Primitive::Lathe { profile, n } => sweep::lathe(profile, *n),
            Primitive::Extrude { outline, depth } => sweep::extrude(outline, *depth),
        }
    }
}

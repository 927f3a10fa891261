//! The precision policy, in one place (style.md, practice 6).
//!
//! Geometry is f64 throughout. Tolerances are *relative* to the size of the
//! thing measured wherever a size exists, so that a scene scaled by 1e6 behaves
//! like the same scene at unit size. The only user-visible tolerance is the
//! clipping epsilon of `setmode e` (004 appendix, default 1e-7), which is
//! passed explicitly to the clipper rather than read from a global.
//!
//! # The policy
//!
//! f64 everywhere in geometry; f32 only for frame-buffer colours and for the
//! boxes of the shadow casters' hierarchy, which are rounded outward (a query
//! finds the same casters or more, and the exact tests reject the extra).
//! Tolerances
//! are relative to the size of what is measured: planarity (1e-4 of the
//! polygon's diameter), zero area (1e-12 of the squared diameter), coincident
//! vertices (1e-12 of the diameter). The clipping epsilon is `setmode e`
//! (default 1e-7), relative to `|w|`, passed to the clipper explicitly.

/// Default clipping epsilon (`setmode e`, 004 appendix).
pub const DEFAULT_CLIP_EPSILON: f64 = 1e-7;

/// Default minimum screen detail (`setmode d`, 004 appendix): polygons whose
/// screen extent in normalized coordinates is below this in both x and y
/// after clipping are ignored.
pub const DEFAULT_MIN_DETAIL: f64 = 0.0002;

/// A polygon whose vertices lie farther than this fraction of its diameter
/// from its best-fit plane is non-planar. Object files written with five or
/// six significant digits stay well inside it.
pub const PLANARITY_TOLERANCE: f64 = 1e-4;

/// A polygon whose area is below this fraction of its squared diameter is
/// degenerate (zero area: a line or a point).
pub const DEGENERATE_AREA: f64 = 1e-12;

/// Two vertices of one polygon closer than this fraction of the polygon's
/// diameter are the same vertex.
pub const COINCIDENT_VERTEX: f64 = 1e-12;

//! Modeling primitives that generate object geometry in the scene language
//! instead of reading it from a file: the geodesic constructions of Brown
//! 1978 (003 section 4) with a radial spherical function to deform them.

pub mod geodesic;

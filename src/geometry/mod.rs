//! The geometry stage (Garcia 1986, 004 sections 4.3-4.5): polygon planes,
//! bounding-box tests against the view volume, back-face removal, clipping
//! in homogeneous coordinates, perspective division and viewport mapping.

pub mod boolean;
pub mod bvh;
pub mod clip;
pub mod face_splitter;
pub mod plane_clip;
pub mod polygon;
pub mod view;

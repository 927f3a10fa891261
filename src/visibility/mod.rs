//! The visibility stage: orders screen polygons so that painting them
//! resolves hidden surfaces. Part 1 has the simple depth sort of Garcia 1986
//! (004 section 4.4); the Newell-Newell-Sancha sorter and the image-space
//! algorithms come later.

pub mod depth_sort;

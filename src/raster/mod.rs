//! Scan conversion: the face sampler of Donovan 1973 (000 section 5) and
//! the frame buffer it paints into. Anti-aliasing scan converters (Garcia's
//! rftb1-rftb4) come later and read the same polygons.

pub mod frame_buffer;
pub mod scan;
pub mod tiler;

//! Exact refraction for the virtual image tree (004 section 6.4): see below.

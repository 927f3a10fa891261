//! A polygon edge as the tiler's active edge list holds it (Garcia 1986,
//! 004 section 5.5, figure 5.3's edge structures), shared by the tiler
//! (coverage) and the row shader (attributes along the edges).

use glam::DVec2;

/// An edge in canonical order (`lo` below `hi`, ties by x).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Edge {
    pub lo: DVec2,
    pub hi: DVec2,
    /// +1 if the polygon walks the edge upwards, else -1.
    pub dir: f64,
    /// Vertex indices of `lo` and `hi`.
    pub lo_vertex: u32,
    pub hi_vertex: u32,
    /// `dx / dy` from `lo` to `hi`.
    pub slope: f64,
}

impl Edge {
    /// The point sampler's crossing at `y` (`lo.y <= y < hi.y`).
    pub fn cross(&self, y: f64) -> Option<f64> {
        (self.lo.y <= y && y < self.hi.y).then(|| self.x_at(y))
    }

    pub fn x_at(&self, y: f64) -> f64 {
        self.lo.x + (y - self.lo.y) * self.slope
    }
}

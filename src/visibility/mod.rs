//! The visibility stage: the algorithms that decide which surface is seen
//! at each pixel. List-priority sorts order polygons for painting (the
//! simple depth sort of Garcia 1986, 004 section 4.4; the
//! Newell-Newell-Sancha sorter of Donovan 1973, 000 section 3); image-space
//! algorithms resolve visibility per pixel (the z-buffer of Firebaugh,
//! 001); the ray caster is the independent oracle.

use std::fmt;
use std::str::FromStr;

pub mod brown;
pub mod depth_sort;
pub mod nns;
pub mod occlusion;
pub mod ray_cast;
pub mod scan_line;
pub mod warnock;
pub mod z_buffer;

/// A visible-surface algorithm, chosen per run (`--visibility`) or per
/// scene (`setmode n on` selects [`Algorithm::Nns`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Algorithm {
    /// Simple depth sort by min/max z (004 section 4.4).
    DepthSort,
    /// Newell, Newell and Sancha with face splitting (000 sections 3-4).
    Nns,
    /// Z-buffer (001).
    ZBuffer,
    /// Scan-line algorithm with an active edge list (001).
    ScanLine,
    /// Warnock's area subdivision (001).
    Warnock,
    /// Brown's priority order for well-tesselated surfaces (003), per
    /// object; objects by the simple depth sort.
    Brown,
    /// Ray casting through a bounding volume hierarchy.
    RayCast,
}

impl Algorithm {
    /// Every algorithm with its command-line name.
    pub const ALL: [(Algorithm, &'static str); 7] = [
        (Algorithm::DepthSort, "depth-sort"),
        (Algorithm::Nns, "nns"),
        (Algorithm::ZBuffer, "z-buffer"),
        (Algorithm::ScanLine, "scan-line"),
        (Algorithm::Warnock, "warnock"),
        (Algorithm::Brown, "brown"),
        (Algorithm::RayCast, "ray-cast"),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(a, _)| *a == self)
            .map(|(_, n)| *n)
            .expect("listed")
    }
}

impl fmt::Display for Algorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Algorithm {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.to_ascii_lowercase().replace('_', "-");
        let alias = match s.as_str() {
            "simple" | "depthsort" | "painter" => "depth-sort",
            "zbuffer" | "z" => "z-buffer",
            "scanline" => "scan-line",
            "area-subdivision" => "warnock",
            "raycast" | "ray" => "ray-cast",
            "newell" => "nns",
            other => other,
        };
        Self::ALL
            .iter()
            .find(|(_, n)| *n == alias)
            .map(|(a, _)| *a)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(_, n)| *n).collect();
                format!(
                    "unknown visibility algorithm `{s}`; expected one of {}",
                    names.join(", ")
                )
            })
    }
}

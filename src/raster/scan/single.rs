//! Single-level front-to-back integrators for pre-blended trees (004
//! sections 5.6-5.8): method 1 (area coverage), method 2 (pixel masks),
//! method 3 (hybrid), and the point and supersampling variants, which are
//! method 2 with one or `N x N` samples instead of 16 (Donovan 000
//! section 6: the pixel is the box-filtered mean of its samples).
//!
//! Each pixel keeps its colour, a coverage value `A` (the coverage byte)
//! and, except for method 1, a sample mask `M`. A fragment of visible
//! share `A_vis = min(f, 1 - A_old)`, where `f` is the exact area
//! (method 1), `popcount(M_cur & !M_old) / n` (masks), or the exact area
//! where the fragment's mask is not clipped by `M_old` (method 3, e.g.
//! the first fragment to touch the pixel), adds `A_vis I_cur`. A pixel is
//! full when `A` reaches 1. In method 3 a full mask with `A < 1` (exact
//! areas below the sample counts) still takes fragments whose mask is empty
//! (slivers between the samples), by their exact area: in a mesh of
//! polygons sharing edges the areas then add up to exactly 1.
//!
//! Transparency, by the [`TransparencyRule`] given:
//!
//! - [`TransparencyRule::Coverage`], 004 section 5.6, the rule of rftb1
//!   and rftb3 (the rftb manual page: rftb1 "simulates linear and
//!   non-linear transparency using a pixel-coverage byte"; rftb3 combines
//!   rftb1's and rftb2's features): the fragment's coverage is reduced to
//!   `Ā = A_vis (1 - T)`, it adds `Ā I_cur` (capped at `1 - A_old`) and
//!   the coverage grows by `Ā`;
//! - otherwise (plytrace's own picture with `--aa area|mask|hybrid`,
//!   rftb2) 004 section 4.9, the rule of the back-to-front painter
//!   `I = I_cur + k_t I_behind`, so that plytrace's paths agree: the
//!   visible share contributes `A_vis I_cur` in full and the coverage
//!   grows by only `A_vis (1 - t)`, so what lies behind shows through
//!   with weight `t`.
//!
//! Either way a transparent fragment changes the coverage and colour,
//! never the mask (004 section 5.8). Levels and special records are
//! ignored.
//!
//! Shades are evaluated once per pixel, at its centre (clamped into the
//! polygon's span). For supersampling that is Donovan's closed form for
//! long spans: a block inside the segment adds `N SH + N(N-1)/2 DSH` per
//! sub-row, the mean of a linear shade over the block, which is its value
//! at the block's centre; partial pixels weight that value by their
//! visible sample count.

use super::TransparencyRule;
use super::band::{BandOut, Fragment, Integrator};
use super::mask::SampleMask;
use super::shade::Shade;

/// How the visible share of a fragment is measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Measure {
    /// Method 1: exact area.
    Area,
    /// Method 2, point, supersampling: sample count.
    Mask,
    /// Method 3: masks, exact area where the mask is not clipped.
    Hybrid,
}

/// Per-pixel state of the single-level methods.
#[derive(Debug)]
pub(crate) struct SingleLevel {
    measure: Measure,
    samples: u32,
    rule: TransparencyRule,
    rgb: Vec<[f32; 3]>,
    cover: Vec<f64>,
    mask: Vec<SampleMask>,
}

impl SingleLevel {
    /// An integrator measuring with `measure` over `samples` samples,
    /// blending transparency by `rule`.
    pub fn new(measure: Measure, samples: u32, rule: TransparencyRule) -> SingleLevel {
        SingleLevel {
            measure,
            samples,
            rule,
            rgb: Vec::new(),
            cover: Vec::new(),
            mask: Vec::new(),
        }
    }

    /// The share `f` of a fragment and its unclipped samples.
    fn share(&self, px: usize, frag: &Fragment) -> (f64, SampleMask) {
        let old = self.mask[px];
        let m_cov = frag.mask.and_not(old);
        let count = m_cov.count() as f64 / self.samples as f64;
        match self.measure {
            Measure::Area => (frag.area, SampleMask::EMPTY),
            Measure::Mask => (count, m_cov),
            Measure::Hybrid if frag.mask.and(old).is_empty() => (frag.area, m_cov),
            Measure::Hybrid => (count, m_cov),
        }
    }
}

impl Integrator for SingleLevel {
    fn reset(&mut self, pixels: usize) {
        self.rgb.clear();
        self.rgb.resize(pixels, [0.0; 3]);
        self.cover.clear();
        self.cover.resize(pixels, 0.0);
        self.mask.clear();
        self.mask.resize(pixels, SampleMask::EMPTY);
    }

    fn pixel(&mut self, px: usize, frag: &Fragment, _: u16, shade: impl FnOnce() -> Shade) -> bool {
        let a_old = self.cover[px];
        if a_old >= 1.0 {
            return false;
        }
        let (f, m_cov) = self.share(px, frag);
        let a_vis = f.min(1.0 - a_old);
        if a_vis <= 0.0 {
            return false;
        }
        let s = shade();
        // Ā = A (1 - T): what the fragment covers (section 5.6).
        let a_bar = a_vis * (1.0 - s.t as f64);
        let w = match self.rule {
            // A_cov = min(Ā, 1 - A_old); a_vis <= 1 - A_old already.
            TransparencyRule::Coverage => a_bar,
            TransparencyRule::Garcia | TransparencyRule::Donovan => a_vis,
        } as f32;
        for c in 0..3 {
            self.rgb[px][c] += w * s.rgb[c];
        }
        let mut a_new = a_old + a_bar;
        if s.t == 0.0 {
            self.mask[px] = self.mask[px].or(m_cov);
        }
        if a_new > 1.0 - 1e-9 {
            a_new = 1.0;
        }
        self.cover[px] = a_new;
        true
    }

    fn background(&mut self, px: usize, bg: [f32; 3]) {
        let w = (1.0 - self.cover[px]) as f32;
        for (v, b) in self.rgb[px].iter_mut().zip(bg) {
            *v += w * b;
        }
    }

    fn output(&mut self, out: &mut BandOut) {
        out.rgb.clear();
        out.rgb.extend_from_slice(&self.rgb);
        out.coverage.clear();
        if self.measure != Measure::Mask {
            out.coverage
                .extend(self.cover.iter().map(|a| (a * 255.0).round() as u8));
        }
        out.mask.clear();
        if self.measure != Measure::Area {
            out.mask.extend(self.mask.iter().map(|m| m.low16()));
        }
    }
}

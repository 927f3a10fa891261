//! The classic painter for back-to-front streams (004 appendix, the
//! "overwriting principle"; Donovan 000 section 5): one sample at the
//! pixel centre, a later polygon overwrites. A transparent polygon blends
//! with what is behind by 004 section 4.9, `I = I_cur + k_t I_old`, or by
//! Donovan's rule (3), `I = I_a` if `I_a > I_b`, else
//! `(1 - w) I_a + w I_b` with `w = t`; "brighter" compares luminances
//! (Rec. 601 weights), and the chosen formula is applied to all three
//! channels. The background, being behind everything, is the buffer's
//! initial colour.

use super::TransparencyRule;
use super::band::{BandOut, Fragment, Integrator};
use super::shade::Shade;

/// The back-to-front painter.
#[derive(Debug)]
pub(crate) struct Painter {
    rule: TransparencyRule,
    initial: [f32; 3],
    rgb: Vec<[f32; 3]>,
}

fn luminance(c: [f32; 3]) -> f32 {
    0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
}

impl Painter {
    /// A painter clearing to `initial`.
    pub fn new(rule: TransparencyRule, initial: [f32; 3]) -> Painter {
        Painter {
            rule,
            initial,
            rgb: Vec::new(),
        }
    }
}

impl Integrator for Painter {
    fn reset(&mut self, pixels: usize) {
        self.rgb.clear();
        self.rgb.resize(pixels, self.initial);
    }

    fn pixel(&mut self, px: usize, frag: &Fragment, _: u16, shade: impl FnOnce() -> Shade) -> bool {
        if !frag.centre {
            return false;
        }
        let s = shade();
        let (old, kt) = (self.rgb[px], s.t);
        self.rgb[px] = match self.rule {
            _ if kt <= 0.0 => s.rgb,
            // (`scan_convert` refuses the coverage rule for the painter.)
            TransparencyRule::Garcia | TransparencyRule::Coverage => {
                std::array::from_fn(|c| old[c] * kt + s.rgb[c])
            }
            TransparencyRule::Donovan if luminance(s.rgb) > luminance(old) => s.rgb,
            TransparencyRule::Donovan => {
                std::array::from_fn(|c| (1.0 - kt) * s.rgb[c] + kt * old[c])
            }
        };
        true
    }

    fn background(&mut self, _: usize, _: [f32; 3]) {}

    fn output(&mut self, out: &mut BandOut) {
        out.rgb.clear();
        out.rgb.extend_from_slice(&self.rgb);
        out.coverage.clear();
        out.mask.clear();
    }
}

//! The classic painter for back-to-front streams (004 appendix, the
//! "overwriting principle"; Donovan 000 section 5): a later polygon
//! overwrites. A transparent polygon blends with what is behind by 004
//! section 4.9, `I = I_cur + k_t I_old`, or by Donovan's rule (3),
//! `I = I_a` if `I_a > I_b`, else `(1 - w) I_a + w I_b` with `w = t`;
//! "brighter" compares luminances (Rec. 601 weights), and the chosen
//! formula is applied to all three channels. The background, being behind
//! everything, is the buffer's initial colour.
//!
//! Point sampling paints the pixel centre. With `n` samples per pixel
//! (Donovan's N x N supersampling, 000 section 6, or the 16 positions of
//! Garcia's 4 x 4 pixel mask) every sample is painted on its own, in
//! stream order, and the pixel is their mean (a box filter). Donovan's
//! rule is not linear in the colour behind, so it cannot be integrated
//! front to back as coverage is; painted per sample, back to front, it is
//! applied exactly where it is defined, at a point with the surface
//! behind already known.

use super::TransparencyRule;
use super::band::{BandOut, Fragment, Integrator};
use super::shade::Shade;

/// The back-to-front painter.
#[derive(Debug)]
pub(crate) struct Painter {
    rule: TransparencyRule,
    initial: [f32; 3],
    /// Samples per pixel (1: the centre only).
    samples: usize,
    /// `samples` colours per pixel.
    rgb: Vec<[f32; 3]>,
}

fn luminance(c: [f32; 3]) -> f32 {
    0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
}

/// `s` painted over `old` by `rule`.
fn over(rule: TransparencyRule, s: &Shade, old: [f32; 3]) -> [f32; 3] {
    let kt = s.t;
    match rule {
        _ if kt <= 0.0 => s.rgb,
        // (`scan_convert` refuses the coverage rule for the painter.)
        TransparencyRule::Garcia | TransparencyRule::Coverage => {
            std::array::from_fn(|c| old[c] * kt + s.rgb[c])
        }
        TransparencyRule::Donovan if luminance(s.rgb) > luminance(old) => s.rgb,
        TransparencyRule::Donovan => std::array::from_fn(|c| (1.0 - kt) * s.rgb[c] + kt * old[c]),
    }
}

impl Painter {
    /// A painter clearing to `initial`, with `samples` samples per pixel
    /// (1, or the `n * n` of the tiler's sample masks).
    pub fn new(rule: TransparencyRule, initial: [f32; 3], samples: u32) -> Painter {
        Painter {
            rule,
            initial,
            samples: samples.max(1) as usize,
            rgb: Vec::new(),
        }
    }
}

impl Integrator for Painter {
    fn reset(&mut self, pixels: usize) {
        self.rgb.clear();
        self.rgb.resize(pixels * self.samples, self.initial);
    }

    fn pixel(&mut self, px: usize, frag: &Fragment, _: u16, shade: impl FnOnce() -> Shade) -> bool {
        if self.samples == 1 {
            if !frag.centre {
                return false;
            }
            let s = shade();
            self.rgb[px] = over(self.rule, &s, self.rgb[px]);
            return true;
        }
        if frag.mask.is_empty() {
            return false;
        }
        let s = shade();
        let n = self.samples;
        for (k, old) in self.rgb[px * n..(px + 1) * n].iter_mut().enumerate() {
            if frag.mask.0[k / 64] >> (k % 64) & 1 == 1 {
                *old = over(self.rule, &s, *old);
            }
        }
        true
    }

    fn background(&mut self, _: usize, _: [f32; 3]) {}

    fn output(&mut self, out: &mut BandOut) {
        out.rgb.clear();
        let n = self.samples;
        if n == 1 {
            out.rgb.extend_from_slice(&self.rgb);
        } else {
            out.rgb.extend(self.rgb.chunks(n).map(|px| {
                let sum = px
                    .iter()
                    .fold([0.0f32; 3], |a, c| std::array::from_fn(|i| a[i] + c[i]));
                sum.map(|v| v / n as f32)
            }));
        }
        out.coverage.clear();
        out.mask.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::super::mask::SampleMask;
    use super::*;

    fn shade(rgb: [f32; 3], t: f32) -> Shade {
        Shade { rgb, t }
    }

    /// Rule (3) by hand: a bright glass over dark keeps its own shade; a
    /// dark glass (t = 0.25) over white is 0.75 of itself + 0.25 white.
    #[test]
    fn donovan_rule_3_per_sample() {
        let mut p = Painter::new(TransparencyRule::Donovan, [1.0; 3], 4);
        p.reset(1);
        let mut mask = SampleMask::EMPTY;
        mask.set_range(0, 2);
        let half = Fragment {
            full: false,
            area: 0.5,
            mask,
            centre: true,
        };
        assert!(p.pixel(0, &half, 1, || shade([0.2; 3], 0.25)));
        let mut out = BandOut::default();
        p.output(&mut out);
        // Two samples 0.75 * 0.2 + 0.25 * 1 = 0.4, two still white.
        assert!((out.rgb[0][0] - 0.7).abs() < 1e-6, "{:?}", out.rgb[0]);
    }
}

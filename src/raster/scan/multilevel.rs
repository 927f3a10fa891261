//! Method 4 (rftb4), 004 section 5.9: multi-level pixel masks. Each pixel
//! is a pixel-struct (figure 5.15: colour, status, fragment list) and
//! partly covered or saved levels live in pixel-fragments (figure 5.16)
//! drawn from a pool. The six cases of section 5.9, for a fragment at
//! tree depth `c` and a pixel at depth `p`:
//!
//! 1. empty (`p = 0`): write the area-weighted colour; full coverage marks
//!    the pixel covered, else a fragment holds the mask;
//! 2. covered and `c >= p`: hidden;
//! 3. complex, `c = p`: `M_cov = M_cur & !M_pix`, `I += f(M_cov) I_cur`,
//!    `M_pix |= M_cov`; a full mask frees the fragment, pixel covered;
//! 4. complex, `c > p`: if visible, the level-`p` state stays saved in its
//!    fragment and a new level (mask `M_pix | M_cov`) is pushed, or the
//!    pixel is marked covered;
//! 5. `c < p`: restore the pixel to the parent's level (pop the fragments
//!    of deeper levels, the colour stays), then blend as in case 1, 3
//!    or 4: the parent adds its own shade times its visible coverage over
//!    its children (post-blended streams);
//! 6. a special record at `c < p`: the same restore, no colour change.
//!
//! The point and supersampling variants run the same logic with 1 or
//! `N x N` samples instead of 16. Extension: each level also carries a
//! coverage value (figure 5.16's `pcover`) so transparency works as in
//! method 3: a visible share is `min(f(M_cov), 1 - pcover)`, and a
//! transparent fragment raises the coverage by `share (1 - t)` and leaves
//! the mask alone. The background pass restores each pixel to level 1
//! and blends the background there as a level-1 polygon.

use super::band::{BandOut, Fragment, Integrator};
use super::mask::SampleMask;
use super::shade::Shade;
use super::{PixelStruct, SavedFragment};

const DEPTH: u8 = 0x1F;
const COVERED: u8 = 1 << 5;
const COMPLEX: u8 = 1 << 6;
const NONE: u32 = u32::MAX;

/// A pixel-struct (figure 5.15).
#[derive(Debug, Clone, Copy)]
struct Pix {
    rgb: [f32; 3],
    stat: u8,
    head: u32,
}

/// A pixel-fragment (figure 5.16).
#[derive(Debug, Clone, Copy)]
struct Frag {
    prev: u32,
    mask: SampleMask,
    stat: u8,
    cover: f64,
}

/// The pixel-structs of a band and their fragment pool.
#[derive(Debug)]
pub(crate) struct MultiLevel {
    samples: u32,
    /// Whether [`Integrator::output`] makes the pixel-structs.
    structs: bool,
    full: SampleMask,
    pixels: Vec<Pix>,
    frags: Vec<Frag>,
    free: Vec<u32>,
    live: usize,
    peak: usize,
    total: u64,
}

impl MultiLevel {
    /// Method 4 logic over `samples` samples per pixel; with `structs`
    /// (16 samples only) the output has the pixel-structs.
    pub fn new(samples: u32, structs: bool) -> MultiLevel {
        MultiLevel {
            samples,
            structs: structs && samples == 16,
            full: SampleMask::full(samples),
            pixels: Vec::new(),
            frags: Vec::new(),
            free: Vec::new(),
            live: 0,
            peak: 0,
            total: 0,
        }
    }

    fn alloc(&mut self, f: Frag) -> u32 {
        self.live += 1;
        self.total += 1;
        self.peak = self.peak.max(self.live);
        match self.free.pop() {
            Some(k) => {
                self.frags[k as usize] = f;
                k
            }
            None => {
                self.frags.push(f);
                (self.frags.len() - 1) as u32
            }
        }
    }

    fn release(&mut self, k: u32) {
        self.live -= 1;
        self.free.push(k);
    }

    /// Cases 5 and 6: pops levels deeper than `level`. Most pixels have
    /// none, so only the test is inlined.
    #[inline]
    fn restore_to(&mut self, px: usize, level: u8) {
        if self.pixels[px].stat & DEPTH > level {
            self.pop_to(px, level);
        }
    }

    #[inline(never)]
    fn pop_to(&mut self, px: usize, level: u8) {
        while self.pixels[px].stat & DEPTH > level {
            let p = self.pixels[px];
            let mut head = p.head;
            if p.stat & COMPLEX != 0 {
                let h = head;
                head = self.frags[h as usize].prev;
                self.release(h);
            }
            let stat = if head == NONE {
                0
            } else {
                self.frags[head as usize].stat
            };
            self.pixels[px].head = head;
            self.pixels[px].stat = stat;
        }
    }

    /// The current level's mask and coverage.
    fn state(&self, px: usize) -> (SampleMask, f64) {
        let p = self.pixels[px];
        if p.stat & COMPLEX != 0 {
            let f = &self.frags[p.head as usize];
            (f.mask, f.cover)
        } else {
            (SampleMask::EMPTY, 0.0)
        }
    }

    /// Cases 1, 3 and 4 once the pixel is at depth `<= level` and not
    /// covered.
    fn blend(
        &mut self,
        px: usize,
        frag: &Fragment,
        level: u8,
        shade: impl FnOnce() -> Shade,
    ) -> bool {
        let (m_pix, c_pix) = self.state(px);
        let m_cov = frag.mask.and_not(m_pix);
        // A full fragment's mask is every sample.
        let count = if frag.full && m_pix.is_empty() {
            self.samples
        } else {
            m_cov.count()
        };
        let share = (count as f64 / self.samples as f64).min(1.0 - c_pix);
        if share <= 0.0 {
            return false;
        }
        let s = shade();
        let p = self.pixels[px];
        for c in 0..3 {
            self.pixels[px].rgb[c] += share as f32 * s.rgb[c];
        }
        let mask = if s.t == 0.0 { m_pix.or(m_cov) } else { m_pix };
        let cover = c_pix + share * (1.0 - s.t as f64);
        let full = mask == self.full || cover > 1.0 - 1e-9;
        let same = p.stat & COMPLEX != 0 && p.stat & DEPTH == level;
        if full {
            if same {
                self.pixels[px].head = self.frags[p.head as usize].prev;
                self.release(p.head);
            }
            self.pixels[px].stat = level | COVERED;
        } else if same {
            let f = &mut self.frags[p.head as usize];
            f.mask = mask;
            f.cover = cover;
        } else {
            let stat = level | COMPLEX;
            let k = self.alloc(Frag {
                prev: p.head,
                mask,
                stat,
                cover,
            });
            self.pixels[px].head = k;
            self.pixels[px].stat = stat;
        }
        true
    }

    fn saved(&self, px: usize, out: &mut PixelStruct) {
        let p = self.pixels[px];
        out.rgb = p.rgb.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
        out.pixstat = p.stat;
        out.fragments.clear();
        let mut k = p.head;
        while k != NONE {
            let f = &self.frags[k as usize];
            out.fragments.push(SavedFragment {
                pmask: f.mask.low16(),
                pstat: f.stat,
                pcover: (f.cover * 255.0).round() as u8,
            });
            k = f.prev;
        }
    }
}

impl Integrator for MultiLevel {
    fn reset(&mut self, pixels: usize) {
        let empty = Pix {
            rgb: [0.0; 3],
            stat: 0,
            head: NONE,
        };
        self.pixels.clear();
        self.pixels.resize(pixels, empty);
        self.frags.clear();
        self.free.clear();
        self.live = 0;
        self.peak = 0;
        self.total = 0;
    }

    fn pixel(
        &mut self,
        px: usize,
        frag: &Fragment,
        level: u16,
        shade: impl FnOnce() -> Shade,
    ) -> bool {
        let level = level as u8;
        self.restore_to(px, level);
        if self.pixels[px].stat & COVERED != 0 {
            return false;
        }
        self.blend(px, frag, level, shade)
    }

    /// Pixels covered at no deeper a level are passed over at the cost
    /// of a test (case 2), the others blended as by `pixel`.
    fn span(
        &mut self,
        base: usize,
        cols: std::ops::Range<u32>,
        full: &Fragment,
        level: u16,
        mut shade: impl FnMut(u32) -> Shade,
        mut seen: impl FnMut(u32),
    ) {
        let lv = level as u8;
        for i in cols {
            let px = base + i as usize;
            let stat = self.pixels[px].stat;
            if stat & COVERED != 0 && stat & DEPTH <= lv {
                continue;
            }
            self.restore_to(px, lv);
            if self.pixels[px].stat & COVERED == 0 && self.blend(px, full, lv, || shade(i)) {
                seen(i);
            }
        }
    }

    fn restore(&mut self, px: usize, level: u16) {
        self.restore_to(px, level as u8);
    }

    /// Case 2 in every pixel: covered at a depth no deeper than `level`
    /// (a deeper one would first be restored).
    fn hidden(&self, pixels: std::ops::Range<usize>, level: u16) -> bool {
        let level = level as u8;
        self.pixels[pixels]
            .iter()
            .all(|p| p.stat & COVERED != 0 && p.stat & DEPTH <= level)
    }

    fn background(&mut self, px: usize, bg: [f32; 3]) {
        let frag = Fragment {
            full: true,
            area: 1.0,
            mask: self.full,
            centre: true,
        };
        self.pixel(px, &frag, 1, || Shade { rgb: bg, t: 0.0 });
    }

    /// Pixels covered at level 1 are passed over at the cost of a test.
    fn background_all(&mut self, pixels: usize, bg: [f32; 3]) {
        for px in 0..pixels {
            let stat = self.pixels[px].stat;
            if stat & COVERED == 0 || stat & DEPTH > 1 {
                self.background(px, bg);
            }
        }
    }

    fn output(&mut self, out: &mut BandOut) {
        out.rgb.clear();
        out.rgb.extend(self.pixels.iter().map(|p| p.rgb));
        out.coverage.clear();
        out.mask.clear();
        let n = self.pixels.len();
        if !self.structs {
            out.pixels.clear();
        } else {
            out.pixels.resize_with(n, || PixelStruct {
                rgb: [0; 3],
                pixstat: 0,
                fragments: Vec::new(),
            });
            for px in 0..n {
                self.saved(px, &mut out.pixels[px]);
            }
        }
    }

    fn fragments(&self) -> (usize, u64) {
        (self.peak, self.total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fragment(mask: SampleMask) -> Fragment {
        Fragment {
            full: false,
            area: f64::from(mask.count()) / 16.0,
            mask,
            centre: true,
        }
    }

    /// `hidden` holds where a fragment is case 2 (covered at a depth no
    /// deeper than its own), and then blending it changes nothing; a
    /// pixel partly covered, or covered only deeper, is not hidden.
    #[test]
    fn hidden_is_case_two() {
        let grey = || Shade {
            rgb: [0.5; 3],
            t: 0.0,
        };
        let mut half = SampleMask::EMPTY;
        half.set_range(0, 8);
        let mut m = MultiLevel::new(16, false);
        m.reset(3);
        assert!(m.pixel(0, &fragment(SampleMask::full(16)), 1, grey));
        assert!(m.pixel(1, &fragment(half), 1, grey));
        assert!(m.pixel(2, &fragment(SampleMask::full(16)), 2, grey));
        assert!(m.hidden(0..1, 1) && m.hidden(0..1, 2));
        assert!(!m.hidden(0..2, 1), "half covered");
        assert!(!m.hidden(2..3, 1), "covered only at depth 2");
        assert!(m.hidden(2..3, 2) && m.hidden(2..3, 3));
        assert!(m.hidden(0..0, 1), "no pixels");
        let before = format!("{:?}", m.pixels);
        assert!(!m.pixel(0, &fragment(SampleMask::full(16)), 2, grey));
        assert!(!m.pixel(2, &fragment(half), 3, grey));
        assert_eq!(format!("{:?}", m.pixels), before);
        assert!(m.pixel(2, &fragment(half), 1, grey), "restored to depth 1");
    }
}

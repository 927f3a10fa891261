//! Sample masks of up to 16 x 16 bits: Garcia's 4 x 4 pixel mask (004
//! section 5.7, figure 5.11), the single centre sample, and Donovan's
//! N x N supersampling blocks (000 section 6). Bit `n * row + column`,
//! row 0 at the top of the pixel.

/// A set of up to 256 sample bits.
#[derive(Debug, Clone, Copy, Eq, Default)]
pub(crate) struct SampleMask(pub [u64; 4]);

/// Word by word in registers: the derived comparison loads the masks,
/// just stored a word at a time, as two 16-byte vectors, which stalls on
/// store forwarding in the method 4 pixel loop.
impl PartialEq for SampleMask {
    #[inline]
    fn eq(&self, other: &SampleMask) -> bool {
        let (a, b) = (&self.0, &other.0);
        ((a[0] ^ b[0]) | (a[1] ^ b[1]) | (a[2] ^ b[2]) | (a[3] ^ b[3])) == 0
    }
}

impl SampleMask {
    /// No sample.
    pub const EMPTY: SampleMask = SampleMask([0; 4]);

    /// The first `n` bits (`n <= 256`).
    pub fn full(n: u32) -> SampleMask {
        let mut m = SampleMask::EMPTY;
        m.set_range(0, n);
        m
    }

    /// Sets bits `lo..hi`.
    pub fn set_range(&mut self, lo: u32, hi: u32) {
        crate::math::for_bit_words(lo, hi, |w, bits| self.0[w] |= bits);
    }

    /// Bits in `self` and not in `other`.
    pub fn and_not(self, other: SampleMask) -> SampleMask {
        SampleMask(std::array::from_fn(|k| self.0[k] & !other.0[k]))
    }

    /// Bits in both.
    pub fn and(self, other: SampleMask) -> SampleMask {
        SampleMask(std::array::from_fn(|k| self.0[k] & other.0[k]))
    }

    /// Bits in either.
    pub fn or(self, other: SampleMask) -> SampleMask {
        SampleMask(std::array::from_fn(|k| self.0[k] | other.0[k]))
    }

    /// Bits in exactly one of the two.
    #[inline]
    pub fn xor(self, other: SampleMask) -> SampleMask {
        SampleMask(std::array::from_fn(|k| self.0[k] ^ other.0[k]))
    }

    /// Number of bits set.
    pub fn count(self) -> u32 {
        self.0.iter().map(|w| w.count_ones()).sum()
    }

    /// Whether no bit is set.
    pub fn is_empty(self) -> bool {
        self == SampleMask::EMPTY
    }

    /// The low 16 bits (the 4 x 4 pixel mask).
    pub fn low16(self) -> u16 {
        self.0[0] as u16
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_counts() {
        assert_eq!(SampleMask::full(16).low16(), 0xFFFF);
        assert_eq!(SampleMask::full(256).count(), 256);
        let mut m = SampleMask::EMPTY;
        m.set_range(60, 70);
        assert_eq!(m.count(), 10);
        assert_eq!(m.0[0] >> 60, 0xF);
        assert_eq!(m.0[1], 0x3F);
        let f = SampleMask::full(100);
        assert_eq!(f.and_not(m).count(), 90);
        assert_eq!(f.and(m), m);
        assert_eq!(m.or(f), f);
        assert_eq!(f.xor(m), f.and_not(m));
        assert_eq!(m.xor(m), SampleMask::EMPTY);
        assert!(SampleMask::EMPTY.is_empty() && !m.is_empty());
    }
}

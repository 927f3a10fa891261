use crate::int::number::product_uint::{CompositeUIntProduct, UIntProduct, UIntProduct64};
use core::fmt::Display;
use core::ops::{Add, AddAssign, BitAnd, BitOr, BitOrAssign, Div, Mul, Shl, ShlAssign, Shr, Sub};

pub trait UIntNumber:
    Copy
    + Clone
    + Ord
    + Send
    + Sync
    + Display
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitOrAssign
    + Shl<u32, Output = Self>
    + Shr<u32, Output = Self>
    + ShlAssign
    + AddAssign
{
    type Product: UIntProduct<Self>;
    const BITS: u32;
    const HALF_BITS: u32;
    const HALF_MASK: Self;
    const LAST_BIT_INDEX: u32;
    const ZERO: Self;
    const ONE: Self;
    const TWO: Self;
    const FOUR: Self;
    const MAX: Self;
    const LAST_BIT: Self;

    fn overflowing_add(self, rhs: Self) -> (Self, bool);
    fn from_u64(value: u64) -> Self;
    fn wrapping_sub(self, rhs: Self) -> Self;
    fn leading_zeros(self) -> u32;
    fn ilog2(self) -> u32;
    fn isqrt(self) -> Self;
    fn to_usize(self) -> usize;
    fn to_f64(self) -> f64;

    /// The quotient and remainder of `high * 2^BITS + low` by `divisor`,
    /// for `high < divisor`: one bit at a time unless a type has faster.
    fn divide_wide(high: Self, low: Self, divisor: Self) -> (Self, Self) {
        let dn = divisor.leading_zeros();
        let norm_divisor = divisor << dn;
        let mut rem_high = if dn == 0 {
            high
        } else {
            (high << dn) | (low >> (Self::BITS - dn))
        };
        let mut rem_low = low << dn;
        let mut quotient = Self::ZERO;
        for _ in 0..Self::BITS {
            let bit = (rem_high & Self::LAST_BIT) != Self::ZERO;
            rem_high = (rem_high << 1) | (rem_low >> Self::LAST_BIT_INDEX);
            rem_low <<= Self::ONE;
            quotient <<= Self::ONE;
            if rem_high >= norm_divisor || bit {
                rem_high = rem_high.wrapping_sub(norm_divisor);
                quotient |= Self::ONE;
            }
        }
        (quotient, rem_high >> dn)
    }
}

impl UIntNumber for u32 {
    type Product = UIntProduct64;
    const BITS: u32 = 32;
    const HALF_BITS: u32 = 16;
    const HALF_MASK: Self = 0xFFFF;
    const LAST_BIT_INDEX: u32 = 31;
    const ZERO: Self = 0;
    const ONE: Self = 1;
    const TWO: Self = 2;
    const FOUR: Self = 4;
    const MAX: Self = Self::MAX;
    const LAST_BIT: Self = Self::ONE << Self::LAST_BIT_INDEX;

    #[inline(always)]
    fn overflowing_add(self, rhs: Self) -> (Self, bool) {
        self.overflowing_add(rhs)
    }
    #[inline(always)]
    fn from_u64(value: u64) -> Self {
        value as Self
    }

    #[inline(always)]
    fn wrapping_sub(self, rhs: Self) -> Self {
        self.wrapping_sub(rhs)
    }

    #[inline(always)]
    fn leading_zeros(self) -> u32 {
        self.leading_zeros()
    }

    #[inline(always)]
    fn ilog2(self) -> u32 {
        self.ilog2()
    }

    #[inline(always)]
    fn isqrt(self) -> Self {
        self.isqrt()
    }
    #[inline(always)]
    fn to_usize(self) -> usize {
        self as usize
    }

    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
}

impl UIntNumber for u64 {
    type Product = CompositeUIntProduct<Self>;
    const BITS: u32 = 64;
    const HALF_BITS: u32 = 32;
    const HALF_MASK: Self = 0xFFFF_FFFF;
    const LAST_BIT_INDEX: u32 = 63;
    const ZERO: Self = 0;
    const ONE: Self = 1;
    const TWO: Self = 2;
    const FOUR: Self = 4;
    const MAX: Self = Self::MAX;
    const LAST_BIT: Self = Self::ONE << Self::LAST_BIT_INDEX;

    #[inline(always)]
    fn overflowing_add(self, rhs: Self) -> (Self, bool) {
        self.overflowing_add(rhs)
    }

    #[inline(always)]
    fn from_u64(value: u64) -> Self {
        value
    }

    #[inline(always)]
    fn wrapping_sub(self, rhs: Self) -> Self {
        self.wrapping_sub(rhs)
    }

    #[inline(always)]
    fn leading_zeros(self) -> u32 {
        self.leading_zeros()
    }

    #[inline(always)]
    fn ilog2(self) -> u32 {
        self.ilog2()
    }

    #[inline(always)]
    fn isqrt(self) -> Self {
        self.isqrt()
    }
    #[inline(always)]
    fn to_usize(self) -> usize {
        self as usize
    }

    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
}

impl UIntNumber for u128 {
    type Product = CompositeUIntProduct<Self>;
    const BITS: u32 = 128;
    const HALF_BITS: u32 = 64;
    const HALF_MASK: Self = 0xFFFF_FFFF_FFFF_FFFF;
    const LAST_BIT_INDEX: u32 = 127;
    const ZERO: Self = 0;
    const ONE: Self = 1;
    const TWO: Self = 2;
    const FOUR: Self = 4;
    const MAX: Self = Self::MAX;
    const LAST_BIT: Self = Self::ONE << Self::LAST_BIT_INDEX;
    #[inline(always)]
    fn overflowing_add(self, rhs: Self) -> (Self, bool) {
        self.overflowing_add(rhs)
    }

    #[inline(always)]
    fn from_u64(value: u64) -> Self {
        value as Self
    }

    #[inline(always)]
    fn wrapping_sub(self, rhs: Self) -> Self {
        self.wrapping_sub(rhs)
    }

    #[inline(always)]
    fn leading_zeros(self) -> u32 {
        self.leading_zeros()
    }

    #[inline(always)]
    fn ilog2(self) -> u32 {
        self.ilog2()
    }

    #[inline(always)]
    fn isqrt(self) -> Self {
        self.isqrt()
    }
    #[inline(always)]
    fn to_usize(self) -> usize {
        self as usize
    }

    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    /// Knuth's algorithm D with 64-bit digits: two digits of the
    /// quotient, each estimated from the divisor's top digit and
    /// corrected at most twice.
    #[inline]
    fn divide_wide(high: u128, low: u128, divisor: u128) -> (u128, u128) {
        if divisor >> 64 == 0 {
            // high < divisor < 2^64, so each step's dividend fits in u128.
            let top = (high << 64) | (low >> 64);
            let (q1, r1) = (top / divisor, top % divisor);
            let next = (r1 << 64) | (low & u64::MAX as u128);
            return ((q1 << 64) | (next / divisor), next % divisor);
        }
        let s = divisor.leading_zeros();
        let d = divisor << s;
        let (n_high, n_low) = if s == 0 {
            (high, low)
        } else {
            ((high << s) | (low >> (128 - s)), low << s)
        };
        let (q1, r1) = divide_digit(n_high, (n_low >> 64) as u64, d);
        let (q0, r0) = divide_digit(r1, n_low as u64, d);
        (((q1 as u128) << 64) | q0 as u128, r0 >> s)
    }
}

/// One digit of algorithm D: `(u * 2^64 + v) / d` and its remainder, for
/// `d` with its top bit set and `u < d`, so the quotient is below 2^64.
#[inline]
fn divide_digit(u: u128, v: u64, d: u128) -> (u64, u128) {
    let d1 = (d >> 64) as u64;
    let d0 = d as u64;
    let mut q = if (u >> 64) as u64 >= d1 {
        u64::MAX
    } else {
        (u / d1 as u128) as u64
    };
    // q * d as a 192-bit number (p_high: 128 bits, p_low: 64 bits).
    let low = q as u128 * d0 as u128;
    let mut p_high = q as u128 * d1 as u128 + (low >> 64);
    let mut p_low = low as u64;
    while p_high > u || (p_high == u && p_low > v) {
        q -= 1;
        let (l, borrow) = p_low.overflowing_sub(d0);
        p_low = l;
        p_high = p_high - d1 as u128 - borrow as u128;
    }
    let (r_low, borrow) = v.overflowing_sub(p_low);
    let r_high = u - p_high - borrow as u128;
    (q, (r_high << 64) | r_low as u128)
}

//! The vendored i_float's wide division (vendor/i_float/VENDORED.md),
//! which divides the 256-bit products of i_overlay's crossings, checked
//! without division: the quotient and remainder must rebuild the dividend
//! (`q * d + r == n`, multiplied here in 32-bit digits) with `r < d`, and
//! the rounded quotient must be the one the crate's one-bit loop gives.

use i_overlay::i_float::int::number::product_uint::UIntProduct;
use i_overlay::i_float::int::number::uint::UIntNumber;
use proptest::prelude::*;

/// `a * b + c` as eight 32-bit digits, least significant first.
fn multiply_add(a: u128, b: u128, c: u128) -> [u64; 8] {
    let digits = |x: u128| [0, 1, 2, 3].map(|i| ((x >> (32 * i)) as u32) as u64);
    let (a, b, c) = (digits(a), digits(b), digits(c));
    let mut out = [0u64; 8];
    out[..4].copy_from_slice(&c);
    for i in 0..4 {
        for j in 0..4 {
            out[i + j] += a[i] * b[j];
            // Each digit stays below 2^64: carry before the next product.
            for k in i + j..7 {
                let carry = out[k] >> 32;
                out[k] &= 0xFFFF_FFFF;
                out[k + 1] += carry;
            }
        }
    }
    out
}

/// `high * 2^128 + low` as eight 32-bit digits.
fn wide(high: u128, low: u128) -> [u64; 8] {
    let mut out = [0u64; 8];
    for i in 0..4 {
        out[i] = ((low >> (32 * i)) as u32) as u64;
        out[i + 4] = ((high >> (32 * i)) as u32) as u64;
    }
    out
}

/// The crate's one-bit-at-a-time loop, the trait's default method, run
/// through a wrapper type that does not override it.
fn one_bit_at_a_time(high: u128, low: u128, d: u128) -> (u128, u128) {
    let s = d.leading_zeros();
    let nd = d << s;
    let (mut rh, mut rl) = if s == 0 {
        (high, low)
    } else {
        ((high << s) | (low >> (128 - s)), low << s)
    };
    let mut q = 0u128;
    for _ in 0..128 {
        let bit = rh >> 127 != 0;
        rh = (rh << 1) | (rl >> 127);
        rl <<= 1;
        q <<= 1;
        if rh >= nd || bit {
            rh = rh.wrapping_sub(nd);
            q |= 1;
        }
    }
    (q, rh >> s)
}

fn check(high: u128, low: u128, d: u128) {
    let (q, r) = <u128 as UIntNumber>::divide_wide(high, low, d);
    assert!(r < d, "remainder {r} of ({high}, {low}) / {d}");
    assert_eq!(
        multiply_add(q, d, r),
        wide(high, low),
        "({high}, {low}) / {d} gave {q} rest {r}"
    );
    assert_eq!((q, r), one_bit_at_a_time(high, low, d));
}

/// A dividend `high * 2^128 + low` with `high < d`, from any three
/// numbers: the operation's precondition.
fn case(h: u128, low: u128, d: u128) -> (u128, u128, u128) {
    let d = d.max(1);
    (h % d, low, d)
}

#[test]
fn edge_cases_divide_exactly() {
    let ds = [
        1,
        2,
        3,
        u64::MAX as u128,
        1 << 64,
        (1 << 64) + 1,
        u128::MAX >> 1,
        (u128::MAX >> 1) - 1,
        u128::MAX,
        0x8000_0000_0000_0000_0000_0000_0000_0001,
        0xFFFF_FFFF_FFFF_FFFF_0000_0000_0000_0000,
    ];
    for d in ds {
        for high in [0, 1, d / 2, d - 1].into_iter().filter(|&h| h < d) {
            for low in [0, 1, u64::MAX as u128, u128::MAX, u128::MAX - 1, 1 << 127] {
                check(high, low, d);
            }
        }
    }
}

#[test]
fn the_rounded_quotient_of_a_product_rounds_half_up() {
    type P = <u128 as UIntNumber>::Product;
    // 7 * 3 / 2 = 10.5 rounds to 11.
    assert_eq!(P::multiply(7, 3).divide_with_rounding(2), 11);
    // (2^61 + 1) * 2^100 / 2^101 = 2^60 + 1/2, over 128 bits: up.
    let (q, k) = (1u128 << 60, 1u128 << 100);
    assert_eq!(P::multiply(2 * q + 1, k).divide_with_rounding(2 * k), q + 1);
    // 2^200 = (2^100 + 1)(2^100 - 1) + 1: rest 1, so down.
    assert_eq!(P::multiply(k, k).divide_with_rounding(k + 1), k - 1);
}

proptest! {
    #[test]
    fn any_quotient_rebuilds_its_dividend(h: u128, low: u128, d: u128, shift in 0u32..128) {
        // Divisors of every length, not only the long ones most draws give.
        let (high, low, d) = case(h, low, (d >> shift).max(1));
        check(high, low, d);
    }

    #[test]
    fn rounding_matches_the_one_bit_loop(
        a: u128,
        b: u128,
        d: u128,
        b_shift in 1u32..128,
        shift in 1u32..128,
    ) {
        type P = <u128 as UIntNumber>::Product;
        let b = b >> b_shift;
        let (high, low) = {
            let n = multiply_add(a, b, 0);
            let join = |k: usize| (0..4).fold(0u128, |acc, i| acc | (n[k + i] as u128) << (32 * i));
            (join(4), join(0))
        };
        // The crate asks for high < d < 2^127: b < 2^127 keeps high below
        // 2^127, and a short d is raised to just above high.
        let d = (d >> shift).max(high + 1);
        let (q, r) = one_bit_at_a_time(high, low, d);
        let half = (d >> 1) + (d & 1);
        prop_assume!(q < u128::MAX || r < half);
        let expected = if r >= half { q + 1 } else { q };
        prop_assert_eq!(P::multiply(a, b).divide_with_rounding(d), expected);
    }
}

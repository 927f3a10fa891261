//! How the computed colours become the bytes of an image: the display
//! modes of the rftb manual page (flags `a r g b y c`) and plytrace's
//! `outmode` (004 appendix, OUTMODE COMMANDS), as [`DisplayMode`].
//!
//! # Fewer bits than computed
//!
//! When an output keeps fewer bits than the 8 computed (an `outmode a` of
//! fewer than 8 bits, the 3-3-2 mode `c`, the adaptive look-up table), the
//! intensity is coded pseudo-randomly after Donovan (000 section on the
//! shader: "if an intensity of 10.75 were desired, we could output 10 1/4
//! of the time and 11 3/4 of the time"): the two neighbouring output levels
//! are chosen with the probabilities that keep the mean. The threshold of
//! each pixel and channel is a fast quasi-random number seeded by the
//! pixel position (the R2 additive recurrence), so the output depends on
//! nothing else (not on threads) and a flat area keeps its mean closely.

use crate::model::OutMode;

/// f32 intensities (0 to 1) to bytes, rounded and clamped, one row at a
/// time: `out` gets `rgb.len()` bytes per channel in `channel`.
pub(super) fn channel_to_bytes(rgb: &[[f32; 3]], channel: usize, out: &mut [u8]) {
    for (o, c) in out.iter_mut().zip(rgb) {
        *o = (c[channel] * 255.0 + 0.5).clamp(0.0, 255.0) as u8;
    }
}

/// The quasi-random threshold in [0, 1) of pixel (`x`, `y`), channel `c`:
/// the R2 sequence, a fast generator seeded by the position alone.
#[inline]
fn threshold(x: u32, y: u32, c: usize) -> f32 {
    const A1: f64 = 0.754_877_666_246_692_8;
    const A2: f64 = 0.569_840_290_998_053_3;
    let t = 0.5 + A1 * f64::from(x) + A2 * f64::from(y) + std::f64::consts::FRAC_1_PI * c as f64;
    t.fract() as f32
}

/// Donovan's pseudo-random intensity coding: `v` (0 to 1) to one of
/// `levels + 1` output levels, the neighbours of `v` chosen with the
/// probabilities that keep the mean of the written bytes. Returns the level.
#[inline]
pub fn dither_level(v: f32, levels: u32, x: u32, y: u32, c: usize) -> u32 {
    let t = v.clamp(0.0, 1.0) * 255.0;
    let mut k = (t * levels as f32 / 255.0) as u32;
    k = k.min(levels.saturating_sub(1));
    let lo = level_byte(k, levels) as f32;
    let hi = level_byte(k + 1, levels) as f32;
    let p = ((t - lo) / (hi - lo)).clamp(0.0, 1.0);
    if threshold(x, y, c) < p { k + 1 } else { k }
}

/// The byte written for level `k` of `levels`.
#[inline]
pub fn level_byte(k: u32, levels: u32) -> u8 {
    ((k * 255 + levels / 2) / levels) as u8
}

/// How a [`PngSink`](super::PngSink) shows the colours (the display modes of the rftb
/// manual page, flags `a r g b y c`, and plytrace's `outmode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DisplayMode {
    /// 8 bits per channel.
    Color,
    /// One channel (0 red, 1 green, 2 blue) as 8-bit grey.
    Channel(usize),
    /// Luminance 0.299 R + 0.587 G + 0.114 B as 8-bit grey.
    Luminance,
    /// RGB, each channel quantized to this many bits (1 to 8) and dithered
    /// (plytrace's `outmode a BITS`).
    Quantized(u8),
    /// rftb `-c`: R-G-B encoded as rrr-ggg-bb, dithered.
    Rgb332,
    /// rftb `-a BITS`: an adaptive look-up table of at most 256 colours,
    /// each channel first quantized to BITS bits and dithered; an indexed
    /// PNG. BITS is lowered until the colours fit.
    Adaptive(u8),
}

impl From<OutMode> for DisplayMode {
    fn from(m: OutMode) -> Self {
        match m {
            OutMode::Color => DisplayMode::Color,
            OutMode::Red => DisplayMode::Channel(0),
            OutMode::Green => DisplayMode::Channel(1),
            OutMode::Blue => DisplayMode::Channel(2),
            OutMode::Luminance => DisplayMode::Luminance,
            OutMode::Quantized(b) if b >= 8 => DisplayMode::Color,
            OutMode::Quantized(b) => DisplayMode::Quantized(b.max(1)),
        }
    }
}

/// Output levels per channel of a mode that keeps fewer than 8 bits.
pub(super) fn levels_of(bits: [u8; 3]) -> [u32; 3] {
    bits.map(|b| (1u32 << b.clamp(1, 8)) - 1)
}

/// One row of RGB bytes, each channel dithered to `levels`.
fn dithered_rgb_row(rgb: &[[f32; 3]], y: u32, levels: [u32; 3], out: &mut Vec<u8>) {
    out.clear();
    for (x, c) in rgb.iter().enumerate() {
        for ch in 0..3 {
            let k = dither_level(c[ch], levels[ch], x as u32, y, ch);
            out.push(level_byte(k, levels[ch]));
        }
    }
}

/// One row of 8-bit bytes in `mode`, as [`PngSink`](super::PngSink) writes it (row `y`
/// of the image for the dither): three bytes a pixel, or one for the
/// grey modes. Not for the adaptive mode, whose palette needs the whole
/// image.
pub fn display_row(mode: DisplayMode, rgb: &[[f32; 3]], y: u32, out: &mut Vec<u8>) {
    mode_row(mode, rgb, y, out);
}

/// Whether `mode` writes one grey byte a pixel (else three, or an index).
pub fn is_grey(mode: DisplayMode) -> bool {
    matches!(mode, DisplayMode::Channel(_) | DisplayMode::Luminance)
}

/// One row of 8-bit bytes in `mode` (not the adaptive mode).
pub(super) fn mode_row(mode: DisplayMode, rgb: &[[f32; 3]], y: u32, out: &mut Vec<u8>) {
    match mode {
        DisplayMode::Color => {
            out.resize(rgb.len() * 3, 0);
            // One flat loop of channels: the compiler vectorizes it.
            for (o, c) in out.iter_mut().zip(rgb.as_flattened()) {
                *o = (c * 255.0 + 0.5).clamp(0.0, 255.0) as u8;
            }
        }
        DisplayMode::Channel(ch) => {
            out.resize(rgb.len(), 0);
            channel_to_bytes(rgb, ch, out);
        }
        DisplayMode::Luminance => {
            out.clear();
            out.extend(rgb.iter().map(|c| {
                let l = 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
                (l * 255.0 + 0.5).clamp(0.0, 255.0) as u8
            }));
        }
        DisplayMode::Quantized(b) => dithered_rgb_row(rgb, y, levels_of([b; 3]), out),
        DisplayMode::Rgb332 => dithered_rgb_row(rgb, y, levels_of([3, 3, 2]), out),
        DisplayMode::Adaptive(_) => unreachable!("the adaptive mode is written at finish"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dither_keeps_the_mean_and_is_deterministic() {
        for (levels, v) in [(7u32, 0.3f32), (3, 0.6), (1, 0.37), (15, 0.91), (7, 0.01)] {
            let mut sum = 0u64;
            for y in 0..64 {
                for x in 0..64 {
                    let k = dither_level(v, levels, x + 100, y + 7, 2);
                    assert_eq!(k, dither_level(v, levels, x + 100, y + 7, 2));
                    sum += u64::from(level_byte(k, levels));
                }
            }
            let mean = sum as f32 / 4096.0 / 255.0;
            assert!((mean - v).abs() <= 0.5 / 255.0, "{levels} {v}: {mean}");
        }
        assert_eq!(dither_level(1.0, 3, 5, 5, 0), 3);
        assert_eq!(dither_level(0.0, 3, 5, 5, 0), 0);
    }
}

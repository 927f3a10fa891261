//! The scan conversion processors of Garcia 1986 (004 chapter 5): a
//! [`RecordStream`] in, rows of pixels out, top row first.
//!
//! SKELETON: the types below are the fixed interface between the record
//! stream, the scan converters and the outputs (PNG, separations,
//! pixel-struct files). The implementation is being written.

use crate::error::Result;
use crate::tree::RecordStream;

/// How coverage is found and blended (004 sections 5.6-5.9; Donovan 000
/// section 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// One sample at the pixel centre (the preview, `--aa none`).
    Point,
    /// Method 1 (rftb1): exact area coverage, one coverage byte.
    Area,
    /// Method 2 (rftb2): 4x4 pixel masks.
    Mask,
    /// Method 3 (rftb3): 4x4 masks and exact area.
    Hybrid,
    /// Method 4 (rftb4): multi-level pixel masks (pixel-structs).
    Multilevel,
    /// Donovan's N x N supersampling, N from 1 to 16.
    Supersample(u32),
}

/// How a transparent polygon blends with what is behind it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TransparencyRule {
    /// 004 section 4.9: `I = I_cur + k_t I_behind`.
    #[default]
    Garcia,
    /// Donovan 000 rule (3): `I = I_a` if `I_a > I_b`, else
    /// `(1 - w) I_a + w I_b`.
    Donovan,
}

/// Options of one scan conversion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The method.
    pub method: Method,
    /// Rows of the frame buffer kept in memory at once per band (the
    /// manual's `act-lines`, at least 1).
    pub act_lines: u32,
    /// Paint the background polygon after everything (`-B`; always for
    /// plytrace's own picture).
    pub paint_background: bool,
    /// The transparency rule.
    pub transparency: TransparencyRule,
    /// Worker threads; 0 means all cores. The output does not depend on it.
    pub threads: usize,
    /// Also produce, per pixel, the 1-based index of the record seen at
    /// the pixel centre (0 for none).
    pub ids: bool,
}

/// Figures of one scan conversion.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ScanStats {
    /// Records that covered at least one pixel.
    pub polygons_tiled: usize,
    /// Pixel writes.
    pub pixels_written: u64,
    /// Method 4: the most pixel-fragments alive at once.
    pub peak_fragments: usize,
    /// Method 4: pixel-fragments allocated in all.
    pub total_fragments: u64,
}

/// A pixel-fragment left at a complex pixel (004 figure 5.16), as saved in
/// a pixel-struct file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SavedFragment {
    /// The 4x4 pixel mask, bit `4 * row + column`, row 0 at the top.
    pub pmask: u16,
    /// The saved pixel status (figure 5.17).
    pub pstat: u8,
    /// The pixel coverage, 0 to 255.
    pub pcover: u8,
}

/// A pixel-struct (004 figure 5.15) of method 4.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PixelStruct {
    /// Accumulated colour.
    pub rgb: [u8; 3],
    /// Pixel status (figure 5.17): bits 0-4 the tree depth, bit 5
    /// covered, bit 6 complex.
    pub pixstat: u8,
    /// The fragment list, head (deepest level) first; empty for simple
    /// pixels.
    pub fragments: Vec<SavedFragment>,
}

/// One finished row of the frame buffer.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    /// Row index from the top.
    pub y: u32,
    /// Colours, 0 to 1, the written intensities (no gamma).
    pub rgb: &'a [[f32; 3]],
    /// Methods 1 and 3: coverage bytes (the `.a` separation).
    pub coverage: Option<&'a [u8]>,
    /// Methods 2 and 3: pixel masks (the `.m` separation).
    pub mask: Option<&'a [u16]>,
    /// Method 4: pixel-structs.
    pub pixels: Option<&'a [PixelStruct]>,
    /// With [`ScanOptions::ids`]: record ids.
    pub ids: Option<&'a [u32]>,
}

/// Receives the rows of a scan conversion, top row first, each once.
pub trait RowSink {
    /// Takes one row.
    fn row(&mut self, row: &Row<'_>) -> Result<()>;
}

/// Scan converts `stream` and hands its rows, top first, to `sink`.
pub fn scan_convert(
    stream: &RecordStream,
    options: &ScanOptions,
    sink: &mut dyn RowSink,
) -> Result<ScanStats> {
    let _ = (stream, options, sink);
    unimplemented!("being written")
}

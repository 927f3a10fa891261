//! Writing images: PNG (8 bits per channel) and binary PPM, after the
//! `outmode` conversion (004 appendix, OUTMODE COMMANDS), and the outputs
//! of the scan conversion processors rftb1-4 and getrgb (004 appendix,
//! the rftb and getrgb manual pages). One concept a file:
//!
//! - here: a frame buffer as 8-bit RGB ([`rgb8`]), the id image's false
//!   colours ([`id_color`]), whole PNG and PPM images ([`write_image`],
//!   [`stage_image`]), and the checks the row sinks share;
//! - `atomic.rs`: the one atomic writer ([`AtomicFile`], [`Staged`],
//!   [`commit_all`]) and the checks of an output's name ([`check_target`],
//!   [`check_inside`]);
//! - `display.rs`: the display modes ([`DisplayMode`]) and the
//!   pseudo-random intensity coding of an output that keeps fewer bits
//!   than computed ([`dither_level`]);
//! - the row sinks, each taking the rows of
//!   [`crate::raster::scan::scan_convert`] as they come and holding at
//!   most a row (the adaptive look-up table mode holds the image: its
//!   palette must precede the pixels): `png_sink.rs` ([`PngSink`]),
//!   `separations.rs` ([`SeparationSink`], the colour separations of
//!   rftb1-3 and getrgb) and `pixel_structs.rs` ([`PixelStructSink`],
//!   rftb4's pixel-struct file and its fragment side file, with their
//!   readers [`read_pixel_structs`] and [`visit_pixel_structs`]). Each
//!   file's doc gives the layout it writes.

mod atomic;
mod display;
mod pixel_structs;
mod png_sink;
mod separations;

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::model::OutMode;
use crate::raster::frame_buffer::FrameBuffer;
use crate::raster::scan::Row;
use display::mode_row;

pub use atomic::{
    AtomicFile, Outside, Staged, check_inside, check_target, commit_all, on_lock_wait,
    remove_temporaries, write_atomically,
};
pub use display::{DisplayMode, display_row, dither_level, is_grey, level_byte};
pub use pixel_structs::{
    FRAGMENT_BYTES, FRAGMENT_HEADER_BYTES, FRAGMENT_SUFFIX, FRAGMENT_TAG, PIXEL_STRUCT_BYTES,
    PixelStructRef, PixelStructSink, PixelStructs, read_pixel_structs, side_header,
    visit_pixel_structs,
};
pub use png_sink::PngSink;
pub use separations::{Planes, SeparationSink};

/// One row of colours as 8-bit RGB bytes in `mode` (row `y` for the
/// dither), the same conversion as the streamed PNG; `out` is replaced.
pub fn rgb8_row(rgb: &[[f32; 3]], y: u32, mode: OutMode, out: &mut Vec<u8>) {
    mode_row(DisplayMode::from(mode), rgb, y, out);
    if out.len() == rgb.len() {
        // One grey byte a pixel: repeated for R, G and B.
        let grey = std::mem::take(out);
        out.extend(grey.iter().flat_map(|&g| [g; 3]));
    }
}

/// The frame buffer as 8-bit RGB bytes, rows from the top, in `mode`
/// (the same conversion as the streamed PNG, dither included).
pub fn rgb8(fb: &FrameBuffer, mode: OutMode) -> Vec<u8> {
    let mut out = Vec::with_capacity(fb.color.len() * 3);
    let mut row = Vec::new();
    for (y, colors) in fb.color.chunks(fb.width.max(1) as usize).enumerate() {
        rgb8_row(colors, y as u32, mode, &mut row);
        out.extend_from_slice(&row);
    }
    out
}

/// A colour for id `id` (0 is black), well spread so that neighbours differ.
pub fn id_color(id: u32) -> [u8; 3] {
    if id == 0 {
        return [0, 0, 0];
    }
    let h = id
        .wrapping_mul(0x9E37_79B9)
        .rotate_left(13)
        .wrapping_mul(0x85EB_CA6B);
    [
        (h >> 24) as u8 | 0x20,
        (h >> 16) as u8 | 0x20,
        (h >> 8) as u8 | 0x20,
    ]
}

fn png_bytes(width: u32, height: u32, rgb: &[u8], w: &mut dyn Write) -> std::io::Result<()> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = enc.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(rgb)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}

/// Writes the image as PNG (with an sRGB chunk).
pub fn write_png(path: &Path, fb: &FrameBuffer, mode: OutMode) -> Result<()> {
    stage_png(AtomicFile::create(path)?, fb, mode)?.commit()
}

/// Writes the image as binary PPM (P6).
pub fn write_ppm(path: &Path, fb: &FrameBuffer, mode: OutMode) -> Result<()> {
    stage_ppm(AtomicFile::create(path)?, fb, mode)?.commit()
}

fn stage_png(file: AtomicFile, fb: &FrameBuffer, mode: OutMode) -> Result<Staged> {
    let rgb = rgb8(fb, mode);
    file.write_with(|w| png_bytes(fb.width, fb.height, &rgb, w))
}

fn stage_ppm(file: AtomicFile, fb: &FrameBuffer, mode: OutMode) -> Result<Staged> {
    let rgb = rgb8(fb, mode);
    file.write_with(|w| {
        write!(w, "P6\n{} {}\n255\n", fb.width, fb.height)?;
        w.write_all(&rgb)
    })
}

/// Writes the image in the format its extension names (`.ppm`, else PNG).
pub fn write_image(path: &Path, fb: &FrameBuffer, mode: OutMode) -> Result<()> {
    stage_image(AtomicFile::create(path)?, fb, mode)?.commit()
}

/// Writes the image into `file` (created before the render, see
/// [`check_target`]) in the format its extension names (`.ppm`, else PNG),
/// ready to be committed with the other outputs of the run.
pub fn stage_image(file: AtomicFile, fb: &FrameBuffer, mode: OutMode) -> Result<Staged> {
    match file.path().extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("ppm") => stage_ppm(file, fb, mode),
        _ => stage_png(file, fb, mode),
    }
}

/// The image formats that [`write_image`] writes, by extension.
pub const IMAGE_EXTENSIONS: [&str; 2] = ["png", "ppm"];

/// Checks that `path` names an image format this program writes (its
/// extension is one of [`IMAGE_EXTENSIONS`], in any case); the message
/// names the supported ones.
pub fn check_image_extension(path: &Path) -> std::result::Result<(), String> {
    let ext = path.extension().and_then(|e| e.to_str());
    match ext {
        Some(e) if IMAGE_EXTENSIONS.iter().any(|s| e.eq_ignore_ascii_case(s)) => Ok(()),
        _ => Err(format!(
            "{}: cannot write {}; the supported image formats are .png and .ppm",
            crate::error::printable(&path.display().to_string(), 256),
            match ext {
                Some(e) => format!("a .{} image", crate::error::printable(e, 32)),
                None => "an image without an extension".into(),
            }
        )),
    }
}

/// Writes the id buffer as a false-colour PNG: one colour per (object,
/// polygon) of `polygons` (indexed by id - 1), black for background, so
/// that images of different algorithms compare directly.
pub fn write_id_png(path: &Path, fb: &FrameBuffer, polygons: &[(u32, u32)]) -> Result<()> {
    stage_id_png(AtomicFile::create(path)?, fb, polygons)?.commit()
}

/// [`write_id_png`] into `file`, ready to be committed.
pub fn stage_id_png(file: AtomicFile, fb: &FrameBuffer, polygons: &[(u32, u32)]) -> Result<Staged> {
    let rgb: Vec<u8> = fb
        .ids
        .iter()
        .flat_map(|&id| {
            if id == 0 {
                [0, 0, 0]
            } else {
                let (o, p) = polygons[id as usize - 1];
                id_color(o.wrapping_mul(0x1000_0193) ^ p.wrapping_add(1))
            }
        })
        .collect();
    file.write_with(|w| png_bytes(fb.width, fb.height, &rgb, w))
}

/// Checks that `row` is the next row, `expected`, of an image `width` wide.
fn check_row(row: &Row<'_>, expected: u32, width: u32, path: &Path) -> Result<()> {
    if row.y != expected || row.rgb.len() != width as usize {
        return Err(Error::Invalid(format!(
            "{}: got row {} of {} pixels, expected row {expected} of {width}",
            path.display(),
            row.y,
            row.rgb.len()
        )));
    }
    Ok(())
}

/// Checks that all `height` rows came.
fn check_complete(next: u32, height: u32, path: &Path) -> Result<()> {
    if next != height {
        return Err(Error::Invalid(format!(
            "{}: {next} rows of {height} written; the image is incomplete",
            path.display()
        )));
    }
    Ok(())
}

/// `seed` with `.ext` appended (not replacing an extension: `a.b` gives
/// `a.b.r`).
pub fn with_suffix(seed: &Path, ext: &str) -> PathBuf {
    let mut s = seed.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// The row's plane, which must be there and `w` long.
fn plane<'a, T>(p: Option<&'a [T]>, w: usize, file: &AtomicFile, what: &str) -> Result<&'a [T]> {
    match p {
        Some(p) if p.len() == w => Ok(p),
        _ => Err(Error::Invalid(format!(
            "{}: the scan converter gave no {what} row of {w} pixels",
            file.path().display()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::scan::RowSink;

    #[test]
    fn outmodes_convert() {
        let mut fb = FrameBuffer::new(1, 1, [1.0, 0.5, 0.0]);
        assert_eq!(rgb8(&fb, OutMode::Green), [128; 3]);
        assert_eq!(rgb8(&fb, OutMode::Color), [255, 128, 0]);
        let y = rgb8(&fb, OutMode::Luminance)[0];
        assert_eq!(y, ((0.299 + 0.587 * 0.5) * 255.0f32).round() as u8);
        fb.color[0] = [1.0, 1.0, 0.0];
        assert_eq!(rgb8(&fb, OutMode::Quantized(1)), [255, 255, 0]);
    }

    #[test]
    fn written_pngs_have_srgb() {
        let dir = tempfile::tempdir().unwrap();
        let mut fb = FrameBuffer::new(2, 1, [0.5; 3]);
        fb.ids = vec![0, 1];
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        write_png(&a, &fb, OutMode::Color).unwrap();
        write_id_png(&b, &fb, &[(0, 0)]).unwrap();
        for p in [a, b] {
            let r = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&p).unwrap()))
                .read_info()
                .unwrap();
            assert!(r.info().srgb.is_some(), "{}", p.display());
        }
    }

    #[test]
    fn ppm_header_and_size() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.ppm");
        let fb = FrameBuffer::new(3, 2, [1.0, 0.0, 0.0]);
        write_image(&path, &fb, OutMode::Color).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"P6\n3 2\n255\n"));
        assert_eq!(bytes.len(), 11 + 18);
        assert_eq!(&bytes[11..14], &[255, 0, 0]);
    }

    pub(super) fn row<'a>(y: u32, rgb: &'a [[f32; 3]]) -> Row<'a> {
        Row {
            y,
            rgb,
            coverage: None,
            mask: None,
            pixels: None,
            ids: None,
        }
    }

    #[test]
    fn unfinished_sinks_leave_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let rgb = [[0.5f32; 3]; 2];
        let mut s = SeparationSink::create(&dir.path().join("s"), 2, 2, Planes::default()).unwrap();
        s.row(&row(0, &rgb)).unwrap();
        assert!(s.finish().is_err());
        let mut p = PngSink::create(&dir.path().join("p.png"), 2, 2, DisplayMode::Color).unwrap();
        p.row(&row(0, &rgb)).unwrap();
        drop(p);
        let mut q = PixelStructSink::create(&dir.path().join("q"), 2, 1).unwrap();
        assert!(q.row(&row(0, &rgb)).is_err(), "no pixel-structs in the row");
        drop(q);
        let s = SeparationSink::create(&dir.path().join("z"), 2, 1, Planes::default()).unwrap();
        let staged = s.finish();
        assert!(staged.is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}

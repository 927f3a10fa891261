//! Writing images: PNG (8 bits per channel) and binary PPM, after the
//! `outmode` conversion (004 appendix, OUTMODE COMMANDS). Files are written
//! to a temporary name in the same directory and renamed when complete, so
//! a failure never leaves a partial image behind.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::raster::frame_buffer::FrameBuffer;
use crate::scene::model::OutMode;

/// The image as 8-bit RGB bytes, top row first, after `mode`.
pub fn rgb8(fb: &FrameBuffer, mode: OutMode) -> Vec<u8> {
    let mut out = Vec::with_capacity(fb.color.len() * 3);
    for c in &fb.color {
        let px = convert(*c, mode);
        out.extend(px.map(to_byte));
    }
    out
}

fn to_byte(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn convert(c: [f32; 3], mode: OutMode) -> [f32; 3] {
    match mode {
        OutMode::Color => c,
        OutMode::Red => [c[0]; 3],
        OutMode::Green => [c[1]; 3],
        OutMode::Blue => [c[2]; 3],
        OutMode::Luminance => [0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]; 3],
        OutMode::Quantized(bits) => {
            let levels = ((1u32 << bits) - 1) as f32;
            c.map(|v| (v.clamp(0.0, 1.0) * levels).round() / levels)
        }
    }
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

/// Writes `bytes` produced by `write` to `path` through a temporary file in
/// the same directory, renamed into place only when everything succeeded.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| Error::Invalid(format!("{}: not a file name", path.display())))?;
    let tmp: PathBuf = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        write(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}

fn png_bytes(width: u32, height: u32, rgb: &[u8], w: &mut dyn Write) -> std::io::Result<()> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(rgb)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}

/// Writes the image as PNG.
pub fn write_png(path: &Path, fb: &FrameBuffer, mode: OutMode) -> Result<()> {
    let rgb = rgb8(fb, mode);
    write_atomically(path, |w| png_bytes(fb.width, fb.height, &rgb, w))
}

/// Writes the image as binary PPM (P6).
pub fn write_ppm(path: &Path, fb: &FrameBuffer, mode: OutMode) -> Result<()> {
    let rgb = rgb8(fb, mode);
    write_atomically(path, |w| {
        write!(w, "P6\n{} {}\n255\n", fb.width, fb.height)?;
        w.write_all(&rgb)
    })
}

/// Writes the image in the format its extension names (`.ppm`, else PNG).
pub fn write_image(path: &Path, fb: &FrameBuffer, mode: OutMode) -> Result<()> {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("ppm") => write_ppm(path, fb, mode),
        _ => write_png(path, fb, mode),
    }
}

/// Writes the id buffer as a false-colour PNG: one colour per (object,
/// polygon) of `polygons` (indexed by id - 1), black for background, so
/// that images of different algorithms compare directly.
pub fn write_id_png(path: &Path, fb: &FrameBuffer, polygons: &[(u32, u32)]) -> Result<()> {
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
    write_atomically(path, |w| png_bytes(fb.width, fb.height, &rgb, w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outmodes_convert() {
        let c = [1.0, 0.5, 0.0];
        assert_eq!(convert(c, OutMode::Green), [0.5; 3]);
        assert_eq!(convert(c, OutMode::Quantized(1)), [1.0, 1.0, 0.0]);
        let y = convert(c, OutMode::Luminance)[0];
        assert!((y - (0.299 + 0.587 * 0.5)).abs() < 1e-6);
        assert_eq!(to_byte(0.5), 128);
    }

    #[test]
    fn failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.png");
        let r = write_atomically(&path, |_| Err(std::io::Error::other("boom")));
        assert!(r.is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
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
}

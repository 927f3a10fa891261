//! [`PngSink`]: the rows of the scan converter streamed into a PNG in a
//! [`DisplayMode`], 8 bits per channel (grey, RGB, or indexed for the
//! adaptive look-up table of rftb `-a`), fast compression, with an sRGB
//! chunk. It holds at most a row, except in the adaptive mode, which
//! holds the image: its palette must precede the pixels.

use std::io::Write;
use std::path::Path;

use super::atomic::{AtomicFile, Staged};
use super::display::{DisplayMode, dither_level, is_grey, level_byte, levels_of, mode_row};
use super::{check_complete, check_row};
use crate::error::{Error, Result};
use crate::raster::scan::{Row, RowSink};

fn png_error(path: &Path, e: png::EncodingError) -> Error {
    match e {
        png::EncodingError::IoError(io) => Error::io(path, io),
        other => Error::io(path, std::io::Error::other(other)),
    }
}

/// A PNG encoder with this sink's settings.
fn png_encoder<W: Write>(
    w: W,
    width: u32,
    height: u32,
    color: png::ColorType,
) -> png::Encoder<'static, W> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(color);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    enc
}

/// Streams rows into a PNG (see the module doc).
pub struct PngSink {
    // Dropped before `file`: an unfinished stream writes into the temporary.
    stream: Option<png::StreamWriter<'static, std::fs::File>>,
    file: AtomicFile,
    mode: DisplayMode,
    width: u32,
    height: u32,
    next: u32,
    buf: Vec<u8>,
    /// The adaptive mode's image, held until the palette is known.
    held: Vec<[f32; 3]>,
}

impl PngSink {
    /// Starts writing a `width` x `height` PNG in `mode` to `path`.
    pub fn create(path: &Path, width: u32, height: u32, mode: DisplayMode) -> Result<PngSink> {
        PngSink::from_file(AtomicFile::create(path)?, width, height, mode)
    }

    /// Starts writing a `width` x `height` PNG in `mode` into `file`,
    /// created before the render.
    pub fn from_file(
        file: AtomicFile,
        width: u32,
        height: u32,
        mode: DisplayMode,
    ) -> Result<PngSink> {
        let path = file.path().to_path_buf();
        let path = path.as_path();
        let stream = match mode {
            DisplayMode::Adaptive(_) => None,
            _ => {
                let color = match mode {
                    DisplayMode::Channel(_) | DisplayMode::Luminance => png::ColorType::Grayscale,
                    _ => png::ColorType::Rgb,
                };
                let w = file.file().try_clone().map_err(|e| Error::io(path, e))?;
                let enc = png_encoder(w, width, height, color);
                let writer = enc.write_header().map_err(|e| png_error(path, e))?;
                Some(
                    writer
                        .into_stream_writer()
                        .map_err(|e| png_error(path, e))?,
                )
            }
        };
        Ok(PngSink {
            stream,
            file,
            mode,
            width,
            height,
            next: 0,
            buf: Vec::new(),
            held: Vec::new(),
        })
    }

    /// Completes the PNG under its temporary name; [`Staged::commit`]
    /// renames it. Returns a note for the log when the adaptive mode had
    /// to lower its bits.
    pub fn finish(mut self) -> Result<(Staged, Option<String>)> {
        check_complete(self.next, self.height, self.file.path())?;
        let mut note = None;
        if let Some(stream) = self.stream.take() {
            stream
                .finish()
                .map_err(|e| png_error(self.file.path(), e))?;
        } else if let DisplayMode::Adaptive(bits) = self.mode {
            note = self.write_adaptive(bits)?;
        }
        Ok((self.file.finish()?, note))
    }

    fn write_adaptive(&mut self, bits: u8) -> Result<Option<String>> {
        let path = self.file.path().to_path_buf();
        let (used, palette, indices) = adaptive_table(&self.held, self.width, bits);
        let w = self
            .file
            .file()
            .try_clone()
            .map_err(|e| Error::io(&path, e))?;
        let mut enc = png_encoder(w, self.width, self.height, png::ColorType::Indexed);
        enc.set_palette(palette.concat());
        let mut writer = enc.write_header().map_err(|e| png_error(&path, e))?;
        writer
            .write_image_data(&indices)
            .map_err(|e| png_error(&path, e))?;
        writer.finish().map_err(|e| png_error(&path, e))?;
        Ok((used != bits).then(|| {
            format!(
                "{}: more than 256 colours at {bits} bits per colour; used {used}",
                path.display()
            )
        }))
    }
}

/// The adaptive look-up table: the bits used (at most `bits`), the palette
/// and one index per pixel.
fn adaptive_table(image: &[[f32; 3]], width: u32, bits: u8) -> (u8, Vec<[u8; 3]>, Vec<u8>) {
    let mut b = bits.clamp(1, 8);
    loop {
        let levels = levels_of([b; 3]);
        let mut table: std::collections::HashMap<[u8; 3], u8> = std::collections::HashMap::new();
        let mut palette = Vec::new();
        let mut indices = Vec::with_capacity(image.len());
        let mut fits = true;
        for (i, c) in image.iter().enumerate() {
            let (x, y) = ((i as u32) % width.max(1), (i as u32) / width.max(1));
            let q: [u8; 3] = std::array::from_fn(|ch| {
                level_byte(dither_level(c[ch], levels[ch], x, y, ch), levels[ch])
            });
            let idx = match table.get(&q) {
                Some(&i) => i,
                None if palette.len() == 256 => {
                    fits = false;
                    break;
                }
                None => {
                    palette.push(q);
                    let i = (palette.len() - 1) as u8;
                    table.insert(q, i);
                    i
                }
            };
            indices.push(idx);
        }
        if fits || b == 1 {
            return (b, palette, indices);
        }
        b -= 1;
    }
}

impl PngSink {
    /// Takes row `y` already in the bytes of the sink's mode (as
    /// [`display_row`](super::display_row) makes them): the PNG is the one [`RowSink::row`]
    /// writes from the same colours.
    pub fn row_bytes(&mut self, y: u32, bytes: &[u8]) -> Result<()> {
        let per_pixel = if is_grey(self.mode) { 1 } else { 3 };
        let path = self.file.path();
        if y != self.next || bytes.len() != self.width as usize * per_pixel {
            return Err(Error::Invalid(format!(
                "{}: got row {y} of {} bytes, expected row {} of {}",
                path.display(),
                bytes.len(),
                self.next,
                self.width as usize * per_pixel
            )));
        }
        let Some(stream) = self.stream.as_mut() else {
            return Err(Error::Invalid(format!(
                "{}: the adaptive look-up table is not written from bytes",
                path.display()
            )));
        };
        self.next += 1;
        stream.write_all(bytes).map_err(|e| Error::io(path, e))
    }
}

impl RowSink for PngSink {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        check_row(row, self.next, self.width, self.file.path())?;
        self.next += 1;
        if let Some(stream) = self.stream.as_mut() {
            mode_row(self.mode, row.rgb, row.y, &mut self.buf);
            let path = self.file.path();
            stream
                .write_all(&self.buf)
                .map_err(|e| Error::io(path, e))?;
        } else {
            self.held.extend_from_slice(row.rgb);
        }
        Ok(())
    }

    fn wants_pixel_structs(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::row;

    #[test]
    fn png_sink_has_srgb_and_modes() {
        let dir = tempfile::tempdir().unwrap();
        let rgb = [[1.0f32, 0.5, 0.0], [0.2, 0.2, 0.2]];
        for (name, mode, color) in [
            ("c.png", DisplayMode::Color, png::ColorType::Rgb),
            ("g.png", DisplayMode::Channel(1), png::ColorType::Grayscale),
            ("y.png", DisplayMode::Luminance, png::ColorType::Grayscale),
            ("q.png", DisplayMode::Rgb332, png::ColorType::Rgb),
            ("a.png", DisplayMode::Adaptive(4), png::ColorType::Indexed),
        ] {
            let path = dir.path().join(name);
            let mut sink = PngSink::create(&path, 2, 2, mode).unwrap();
            sink.row(&row(0, &rgb)).unwrap();
            sink.row(&row(1, &rgb)).unwrap();
            let (staged, note) = sink.finish().unwrap();
            assert!(note.is_none());
            staged.commit().unwrap();
            let decoder =
                png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
            let reader = decoder.read_info().unwrap();
            let info = reader.info();
            assert!(info.srgb.is_some(), "{name}: no sRGB chunk");
            assert_eq!(info.color_type, color, "{name}");
        }
        let mut r = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(dir.path().join("g.png")).unwrap(),
        ))
        .read_info()
        .unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        r.next_frame(&mut buf).unwrap();
        assert_eq!(&buf[..4], &[128, 51, 128, 51]);
    }

    #[test]
    fn adaptive_table_lowers_bits_to_fit() {
        let w = 64u32;
        let image: Vec<[f32; 3]> = (0..w * w)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                [
                    x as f32 / 63.0,
                    y as f32 / 63.0,
                    ((x + y) % 64) as f32 / 63.0,
                ]
            })
            .collect();
        let (bits, palette, indices) = adaptive_table(&image, w, 8);
        assert!(bits < 8 && palette.len() <= 256, "{bits}");
        assert_eq!(indices.len(), image.len());
        let (bits, _, _) = adaptive_table(&[[0.5; 3]; 4], 2, 8);
        assert_eq!(bits, 8);
    }
}

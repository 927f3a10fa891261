//! The pixel-struct file of rftb4 (004 figure 5.15) and its fragment side
//! file: [`PixelStructSink`] writes them, [`read_pixel_structs`] and
//! [`visit_pixel_structs`] (getrgb's) read them back. The getrgb manual
//! page: "A pixel-struct file is assumed to contain a linear list of
//! 64-bit data structures", so the file `OUTPUT` is exactly `hres * vres`
//! of them and nothing else (getrgb can read it without knowing the
//! resolution); what a pointer cannot carry into a file, the fragment
//! lists, and the resolution go to the side file `OUTPUT.frag`. All
//! integers little-endian:
//!
//! ```text
//! OUTPUT:       hres * vres pixel-structs, top row first, 8 bytes each:
//!                 flist u32, r u8, g u8, b u8, pixstat u8
//! OUTPUT.frag:  "FRAG", hres u32, vres u32 (12 bytes), then the fragment
//!                 lists one after the other, each
//!                 count u32, then count x (pmask u16, pstat u8, pcover u8)
//! ```
//!
//! `flist` is 0 for a pixel without fragments, else 1 + the byte offset of
//! its list (of the count) from the first list (byte 12 of the side file).
//! Lists are stored in pixel order, so the lists are exactly those that the
//! pixels point to. A fragment list keeps the order of
//! [`PixelStruct::fragments`] (head, the deepest level, first). After
//! `-B` (the background pass frees every fragment, 004 section 5.9) the
//! side file is its 12-byte header.

use std::path::Path;

use super::atomic::{AtomicFile, Staged};
use super::{check_complete, check_row, plane, with_suffix};
use crate::error::{Error, Location, Result};
use crate::raster::scan::{PixelStruct, Row, RowSink, SavedFragment};

/// Bytes of one saved fragment in a pixel-struct file.
pub const FRAGMENT_BYTES: usize = 4;
/// Bytes of one pixel-struct.
pub const PIXEL_STRUCT_BYTES: usize = 8;
/// The suffix of rftb4's fragment side file, `OUTPUT.frag`.
pub const FRAGMENT_SUFFIX: &str = "frag";
/// The tag that starts a fragment side file.
pub const FRAGMENT_TAG: &[u8; 4] = b"FRAG";
/// Bytes of the side file's header: the tag, hres u32, vres u32.
pub const FRAGMENT_HEADER_BYTES: usize = 12;

/// Writes the pixel-struct file of rftb4 and its fragment side file
/// `PATH.frag` (layouts in the module doc), both streamed.
pub struct PixelStructSink {
    file: AtomicFile,
    side: AtomicFile,
    side_len: u64,
    width: u32,
    height: u32,
    next: u32,
    buf: Vec<u8>,
    frag_buf: Vec<u8>,
}

impl PixelStructSink {
    /// Starts the files `path` and `path.frag`.
    pub fn create(path: &Path, width: u32, height: u32) -> Result<PixelStructSink> {
        let file = AtomicFile::create(path)?;
        let mut side = AtomicFile::create(&with_suffix(path, FRAGMENT_SUFFIX))?;
        let mut header = FRAGMENT_TAG.to_vec();
        header.extend_from_slice(&width.to_le_bytes());
        header.extend_from_slice(&height.to_le_bytes());
        side.write_all(&header)?;
        Ok(PixelStructSink {
            file,
            side,
            side_len: 0,
            width,
            height,
            next: 0,
            buf: Vec::new(),
            frag_buf: Vec::new(),
        })
    }

    /// Completes both files under their temporary names: the pixel-struct
    /// file, then the side file.
    pub fn finish(self) -> Result<Vec<Staged>> {
        check_complete(self.next, self.height, self.file.path())?;
        Ok(vec![self.file.finish()?, self.side.finish()?])
    }
}

impl RowSink for PixelStructSink {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        check_row(row, self.next, self.width, self.file.path())?;
        self.next += 1;
        let pixels = plane(row.pixels, self.width as usize, &self.file, "pixel-struct")?;
        self.buf.clear();
        self.frag_buf.clear();
        for p in pixels {
            let flist = if p.fragments.is_empty() {
                0
            } else {
                let at = self.side_len + self.frag_buf.len() as u64 + 1;
                let at = u32::try_from(at).map_err(|_| {
                    Error::Invalid(format!(
                        "{}: the fragment lists pass 4 GiB",
                        self.side.path().display()
                    ))
                })?;
                push_fragments(&p.fragments, &mut self.frag_buf);
                at
            };
            self.buf.extend_from_slice(&flist.to_le_bytes());
            self.buf
                .extend_from_slice(&[p.rgb[0], p.rgb[1], p.rgb[2], p.pixstat]);
        }
        self.file.write_all(&self.buf)?;
        self.side.write_all(&self.frag_buf)?;
        self.side_len += self.frag_buf.len() as u64;
        Ok(())
    }
}

fn push_fragments(fragments: &[SavedFragment], out: &mut Vec<u8>) {
    out.extend_from_slice(&(fragments.len() as u32).to_le_bytes());
    for f in fragments {
        out.extend_from_slice(&f.pmask.to_le_bytes());
        out.push(f.pstat);
        out.push(f.pcover);
    }
}

/// A pixel-struct file as read back.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PixelStructs {
    /// `(hres, vres)` from the side file, when there was one.
    pub resolution: Option<(u32, u32)>,
    /// The pixels, top row first; without a side file no pixel has
    /// fragments (`flist` is not followed).
    pub pixels: Vec<PixelStruct>,
}

/// Reads a pixel-struct file (`bytes`, named `path` in errors) and, when
/// given, its fragment side file (`side`: bytes and name), checking that
/// the file is a whole number of 8-byte pixel-structs, that the side file
/// is for as many pixels, and that its lists are exactly those the pixels
/// point to, in pixel order (layouts in the module doc). The pixels take
/// about four times the file's bytes in memory: a program reading files
/// it did not make uses [`visit_pixel_structs`], which holds nothing.
pub fn read_pixel_structs(
    bytes: &[u8],
    path: &Path,
    side: Option<(&[u8], &Path)>,
) -> Result<PixelStructs> {
    let mut pixels = Vec::new();
    let resolution = visit_pixel_structs(bytes, path, side, |p| {
        if pixels.is_empty() {
            pixels.reserve_exact(bytes.len() / PIXEL_STRUCT_BYTES);
        }
        pixels.push(PixelStruct {
            rgb: p.rgb,
            pixstat: p.pixstat,
            fragments: read_fragments(p.fragments),
        });
        Ok(())
    })?;
    Ok(PixelStructs { resolution, pixels })
}

/// One pixel-struct as [`visit_pixel_structs`] hands it over.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelStructRef<'a> {
    /// Its index in the linear list.
    pub index: usize,
    /// The colour.
    pub rgb: [u8; 3],
    /// The pixel status.
    pub pixstat: u8,
    /// Its fragment list without the count, [`FRAGMENT_BYTES`] a fragment
    /// (empty without a side file or for a simple pixel).
    pub fragments: &'a [u8],
}

/// Checks the headers of a pixel-struct file and its side file, then hands
/// every pixel-struct to `visit` in order, stopping at the first error
/// (the visitor's own included), and returns the side file's resolution.
/// It allocates nothing: the lists are checked as the pixels reach them,
/// each nonzero `flist` pointing at the next list, and no list left over.
pub fn visit_pixel_structs(
    bytes: &[u8],
    path: &Path,
    side: Option<(&[u8], &Path)>,
    mut visit: impl FnMut(PixelStructRef<'_>) -> Result<()>,
) -> Result<Option<(u32, u32)>> {
    if bytes.is_empty() || !bytes.len().is_multiple_of(PIXEL_STRUCT_BYTES) {
        return Err(Error::at(
            Location::file(path),
            format!(
                "{} bytes is not a whole, non-zero number of 8-byte pixel-structs (a \
                 pixel-struct file is \"a linear list of 64-bit data structures\")",
                bytes.len()
            ),
        ));
    }
    let n = bytes.len() / PIXEL_STRUCT_BYTES;
    let (resolution, section, side_path) = side_lists(side, path, n)?;
    let width = resolution.map_or(n, |(w, _)| w as usize).max(1);
    let broken = |at: usize| {
        Error::at(
            Location::file(side_path),
            format!(
                "the fragment lists are broken at byte {}",
                at as u64 + FRAGMENT_HEADER_BYTES as u64
            ),
        )
    };
    // The offset of the next list in the side file's lists.
    let mut next = 0usize;
    for (index, p) in bytes.chunks_exact(PIXEL_STRUCT_BYTES).enumerate() {
        let flist = u32::from_le_bytes([p[0], p[1], p[2], p[3]]);
        let fragments = match section {
            Some(section) if flist != 0 => {
                if flist as usize - 1 != next {
                    return Err(Error::at(
                        Location::file(path),
                        format!(
                            "pixel {index} (x {}, y {}): flist {flist} points at no fragment \
                             list of {} (the next list is at flist {})",
                            index % width,
                            index / width,
                            side_path.display(),
                            next as u64 + 1
                        ),
                    ));
                }
                let (list, end) = fragment_list(section, next).ok_or_else(|| broken(next))?;
                next = end;
                list
            }
            _ => &[][..],
        };
        visit(PixelStructRef {
            index,
            rgb: [p[4], p[5], p[6]],
            pixstat: p[7],
            fragments,
        })?;
    }
    if let Some(section) = section
        && next != section.len()
    {
        return Err(Error::at(
            Location::file(side_path),
            format!(
                "{} bytes of fragment lists from byte {} are pointed to by no pixel",
                section.len() - next,
                next as u64 + FRAGMENT_HEADER_BYTES as u64
            ),
        ));
    }
    Ok(resolution)
}

/// The side file's resolution and fragment lists (after its header) and
/// the name errors about the lists give (the pixel-struct file's without
/// a side file), checked to be for the `n` pixel-structs of `path`.
fn side_lists<'a>(
    side: Option<(&'a [u8], &'a Path)>,
    path: &'a Path,
    n: usize,
) -> Result<SideLists<'a>> {
    let lists = match side {
        None => (None, None, path),
        Some((side, side_path)) => {
            let (w, h) = side_header(side, side_path)?;
            let pixels = u64::from(w) * u64::from(h);
            if pixels != n as u64 {
                return Err(Error::at(
                    Location::file(side_path),
                    format!(
                        "it is for a {w} x {h} image ({pixels} pixel-structs), but {} holds \
                         {n}: the two files are not from the same rftb4 run",
                        path.display()
                    ),
                ));
            }
            (
                Some((w, h)),
                Some(&side[FRAGMENT_HEADER_BYTES..]),
                side_path,
            )
        }
    };
    Ok(lists)
}

/// What [`side_lists`] finds: the resolution, the fragment lists and the
/// side file's name.
type SideLists<'a> = (Option<(u32, u32)>, Option<&'a [u8]>, &'a Path);

/// The resolution a fragment side file starts with.
pub fn side_header(side: &[u8], side_path: &Path) -> Result<(u32, u32)> {
    if side.len() < FRAGMENT_HEADER_BYTES || &side[..4] != FRAGMENT_TAG {
        return Err(Error::at(
            Location::file(side_path),
            format!(
                "not an rftb4 fragment file: it must start with `FRAG` and the \
                 resolution ({FRAGMENT_HEADER_BYTES} bytes)"
            ),
        ));
    }
    let w = u32::from_le_bytes([side[4], side[5], side[6], side[7]]);
    let h = u32::from_le_bytes([side[8], side[9], side[10], side[11]]);
    Ok((w, h))
}

/// The fragments of the list at `at` in `section` (without its count) and
/// the offset after it; `None` when no whole, non-empty list starts there.
/// A list's offset must fit `flist` (a u32 less one).
fn fragment_list(section: &[u8], at: usize) -> Option<(&[u8], usize)> {
    if u32::try_from(at).ok()? == u32::MAX {
        return None;
    }
    let head = section.get(at..at.checked_add(4)?)?;
    let count = u32::from_le_bytes([head[0], head[1], head[2], head[3]]) as usize;
    let end = count
        .checked_mul(FRAGMENT_BYTES)?
        .checked_add(at + 4)
        .filter(|&e| e <= section.len() && count > 0)?;
    Some((&section[at + 4..end], end))
}

/// The fragments of a list (already checked: a whole number of them).
fn read_fragments(list: &[u8]) -> Vec<SavedFragment> {
    list.chunks_exact(FRAGMENT_BYTES)
        .map(|f| SavedFragment {
            pmask: u16::from_le_bytes([f[0], f[1]]),
            pstat: f[2],
            pcover: f[3],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::commit_all;
    use crate::output::tests::row;

    #[test]
    fn pixel_struct_round_trip_2x2() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ps");
        let f = |pmask, pstat, pcover| SavedFragment {
            pmask,
            pstat,
            pcover,
        };
        let px = |rgb, pixstat, fragments| PixelStruct {
            rgb,
            pixstat,
            fragments,
        };
        let rows = [
            vec![
                px([1, 2, 3], 0x21, vec![]),
                px([4, 5, 6], 0x62, vec![f(0x1234, 7, 8), f(0xFFFF, 9, 10)]),
            ],
            vec![
                px([7, 8, 9], 0x63, vec![f(1, 2, 3)]),
                px([0, 0, 0], 0, vec![]),
            ],
        ];
        let rgb = [[0.0f32; 3]; 2];
        let mut sink = PixelStructSink::create(&path, 2, 2).unwrap();
        for (y, r) in rows.iter().enumerate() {
            let mut row = row(y as u32, &rgb);
            row.pixels = Some(r);
            sink.row(&row).unwrap();
        }
        commit_all(sink.finish().unwrap()).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            0, 0, 0, 0, 1, 2, 3, 0x21,
            1, 0, 0, 0, 4, 5, 6, 0x62,
            13, 0, 0, 0, 7, 8, 9, 0x63,
            0, 0, 0, 0, 0, 0, 0, 0,
        ];
        assert_eq!(bytes, expected, "exactly 2 x 2 pixel-structs");
        let side_path = with_suffix(&path, "frag");
        let side = std::fs::read(&side_path).unwrap();
        #[rustfmt::skip]
        let expected_side: Vec<u8> = vec![
            b'F', b'R', b'A', b'G', 2, 0, 0, 0, 2, 0, 0, 0,
            2, 0, 0, 0, 0x34, 0x12, 7, 8, 0xFF, 0xFF, 9, 10,
            1, 0, 0, 0, 1, 0, 2, 3,
        ];
        assert_eq!(side, expected_side);
        let back = read_pixel_structs(&bytes, &path, Some((&side, &side_path))).unwrap();
        assert_eq!(back.resolution, Some((2, 2)));
        assert_eq!(back.pixels, rows.concat());
        let alone = read_pixel_structs(&bytes, &path, None).unwrap();
        assert_eq!(alone.resolution, None);
        assert!(alone.pixels.iter().all(|p| p.fragments.is_empty()));
        assert!(read_pixel_structs(&bytes[..24], &path, Some((&side, &side_path))).is_err());
        assert!(read_pixel_structs(&bytes[..31], &path, None).is_err());
        assert!(read_pixel_structs(&[], &path, None).is_err());
        let cut = &side[..side.len() - 1];
        assert!(read_pixel_structs(&bytes, &path, Some((cut, &side_path))).is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }
}

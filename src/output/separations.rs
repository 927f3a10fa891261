//! [`SeparationSink`]: the colour separations of rftb1-3 and getrgb (004
//! appendix, the rftb and getrgb manual pages), `SEED.r`, `SEED.g`,
//! `SEED.b` (one byte per pixel, `hres x vres`, top row first, no
//! header), `SEED.a` (one coverage byte per pixel) and `SEED.m` (one 4x4
//! pixel mask per pixel, u16 little-endian, bit `4 * row + column`),
//! streamed a row at a time.

use std::path::{Path, PathBuf};

use super::atomic::{AtomicFile, Staged};
use super::display::channel_to_bytes;
use super::{check_complete, check_row, plane, with_suffix};
use crate::error::Result;
use crate::raster::scan::{Row, RowSink};

/// Which planes a [`SeparationSink`] writes besides `.r .g .b`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Planes {
    /// `.a`, the coverage bytes.
    pub coverage: bool,
    /// `.m`, the pixel masks.
    pub mask: bool,
}

/// Writes the separations `SEED.r .g .b [.a] [.m]` (see the module doc).
pub struct SeparationSink {
    files: Vec<AtomicFile>,
    planes: Planes,
    width: u32,
    height: u32,
    next: u32,
    buf: Vec<u8>,
}

impl SeparationSink {
    /// The files this sink writes for `seed`.
    pub fn paths(seed: &Path, planes: Planes) -> Vec<PathBuf> {
        let mut exts = vec!["r", "g", "b"];
        if planes.coverage {
            exts.push("a");
        }
        if planes.mask {
            exts.push("m");
        }
        exts.into_iter().map(|e| with_suffix(seed, e)).collect()
    }

    /// Starts the files of `seed`.
    pub fn create(seed: &Path, width: u32, height: u32, planes: Planes) -> Result<SeparationSink> {
        let files = Self::paths(seed, planes)
            .iter()
            .map(|p| AtomicFile::create(p))
            .collect::<Result<Vec<_>>>()?;
        Ok(SeparationSink {
            files,
            planes,
            width,
            height,
            next: 0,
            buf: Vec::new(),
        })
    }

    /// Completes the files under their temporary names.
    pub fn finish(self) -> Result<Vec<Staged>> {
        check_complete(self.next, self.height, self.files[0].path())?;
        self.files.into_iter().map(AtomicFile::finish).collect()
    }
}

impl RowSink for SeparationSink {
    fn row(&mut self, row: &Row<'_>) -> Result<()> {
        check_row(row, self.next, self.width, self.files[0].path())?;
        self.next += 1;
        let w = self.width as usize;
        self.buf.resize(w, 0);
        for ch in 0..3 {
            channel_to_bytes(row.rgb, ch, &mut self.buf);
            self.files[ch].write_all(&self.buf)?;
        }
        let mut i = 3;
        if self.planes.coverage {
            let cov = plane(row.coverage, w, &self.files[i], "coverage")?;
            self.files[i].write_all(cov)?;
            i += 1;
        }
        if self.planes.mask {
            let masks = plane(row.mask, w, &self.files[i], "mask")?;
            self.buf.clear();
            self.buf.extend(masks.iter().flat_map(|m| m.to_le_bytes()));
            self.files[i].write_all(&self.buf)?;
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
    use crate::output::commit_all;
    use crate::output::tests::row;

    #[test]
    fn separations_2x2_layout() {
        let dir = tempfile::tempdir().unwrap();
        let seed = dir.path().join("t");
        let planes = Planes {
            coverage: true,
            mask: true,
        };
        let mut sink = SeparationSink::create(&seed, 2, 2, planes).unwrap();
        let rows = [
            [[1.0, 0.0, 0.5], [0.0, 1.0, 0.25]],
            [[2.0, -1.0, 0.0], [0.2, 0.4, 0.6]],
        ];
        let covs = [[255u8, 1], [2, 3]];
        let masks = [[0xFFFFu16, 0x0102], [0x8000, 0]];
        for y in 0..2 {
            let mut r = row(y as u32, &rows[y]);
            r.coverage = Some(&covs[y]);
            r.mask = Some(&masks[y]);
            sink.row(&r).unwrap();
        }
        commit_all(sink.finish().unwrap()).unwrap();
        let read = |e: &str| std::fs::read(with_suffix(&seed, e)).unwrap();
        assert_eq!(read("r"), [255, 0, 255, 51]);
        assert_eq!(read("g"), [0, 255, 0, 102]);
        assert_eq!(read("b"), [128, 64, 0, 153]);
        assert_eq!(read("a"), [255, 1, 2, 3]);
        assert_eq!(read("m"), [0xFF, 0xFF, 0x02, 0x01, 0x00, 0x80, 0, 0]);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 5);
    }
}

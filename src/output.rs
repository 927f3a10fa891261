//! Writing images: PNG (8 bits per channel) and binary PPM, after the
//! `outmode` conversion (004 appendix, OUTMODE COMMANDS), and the outputs
//! of the scan conversion processors rftb1-4 and getrgb (004 appendix,
//! the rftb and getrgb manual pages). Files are written to a temporary
//! name in the same directory and renamed when complete, so a failure
//! never leaves a partial image behind; a set of files is renamed under
//! an advisory lock of its directories, so that two processes writing
//! the same names leave one set whole ([`commit_all`]).
//!
//! # The row sinks
//!
//! Each takes the rows of [`crate::raster::scan::scan_convert`] as they
//! come and holds at most a row (the adaptive look-up table mode holds the
//! image: its palette must precede the pixels):
//!
//! - [`PngSink`]: a PNG in a [`DisplayMode`], streamed, fast compression,
//!   with an sRGB chunk.
//! - [`SeparationSink`]: the colour separations of rftb1-3 and getrgb,
//!   `SEED.r`, `SEED.g`, `SEED.b` (one byte per pixel, `hres x vres`, top
//!   row first, no header), `SEED.a` (one coverage byte per pixel) and
//!   `SEED.m` (one 4x4 pixel mask per pixel, u16 little-endian, bit
//!   `4 * row + column`).
//! - [`PixelStructSink`]: the pixel-struct file of rftb4 (004 figure 5.15)
//!   and its fragment side file. The getrgb manual page: "A pixel-struct
//!   file is assumed to contain a linear list of 64-bit data structures",
//!   so the file `OUTPUT` is exactly `hres * vres` of them and nothing
//!   else (getrgb can read it without knowing the resolution); what a
//!   pointer cannot carry into a file, the fragment lists, and the
//!   resolution go to the side file `OUTPUT.frag`. All integers
//!   little-endian:
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

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Location, Result};
use crate::model::OutMode;
use crate::raster::frame_buffer::FrameBuffer;
use crate::raster::scan::{PixelStruct, Row, RowSink, SavedFragment};

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

/// Writes `bytes` produced by `write` to `path` through a temporary file in
/// the same directory, renamed into place only when everything succeeded.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    AtomicFile::create(path)?.write_with(write)?.commit()
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

/// Checks, before anything is rendered, that `path` can be an output:
/// its directory exists, and it is absent or a regular file. A symbolic
/// link, FIFO, socket, device or directory is refused (an output is never
/// written through a link or into a special file: the rename would replace
/// a link rather than follow it, so it is refused explicitly).
pub fn check_target(path: &Path) -> Result<()> {
    let refuse = |why: &str| Error::io(path, std::io::Error::other(why.to_owned()));
    match std::fs::symlink_metadata(path) {
        Ok(m) => {
            let t = m.file_type();
            if t.is_symlink() {
                return Err(refuse(
                    "is a symbolic link; outputs are never written through links (remove it or choose another name)",
                ));
            }
            if t.is_dir() {
                return Err(refuse("is a directory, not a file name"));
            }
            if !t.is_file() {
                return Err(refuse(
                    "is not a regular file (a FIFO, socket or device); outputs are written only to regular files",
                ));
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(Error::io(path, e)),
    }
    if path.file_name().is_none() {
        return Err(refuse("not a file name"));
    }
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return Err(refuse(&format!(
            "the directory {} does not exist",
            dir.display()
        )));
    }
    Ok(())
}

/// How an output name taken from a file rather than from the user (a
/// scene's `fname`, a part's `plytrace-output`) would leave the working
/// directory ([`check_inside`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outside {
    /// Empty, absolute, or with `..` among its components.
    ByName,
    /// Its directory is a link (or under one) that leads out.
    ByLink,
}

/// Checks that `name`, an output named by a file, stays inside the
/// working directory: not empty, relative, no `..`, and its directory
/// (when it exists) inside the working directory once links are followed.
pub fn check_inside(name: &Path) -> std::result::Result<(), Outside> {
    use std::path::Component;
    let by_name = name.as_os_str().is_empty()
        || name.is_absolute()
        || name.components().any(|c| {
            matches!(
                c,
                Component::ParentDir | Component::RootDir | Component::Prefix(_)
            )
        });
    if by_name {
        return Err(Outside::ByName);
    }
    if let Some(dir) = name.parent().filter(|d| !d.as_os_str().is_empty())
        && let (Ok(real), Ok(cwd)) = (
            dir.canonicalize(),
            std::env::current_dir().and_then(|c| c.canonicalize()),
        )
        && !real.starts_with(&cwd)
    {
        return Err(Outside::ByLink);
    }
    Ok(())
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

// ---------------------------------------------------------------------------
// Atomic files

static TEMP_COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// A temporary name beside `path`: `.NAME.PID.N.tmp`.
fn temp_beside(path: &Path, what: &str) -> Result<PathBuf> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| Error::Invalid(format!("{}: not a file name", path.display())))?;
    let n = TEMP_COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    Ok(dir.join(format!(
        ".{}.{}.{n}.{what}",
        name.to_string_lossy(),
        std::process::id()
    )))
}

/// The temporary files of this process not yet renamed or removed, so that
/// a program ended by a signal can remove them ([`remove_temporaries`]);
/// `None` once they have been removed, after which no more are made.
static TEMPORARIES: std::sync::Mutex<Option<Vec<PathBuf>>> =
    std::sync::Mutex::new(Some(Vec::new()));

/// Notes a temporary file; false when the process is ending.
fn note_temporary(tmp: &Path) -> bool {
    let mut live = TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner());
    match live.as_mut() {
        Some(list) => {
            list.push(tmp.to_path_buf());
            true
        }
        None => false,
    }
}

/// Forgets a temporary file that was renamed or removed.
fn forget_temporary(tmp: &Path) {
    let mut live = TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(list) = live.as_mut()
        && let Some(i) = list.iter().rposition(|p| p == tmp)
    {
        list.swap_remove(i);
    }
}

/// Removes every temporary file of this process's outputs not yet renamed
/// into place, and makes no more: for a program about to end on a signal,
/// so that nothing of an unfinished run is left on disk.
pub fn remove_temporaries() {
    let mut live = TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner());
    for tmp in live.take().unwrap_or_default() {
        let _ = std::fs::remove_file(tmp);
    }
}

/// Creates a new temporary file beside `path`. A name taken already (left
/// by a killed process that had this one's process id) is passed over for
/// the next.
fn create_temporary(path: &Path) -> Result<(PathBuf, std::fs::File)> {
    let mut last = None;
    for _ in 0..64 {
        let tmp = temp_beside(path, "tmp")?;
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(Error::io(path, e)),
        }
    }
    Err(Error::io(path, last.expect("tried at least once")))
}

/// A file being written under a temporary name beside its destination; the
/// temporary is removed when dropped unfinished.
#[derive(Debug)]
pub struct AtomicFile {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<std::fs::File>,
}

impl AtomicFile {
    /// Creates the temporary file for `path` (which shows at once whether
    /// the destination directory is writable). What [`check_target`]
    /// refuses (a directory, link or special file at `path`, a missing
    /// directory) is refused now rather than at the rename.
    pub fn create(path: &Path) -> Result<AtomicFile> {
        check_target(path)?;
        crate::input_guard::check(path)?;
        let (tmp, file) = create_temporary(path)?;
        if !note_temporary(&tmp) {
            drop(file);
            let _ = std::fs::remove_file(&tmp);
            return Err(Error::Cancelled);
        }
        Ok(AtomicFile {
            path: path.to_path_buf(),
            tmp,
            file: Some(file),
        })
    }

    /// The destination.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The open temporary file.
    pub fn file(&self) -> &std::fs::File {
        self.file.as_ref().expect("open until finished")
    }

    /// Writes `bytes`, naming the destination on error.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        let mut f = self.file();
        f.write_all(bytes).map_err(|e| Error::io(&self.path, e))
    }

    /// Writes the whole file with `write` (buffered) and finishes it.
    pub fn write_with(
        self,
        write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<Staged> {
        let mut w = std::io::BufWriter::new(self.file());
        write(&mut w)
            .and_then(|()| w.flush())
            .map_err(|e| Error::io(&self.path, e))?;
        drop(w);
        self.finish()
    }

    /// Syncs the temporary file to disk; the rename is left to
    /// [`Staged::commit`] so that several files can be committed together.
    pub fn finish(mut self) -> Result<Staged> {
        let file = self.file.take().expect("open until finished");
        file.sync_all().map_err(|e| Error::io(&self.path, e))?;
        drop(file);
        Ok(Staged {
            path: std::mem::take(&mut self.path),
            tmp: std::mem::take(&mut self.tmp),
        })
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            self.file.take();
            let _ = std::fs::remove_file(&self.tmp);
            forget_temporary(&self.tmp);
        }
    }
}

/// A complete temporary file waiting to be renamed into place; removed when
/// dropped uncommitted.
#[derive(Debug)]
pub struct Staged {
    path: PathBuf,
    tmp: PathBuf,
}

impl Staged {
    /// Renames the file into place.
    pub fn commit(mut self) -> Result<()> {
        let tmp = std::mem::take(&mut self.tmp);
        let renamed = std::fs::rename(&tmp, &self.path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            Error::io(&self.path, e)
        });
        forget_temporary(&tmp);
        renamed
    }

    /// The destination.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            let _ = std::fs::remove_file(&self.tmp);
            forget_temporary(&self.tmp);
        }
    }
}

/// What a process says while its set of outputs waits for another
/// process's ([`on_lock_wait`]).
static WAIT_NOTICE: std::sync::OnceLock<fn(&Path)> = std::sync::OnceLock::new();

/// Sets what is called, with the directory, when a set of outputs waits
/// for another process committing into the same directory (a program
/// says so, as cargo says it waits for a lock). Set once; later calls
/// are ignored.
pub fn on_lock_wait(notice: fn(&Path)) {
    let _ = WAIT_NOTICE.set(notice);
}

/// Exclusive locks (`flock`) on the directories of a set of outputs,
/// held while the set is renamed into place and released when dropped:
/// two processes that commit sets under the same names (two merges into
/// one seed's separations) take turns, so the names end up all from one
/// of them, never a mix. Advisory and best effort: a directory that
/// cannot be opened or locked (a file system without locks) is committed
/// without. Directories are locked in one order (their canonical names),
/// so that two sets never wait for each other.
struct DirectoryLocks {
    /// The open directories, locked while held.
    #[cfg(unix)]
    _held: Vec<nix::fcntl::Flock<std::fs::File>>,
}

impl DirectoryLocks {
    fn take(files: &[Staged]) -> DirectoryLocks {
        let mut dirs: Vec<PathBuf> = files
            .iter()
            .filter_map(|f| {
                f.path
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."))
                    .canonicalize()
                    .ok()
            })
            .collect();
        dirs.sort();
        dirs.dedup();
        #[cfg(unix)]
        {
            let held = dirs.iter().filter_map(|d| lock_directory(d)).collect();
            DirectoryLocks { _held: held }
        }
        #[cfg(not(unix))]
        {
            let _ = dirs;
            DirectoryLocks {}
        }
    }
}

/// An exclusive lock on directory `dir`, waiting (and saying so) while
/// another process holds it; `None` when it cannot be had.
#[cfg(unix)]
fn lock_directory(dir: &Path) -> Option<nix::fcntl::Flock<std::fs::File>> {
    use nix::fcntl::{Flock, FlockArg};
    let handle = std::fs::File::open(dir).ok()?;
    match Flock::lock(handle, FlockArg::LockExclusiveNonblock) {
        Ok(lock) => Some(lock),
        Err((handle, nix::errno::Errno::EWOULDBLOCK)) => {
            if let Some(notice) = WAIT_NOTICE.get() {
                notice(dir);
            }
            Flock::lock(handle, FlockArg::LockExclusive).ok()
        }
        Err(_) => None,
    }
}

/// Renames all `files` into place, so that a set of outputs appears whole
/// or not at all: if one fails, those already renamed are taken back, and
/// a file they replaced (left by an earlier run under the same name) is
/// put back as it was. A set of several files is renamed under the locks
/// of their directories (flock, advisory), so that sets committed at
/// once by two processes do not mix.
pub fn commit_all(files: Vec<Staged>) -> Result<()> {
    let _locks = (files.len() > 1).then(|| DirectoryLocks::take(&files));
    // (destination, the earlier file moved aside, if there was one)
    let mut done: Vec<(PathBuf, Option<PathBuf>)> = Vec::with_capacity(files.len());
    let mut result = Ok(());
    for f in files {
        let path = f.path().to_path_buf();
        let kept = match keep_aside(&path) {
            Ok(k) => k,
            Err(e) => {
                result = Err(e);
                break;
            }
        };
        if let Err(e) = f.commit() {
            if let Some(k) = &kept {
                let _ = std::fs::rename(k, &path);
            }
            result = Err(e);
            break;
        }
        done.push((path, kept));
    }
    for (path, kept) in done {
        match (&result, kept) {
            (Ok(()), Some(k)) => {
                let _ = std::fs::remove_file(k);
            }
            (Err(_), Some(k)) => {
                let _ = std::fs::rename(k, &path);
            }
            (Err(_), None) => {
                let _ = std::fs::remove_file(&path);
            }
            (Ok(()), None) => {}
        }
    }
    result
}

/// Keeps an existing file at `path` under a temporary name beside it (a
/// second link, so that `path` never goes missing; moved where links are
/// not possible) until the set it is replaced in is committed.
fn keep_aside(path: &Path) -> Result<Option<PathBuf>> {
    if std::fs::symlink_metadata(path).is_err() {
        return Ok(None);
    }
    let aside = temp_beside(path, "old")?;
    std::fs::hard_link(path, &aside)
        .or_else(|_| std::fs::rename(path, &aside))
        .map_err(|e| Error::io(path, e))?;
    Ok(Some(aside))
}

// ---------------------------------------------------------------------------
// Conversions

/// f32 intensities (0 to 1) to bytes, rounded and clamped, one row at a
/// time: `out` gets `rgb.len()` bytes per channel in `channel`.
fn channel_to_bytes(rgb: &[[f32; 3]], channel: usize, out: &mut [u8]) {
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

/// How a [`PngSink`] shows the colours (the display modes of the rftb
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
fn levels_of(bits: [u8; 3]) -> [u32; 3] {
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

/// One row of 8-bit bytes in `mode`, as [`PngSink`] writes it (row `y`
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
fn mode_row(mode: DisplayMode, rgb: &[[f32; 3]], y: u32, out: &mut Vec<u8>) {
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

// ---------------------------------------------------------------------------
// Row sinks

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
    /// [`display_row`] makes them): the PNG is the one [`RowSink::row`]
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

/// `seed` with `.ext` appended (not replacing an extension: `a.b` gives
/// `a.b.r`).
pub fn with_suffix(seed: &Path, ext: &str) -> PathBuf {
    let mut s = seed.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
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
    let (resolution, section, side_path) = match side {
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
    fn a_failed_commit_puts_back_what_it_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let image = dir.path().join("a.png");
        std::fs::write(&image, b"earlier run").unwrap();
        let mut first = AtomicFile::create(&image).unwrap();
        first.write_all(b"new image").unwrap();
        let mut second = AtomicFile::create(&dir.path().join("a.out")).unwrap();
        second.write_all(b"tree").unwrap();
        let (first, second) = (first.finish().unwrap(), second.finish().unwrap());
        // The second file's temporary goes missing: its rename fails.
        std::fs::remove_file(&second.tmp).unwrap();
        assert!(commit_all(vec![first, second]).is_err());
        assert_eq!(std::fs::read(&image).unwrap(), b"earlier run");
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["a.png"], "no temporary left");
        // A set that commits replaces the earlier file and keeps no copy.
        let mut again = AtomicFile::create(&image).unwrap();
        again.write_all(b"newer").unwrap();
        commit_all(vec![again.finish().unwrap()]).unwrap();
        assert_eq!(std::fs::read(&image).unwrap(), b"newer");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_stale_temporary_name_is_passed_over() {
        let dir = tempfile::tempdir().unwrap();
        let image = dir.path().join("b.png");
        // What a killed process with this process id would have left.
        let n = TEMP_COUNTER.load(std::sync::atomic::Ordering::Relaxed);
        for k in n..n + 8 {
            let stale = format!(".b.png.{}.{k}.tmp", std::process::id());
            std::fs::write(dir.path().join(stale), b"stale").unwrap();
        }
        let mut f = AtomicFile::create(&image).unwrap();
        f.write_all(b"fresh").unwrap();
        commit_all(vec![f.finish().unwrap()]).unwrap();
        assert_eq!(std::fs::read(&image).unwrap(), b"fresh");
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
    fn check_target_refuses_links_directories_and_missing_directories() {
        let dir = tempfile::tempdir().unwrap();
        let ok = dir.path().join("new.png");
        assert!(check_target(&ok).is_ok());
        std::fs::write(&ok, b"old").unwrap();
        assert!(check_target(&ok).is_ok(), "a regular file may be replaced");
        let link = dir.path().join("link.png");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&ok, &link).unwrap();
            let e = AtomicFile::create(&link).unwrap_err().to_string();
            assert!(e.contains("is a symbolic link"), "{e}");
            assert!(write_png(&link, &FrameBuffer::new(1, 1, [0.0; 3]), OutMode::Color).is_err());
            assert_eq!(std::fs::read(&ok).unwrap(), b"old");
        }
        let e = check_target(dir.path()).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        let e = check_target(&dir.path().join("no/such/x.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not exist"), "{e}");
        assert!(check_image_extension(Path::new("a.PNG")).is_ok());
        assert!(check_image_extension(Path::new("a.ppm")).is_ok());
        assert!(check_image_extension(Path::new("a.jpg")).is_err());
        assert!(check_image_extension(Path::new("a")).is_err());
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

    fn row<'a>(y: u32, rgb: &'a [[f32; 3]]) -> Row<'a> {
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

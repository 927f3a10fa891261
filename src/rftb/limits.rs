//! The refusals before the work of rftb1-4 and getrgb: the resolution and
//! the bands of act-lines rows within the budgets (Garcia 1986, section
//! 5.10: the virtual frame buffer), outputs within the file size limit,
//! no output over an input or the log, inputs read only from regular
//! files.

use super::*;

/// Bytes a pixel of a band of `act-lines` rows takes in memory while it is
/// scan converted and delivered (the integrator's state and the band's
/// output), generously: methods 1-3 hold about 45, method 4 about 70 plus
/// its fragments.
pub fn band_bytes_per_pixel(program: Program) -> u64 {
    match program {
        Program::Rftb4 => 128,
        _ => 64,
    }
}

/// Scan threads of a run: the cores, as the scan converter takes them.
/// Looked up once: on Linux it reads the cgroup files, which took a
/// quarter of the time of the `rftb_args` fuzz target's checks.
pub(super) fn scan_threads() -> u64 {
    static THREADS: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get() as u64))
}

/// Refuses a `hres x vres` image beyond the pixel budget.
pub fn check_pixels(hres: u32, vres: u32, budgets: &Budgets) -> Result<()> {
    let pixels = u64::from(hres) * u64::from(vres);
    if pixels <= budgets.pixels {
        return Ok(());
    }
    Err(Error::Budget {
        flag: "--max-pixels",
        message: format!(
            "{} (hres x vres)",
            Budgets::exceeded(
                &format!("a {hres} x {vres} image ({pixels} pixels)"),
                format!("{} pixels", budgets.pixels),
                "--max-pixels"
            )
        ),
    })
}

/// What the bands of `args` hold in memory at once, in bytes, and the
/// number of bands: up to 2 x threads + 1 of `act-lines` rows (see
/// `crate::raster::scan`).
pub fn band_memory(program: Program, args: &Args) -> (u64, u64) {
    let rows = u64::from(args.act_lines.min(args.vres));
    let bands = u64::from(args.vres).div_ceil(rows.max(1));
    let in_flight = (2 * scan_threads() + 1).min(bands.max(1));
    let need = rows
        .saturating_mul(u64::from(args.hres))
        .saturating_mul(band_bytes_per_pixel(program))
        .saturating_mul(in_flight);
    (need, in_flight)
}

/// Bytes of memory per byte of a tree file, read and prepared for scan
/// conversion. Measured (peak resident size over file size, rftb1-4 at
/// 64x64): tiny faceted triangles 9, tiny Gouraud triangles 25, tiny
/// Phong triangles 23, Gouraud polygons of 1000 vertices 22. With the
/// default frame memory budget a tree file may have about 32 MiB.
pub const TREE_MEMORY_PER_BYTE: u64 = 32;

/// Refuses what `args` would take beyond its budgets, before anything is
/// read, allocated or written: the pixels, and the bands in memory.
pub fn check_budgets(program: Program, args: &Args) -> Result<()> {
    check_pixels(args.hres, args.vres, &args.budgets)?;
    let (need, bands) = band_memory(program, args);
    if need > args.budgets.frame_memory {
        return Err(Error::Budget {
            flag: "--max-frame-memory",
            message: format!(
                "{}; lower act-lines (the fifth argument) or the width",
                Budgets::exceeded(
                    &format!(
                        "act-lines {} of {} pixels: {bands} bands in memory at once ({} MiB)",
                        args.act_lines.min(args.vres),
                        args.hres,
                        need.div_ceil(1 << 20)
                    ),
                    format!("{} MiB", args.budgets.frame_memory >> 20),
                    "--max-frame-memory"
                )
            ),
        });
    }
    Ok(())
}

/// The file size limit of this process (`ulimit -f`), in bytes, when
/// there is one.
pub fn file_size_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max file size"))?;
    let soft = line["Max file size".len()..].split_whitespace().next()?;
    soft.parse().ok()
}

/// Refuses an output of `bytes` bytes that the file size limit would cut
/// short (the system would end the program with SIGXFSZ, or fail the
/// write, half way).
pub fn check_output_size(path: &Path, bytes: u64) -> Result<()> {
    match file_size_limit() {
        Some(limit) if bytes > limit => Err(Error::Invalid(format!(
            "{}: this output would have {bytes} bytes, more than the file size limit of \
             {limit} bytes (`ulimit -f`); lower hres or vres, or raise the limit",
            crate::error::printable(&path.display().to_string(), 200)
        ))),
        _ => Ok(()),
    }
}

/// A name for comparing file names that may not exist yet: the canonical
/// directory and the file name (`./a` and `a` are the same name).
pub(super) fn name_key(path: &Path) -> PathBuf {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    match path.file_name() {
        Some(name) => dir.join(name),
        None => path.to_path_buf(),
    }
}

pub(super) fn shown(p: &Path) -> String {
    crate::error::printable(&p.display().to_string(), 200)
}

/// Refuses, before any work, a set of outputs in which one output is an
/// input, another output or the program's log `log` (each compared as a
/// name and, when it exists, as a file: a link or another spelling is
/// caught too). The message names both.
pub fn check_names(inputs: &[PathBuf], outputs: &[PathBuf], log: &Path) -> Result<()> {
    let same = |a: &Path, b: &Path| {
        if name_key(a) == name_key(b) {
            return true;
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
                return (x.dev(), x.ino()) == (y.dev(), y.ino());
            }
        }
        false
    };
    for (i, out) in outputs.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|p| same(out, p)) {
            return Err(Error::Invalid(format!(
                "{}: this output is the input {}; it is not written over (name another \
                 output)",
                shown(out),
                shown(input)
            )));
        }
        if let Some(other) = outputs[..i].iter().find(|p| same(out, p)) {
            return Err(Error::Invalid(format!(
                "{}: this output is also the output {} of this run; name another output",
                shown(out),
                shown(other)
            )));
        }
        if same(out, log) {
            return Err(Error::Invalid(format!(
                "{}: this output is {}, the log this program appends to; name another output",
                shown(out),
                shown(log)
            )));
        }
    }
    Ok(())
}

/// Reads the input `path` (a regular file only, noted so that no output
/// writes over it) when its size is within `limit` bytes; `budget` says
/// what the limit is, for the message (a `--max-frame-memory` budget).
pub(super) fn read_input(
    path: &Path,
    limit: u64,
    budget: impl FnOnce(u64) -> String,
) -> Result<Vec<u8>> {
    if let Ok(meta) = std::fs::metadata(path)
        && meta.is_file()
        && meta.len() > limit
    {
        return Err(Error::Budget {
            flag: "--max-frame-memory",
            message: format!("{}: {}", shown(path), budget(meta.len())),
        });
    }
    crate::scene::object_file::read_regular(path, limit)
}

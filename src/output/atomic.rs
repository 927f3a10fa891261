//! The one atomic writer of the outputs. Files are written to a temporary
//! name in the same directory and renamed when complete, so a failure
//! never leaves a partial image behind; a set of files is renamed under
//! an advisory lock of its directories, so that two processes writing
//! the same names leave one set whole ([`commit_all`]). Before anything is
//! rendered, an output's name is checked: a regular file or nothing, in a
//! directory that exists ([`check_target`]), and, when a file rather than
//! the user names it, inside the working directory ([`check_inside`]).

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Writes `bytes` produced by `write` to `path` through a temporary file in
/// the same directory, renamed into place only when everything succeeded.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    AtomicFile::create(path)?.write_with(write)?.commit()
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::OutMode;
    use crate::output::{check_image_extension, write_png};
    use crate::raster::frame_buffer::FrameBuffer;

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
}

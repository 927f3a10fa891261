//! The files a process has read, so that none of its outputs writes over
//! one: a scene named `scene.txt` rendered with `-o on` would otherwise
//! have its tree's text form written over it (FNAME.txt), and a manual
//! program given the same name for its input and its output would lose
//! its input. Files are known by device and inode, so another name for
//! the same file (a link, `./x`, another case on a folding file system)
//! is caught too.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{Error, Result};

/// A file's identity: device and inode (the canonical path elsewhere).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Identity {
    #[cfg(unix)]
    id: (u64, u64),
    #[cfg(not(unix))]
    id: PathBuf,
}

fn identity(path: &Path, meta: &std::fs::Metadata) -> Option<Identity> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = path;
        Some(Identity {
            id: (meta.dev(), meta.ino()),
        })
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        path.canonicalize().ok().map(|id| Identity { id })
    }
}

/// What was read: identities and the names they were read by.
static READ: Mutex<Vec<(Identity, PathBuf)>> = Mutex::new(Vec::new());

/// Notes that `path` (with metadata `meta`, taken from the open file) was
/// read as an input.
pub fn note(path: &Path, meta: &std::fs::Metadata) {
    if let Some(id) = identity(path, meta) {
        let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
        if !read.iter().any(|(i, _)| *i == id) {
            read.push((id, path.to_path_buf()));
        }
    }
}

/// FNV-1a 64-bit hashes of the contents of the inputs read, in order.
static CONTENTS: Mutex<Vec<u64>> = Mutex::new(Vec::new());

/// The FNV-1a 64-bit hash of `bytes`, continuing from `h` (start with
/// [`FNV_OFFSET`]).
pub fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// FNV-1a's starting value.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// Notes the contents of an input read (a scene, a called file, an
/// object file, a tree file, standard input), for the fingerprint of
/// the outputs.
pub fn note_contents(bytes: &[u8]) {
    let h = fnv1a(FNV_OFFSET, bytes);
    CONTENTS.lock().unwrap_or_else(|e| e.into_inner()).push(h);
}

/// The hashes of the contents read so far, in the order read.
pub fn contents() -> Vec<u64> {
    CONTENTS.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Refuses `target` when it is a file this process has read.
pub fn check(target: &Path) -> Result<()> {
    let Ok(meta) = std::fs::metadata(target) else {
        return Ok(());
    };
    let Some(id) = identity(target, &meta) else {
        return Ok(());
    };
    let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
    // An input deleted since may have left its inode to a new file: a
    // record counts only while its name still leads to the same file.
    read.retain(|(i, p)| {
        std::fs::metadata(p)
            .ok()
            .and_then(|m| identity(p, &m))
            .is_some_and(|now| now == *i)
    });
    match read.iter().find(|(i, _)| *i == id) {
        Some((_, input)) => Err(Error::Invalid(format!(
            "{}: this output is {}, an input of this run; it is not written over \
             (name another output)",
            crate::error::printable(&target.display().to_string(), 200),
            if input == target {
                "the file read".to_string()
            } else {
                format!(
                    "the file read as {}",
                    crate::error::printable(&input.display().to_string(), 200)
                )
            }
        ))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_input_is_not_an_output() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.txt");
        std::fs::write(&scene, "ident\n").unwrap();
        let other = dir.path().join("other.txt");
        std::fs::write(&other, "x").unwrap();
        assert!(check(&scene).is_ok(), "not read yet");
        let meta = std::fs::metadata(&scene).unwrap();
        note(&scene, &meta);
        let e = check(&scene).unwrap_err().to_string();
        assert!(e.contains("an input of this run"), "{e}");
        // Another name for the same file.
        let link = dir.path().join("link.txt");
        std::fs::hard_link(&scene, &link).unwrap();
        assert!(check(&link).unwrap_err().to_string().contains("read as"));
        assert!(check(&other).is_ok());
        assert!(check(&dir.path().join("absent.txt")).is_ok());
        // Once the input is gone, a new file that takes its inode is free.
        std::fs::remove_file(&scene).unwrap();
        std::fs::remove_file(&link).unwrap();
        let fresh = dir.path().join("fresh.txt");
        std::fs::write(&fresh, "new").unwrap();
        assert!(check(&fresh).is_ok());
    }
}

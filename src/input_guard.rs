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

/// Files known by identity and by the names they were read by: the
/// process's inputs ([`note`], [`check`]), or the inputs of one task
/// that keeps its own (a merge's parts).
#[derive(Debug, Default)]
pub struct Inputs(Vec<(Identity, PathBuf)>);

impl Inputs {
    /// No files.
    pub const fn new() -> Inputs {
        Inputs(Vec::new())
    }

    /// Adds `path`, read with metadata `meta` (taken from the open file).
    pub fn add(&mut self, path: &Path, meta: &std::fs::Metadata) {
        if let Some(id) = identity(path, meta) {
            self.insert(id, path.to_path_buf());
        }
    }

    /// By identity and name: a file that takes the inode of an input
    /// since deleted is an input of its own, though the old record stays
    /// until the next check.
    fn insert(&mut self, id: Identity, path: PathBuf) {
        if !self.0.iter().any(|(i, p)| *i == id && *p == path) {
            self.0.push((id, path));
        }
    }

    /// The name by which `target`, when it is one of the files, was read.
    pub fn find(&mut self, target: &Path) -> Option<&Path> {
        let meta = std::fs::metadata(target).ok()?;
        let id = identity(target, &meta)?;
        // An input deleted since may have left its inode to a new file: a
        // record counts only while its name still leads to the same file.
        self.0.retain(|(i, p)| {
            std::fs::metadata(p)
                .ok()
                .and_then(|m| identity(p, &m))
                .is_some_and(|now| now == *i)
        });
        self.0
            .iter()
            .find(|(i, _)| *i == id)
            .map(|(_, p)| p.as_path())
    }

    /// Refuses `target` when it is one of the files.
    pub fn check(&mut self, target: &Path) -> Result<()> {
        match self.find(target) {
            Some(input) => Err(Error::Invalid(format!(
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
}

/// What the process read.
static READ: Mutex<Inputs> = Mutex::new(Inputs::new());

/// Notes that `path` (with metadata `meta`, taken from the open file) was
/// read as an input.
pub fn note(path: &Path, meta: &std::fs::Metadata) {
    if let Some(id) = identity(path, meta) {
        let noted = Noted::Read(id, path.to_path_buf());
        if !record(&noted) {
            noted.enter();
        }
    }
}

/// The hashes ([`content_hash`]) of the contents of the inputs read, in
/// order.
static CONTENTS: Mutex<Vec<u64>> = Mutex::new(Vec::new());

/// Where [`content_hash`] starts (FNV-1a's offset basis: any constant
/// would do).
const SEED: u64 = 0xcbf2_9ce4_8422_2325;

/// The hash of an input's contents, eight bytes at a time (little-endian
/// words, the last one padded with zeros, then the length), by the steps
/// of MurmurHash3's 64-bit lane: each word is mixed on its own (two odd
/// multiplications about a rotation) before it enters the running hash,
/// so that a change of a few bits in one word is never undone by the
/// next; the result is mixed once more at the end. Byte by byte, FNV-1a
/// spent a sixth of the time of reading office2's object files on its
/// chain of multiplications. The fingerprint of parts hashes with it
/// too. Each step is one-to-one in the hash so far and in the word, so
/// inputs that differ in one word never hash the same.
pub fn content_hash(bytes: &[u8]) -> u64 {
    let step = |h: u64, word: u64| {
        let k = word
            .wrapping_mul(0x87c3_7b91_1142_53d5)
            .rotate_left(31)
            .wrapping_mul(0x4cf5_ad43_2745_937f);
        (h ^ k)
            .rotate_left(27)
            .wrapping_mul(5)
            .wrapping_add(0x52dc_e729)
    };
    let mut words = bytes.chunks_exact(8);
    let h = (&mut words).fold(SEED, |h, w| {
        step(h, u64::from_le_bytes(w.try_into().expect("eight bytes")))
    });
    let mut last = [0u8; 8];
    last[..words.remainder().len()].copy_from_slice(words.remainder());
    let mut h = step(step(h, u64::from_le_bytes(last)), bytes.len() as u64);
    // MurmurHash3's final mix.
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^ (h >> 33)
}

/// Notes the contents of an input read (a scene, a called file, an
/// object file, a tree file, standard input), for the fingerprint of
/// the outputs.
pub fn note_contents(bytes: &[u8]) {
    let noted = Noted::Contents(content_hash(bytes));
    if !record(&noted) {
        noted.enter();
    }
}

/// One note of an input read.
#[derive(Debug, Clone)]
enum Noted {
    /// A file read, and the name it was read by ([`note`]).
    Read(Identity, PathBuf),
    /// The hash of an input's contents ([`note_contents`]).
    Contents(u64),
}

impl Noted {
    /// Enters the note in the process's lists.
    fn enter(self) {
        match self {
            Noted::Read(id, path) => READ
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert(id, path),
            Noted::Contents(h) => CONTENTS.lock().unwrap_or_else(|e| e.into_inner()).push(h),
        }
    }
}

thread_local! {
    /// The notes of a [`recording`] on this thread.
    static RECORDING: std::cell::RefCell<Option<Vec<Noted>>> =
        const { std::cell::RefCell::new(None) };
}

/// Adds `noted` to this thread's recording, if one is running.
fn record(noted: &Noted) -> bool {
    RECORDING.with_borrow_mut(|r| r.as_mut().map(|r| r.push(noted.clone())).is_some())
}

/// The notes of reading done ahead of its turn, held until the reader
/// that wanted it takes it: the outputs' fingerprint then lists the
/// inputs in the order the scene reads them.
#[derive(Debug, Default, Clone)]
pub struct Notes(Vec<Noted>);

impl Notes {
    /// Enters the notes in the process's lists, in the order made.
    pub fn enter(self) {
        self.0.into_iter().for_each(Noted::enter);
    }
}

/// Runs `f` with the notes it makes on this thread held back, not
/// entered: the inputs it reads are the process's only once the notes
/// are entered.
pub fn recording<T>(f: impl FnOnce() -> T) -> (T, Notes) {
    /// Puts back the recording `f` ran inside, even if it panics.
    struct Restore(Option<Vec<Noted>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            RECORDING.set(self.0.take());
        }
    }
    let restore = Restore(RECORDING.replace(Some(Vec::new())));
    let value = f();
    let notes = RECORDING.take().unwrap_or_default();
    drop(restore);
    (value, Notes(notes))
}

/// The hashes of the contents read so far, in the order read.
pub fn contents() -> Vec<u64> {
    CONTENTS.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Refuses `target` when it is a file this process has read.
pub fn check(target: &Path) -> Result<()> {
    READ.lock().unwrap_or_else(|e| e.into_inner()).check(target)
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

    /// A file read under a second name after the first is gone (as a new
    /// file can take a deleted input's inode) is still an input: the
    /// stale record of the first name does not stand in for it.
    #[test]
    fn an_input_read_again_after_its_first_name_is_gone_is_an_input() {
        let dir = tempfile::tempdir().unwrap();
        let first = dir.path().join("first.det");
        std::fs::write(&first, "x").unwrap();
        let second = dir.path().join("second.det");
        std::fs::hard_link(&first, &second).unwrap();
        note(&first, &std::fs::metadata(&first).unwrap());
        std::fs::remove_file(&first).unwrap();
        note(&second, &std::fs::metadata(&second).unwrap());
        let e = check(&second).unwrap_err().to_string();
        assert!(e.contains("an input of this run"), "{e}");
    }

    /// Every change of one or two bits of an input, in any byte of a word
    /// or of the padded tail, and every change of its length, gives a
    /// hash of its own.
    #[test]
    fn a_changed_input_hashes_differently() {
        let input: Vec<u8> = (0..37u8).map(|b| b.wrapping_mul(89)).collect();
        let bits = input.len() * 8;
        let flipped = |flips: &[usize]| {
            let mut changed = input.clone();
            for &k in flips {
                changed[k / 8] ^= 1 << (k % 8);
            }
            content_hash(&changed)
        };
        let mut seen = std::collections::HashSet::from([content_hash(&input)]);
        for a in 0..bits {
            assert!(seen.insert(flipped(&[a])), "bit {a}");
            for b in a + 1..bits {
                assert!(seen.insert(flipped(&[a, b])), "bits {a} and {b}");
            }
        }
        for len in 0..input.len() {
            assert!(seen.insert(content_hash(&input[..len])), "length {len}");
        }
        // A zero byte more is another input, though the padding is zeros.
        let mut longer = input.clone();
        longer.push(0);
        assert!(seen.insert(content_hash(&longer)));
    }

    #[test]
    fn recorded_notes_count_once_entered() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("ahead.det");
        std::fs::write(&input, "read ahead").unwrap();
        let bytes = format!("unique contents {:?}", dir.path()).into_bytes();
        let h = content_hash(&bytes);
        let ((), notes) = recording(|| {
            note(&input, &std::fs::metadata(&input).unwrap());
            note_contents(&bytes);
        });
        assert!(check(&input).is_ok(), "held back while recorded");
        assert!(!contents().contains(&h));
        notes.enter();
        assert!(check(&input).is_err(), "an input once entered");
        assert!(contents().contains(&h));
        // Outside a recording, notes are entered at once.
        let other = dir.path().join("other.det");
        std::fs::write(&other, "x").unwrap();
        note(&other, &std::fs::metadata(&other).unwrap());
        assert!(check(&other).is_err());
    }
}

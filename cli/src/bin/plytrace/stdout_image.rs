//! `-o -`: the image to standard output. A run renders into a file in a
//! private temporary folder, as it would anywhere (staged, committed only
//! when complete), and the finished file is copied to stdout: a failed or
//! cancelled run sends nothing, and memory stays bounded however large
//! the image is. An image that cannot be sent whole (a full disk, a
//! reader that closed the pipe) is an error of the run.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use plytrace::{Error, Result};

/// The private folder, while the program has one.
static FOLDER: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Makes the private folder (readable by the user alone) and returns the
/// name of the image file in it, with `extension` for the format.
pub fn prepare(extension: &str) -> Result<PathBuf> {
    let dir = std::env::temp_dir().join(format!("plytrace-stdout-{}", std::process::id()));
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
    builder.create(&dir).map_err(|e| Error::io(&dir, e))?;
    let file = dir.join(format!("image.{extension}"));
    *FOLDER.lock().unwrap_or_else(|e| e.into_inner()) = Some(dir);
    Ok(file)
}

/// Copies the finished image to stdout and removes it.
pub fn send(path: &Path) -> Result<()> {
    let copied = std::fs::File::open(path).and_then(|mut f| {
        let mut o = std::io::stdout().lock();
        std::io::copy(&mut f, &mut o)?;
        std::io::Write::flush(&mut o)
    });
    let _ = std::fs::remove_file(path);
    match copied {
        // The reader left (`| head -c 100`): whoever reads the image did
        // not get it whole, which a script must be able to see.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(Error::Invalid(
            "<stdout>: the reader closed the pipe before the whole image was sent".into(),
        )),
        other => other.map_err(|e| Error::io(Path::new("<stdout>"), e)),
    }
}

/// Removes the private folder and what is in it.
pub fn cleanup() {
    if let Some(dir) = FOLDER.lock().unwrap_or_else(|e| e.into_inner()).take() {
        let _ = std::fs::remove_dir_all(dir);
    }
}

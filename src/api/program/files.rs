//! The files of a run: each output created as a temporary beside its
//! place before anything is rendered, then committed together (renamed
//! into place) or not at all; the checks of an output's name and place;
//! the images written from a frame buffer.

/// An output being written: a temporary file beside `path`, removed if
/// it is dropped unfinished; [`AtomicFile::finish`] stages it.
///
/// ```
/// use plytrace::api::program::files::AtomicFile;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-atomic.txt", std::process::id()));
/// let mut file = AtomicFile::create(&path)?;
/// file.write_all(b"hello")?;
/// assert!(!path.exists(), "not in place before the commit");
/// file.finish()?.commit()?;
/// assert_eq!(std::fs::read(&path).map_err(|e| plytrace::Error::io(&path, e))?, b"hello");
/// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::output::AtomicFile;

/// A finished output waiting under its temporary name for its commit;
/// dropped uncommitted, it is removed.
///
/// ```
/// use plytrace::api::program::files::{AtomicFile, Staged};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-staged.txt", std::process::id()));
/// let staged: Staged = AtomicFile::create(&path)?.finish()?;
/// assert_eq!(staged.path(), path);
/// drop(staged);
/// assert!(!path.exists(), "never committed");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::output::Staged;

/// Commits every staged output of a run, or (on an error) none.
///
/// ```
/// use plytrace::api::program::files::{commit_all, AtomicFile};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let dir = std::env::temp_dir();
/// let a = dir.join(format!("plytrace-doc-{}-commit-a", std::process::id()));
/// let b = dir.join(format!("plytrace-doc-{}-commit-b", std::process::id()));
/// commit_all(vec![AtomicFile::create(&a)?.finish()?, AtomicFile::create(&b)?.finish()?])?;
/// assert!(a.exists() && b.exists());
/// for p in [&a, &b] {
///     std::fs::remove_file(p).map_err(|e| plytrace::Error::io(p, e))?;
/// }
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::output::commit_all;

/// Writes a frame buffer into an output as PNG or binary PPM (by the
/// file's extension) in the scene's output mode, and stages it.
///
/// ```
/// use plytrace::api::program::files::{stage_image, AtomicFile};
/// use plytrace::api::program::rows::FrameBuffer;
/// use plytrace::api::program::session::Scene;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-stage.ppm", std::process::id()));
/// let frame = FrameBuffer::new(3, 2, [1.0, 0.0, 0.0]);
/// stage_image(AtomicFile::create(&path)?, &frame, Scene::default().outmode)?.commit()?;
/// let ppm = std::fs::read(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// assert!(ppm.starts_with(b"P6\n3 2\n255\n"));
/// assert_eq!(&ppm[ppm.len() - 3..], [255, 0, 0]);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::output::stage_image;

/// Writes the id image (`--id-image`): each polygon painted in a colour
/// of its own, the background black; as PNG, staged.
///
/// ```
/// use plytrace::api::program::files::{stage_id_png, AtomicFile};
/// use plytrace::api::program::rows::FrameBuffer;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-ids.png", std::process::id()));
/// let frame = FrameBuffer::new(4, 4, [0.0; 3]);
/// stage_id_png(AtomicFile::create(&path)?, &frame, &[])?.commit()?;
/// let png = std::fs::read(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// assert!(png.starts_with(b"\x89PNG"));
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::output::stage_id_png;

/// A [`crate::api::program::rows::RowSink`] that writes a PNG band by
/// band as the rows come: the whole image is never in memory.
///
/// ```
/// use plytrace::api::program::files::{AtomicFile, PngSink};
/// use plytrace::api::program::rows::{Row, RowSink};
/// use plytrace::api::program::session::Scene;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-sink.png", std::process::id()));
/// let mut sink = PngSink::from_file(AtomicFile::create(&path)?, 2, 2, Scene::default().outmode.into())?;
/// for y in 0..2 {
///     sink.row(&Row::colors(y, &[[1.0, 1.0, 1.0]; 2]))?;
/// }
/// let (staged, _note) = sink.finish()?;
/// staged.commit()?;
/// let png = std::fs::read(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
/// assert_eq!(&png[12..24], b"IHDR\0\0\0\x02\0\0\0\x02");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::output::PngSink;

/// Checks, before anything is rendered, that a path can be an output:
/// its directory exists, and it is absent or a regular file.
///
/// ```
/// use plytrace::api::program::files::check_target;
///
/// let dir = std::env::temp_dir();
/// assert!(check_target(&dir.join("plytrace-doc-not-yet-there.png")).is_ok());
/// assert!(check_target(&dir).is_err(), "a directory");
/// assert!(check_target(&dir.join("no-such-folder/x.png")).is_err());
/// ```
#[doc(inline)]
pub use crate::output::check_target;

/// Sets what is called (with the directory) when a set of outputs waits
/// for another process committing a set into the same directory.
///
/// ```
/// use plytrace::api::program::files::on_lock_wait;
///
/// on_lock_wait(|dir| eprintln!("waiting for another process writing into {}", dir.display()));
/// ```
#[doc(inline)]
pub use crate::output::on_lock_wait;

/// Checks that an output name taken from a file (a scene's `fname`, a
/// part's image name) stays inside the working directory: relative, no
/// `..`, its directory not a link out.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::files::{check_inside, Outside};
///
/// assert!(check_inside(Path::new("frames/f1.png")).is_ok());
/// assert_eq!(check_inside(Path::new("../f1.png")), Err(Outside::ByName));
/// assert_eq!(check_inside(Path::new("/tmp/f1.png")), Err(Outside::ByName));
/// ```
#[doc(inline)]
pub use crate::output::check_inside;

/// How a name would leave the working directory (see [`check_inside`]).
///
/// ```
/// use plytrace::api::program::files::Outside;
///
/// assert_ne!(Outside::ByName, Outside::ByLink);
/// ```
#[doc(inline)]
pub use crate::output::Outside;

/// Refuses a path that names a file this process has read (a scene, an
/// object file, a part): an output is never written over an input.
///
/// ```
/// use plytrace::api::program::files::check_not_input;
///
/// let path = std::env::temp_dir().join("plytrace-doc-never-read.txt");
/// assert!(check_not_input(&path).is_ok());
/// ```
#[doc(inline)]
pub use crate::input_guard::check as check_not_input;

/// Checks that a path names an image format the program writes (`.png`
/// or `.ppm`, in any case).
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::files::check_image_extension;
///
/// assert!(check_image_extension(Path::new("out.PNG")).is_ok());
/// assert!(check_image_extension(Path::new("out.jpg")).unwrap_err().contains("png"));
/// ```
#[doc(inline)]
pub use crate::output::check_image_extension;

/// A time as `YYYY-MM-DD HH:MM:SS UTC`, as the logs of every program
/// write it.
///
/// ```
/// use std::time::{Duration, SystemTime};
/// use plytrace::api::program::files::utc_timestamp;
///
/// let t = SystemTime::UNIX_EPOCH + Duration::from_secs(86_400 + 3_661);
/// assert_eq!(utc_timestamp(t), "1970-01-02 01:01:01 UTC");
/// ```
#[doc(inline)]
pub use crate::rftb::utc_timestamp;

/// How colours become bytes in an image file: the scene's output mode
/// (`setmode` colour, grey levels, dithering).
///
/// ```
/// use plytrace::api::program::files::DisplayMode;
/// use plytrace::api::program::session::Scene;
///
/// let mode = DisplayMode::from(Scene::default().outmode);
/// assert_eq!(mode, Scene::default().outmode.into());
/// ```
#[doc(inline)]
pub use crate::output::DisplayMode;

//! Parts of one image rendered by separate processes (`--part I/N`) and
//! their merge (`plytrace merge`): each part file holds its rows and says
//! which render it belongs to; the merge checks that they are parts of
//! one render, every part once, and writes the image byte for byte as one
//! process would.
//!
//! ```
//! # use std::path::Path;
//! # use plytrace::api::program::session::{Interpreter, NoHost};
//! use plytrace::api::Budgets;
//! use plytrace::api::program::files::PngSink;
//! use plytrace::api::program::parts::{merge, missing, PartInfo, PartSink, PartSpec};
//! use plytrace::api::program::pipeline::{plan_with, scan_into, scan_rows_into, Plan, RenderOptions, Reuse};
//! use plytrace::api::program::rows::part_rows;
//!
//! # fn main() -> Result<(), plytrace::Error> {
//! # let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
//! # let mut interp = Interpreter::new();
//! # interp.execute_source("resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n", Path::new("cube.des"), &dir, &mut NoHost)?;
//! # let scene = interp.scene();
//! let tmp = std::env::temp_dir().join(format!("plytrace-doc-{}-parts", std::process::id()));
//! std::fs::create_dir_all(&tmp).map_err(|e| plytrace::Error::io(&tmp, e))?;
//! let prepared = || match plan_with(&scene, &RenderOptions::default(), &Reuse::default()) {
//!     Ok(Plan::Tree(p)) => *p,
//!     _ => unreachable!(),
//! };
//! let mut files = Vec::new();
//! for index in 0..2 {
//!     let p = prepared();
//!     let rows = part_rows(&p.picture, &p.scan, index, 2);
//!     let info = PartInfo {
//!         part: PartSpec { index, count: 2 },
//!         image: (16, 16),
//!         first: rows.start,
//!         rows: rows.len() as u32,
//!         output: "whole.png".into(),
//!         fingerprint: "0123456789abcdef".into(),
//!     };
//!     let path = tmp.join(format!("part-{index}.png"));
//!     let mut sink = PartSink::create(&path, info, scene.outmode.into())?;
//!     scan_rows_into(p, rows, &mut sink)?;
//!     sink.finish()?.commit()?;
//!     files.push(path);
//! }
//! assert!(missing(&files, None, &Budgets::default())?.0.is_empty(), "both parts are there");
//! assert_eq!(missing(&files[..1], None, &Budgets::default())?.0, [1]);
//! let merged = tmp.join("merged.png");
//! assert_eq!(merge(&files, Some(&merged), None, &Budgets::default())?.size, (16, 16));
//! let whole = tmp.join("whole.png");
//! let mut sink = PngSink::create(&whole, 16, 16, scene.outmode.into())?;
//! scan_into(prepared(), &mut sink)?;
//! sink.finish()?.0.commit()?;
//! let same = std::fs::read(&merged).ok() == std::fs::read(&whole).ok();
//! std::fs::remove_dir_all(&tmp).map_err(|e| plytrace::Error::io(&tmp, e))?;
//! assert!(same, "the merged parts are the one-process image");
//! # Ok(())
//! # }
//! ```

/// Part `index` of `count` (`--part I/N`, `I` from 0).
///
/// ```
/// use plytrace::api::program::parts::PartSpec;
///
/// let spec: PartSpec = "2/8".parse().unwrap();
/// assert_eq!((spec.index, spec.count, spec.to_string()), (2, 8, "2/8".to_string()));
/// assert!("8/8".parse::<PartSpec>().is_err(), "the index runs from 0 to 7");
/// ```
#[doc(inline)]
pub use crate::part::PartSpec;

/// What a part file says of itself: which part, of which image, its rows
/// and the render's fingerprint (see the [module](self) example).
///
/// ```
/// use plytrace::api::program::parts::{PartInfo, PartSpec};
///
/// let info = PartInfo {
///     part: PartSpec { index: 0, count: 1 },
///     image: (4, 4),
///     first: 0,
///     rows: 4,
///     output: "whole.png".into(),
///     fingerprint: "0123456789abcdef".into(),
/// };
/// assert_eq!(info.clone(), info);
/// ```
#[doc(inline)]
pub use crate::part::PartInfo;

/// Writes a part file from the rows of its part (a row sink; see the
/// [module](self) example). Rows outside the part are refused.
///
/// ```
/// use plytrace::api::program::parts::{PartInfo, PartSink, PartSpec};
/// use plytrace::api::program::rows::{Row, RowSink};
/// use plytrace::api::program::session::Scene;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-part.png", std::process::id()));
/// let info = PartInfo {
///     part: PartSpec { index: 1, count: 2 },
///     image: (2, 2),
///     first: 1,
///     rows: 1,
///     output: "whole.png".into(),
///     fingerprint: "0123456789abcdef".into(),
/// };
/// let mut sink = PartSink::create(&path, info, Scene::default().outmode.into())?;
/// assert!(sink.row(&Row::colors(0, &[[0.0; 3]; 2])).is_err(), "row 0 is not in the part");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::part::PartSink;

/// The fingerprint of a render: the program, its version, the contents
/// of every input read so far and the flags that decide the pixels,
/// hashed; parts of one render have the same.
///
/// ```
/// use plytrace::api::program::parts::fingerprint;
///
/// let a = fingerprint("plytrace", "--size 64x48");
/// assert_eq!(a.len(), 16);
/// assert_eq!(a, fingerprint("plytrace", "--size 64x48"));
/// assert_ne!(a, fingerprint("plytrace", "--size 64x64"));
/// ```
#[doc(inline)]
pub use crate::part::fingerprint;

/// Notes an input that is not a file (a scene on standard input) for the
/// [`fingerprint`].
///
/// ```
/// use plytrace::api::program::parts::{fingerprint, note_input};
///
/// let before = fingerprint("plytrace", "");
/// note_input(b"resolution 8 8\n");
/// assert_ne!(fingerprint("plytrace", ""), before);
/// ```
#[doc(inline)]
pub use crate::part::note_input;

/// The form of a merged image: PNG, PPM or the separations.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::parts::MergeFormat;
///
/// assert_eq!(MergeFormat::of(Path::new("out.PPM")), MergeFormat::Ppm);
/// assert_eq!(MergeFormat::of(Path::new("out.png")), MergeFormat::Png);
/// ```
#[doc(inline)]
pub use crate::part::MergeFormat;

/// What [`merge`] did: the files written, the image's size, the parts
/// merged (see the [module](self) example).
///
/// ```
/// use plytrace::api::program::parts::Merged;
///
/// let m = Merged { written: vec!["out.png".into()], size: (4, 4), parts: 2 };
/// assert_eq!(m.parts, 2);
/// ```
#[doc(inline)]
pub use crate::part::Merged;

/// Merges part files into the image, after checking that they are the
/// parts of one render, every part once, of an image within the pixel
/// budget; nothing is written otherwise, never over a part, and without
/// an output named, only the parts' name inside the working directory
/// (see the [module](self) example).
///
/// ```
/// use plytrace::api::Budgets;
/// use plytrace::api::program::parts::merge;
///
/// let none = std::env::temp_dir().join("plytrace-doc-no-such-part.png");
/// assert!(merge(&[none], None, None, &Budgets::default()).is_err());
/// ```
#[doc(inline)]
pub use crate::part::merge;

/// The indices of the parts still to render, and warnings for part files
/// that cannot be read (see the [module](self) example).
///
/// ```
/// use plytrace::api::Budgets;
/// use plytrace::api::program::parts::missing;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let (todo, warnings) = missing(&[], Some(3), &Budgets::default())?;
/// assert_eq!((todo, warnings.len()), (vec![0, 1, 2], 0));
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::part::missing;

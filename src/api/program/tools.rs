//! The manual's other programs (004 appendix B) and the tools of
//! `plytrace` besides rendering: each program in `src/bin` is a line over
//! one of these entry points, which read the process's arguments, print
//! their messages and give the exit code.

/// The renderers from tree files of the manual's rftb page (chapter 5):
/// which of `rftb1` (pixel coverage) to `rftb4` (multi-level masks).
///
/// ```
/// use plytrace::api::program::tools::Rftb;
///
/// assert_eq!(Rftb::Rftb1.name(), "rftb1");
/// assert_ne!(Rftb::Rftb2, Rftb::Rftb4);
/// ```
#[doc(inline)]
pub use crate::rftb::Program as Rftb;

/// The `rftb1` to `rftb4` programs: reads the tree file the command line
/// names and scan converts it; returns the exit code.
///
/// ```no_run
/// use plytrace::api::program::tools::{run_rftb, Rftb};
///
/// // src/bin/rftb1.rs:
/// fn main() -> std::process::ExitCode {
///     run_rftb(Rftb::Rftb1)
/// }
/// ```
///
/// Its arguments come from the process, so the example that runs checks
/// the program's name instead:
///
/// ```
/// use plytrace::api::program::tools::Rftb;
///
/// let names: Vec<&str> = [Rftb::Rftb1, Rftb::Rftb2, Rftb::Rftb3, Rftb::Rftb4].iter().map(|p| p.name()).collect();
/// assert_eq!(names, ["rftb1", "rftb2", "rftb3", "rftb4"]);
/// ```
#[doc(inline)]
pub use crate::rftb::main as run_rftb;

/// The `getrgb` program: the colours of a tree file's pixels; returns
/// the exit code.
///
/// ```no_run
/// // src/bin/getrgb.rs:
/// fn main() -> std::process::ExitCode {
///     plytrace::api::program::tools::run_getrgb()
/// }
/// ```
///
/// The arguments come from the process, so what runs here is the type
/// the programs rely on:
///
/// ```
/// use std::process::ExitCode;
///
/// let entry: fn() -> ExitCode = plytrace::api::program::tools::run_getrgb;
/// assert_eq!(std::mem::size_of_val(&entry), std::mem::size_of::<usize>());
/// ```
#[doc(inline)]
pub use crate::rftb::getrgb_main as run_getrgb;

/// Which of the manual's object file converters: `mkdet` (geometry),
/// `mkpcl` (polygon colours) or `mkvcl` (vertex colours).
///
/// ```
/// use plytrace::api::program::tools::ConvertKind;
///
/// assert_ne!(ConvertKind::Det, ConvertKind::Pcl);
/// ```
#[doc(inline)]
pub use crate::scene::object_file::ConvertKind;

/// The `mkdet`, `mkpcl` and `mkvcl` programs (004 appendix B, the mkdet
/// manual page) with their arguments; returns the exit code.
///
/// ```
/// use std::path::Path;
/// use std::process::ExitCode;
/// use plytrace::api::program::tools::{run_convert, ConvertKind};
///
/// let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/objects/square.det");
/// let output = std::env::temp_dir().join(format!("plytrace-doc-{}-square.bin", std::process::id()));
/// let args = [input.display().to_string(), output.display().to_string()];
/// let code = run_convert(ConvertKind::Det, &args);
/// let det = std::fs::read(&output).unwrap_or_default();
/// let _ = std::fs::remove_file(&output);
/// assert_eq!(code, ExitCode::SUCCESS);
/// assert!(det.starts_with(b"DET"));
/// assert_eq!(run_convert(ConvertKind::Det, &["only-one".into()]), ExitCode::from(2), "bad usage");
/// ```
#[doc(inline)]
pub use crate::convert::main as run_convert;

/// `plytrace continuity FILE [bezier|hermite]`: the report of a patch
/// file's continuity across shared edges (C0, C1, G1; Firebaugh section 8).
///
/// ```
/// use plytrace::api::program::tools::continuity_report;
///
/// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-one.bpt", std::process::id()));
/// let points: String = (0..4).flat_map(|i| (0..4).map(move |j| format!("{i} {j} 0\n"))).collect();
/// std::fs::write(&path, format!("1\n3 3\n{points}")).unwrap();
/// let report = continuity_report(&path, None);
/// std::fs::remove_file(&path).unwrap();
/// assert!(!report.unwrap().is_empty());
/// assert!(continuity_report(&path, None).is_err(), "the file is gone");
/// ```
#[doc(inline)]
pub use crate::modeling::patch::continuity_report;

/// Brown's tessellation check of a triangulated mesh about a centre (003
/// section 3): the Angle and Edge Conditions.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::tools::{check_tessellation, read_mesh, TessellationReport};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let cube = read_mesh(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/objects/cube.stl"))?;
/// let report: TessellationReport = check_tessellation(&cube, glam::DVec3::splat(0.5)).unwrap();
/// assert!(report.max_edge > 0.0);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::modeling::geodesic::check_tessellation;

/// What [`check_tessellation`] found.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::tools::{check_tessellation, read_mesh};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let cube = read_mesh(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/objects/cube.stl"))?;
/// let report = check_tessellation(&cube, glam::DVec3::splat(0.5)).unwrap();
/// assert!(report.max_edge_ratio >= 1.0);
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::modeling::geodesic::TessellationReport;

/// Reads a mesh file (OBJ, PLY or STL, by its extension).
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::tools::read_mesh;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/objects");
/// let cube = read_mesh(&dir.join("cube.obj"))?;
/// assert_eq!(cube.vertices.len(), 8);
/// assert!(read_mesh(&dir.join("cube.txt")).is_err(), "not a mesh format");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::mesh_import::read_mesh;

/// Reads a `DET` object file (the manual's binary geometry) as a mesh.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::program::tools::read_det;
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/objects");
/// let square = read_det(&dir.join("square.det"))?;
/// assert_eq!((square.vertices.len(), square.polygons.len()), (4, 1));
/// assert!(read_det(&dir.join("cube.obj")).is_err(), "not a DET file");
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::scene::object_file::read_det;

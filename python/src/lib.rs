//! `plytrace._native`: the renderer's library API (`plytrace::api`) for
//! Python. The Python package (`plytrace/__init__.py`, `plytrace/mpl.py`)
//! checks and converts the arguments and documents them; this module only
//! moves arrays across and runs the work with the GIL released, in a
//! worker thread that a Ctrl-C in Python cancels.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use numpy::ndarray::Array2;
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyboardInterrupt, PyMemoryError, PyOSError, PyRuntimeError,
    PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

mod layered;

use plytrace::api::{
    self, Antialiasing, Budgets, Camera, Light, Material, MeshData, Options, Projected,
    Projection as CameraProjection, VectorFormat,
};

create_exception!(
    _native,
    SceneError,
    PyValueError,
    "An error in a scene description, with its place: `file`, `line` and \
     `column` (1-based; 0 when not known) and the `message` alone."
);

/// The budgets as Python names them (`plytrace.Budgets`' fields), with
/// the program's flag for each and whether going over it is running out
/// of memory (`MemoryError`) rather than of work (`ValueError`).
const BUDGETS: [(&str, &str, bool); 10] = [
    ("polygons", "--max-polygons", true),
    ("call_depth", "--max-call-depth", false),
    ("tree_nodes", "--max-tree-nodes", true),
    ("splits", "--max-splits", false),
    ("pixels", "--max-pixels", true),
    ("frame_memory", "--max-frame-memory", true),
    ("overdraw", "--max-overdraw", false),
    ("pair_tests", "--max-pair-tests", false),
    ("model_memory", "--max-model-memory", true),
    ("rays", "--max-rays", false),
];

/// A budget's message with the program's flag (`` `--max-pixels N`
/// raises it``) told as Python's argument, and whether it is of memory;
/// `None` for another message.
fn budget_message(message: &str) -> Option<(String, bool)> {
    BUDGETS.iter().find_map(|(field, flag, memory)| {
        let hint = format!("`{flag} N` raises it");
        message.contains(&hint).then(|| {
            let python = format!("`budgets=plytrace.Budgets({field}=N)` raises it");
            (message.replace(&hint, &python), *memory)
        })
    })
}

/// The library's error as a Python exception: input errors (with file,
/// line and column) as `SceneError`, bad requests as `ValueError` (or
/// `MemoryError` for a memory budget), files as `OSError`, a cancelled
/// render as `KeyboardInterrupt`. A budget's message names the argument
/// that raises it.
fn to_py(py: Python<'_>, e: plytrace::Error) -> PyErr {
    let text = e.to_string();
    let text = budget_message(&text).map_or(text, |(m, _)| m);
    match &e {
        plytrace::Error::Input(d) => {
            let err = SceneError::new_err(text);
            let value = err.value(py);
            let file = d.location.file.display().to_string();
            let message = budget_message(&d.message).map_or_else(|| d.message.clone(), |(m, _)| m);
            let _ = value.setattr("file", file);
            let _ = value.setattr("line", d.location.line);
            let _ = value.setattr("column", d.location.column);
            let _ = value.setattr("message", message);
            err
        }
        plytrace::Error::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(text)
        }
        plytrace::Error::Io { .. } => PyOSError::new_err(text),
        plytrace::Error::Invalid(m) | plytrace::Error::Budget { message: m, .. } => {
            match budget_message(m) {
                Some((m, true)) => PyMemoryError::new_err(m),
                Some((m, false)) => PyValueError::new_err(m),
                None => PyValueError::new_err(m.clone()),
            }
        }
        plytrace::Error::Cancelled => PyKeyboardInterrupt::new_err(text),
        _ => PyValueError::new_err(text),
    }
}

/// Bytes in a MiB (the unit of the memory budgets' flags and fields).
const MIB: u64 = 1 << 20;

/// Budgets from `plytrace.Budgets`' fields (a dict, checked in Python:
/// whole numbers, 0 or more); the memory budgets are in MiB. A field not
/// given keeps its default.
fn budgets_from(fields: Option<&Bound<'_, PyDict>>) -> PyResult<Budgets> {
    let mut b = Budgets::default();
    let Some(fields) = fields else {
        return Ok(b);
    };
    for (key, value) in fields.iter() {
        let key: String = key.extract()?;
        let n: u64 = value.extract()?;
        let size = usize::try_from(n).unwrap_or(usize::MAX);
        match key.as_str() {
            "polygons" => b.polygons = size,
            "call_depth" => b.call_depth = size,
            "tree_nodes" => b.tree_nodes = size,
            "splits" => b.splits = size,
            "pixels" => b.pixels = n,
            "frame_memory" => b.frame_memory = n.saturating_mul(MIB),
            "overdraw" => b.overdraw = n,
            "pair_tests" => b.pair_tests = n,
            "model_memory" => b.model_memory = n.saturating_mul(MIB),
            "rays" => b.rays = n,
            other => return Err(PyValueError::new_err(format!("no budget {other:?}"))),
        }
    }
    Ok(b)
}

/// The default budgets as `plytrace.Budgets`' fields.
#[pyfunction]
fn default_budgets(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let b = Budgets::default();
    let d = PyDict::new(py);
    let values: [u64; 10] = [
        b.polygons as u64,
        b.call_depth as u64,
        b.tree_nodes as u64,
        b.splits as u64,
        b.pixels,
        b.frame_memory / MIB,
        b.overdraw,
        b.pair_tests,
        b.model_memory / MIB,
        b.rays,
    ];
    for ((field, _, _), v) in BUDGETS.iter().zip(values) {
        d.set_item(field, v)?;
    }
    Ok(d)
}

/// Refuses a mesh of `vertices`, `faces` and `corners` (indices of all
/// faces) over `budgets` (`plytrace::api::Scene::check_mesh` on an empty
/// scene): the Python layer asks before it copies the arrays.
#[pyfunction]
#[pyo3(signature = (name, vertices, faces, corners, budgets=None))]
fn check_mesh(
    py: Python<'_>,
    name: &str,
    vertices: usize,
    faces: usize,
    corners: usize,
    budgets: Option<&Bound<'_, PyDict>>,
) -> PyResult<()> {
    let mut scene = api::Scene::new(Camera::looking_at([0.0, -1.0, 0.0], [0.0; 3]), 1, 1);
    scene.set_budgets(budgets_from(budgets)?);
    scene
        .check_mesh(name, vertices, faces, corners)
        .map_err(|e| to_py(py, e))
}

/// Writes `data` to `path` through the library's atomic writer: a
/// temporary file beside it, renamed into place once complete (an
/// earlier file survives a failed write whole), refused over a file this
/// process has read as an input, or over a directory, link or special
/// file.
#[pyfunction]
fn write_file(py: Python<'_>, path: std::path::PathBuf, data: &[u8]) -> PyResult<()> {
    use plytrace::api::program::files::AtomicFile;
    cancellable(py, || {
        let mut file = AtomicFile::create(&path)?;
        file.write_all(data)?;
        file.finish()?.commit()
    })
}

/// Renders in flight in this process (the cancel flag is process-wide).
static IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);

/// Clears the cancel flag when the last render in flight ends.
struct InFlight;

impl InFlight {
    fn enter() -> InFlight {
        if IN_FLIGHT.fetch_add(1, Ordering::SeqCst) == 0 {
            plytrace::api::program::control::reset_cancel();
        }
        InFlight
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        if IN_FLIGHT.fetch_sub(1, Ordering::SeqCst) == 1 {
            plytrace::api::program::control::reset_cancel();
        }
    }
}

/// Runs `work` in a worker thread with the GIL released. The calling
/// thread wakes every 50 ms to run Python's signal handlers: on
/// `KeyboardInterrupt` (Ctrl-C) it asks the renderer to stop
/// (`plytrace::api::program::control`), waits for the worker and raises it.
fn cancellable<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> plytrace::Result<T> + Send,
{
    let _in_flight = InFlight::enter();
    let done = (Mutex::new(false), Condvar::new());
    let (result, interrupted) = std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
            *done.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
            done.1.notify_all();
            r
        });
        let mut interrupted: Option<PyErr> = None;
        loop {
            let finished = py.detach(|| {
                let guard = done.0.lock().unwrap_or_else(|e| e.into_inner());
                let (guard, _) = done
                    .1
                    .wait_timeout_while(guard, Duration::from_millis(50), |d| !*d)
                    .unwrap_or_else(|e| e.into_inner());
                *guard
            });
            if finished {
                break;
            }
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                plytrace::api::program::control::request_cancel();
                interrupted = Some(e);
            }
        }
        (py.detach(|| worker.join()), interrupted)
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    match result {
        Ok(Ok(Ok(v))) => Ok(v),
        Ok(Ok(Err(e))) => Err(to_py(py, e)),
        Ok(Err(panic)) | Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| panic.downcast_ref::<&str>().copied())
                .unwrap_or("unknown");
            Err(PyRuntimeError::new_err(format!(
                "plytrace failed (a bug; please report it): {what}"
            )))
        }
    }
}

/// A contiguous copy of an `(n, k)` float array as rows.
fn rows<const K: usize>(a: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<[f64; K]>> {
    let shape = a.shape();
    if shape[1] != K {
        return Err(PyValueError::new_err(format!(
            "{what} must have shape (n, {K}), not {shape:?}"
        )));
    }
    Ok(a.as_array()
        .rows()
        .into_iter()
        .map(|r| std::array::from_fn(|k| r[k]))
        .collect())
}

/// A scene, read from a `.des` file or its text, or built from arrays.
#[pyclass(module = "plytrace._native")]
struct NativeScene {
    scene: api::Scene,
}

impl NativeScene {
    /// `budgets` given, else the scene's own.
    fn budgets(&self, budgets: Option<&Bound<'_, PyDict>>) -> PyResult<Budgets> {
        match budgets {
            Some(b) => budgets_from(Some(b)),
            None => Ok(self.scene.budgets()),
        }
    }
}

#[pymethods]
impl NativeScene {
    /// An empty scene seen from `eye` looking at `target` with `up` up:
    /// a perspective of `fovy` degrees, or with `ortho` = (left, right,
    /// bottom, top) an orthographic view; `near` and `far` bound it.
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (eye, target, up, fovy, near, far, ortho, width, height))]
    fn new(
        eye: [f64; 3],
        target: [f64; 3],
        up: [f64; 3],
        fovy: f64,
        near: f64,
        far: f64,
        ortho: Option<[f64; 4]>,
        width: u32,
        height: u32,
    ) -> NativeScene {
        let projection = match ortho {
            Some([left, right, bottom, top]) => CameraProjection::Orthographic {
                left,
                right,
                bottom,
                top,
                near,
                far,
            },
            None => CameraProjection::Perspective { fovy, near, far },
        };
        let camera = Camera {
            eye,
            target,
            up,
            twist: 0.0,
            projection,
        };
        NativeScene {
            scene: api::Scene::new(camera, width, height),
        }
    }

    /// Reads a scene descriptor file within `budgets`.
    #[staticmethod]
    #[pyo3(signature = (path, budgets=None))]
    fn from_file(
        py: Python<'_>,
        path: std::path::PathBuf,
        budgets: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<NativeScene> {
        let budgets = budgets_from(budgets)?;
        let scene = cancellable(py, || api::Scene::from_file_with(&path, budgets))?;
        Ok(NativeScene { scene })
    }

    /// Reads a scene from its text within `budgets`; object files are
    /// looked up in `dir`.
    #[staticmethod]
    #[pyo3(signature = (text, dir, budgets=None))]
    fn from_text(
        py: Python<'_>,
        text: String,
        dir: std::path::PathBuf,
        budgets: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<NativeScene> {
        let budgets = budgets_from(budgets)?;
        let scene = cancellable(py, || api::Scene::from_text_with(&text, &dir, budgets))?;
        Ok(NativeScene { scene })
    }

    /// Sets the budgets the scene is added to and rendered within.
    fn set_budgets(&mut self, budgets: &Bound<'_, PyDict>) -> PyResult<()> {
        self.scene.set_budgets(budgets_from(Some(budgets))?);
        Ok(())
    }

    /// Adds a light.
    fn add_light(
        &mut self,
        py: Python<'_>,
        position: [f64; 3],
        color: [f64; 3],
        range: f64,
        shadows: bool,
    ) -> PyResult<()> {
        self.scene
            .add_light(Light {
                position,
                color,
                range,
                shadows,
            })
            .map_err(|e| to_py(py, e))
    }

    /// Adds a mesh: `vertices` (n, 3), faces as `indices` flattened with
    /// `sizes` (vertices per face), optional colours per face or vertex,
    /// and the surface: colour, diffuse, specular, shininess,
    /// reflectance, transmittance, index, transparency, roll-off,
    /// two-sided, smooth.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (name, vertices, indices, sizes, face_colors, vertex_colors, color, coefficients, two_sided, smooth))]
    fn add_mesh(
        &mut self,
        name: &str,
        vertices: PyReadonlyArray2<'_, f64>,
        indices: PyReadonlyArray1<'_, u32>,
        sizes: PyReadonlyArray1<'_, u32>,
        face_colors: Option<PyReadonlyArray2<'_, f64>>,
        vertex_colors: Option<PyReadonlyArray2<'_, f64>>,
        color: [f64; 3],
        coefficients: [f64; 7],
        two_sided: bool,
        smooth: bool,
    ) -> PyResult<()> {
        let py = vertices.py();
        // The budgets, before any copy is made.
        self.scene
            .check_mesh(name, vertices.shape()[0], sizes.len(), indices.len())
            .map_err(|e| to_py(py, e))?;
        let vertices = rows::<3>(&vertices, "vertices")?;
        let indices = indices.as_array();
        let mut faces = Vec::with_capacity(sizes.len());
        let mut at = 0usize;
        for &n in sizes.as_array().iter() {
            let n = n as usize;
            if at + n > indices.len() {
                return Err(PyValueError::new_err("face sizes exceed the indices"));
            }
            faces.push(indices.slice(numpy::ndarray::s![at..at + n]).to_vec());
            at += n;
        }
        if at != indices.len() {
            return Err(PyValueError::new_err(
                "face sizes do not add up to the indices",
            ));
        }
        let mut mesh = MeshData::new(vertices, faces);
        mesh.face_colors = face_colors
            .map(|c| rows::<3>(&c, "face colours"))
            .transpose()?;
        mesh.vertex_colors = vertex_colors
            .map(|c| rows::<3>(&c, "vertex colours"))
            .transpose()?;
        let mut material = Material::color(color);
        let [
            diffuse,
            specular,
            shininess,
            reflectance,
            transmittance,
            index,
            transparency,
        ] = coefficients;
        material.surface.diffuse = diffuse;
        material.surface.specular = specular;
        material.surface.shininess = shininess;
        material.surface.reflectance = reflectance;
        material.surface.transmittance = transmittance;
        material.surface.index = index;
        material.surface.transparency = (transparency, 0.0);
        material.two_sided = two_sided;
        material.smooth = smooth;
        let scene = &mut self.scene;
        cancellable(py, || scene.add_mesh(name, &mesh, &material))
    }

    /// The background colour, 0 to 1.
    fn set_background(&mut self, py: Python<'_>, rgb: [f64; 3]) -> PyResult<()> {
        self.scene.set_background(rgb).map_err(|e| to_py(py, e))
    }

    /// The ambient light's colour, 0 to 1.
    fn set_ambient(&mut self, py: Python<'_>, rgb: [f64; 3]) -> PyResult<()> {
        self.scene.set_ambient(rgb).map_err(|e| to_py(py, e))
    }

    /// The image size the scene gives, (width, height).
    fn size(&self) -> (u32, u32) {
        self.scene.size()
    }

    /// Renders to an (height, width, 3) uint8 array.
    #[pyo3(signature = (size, antialias, shadows, budgets=None))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        size: Option<(u32, u32)>,
        antialias: bool,
        shadows: bool,
        budgets: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut options = Options::default()
            .with_shadows(shadows)
            .with_budgets(self.budgets(budgets)?);
        options.size = size;
        options.antialiasing = (!antialias).then_some(Antialiasing::Point);
        let scene = &self.scene;
        let image = cancellable(py, || api::render(scene, &options))?;
        let (w, h) = (image.width as usize, image.height as usize);
        Ok(PyArray1::from_vec(py, image.rgb)
            .reshape([h, w, 3])?
            .into_any())
    }

    /// Renders to the bytes of a PNG file.
    #[pyo3(signature = (size, antialias, shadows, budgets=None))]
    fn render_png<'py>(
        &self,
        py: Python<'py>,
        size: Option<(u32, u32)>,
        antialias: bool,
        shadows: bool,
        budgets: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let mut options = Options::default()
            .with_shadows(shadows)
            .with_budgets(self.budgets(budgets)?);
        options.size = size;
        options.antialiasing = (!antialias).then_some(Antialiasing::Point);
        let scene = &self.scene;
        let png = cancellable(py, || api::render(scene, &options)?.to_png())?;
        Ok(PyBytes::new(py, &png))
    }

    /// Renders to the bytes of an SVG, PDF or TikZ (`tex`) file.
    #[pyo3(signature = (format, size, shadows, budgets=None))]
    fn render_vector<'py>(
        &self,
        py: Python<'py>,
        format: &str,
        size: Option<(u32, u32)>,
        shadows: bool,
        budgets: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let format = match format {
            "svg" => VectorFormat::Svg,
            "pdf" => VectorFormat::Pdf,
            "tex" => VectorFormat::Tikz,
            other => {
                return Err(PyValueError::new_err(format!(
                    "format {other:?}: expected \"svg\", \"pdf\" or \"tex\""
                )));
            }
        };
        let mut options = Options::default()
            .with_shadows(shadows)
            .with_budgets(self.budgets(budgets)?);
        options.size = size;
        let scene = &self.scene;
        let bytes = cancellable(py, || api::render_vector(scene, &options, format))?;
        Ok(PyBytes::new(py, &bytes))
    }
}

/// matplotlib's path codes.
const MOVETO: u8 = 1;
const LINETO: u8 = 2;
const CLOSEPOLY: u8 = 79;

/// 3-D polygons seen through a 4 x 4 matrix, for hidden-surface removal
/// in another program's picture (`plytrace::api::Projected`).
#[pyclass(module = "plytrace._native", frozen)]
struct Projection {
    inner: Projected,
}

/// Paths for matplotlib, concatenated: vertices, codes and where each
/// path starts.
#[derive(Default)]
struct Paths {
    verts: Vec<f64>,
    codes: Vec<u8>,
    starts: Vec<i64>,
}

impl Paths {
    fn start(&mut self) {
        self.starts.push(self.codes.len() as i64);
    }

    fn push(&mut self, p: [f64; 2], code: u8) {
        self.verts.extend_from_slice(&p);
        self.codes.push(code);
    }

    /// `ring` as a closed subpath, counter-clockwise (so that rings of
    /// one fill that overlap add up under the nonzero rule instead of
    /// cancelling).
    fn ring(&mut self, ring: &[[f64; 2]]) {
        let n = ring.len();
        let reverse = signed_area(ring) < 0.0;
        for k in 0..n {
            let p = ring[if reverse { n - 1 - k } else { k }];
            self.push(p, if k == 0 { MOVETO } else { LINETO });
        }
        let first = self.verts.len() - 2 * n;
        let p0 = [self.verts[first], self.verts[first + 1]];
        self.push(p0, CLOSEPOLY);
    }

    /// `ring` grown by `grow` = (x, y) on every side: each edge moved
    /// out by that much (in a space scaled so that it is the same both
    /// ways), corners mitred but moved at most twice as far.
    fn grown_ring(&mut self, ring: &[[f64; 2]], grow: (f64, f64)) {
        let n = ring.len();
        let mut q: Vec<[f64; 2]> = ring
            .iter()
            .map(|p| [p[0] / grow.0, p[1] / grow.1])
            .collect();
        if signed_area(&q) < 0.0 {
            q.reverse();
        }
        // Counter-clockwise: the outward normal of (dx, dy) is (dy, -dx).
        let side = 1.0;
        // Outward unit normal of edge k (from point k to k + 1).
        let normal = |k: usize| {
            let (a, b) = (q[k], q[(k + 1) % n]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len = dx.hypot(dy);
            (len > 0.0).then(|| [side * dy / len, -side * dx / len])
        };
        let normals: Vec<Option<[f64; 2]>> = (0..n).map(normal).collect();
        for k in 0..n {
            let before = normals[(k + n - 1) % n].or(normals[k]);
            let after = normals[k].or(before);
            let p = match (before, after) {
                (Some(a), Some(b)) => {
                    let (sx, sy) = (a[0] + b[0], a[1] + b[1]);
                    let d = 1.0 + a[0] * b[0] + a[1] * b[1];
                    // Mitre: (a + b) / (1 + a.b), at most 2 long.
                    let (mut mx, mut my) = if d > 1e-9 {
                        (sx / d, sy / d)
                    } else {
                        (a[0], a[1])
                    };
                    let len = mx.hypot(my);
                    if len > 2.0 {
                        mx *= 2.0 / len;
                        my *= 2.0 / len;
                    }
                    [q[k][0] + mx, q[k][1] + my]
                }
                _ => q[k],
            };
            self.push(
                [p[0] * grow.0, p[1] * grow.1],
                if k == 0 { MOVETO } else { LINETO },
            );
        }
        let first = self.verts.len() - 2 * n;
        let p0 = [self.verts[first], self.verts[first + 1]];
        self.push(p0, CLOSEPOLY);
    }

    /// The edges of `ring` flagged in `edges`, as open runs (or the
    /// closed ring when all are).
    fn edges(&mut self, ring: &[[f64; 2]], edges: &[bool]) {
        let n = ring.len();
        if edges.iter().all(|e| *e) {
            self.ring(ring);
            return;
        }
        // Start after an edge that is not drawn, so no run wraps.
        let Some(gap) = edges.iter().position(|e| !*e) else {
            return;
        };
        let mut drawing = false;
        for i in 1..=n {
            let k = (gap + i) % n;
            if edges[k] {
                if !drawing {
                    self.push(ring[k], MOVETO);
                    drawing = true;
                }
                self.push(ring[(k + 1) % n], LINETO);
            } else {
                drawing = false;
            }
        }
    }

    fn finish(
        mut self,
        py: Python<'_>,
    ) -> PyResult<(Bound<'_, PyAny>, Bound<'_, PyAny>, Bound<'_, PyAny>)> {
        self.starts.push(self.codes.len() as i64);
        let n = self.codes.len();
        let verts = Array2::from_shape_vec((n, 2), self.verts)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((
            PyArray2::from_owned_array(py, verts).into_any(),
            PyArray1::from_vec(py, self.codes).into_any(),
            PyArray1::from_vec(py, self.starts).into_any(),
        ))
    }
}

/// Twice the signed area of a closed polygon (positive counter-clockwise).
fn signed_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1])
        .sum()
}

/// The paint order as arrays for Python.
type PaintArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    (Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>),
    (Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>),
    usize,
    Option<String>,
);

#[pymethods]
impl Projection {
    /// `points` (n, 3) of all polygons one after the other, `sizes` the
    /// points of each, `matrix` the 4 x 4 projection (`M @ p`); `open`:
    /// per polygon, whether it lacks its closing edge.
    #[new]
    #[pyo3(signature = (points, sizes, matrix, open=None))]
    fn new(
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        sizes: PyReadonlyArray1<'_, i64>,
        matrix: PyReadonlyArray2<'_, f64>,
        open: Option<PyReadonlyArray1<'_, bool>>,
    ) -> PyResult<Projection> {
        let open: Vec<bool> = open.map(|o| o.as_array().to_vec()).unwrap_or_default();
        let points = rows::<3>(&points, "points")?;
        let m = rows::<4>(&matrix, "matrix")?;
        let matrix: [[f64; 4]; 4] = m
            .try_into()
            .map_err(|_| PyValueError::new_err("matrix must have shape (4, 4)"))?;
        let mut polygons: Vec<&[[f64; 3]]> = Vec::with_capacity(sizes.len());
        let mut at = 0usize;
        for &n in sizes.as_array().iter() {
            let n = usize::try_from(n).map_err(|_| PyValueError::new_err("negative size"))?;
            let Some(poly) = points.get(at..at + n) else {
                return Err(PyValueError::new_err("polygon sizes exceed the points"));
            };
            polygons.push(poly);
            at += n;
        }
        let inner = cancellable(py, || Projected::new_with_open(&polygons, matrix, &open))?;
        Ok(Projection { inner })
    }

    /// The visible pieces back to front, in patches: (sources (of each
    /// patch's first ring), whole (every ring a whole polygon), fill
    /// paths, edge paths, splits, warning). Each paths item is (vertices
    /// (v, 2), codes (v,), starts (patches + 1,)); the edge paths hold the
    /// polygon edges of the rings that are not whole. With `grow` =
    /// (x, y), the rings of the sources `grown` marks are grown by that
    /// much on every side (to close the seams anti-aliasing leaves
    /// between adjacent polygons). `keys`: per source; sources of one key
    /// are filled together where the order allows.
    #[pyo3(signature = (grow=None, grown=None, keys=None))]
    fn paint_order<'py>(
        &self,
        py: Python<'py>,
        grow: Option<(f64, f64)>,
        grown: Option<PyReadonlyArray1<'_, bool>>,
        keys: Option<PyReadonlyArray1<'_, u32>>,
    ) -> PyResult<PaintArrays<'py>> {
        let grow = grow.filter(|g| g.0 > 0.0 && g.1 > 0.0 && g.0.is_finite() && g.1.is_finite());
        let grown: Option<Vec<bool>> = grown.map(|g| g.as_array().to_vec());
        let keys: Option<Vec<u32>> = keys.map(|k| k.as_array().to_vec());
        let inner = &self.inner;
        let order = cancellable(py, || inner.paint_order_by(keys.as_deref()))?;
        let (mut fills, mut edges) = (Paths::default(), Paths::default());
        let mut sources = Vec::with_capacity(order.patches.len());
        let mut whole = Vec::with_capacity(order.patches.len());
        for patch in &order.patches {
            sources.push(patch.source() as i64);
            whole.push(patch.rings.iter().all(|r| r.whole));
            fills.start();
            edges.start();
            for ring in &patch.rings {
                let grows = grow.filter(|_| {
                    grown
                        .as_ref()
                        .is_none_or(|g| g.get(ring.source).copied().unwrap_or(false))
                });
                match grows {
                    Some(g) => fills.grown_ring(&ring.points, g),
                    None => fills.ring(&ring.points),
                }
                if !ring.whole {
                    edges.edges(&ring.points, &ring.edges);
                }
            }
        }
        Ok((
            PyArray1::from_vec(py, sources).into_any(),
            PyArray1::from_vec(py, whole).into_any(),
            fills.finish(py)?,
            edges.finish(py)?,
            order.splits,
            order.warning,
        ))
    }

    /// The paint order (as `paint_order`, every source grown where
    /// `grown` says), and where in it the polylines' visible parts and
    /// the `anchors` (m, 3) are painted: `opaque` per source says which
    /// polygons hide what is behind them. Returns (the paint arrays,
    /// (xy (k, 2) with NaN rows between parts, line (r,), slot (r,),
    /// starts (r + 1,)) per run of parts of one polyline painted before
    /// patch `slot` (the patch count: after all), the anchors' slots (m,)
    /// (-1: behind the eye)).
    #[pyo3(signature = (grow, grown, keys, opaque, points, sizes, anchors))]
    #[allow(clippy::too_many_arguments)]
    fn layered<'py>(
        &self,
        py: Python<'py>,
        grow: Option<(f64, f64)>,
        grown: PyReadonlyArray1<'_, bool>,
        keys: PyReadonlyArray1<'_, u32>,
        opaque: PyReadonlyArray1<'_, bool>,
        points: PyReadonlyArray2<'_, f64>,
        sizes: PyReadonlyArray1<'_, i64>,
        anchors: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<layered::LayeredArrays<'py>> {
        let grow = grow.filter(|g| g.0 > 0.0 && g.1 > 0.0 && g.0.is_finite() && g.1.is_finite());
        let grown = grown.as_array().to_vec();
        let keys = keys.as_array().to_vec();
        let opaque = opaque.as_array().to_vec();
        let points = rows::<3>(&points, "points")?;
        let anchors = rows::<3>(&anchors, "anchors")?;
        let sizes = sizes.as_array().to_vec();
        let (segments, first) = layered::polyline_segments(&points, &sizes)?;
        let inner = &self.inner;
        let result = cancellable(py, || {
            inner.layered(Some(&keys), &opaque, &segments, &anchors)
        })?;
        layered::arrays(py, &result, grow, Some(&grown), &first)
    }

    /// The visible parts of polylines (`points` (n, 3) one after the
    /// other, `sizes` the points of each): (xy (k, 2) with NaN rows
    /// between pieces, starts (polylines + 1,), visible (n,) per point).
    fn visible_polylines<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'_, f64>,
        sizes: PyReadonlyArray1<'_, i64>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let points = rows::<3>(&points, "points")?;
        let sizes: Vec<usize> = sizes
            .as_array()
            .iter()
            .map(|&n| usize::try_from(n).map_err(|_| PyValueError::new_err("negative size")))
            .collect::<PyResult<_>>()?;
        if sizes.iter().sum::<usize>() != points.len() {
            return Err(PyValueError::new_err(
                "polyline sizes do not add up to the points",
            ));
        }
        // Each point as a segment of no length (for markers), then each
        // polyline's segments.
        let mut segments: Vec<[[f64; 3]; 2]> = points.iter().map(|p| [*p, *p]).collect();
        let mut first_segment = Vec::with_capacity(sizes.len());
        let mut at = 0;
        for &n in &sizes {
            first_segment.push(segments.len());
            for k in at..(at + n).saturating_sub(1) {
                segments.push([points[k], points[k + 1]]);
            }
            at += n;
        }
        let inner = &self.inner;
        let pieces = cancellable(py, || inner.visible_segments(&segments))?;
        let mut visible = vec![false; points.len()];
        let mut by_segment: Vec<Vec<[[f64; 2]; 2]>> = vec![Vec::new(); segments.len()];
        for p in &pieces {
            if p.segment < points.len() {
                visible[p.segment] = true;
            } else {
                by_segment[p.segment].push(p.points);
            }
        }
        let mut xy: Vec<f64> = Vec::new();
        let mut starts = Vec::with_capacity(sizes.len() + 1);
        for (line, &n) in sizes.iter().enumerate() {
            starts.push((xy.len() / 2) as i64);
            let mut last: Option<[f64; 2]> = None;
            let first = first_segment[line];
            for pieces in &by_segment[first..first + n.saturating_sub(1)] {
                for [a, b] in pieces {
                    if last != Some(*a) {
                        if last.is_some() {
                            xy.extend_from_slice(&[f64::NAN, f64::NAN]);
                        }
                        xy.extend_from_slice(a);
                    }
                    xy.extend_from_slice(b);
                    last = Some(*b);
                }
            }
        }
        starts.push((xy.len() / 2) as i64);
        let k = xy.len() / 2;
        let xy = Array2::from_shape_vec((k, 2), xy)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((
            PyArray2::from_owned_array(py, xy).into_any(),
            PyArray1::from_vec(py, starts).into_any(),
            PyArray1::from_vec(py, visible).into_any(),
        ))
    }
}

/// The native part of the `plytrace` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_IMAGE_SIDE", api::MAX_IMAGE_SIDE)?;
    m.add("MAX_IMAGE_PIXELS", api::MAX_IMAGE_PIXELS)?;
    m.add_function(wrap_pyfunction!(default_budgets, m)?)?;
    m.add_function(wrap_pyfunction!(write_file, m)?)?;
    m.add_function(wrap_pyfunction!(check_mesh, m)?)?;
    m.add_class::<NativeScene>()?;
    m.add_class::<Projection>()?;
    Ok(())
}

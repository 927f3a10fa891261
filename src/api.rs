//! The small public face of the library: a [`Scene`] read from a scene
//! descriptor file or built in code from arrays, and [`fn@render`],
//! [`render_vector`] and [`render_rows`] to turn it into pixels or vector
//! graphics. Everything the `plytrace` program does with a scene goes
//! through the modules behind it (Garcia 1986, figure 3.2: scene →
//! geometry → visibility → virtual image tree → scan conversion); this
//! module only gathers what a caller needs and checks what it is given.
//!
//! ```
//! use plytrace::api::{Camera, Light, Material, MeshData, Options, Scene, VectorFormat};
//!
//! let cube = MeshData::new(
//!     vec![[-1., -1., -1.], [1., -1., -1.], [1., 1., -1.], [-1., 1., -1.],
//!          [-1., -1., 1.], [1., -1., 1.], [1., 1., 1.], [-1., 1., 1.]],
//!     vec![vec![0, 3, 2, 1], vec![4, 5, 6, 7], vec![0, 1, 5, 4],
//!          vec![2, 3, 7, 6], vec![1, 2, 6, 5], vec![0, 4, 7, 3]],
//! );
//! let mut scene = Scene::new(Camera::looking_at([4., -6., 3.], [0., 0., 0.]), 64, 64);
//! scene.add_light(Light::point([5., -5., 8.], [1., 1., 1.]))?;
//! scene.add_mesh("cube", &cube, &Material::color([0.2, 0.6, 1.0]))?;
//! let image = plytrace::api::render(&scene, &Options::default())?;
//! assert_eq!((image.width, image.height, image.rgb.len()), (64, 64, 64 * 64 * 3));
//! let png = image.to_png()?;
//! let svg = plytrace::api::render_vector(&scene, &Options::default(), VectorFormat::Svg)?;
//! assert!(png.starts_with(b"\x89PNG") && svg.starts_with(b"<?xml"));
//! # Ok::<(), plytrace::Error>(())
//! ```

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::math::{self, Matrix4};
use crate::model::{self, LightKind, Surface, SurfaceType, Viewport};
use crate::model::{ColorEntry, Mesh};
use crate::render::{self, RenderOptions, RenderStats};
use crate::scene::build::{ObjectParts, build_object};

pub mod program;
mod projected;

pub use projected::{Layered, PaintOrder, Patch, PlacedSegment, Projected, Ring, SegmentPiece};

/// Limits on the work of a render (the program's `--max-*` flags): the
/// image's pixels, polygons, tree nodes, splits, memory, rays. A render
/// over one stops with an error that names the flag that raises it.
///
/// ```
/// use plytrace::api::{render, Budgets, Camera, Options, Scene};
///
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 64, 64);
/// let tight = Budgets { pixels: 1000, ..Budgets::default() };
/// let e = render(&scene, &Options { budgets: tight, ..Options::default() }).unwrap_err();
/// assert!(e.to_string().contains("--max-pixels"));
/// assert!(Budgets::default().pixels >= 64 * 64);
/// ```
#[doc(inline)]
pub use crate::budget::Budgets;

/// The largest side of an image and the most pixels it may have, as the
/// scene language's `resolution` and the program's `--size` allow:
/// [`fn@render`] and [`render_vector`] refuse a size beyond them.
///
/// ```
/// use plytrace::api::{render, Camera, Options, Scene, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
///
/// assert_eq!((MAX_IMAGE_SIDE, MAX_IMAGE_PIXELS), (65536, 1 << 28));
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
/// let wide = Options { size: Some((65537, 1)), ..Options::default() };
/// assert!(render(&scene, &wide).is_err());
/// ```
pub use crate::scene::interpreter::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};

/// The anti-aliasing methods of [`Options::antialiasing`] (the scan
/// conversion methods of the virtual image tree).
///
/// ```
/// use plytrace::api::{render, Antialiasing, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
/// scene.set_background([0., 1., 0.])?;
/// let options = Options { antialiasing: Some(Antialiasing::Supersample(2)), ..Options::default() };
/// let image = render(&scene, &options)?;
/// assert!(image.rgb.chunks(3).all(|p| p == [0, 255, 0]));
/// # Ok(())
/// # }
/// ```
#[doc(inline)]
pub use crate::raster::scan::Method as Antialiasing;
/// The vector formats of [`render_vector`]; [`VectorFormat::from_path`]
/// picks one by a file name's extension.
///
/// ```
/// use std::path::Path;
/// use plytrace::api::VectorFormat;
///
/// assert_eq!(VectorFormat::from_path(Path::new("cube.SVG")), Some(VectorFormat::Svg));
/// assert_eq!(VectorFormat::from_path(Path::new("cube.tex")), Some(VectorFormat::Tikz));
/// assert_eq!(VectorFormat::from_path(Path::new("cube.png")), None);
/// ```
#[doc(inline)]
pub use crate::vector::Format as VectorFormat;

/// How the scene is seen: an eye, the point it looks at, a twist about
/// the line of sight, and a projection.
///
/// ```
/// use plytrace::api::{render, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut camera = Camera::looking_at([0., -5., 0.], [0., 0., 0.]);
/// camera.twist = 90.0;
/// assert!(render(&Scene::new(camera, 16, 16), &Options::default()).is_ok());
/// // A camera looking at its own eye has no line of sight.
/// camera.target = camera.eye;
/// assert!(render(&Scene::new(camera, 16, 16), &Options::default()).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// The eye.
    pub eye: [f64; 3],
    /// The point looked at.
    pub target: [f64; 3],
    /// The world direction shown up on the screen.
    pub up: [f64; 3],
    /// Rotation about the line of sight, degrees (the manual's `lookat`).
    pub twist: f64,
    /// The projection.
    pub projection: Projection,
}

/// The projection of a [`Camera`].
///
/// ```
/// use plytrace::api::{render, Camera, Options, Projection, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut camera = Camera::looking_at([0., -5., 0.], [0., 0., 0.]);
/// camera.projection = Projection::Orthographic {
///     left: -2., right: 2., bottom: -1., top: 1., near: 0.1, far: 100.,
/// };
/// let image = render(&Scene::new(camera, 32, 16), &Options::default())?;
/// assert_eq!((image.width, image.height), (32, 16));
/// // A field of view of 180 degrees or more is refused.
/// camera.projection = Projection::Perspective { fovy: 200., near: 0.1, far: 100. };
/// assert!(render(&Scene::new(camera, 32, 16), &Options::default()).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// `perspective fovy aspect near far`; the aspect is the image's.
    Perspective {
        /// Vertical field of view, degrees.
        fovy: f64,
        /// Nearest distance drawn.
        near: f64,
        /// Farthest distance drawn.
        far: f64,
    },
    /// `ortho left right bottom top near far`, in eye coordinates.
    Orthographic {
        /// Left edge.
        left: f64,
        /// Right edge.
        right: f64,
        /// Bottom edge.
        bottom: f64,
        /// Top edge.
        top: f64,
        /// Nearest distance drawn.
        near: f64,
        /// Farthest distance drawn.
        far: f64,
    },
}

impl Camera {
    /// A camera at `eye` looking at `target` with a 45-degree perspective
    /// (near 0.01, far 10,000) and +z up, as in most plotting tools. (The
    /// scene language's `lookat` keeps +y up, as IRIS GL did: set `up` to
    /// `[0, 1, 0]` for the same view.)
    ///
    /// ```
    /// use plytrace::api::{Camera, Projection};
    ///
    /// let camera = Camera::looking_at([4., -6., 3.], [0., 0., 0.]);
    /// assert_eq!((camera.eye, camera.target), ([4., -6., 3.], [0., 0., 0.]));
    /// assert_eq!((camera.up, camera.twist), ([0., 0., 1.], 0.));
    /// assert_eq!(camera.projection, Projection::Perspective { fovy: 45., near: 0.01, far: 10_000. });
    /// ```
    pub fn looking_at(eye: [f64; 3], target: [f64; 3]) -> Camera {
        Camera {
            eye,
            target,
            up: [0.0, 0.0, 1.0],
            twist: 0.0,
            projection: Projection::Perspective {
                fovy: 45.0,
                near: 0.01,
                far: 10_000.0,
            },
        }
    }

    /// World to clip coordinates for an image of `aspect` = width / height:
    /// the projection, pre-multiplied by the view (IRIS GL order).
    fn matrix(&self, aspect: f64) -> Result<Matrix4> {
        let projection = match self.projection {
            Projection::Perspective { fovy, near, far } => {
                check_range("fovy", fovy, 0.0, 180.0)?;
                check_depths(near, far)?;
                math::perspective(fovy, aspect, near, far)
            }
            Projection::Orthographic {
                left,
                right,
                bottom,
                top,
                near,
                far,
            } => {
                let all = [left, right, bottom, top, near, far];
                if all.iter().any(|v| !v.is_finite())
                    || left == right
                    || bottom == top
                    || near == far
                {
                    return Err(invalid(
                        "an orthographic camera needs finite, distinct bounds",
                    ));
                }
                math::ortho(left, right, bottom, top, near, far)
            }
        };
        let (eye, target) = (
            finite3("camera eye", self.eye)?,
            finite3("camera target", self.target)?,
        );
        let up = finite3("camera up", self.up)?;
        if !self.twist.is_finite() {
            return Err(invalid(&format!(
                "camera twist {}: expected a finite angle",
                self.twist
            )));
        }
        let view = math::lookat_up(eye, target, up, self.twist).ok_or_else(|| {
            invalid("the camera's eye and target are the same point, or it looks along `up`")
        })?;
        Ok(view.mul(&projection))
    }
}

/// A light source.
///
/// ```
/// use plytrace::api::{render, Camera, Light, MeshData, Material, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let square = MeshData::new(
///     vec![[-1., 0., -1.], [1., 0., -1.], [1., 0., 1.], [-1., 0., 1.]],
///     vec![vec![0, 1, 2, 3]],
/// );
/// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
/// scene.add_mesh("square", &square, &Material::color([1., 1., 1.]))?;
/// scene.set_ambient([0., 0., 0.])?;
/// // A red light that casts no shadows (the manual's `Diffuse`).
/// let red = Light { color: [1., 0., 0.], shadows: false, ..Light::point([0., -5., 0.], [1., 1., 1.]) };
/// scene.add_light(red)?;
/// let image = render(&scene, &Options::default())?;
/// let centre = &image.rgb[(8 * 16 + 8) * 3..][..3];
/// assert!(centre[0] > 0 && centre[1..] == [0, 0], "white lit red: {centre:?}");
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Position in world coordinates.
    pub position: [f64; 3],
    /// Colour, 0 to 1.
    pub color: [f64; 3],
    /// Distance at which its light falls to nothing (004 section 4.8).
    pub range: f64,
    /// Whether it casts shadows (the manual's `Point`; else `Diffuse`).
    pub shadows: bool,
}

impl Light {
    /// A shadow-casting light with a range of 10,000.
    ///
    /// ```
    /// use plytrace::api::Light;
    ///
    /// let light = Light::point([5., -5., 8.], [1., 0.9, 0.8]);
    /// assert!(light.shadows);
    /// assert_eq!((light.position, light.color, light.range), ([5., -5., 8.], [1., 0.9, 0.8], 10_000.));
    /// ```
    pub fn point(position: [f64; 3], color: [f64; 3]) -> Light {
        Light {
            position,
            color,
            range: 10_000.0,
            shadows: true,
        }
    }

    /// Checks the light as the scene language's `light` command does: a
    /// finite position, colour components finite and not negative, a
    /// finite positive range.
    ///
    /// ```
    /// use plytrace::api::Light;
    ///
    /// let mut light = Light::point([5., -5., 8.], [1., 1., 1.]);
    /// assert!(light.validate().is_ok());
    /// light.range = f64::INFINITY;
    /// assert!(light.validate().unwrap_err().to_string().contains("light range"));
    /// ```
    pub fn validate(&self) -> Result<()> {
        finite3("light position", self.position)?;
        if self.color.iter().any(|c| !c.is_finite() || *c < 0.0) {
            return Err(invalid(&format!(
                "light color {:?}: expected finite components, 0 or more",
                self.color
            )));
        }
        if !(self.range.is_finite() && self.range > 0.0) {
            return Err(invalid(&format!(
                "light range {}: expected a finite number more than 0",
                self.range
            )));
        }
        Ok(())
    }
}

/// The surface of an object: the coefficients of the scene language's
/// `color`, `diffuse`, `specular`, `shininess`, `reflectance`,
/// `transmittance`, `index` and `transparency` commands (004 section 4.8),
/// and whether both sides of its faces are seen (`type polygon open`).
///
/// ```
/// use plytrace::api::{render, Camera, MeshData, Material, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// // A square facing -y, seen from behind (from +y).
/// let square = MeshData::new(
///     vec![[-1., 0., -1.], [1., 0., -1.], [1., 0., 1.], [-1., 0., 1.]],
///     vec![vec![0, 1, 2, 3]],
/// );
/// let centre = |material: &Material| -> Result<Vec<u8>, plytrace::Error> {
///     let mut scene = Scene::new(Camera::looking_at([0., 5., 0.], [0., 0., 0.]), 16, 16);
///     scene.add_mesh("square", &square, material)?;
///     Ok(render(&scene, &Options::default())?.rgb[(8 * 16 + 8) * 3..][..3].to_vec())
/// };
/// let mut red = Material::color([1., 0., 0.]);
/// red.surface.diffuse = 0.0; // ambient only: k_a = 1 - k_d = 1
/// assert_eq!(centre(&red)?, [0, 0, 0], "its back is culled");
/// red.two_sided = true;
/// assert_eq!(centre(&red)?, [255, 0, 0]);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Material {
    /// The scene language's surface attributes.
    pub surface: Surface,
    /// Both sides of each face are drawn (an open surface).
    pub two_sided: bool,
    /// Vertex normals are interpolated (`type polygon curved`).
    pub smooth: bool,
}

impl Material {
    /// The default surface in colour `rgb`.
    ///
    /// ```
    /// use plytrace::api::Material;
    ///
    /// let m = Material::color([0.2, 0.6, 1.0]);
    /// assert_eq!(m.surface.color.to_array(), [0.2, 0.6, 1.0]);
    /// assert_eq!(m.surface.diffuse, 0.6, "the scene language's default");
    /// assert!(!m.two_sided && !m.smooth);
    /// ```
    pub fn color(rgb: [f64; 3]) -> Material {
        let mut m = Material::default();
        m.surface.color = DVec3::from_array(rgb);
        m
    }

    /// Checks the coefficients as the scene language's commands do: the
    /// colour, `diffuse`, `specular`, `reflectance`, `transmittance` and
    /// the transparency from 0 to 1, `shininess` and the transparency's
    /// roll-off 0 or more, `index` more than 0; every one finite.
    ///
    /// ```
    /// use plytrace::api::Material;
    ///
    /// let mut m = Material::color([0.2, 0.6, 1.0]);
    /// assert!(m.validate().is_ok());
    /// m.surface.shininess = f64::NAN;
    /// assert!(m.validate().unwrap_err().to_string().contains("shininess NaN"));
    /// ```
    pub fn validate(&self) -> Result<()> {
        let s = &self.surface;
        check_color("material color", s.color.to_array())?;
        let unit = [
            ("diffuse", s.diffuse),
            ("specular", s.specular),
            ("reflectance", s.reflectance),
            ("transmittance", s.transmittance),
            ("transparency", s.transparency.0),
        ];
        for (what, v) in unit {
            if !(0.0..=1.0).contains(&v) {
                return Err(invalid(&format!(
                    "material {what} {v}: expected a number from 0 to 1"
                )));
            }
        }
        for (what, v) in [("shininess", s.shininess), ("roll-off", s.transparency.1)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(&format!(
                    "material {what} {v}: expected a finite number, 0 or more"
                )));
            }
        }
        if !(s.index.is_finite() && s.index > 0.0) {
            return Err(invalid(&format!(
                "material index {}: expected a finite number more than 0",
                s.index
            )));
        }
        Ok(())
    }
}

/// An object's geometry as arrays: vertices, and faces as lists of
/// 0-based vertex indices, counter-clockwise seen from outside (the
/// convention of OBJ, PLY and numpy-based tools; the scene language's
/// object files are clockwise). Optional colours per face or per vertex.
///
/// ```
/// use plytrace::api::MeshData;
///
/// let mut triangle = MeshData::new(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![vec![0, 1, 2]]);
/// triangle.vertex_colors = Some(vec![[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]]);
/// assert!(triangle.validate().is_ok());
/// // Face colours must be one per face.
/// triangle.face_colors = Some(vec![[1., 1., 1.]; 2]);
/// assert!(triangle.validate().is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshData {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Faces: at least three vertex indices each.
    pub faces: Vec<Vec<u32>>,
    /// One colour per face, 0 to 1.
    pub face_colors: Option<Vec<[f64; 3]>>,
    /// One colour per vertex, 0 to 1 (Gouraud shaded).
    pub vertex_colors: Option<Vec<[f64; 3]>>,
}

impl MeshData {
    /// A mesh of `vertices` and counter-clockwise `faces`.
    ///
    /// ```
    /// use plytrace::api::MeshData;
    ///
    /// let square = MeshData::new(
    ///     vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
    ///     vec![vec![0, 1, 2, 3]],
    /// );
    /// assert_eq!((square.vertices.len(), square.faces.len()), (4, 1));
    /// assert!(square.face_colors.is_none() && square.vertex_colors.is_none());
    /// ```
    pub fn new(vertices: Vec<[f64; 3]>, faces: Vec<Vec<u32>>) -> MeshData {
        MeshData {
            vertices,
            faces,
            ..MeshData::default()
        }
    }

    /// Checks the arrays: finite coordinates and colours, faces of three
    /// or more indices within the vertices, colour arrays of the right
    /// length.
    ///
    /// ```
    /// use plytrace::api::MeshData;
    ///
    /// let mut mesh = MeshData::new(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![vec![0, 1, 2]]);
    /// assert!(mesh.validate().is_ok());
    /// mesh.faces[0][2] = 3;
    /// let error = mesh.validate().unwrap_err().to_string();
    /// assert!(error.contains("face 0 names vertex 3, but there are 3 vertices"), "{error}");
    /// mesh.faces[0] = vec![0, 1];
    /// assert!(mesh.validate().is_err(), "a face needs three vertices");
    /// ```
    pub fn validate(&self) -> Result<()> {
        if let Some(i) = self
            .vertices
            .iter()
            .position(|v| v.iter().any(|c| !c.is_finite()))
        {
            return Err(invalid(&format!(
                "vertex {i} is not finite: {:?}",
                self.vertices[i]
            )));
        }
        let n = self.vertices.len();
        for (f, face) in self.faces.iter().enumerate() {
            if face.len() < 3 {
                return Err(invalid(&format!(
                    "face {f} has {} vertices; a face needs 3",
                    face.len()
                )));
            }
            if let Some(&i) = face.iter().find(|&&i| i as usize >= n) {
                return Err(invalid(&format!(
                    "face {f} names vertex {i}, but there are {n} vertices"
                )));
            }
        }
        for (what, colors, want) in [
            ("face_colors", &self.face_colors, self.faces.len()),
            ("vertex_colors", &self.vertex_colors, n),
        ] {
            let Some(colors) = colors else { continue };
            if colors.len() != want {
                return Err(invalid(&format!(
                    "{what} has {} colours for {want} {}",
                    colors.len(),
                    if what == "face_colors" {
                        "faces"
                    } else {
                        "vertices"
                    }
                )));
            }
            if let Some(i) = colors.iter().position(|c| c.iter().any(|v| !v.is_finite())) {
                return Err(invalid(&format!("{what}[{i}] is not finite")));
            }
        }
        Ok(())
    }

    /// The scene language's mesh: faces clockwise from outside.
    fn to_mesh(&self) -> Mesh {
        Mesh {
            vertices: self
                .vertices
                .iter()
                .map(|v| DVec3::from_array(*v))
                .collect(),
            polygons: self
                .faces
                .iter()
                .map(|f| f.iter().rev().copied().collect())
                .collect(),
        }
    }
}

/// A scene ready to render.
///
/// ```
/// use plytrace::api::{render, Camera, Light, Material, MeshData, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let triangle = MeshData::new(vec![[-1., 0., -1.], [1., 0., -1.], [0., 0., 1.]], vec![vec![0, 1, 2]]);
/// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
/// scene.add_light(Light::point([2., -5., 3.], [1., 1., 1.]))?;
/// scene.add_mesh("triangle", &triangle, &Material::color([0., 1., 0.]))?;
/// let image = render(&scene, &Options::default())?;
/// assert_eq!(image.stats.polygons_tiled, 1);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct Scene {
    inner: model::Scene,
    camera: Option<(Camera, u32, u32)>,
    budgets: Budgets,
}

impl Scene {
    /// An empty scene of `width` x `height` pixels seen by `camera`, with
    /// the scene language's defaults (black background, white ambient).
    ///
    /// ```
    /// use plytrace::api::{render, Camera, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 32, 16);
    /// assert_eq!(scene.size(), (32, 16));
    /// let image = render(&scene, &Options::default())?;
    /// assert!(image.rgb.iter().all(|&b| b == 0), "an empty scene: black background");
    /// # Ok(())
    /// # }
    /// ```
    pub fn new(camera: Camera, width: u32, height: u32) -> Scene {
        let inner = model::Scene {
            viewport: Viewport::of_size(width.max(1), height.max(1)),
            ..model::Scene::default()
        };
        Scene {
            inner,
            camera: Some((camera, width.max(1), height.max(1))),
            budgets: Budgets::default(),
        }
    }

    /// Reads a scene descriptor file, as `plytrace -f FILE` does (its
    /// `run` commands are not acted on: render it with [`fn@render`]).
    ///
    /// ```
    /// use plytrace::api::{render, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let path = std::env::temp_dir().join(format!("plytrace-doc-{}-from_file.des", std::process::id()));
    /// std::fs::write(&path, "resolution 16 8\nbackground 0 0 1\n").map_err(|e| plytrace::Error::io(&path, e))?;
    /// let scene = Scene::from_file(&path);
    /// std::fs::remove_file(&path).map_err(|e| plytrace::Error::io(&path, e))?;
    /// let image = render(&scene?, &Options::default())?;
    /// assert_eq!((image.width, image.height, &image.rgb[..3]), (16, 8, &[0, 0, 255][..]));
    /// assert!(Scene::from_file(&path).is_err(), "the file is gone");
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_file(path: &Path) -> Result<Scene> {
        Scene::from_file_with(path, Budgets::default())
    }

    /// [`Scene::from_file`] within `budgets` (as `plytrace --max-polygons
    /// N ... -f FILE`), which the scene keeps ([`Scene::budgets`]).
    ///
    /// ```
    /// use std::path::Path;
    /// use plytrace::api::{Budgets, Scene};
    ///
    /// let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ccube.des");
    /// let tight = Budgets { polygons: 2, ..Budgets::default() };
    /// let e = Scene::from_file_with(&scene, tight).unwrap_err().to_string();
    /// assert!(e.contains("--max-polygons"), "{e}");
    /// ```
    pub fn from_file_with(path: &Path, budgets: Budgets) -> Result<Scene> {
        let mut interp = crate::scene::Interpreter::new();
        interp.set_budgets(budgets);
        interp.execute_file(path, true, &mut crate::scene::NoHost)?;
        Ok(Scene {
            inner: interp.into_scene(),
            camera: None,
            budgets,
        })
    }

    /// Reads a scene from the text of a scene descriptor file; object
    /// files are looked up from `dir`.
    ///
    /// ```
    /// use std::path::Path;
    /// use plytrace::api::{render, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// // `cube` is read from `det/cube.det` under the directory given.
    /// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes");
    /// let text = "resolution 16 16\nlookat 0 0 6 0 0 0 0\ndefobj cube\nendobj\n";
    /// let scene = Scene::from_text(text, &dir)?;
    /// assert_eq!(scene.size(), (16, 16));
    /// assert!(render(&scene, &Options::default())?.stats.polygons_tiled > 0);
    /// assert!(Scene::from_text("defobj nothing_here\nendobj\n", &dir).is_err());
    /// // What a scene file may not do, its text may not either.
    /// let e = Scene::from_text("defobj cube\n", &dir).unwrap_err().to_string();
    /// assert!(e.contains("no `endobj`"), "{e}");
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_text(text: &str, dir: &Path) -> Result<Scene> {
        Scene::from_text_with(text, dir, Budgets::default())
    }

    /// [`Scene::from_text`] within `budgets`, which the scene keeps.
    pub fn from_text_with(text: &str, dir: &Path, budgets: Budgets) -> Result<Scene> {
        let mut interp = crate::scene::Interpreter::new();
        interp.set_budgets(budgets);
        interp.execute_input(text, Path::new("<text>"), dir, &mut crate::scene::NoHost)?;
        Ok(Scene {
            inner: interp.into_scene(),
            camera: None,
            budgets,
        })
    }

    /// The limits this scene is read, added to and rendered within:
    /// [`Budgets::default`] unless set.
    pub fn budgets(&self) -> Budgets {
        self.budgets
    }

    /// Sets [`Scene::budgets`]; meshes already added are not checked again.
    ///
    /// ```
    /// use plytrace::api::{Budgets, Camera, MeshData, Material, Scene};
    ///
    /// let triangle = MeshData::new(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![vec![0, 1, 2]]);
    /// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// scene.set_budgets(Budgets { polygons: 1, ..Budgets::default() });
    /// assert!(scene.add_mesh("first", &triangle, &Material::default()).is_ok());
    /// let e = scene.add_mesh("second", &triangle, &Material::default()).unwrap_err();
    /// assert!(e.to_string().contains("--max-polygons"), "{e}");
    /// ```
    pub fn set_budgets(&mut self, budgets: Budgets) {
        self.budgets = budgets;
    }

    /// Refuses a mesh of `vertices`, `faces` and `corners` (vertex
    /// indices, all faces together) that would take the scene past its
    /// [`Budgets::polygons`] or that alone would hold more than
    /// [`Budgets::model_memory`]: what [`Scene::add_mesh`] checks first,
    /// for a caller to check before it builds the [`MeshData`].
    ///
    /// ```
    /// use plytrace::api::{Camera, Scene};
    ///
    /// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// assert!(scene.check_mesh("small", 3, 1, 3).is_ok());
    /// let e = scene.check_mesh("huge", 3, 10_000_000, 30_000_000).unwrap_err().to_string();
    /// assert!(e.contains("10000000") && e.contains("--max-polygons"), "{e}");
    /// ```
    pub fn check_mesh(
        &self,
        name: &str,
        vertices: usize,
        faces: usize,
        corners: usize,
    ) -> Result<()> {
        let shown = crate::error::printable(name, crate::error::MAX_SHOWN_TOKEN);
        let before: usize = self.inner.objects.iter().map(|o| o.polygons.len()).sum();
        let total = before.saturating_add(faces);
        if total > self.budgets.polygons {
            return Err(Error::budget(
                &format!(
                    "the mesh `{shown}` of {faces} faces (with the scene's {before} polygons, {total})"
                ),
                self.budgets.polygons,
                "--max-polygons",
            ));
        }
        let need = crate::modeling::model_bytes(vertices, faces, corners);
        if need > self.budgets.model_memory {
            return Err(Error::budget(
                &format!(
                    "the mesh `{shown}` of {vertices} vertices and {faces} faces ({} MiB)",
                    need.div_ceil(1 << 20)
                ),
                format!("{} MiB", self.budgets.model_memory >> 20),
                "--max-model-memory",
            ));
        }
        Ok(())
    }

    /// Adds a light.
    ///
    /// ```
    /// use plytrace::api::{render, Camera, Light, Material, MeshData, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let square = MeshData::new(
    ///     vec![[-1., 0., -1.], [1., 0., -1.], [1., 0., 1.], [-1., 0., 1.]],
    ///     vec![vec![0, 1, 2, 3]],
    /// );
    /// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// scene.add_mesh("square", &square, &Material::color([1., 1., 1.]))?;
    /// let dark = render(&scene, &Options::default())?.rgb[(8 * 16 + 8) * 3];
    /// scene.add_light(Light::point([0., -5., 0.], [1., 1., 1.]))?;
    /// let lit = render(&scene, &Options::default())?.rgb[(8 * 16 + 8) * 3];
    /// assert!(lit > dark, "{lit} > {dark}");
    /// # Ok(())
    /// # }
    /// ```
    pub fn add_light(&mut self, light: Light) -> Result<()> {
        light.validate()?;
        self.inner.lights.push(model::Light {
            position: DVec3::from_array(light.position),
            color: DVec3::from_array(light.color),
            range: light.range,
            kind: if light.shadows {
                LightKind::Point
            } else {
                LightKind::Diffuse
            },
        });
        Ok(())
    }

    /// Adds an object made from `mesh` with `material`, in world
    /// coordinates. Degenerate faces are skipped, as in object files.
    ///
    /// ```
    /// use plytrace::api::{render, Camera, Material, MeshData, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// let mut square = MeshData::new(
    ///     vec![[-1., 0., -1.], [1., 0., -1.], [1., 0., 1.], [-1., 0., 1.]],
    ///     vec![vec![0, 1, 2, 3]],
    /// );
    /// square.face_colors = Some(vec![[0., 0., 1.]]);
    /// scene.add_mesh("square", &square, &Material::default())?;
    /// let image = render(&scene, &Options::default())?;
    /// let centre = &image.rgb[(8 * 16 + 8) * 3..][..3];
    /// assert!(centre[..2] == [0, 0] && centre[2] > 0, "blue in the middle: {centre:?}");
    /// square.vertices[0][0] = f64::NAN;
    /// assert!(scene.add_mesh("broken", &square, &Material::default()).is_err());
    /// # Ok(())
    /// # }
    /// ```
    pub fn add_mesh(&mut self, name: &str, mesh: &MeshData, material: &Material) -> Result<()> {
        let corners = mesh.faces.iter().map(Vec::len).sum();
        self.check_mesh(name, mesh.vertices.len(), mesh.faces.len(), corners)?;
        mesh.validate()?;
        material.validate()?;
        let colors = |c: &Option<Vec<[f64; 3]>>| {
            c.as_ref().map(|c| {
                Arc::new(
                    c.iter()
                        .map(|rgb| ColorEntry {
                            color: DVec3::from_array(*rgb),
                            diffuse: material.surface.diffuse,
                            reflectance: material.surface.reflectance,
                            transmittance: material.surface.transmittance,
                        })
                        .collect::<Vec<_>>(),
                )
            })
        };
        let parts = ObjectParts {
            number: self.inner.objects.len() as u32,
            name: name.to_string(),
            mesh: Arc::new(mesh.to_mesh()),
            polygon_colors: colors(&mesh.face_colors),
            vertex_colors: colors(&mesh.vertex_colors),
            transform: Matrix4::IDENTITY,
            surface: material.surface,
            surface_type: SurfaceType {
                open: material.two_sided,
                curved: material.smooth,
                ..SurfaceType::default()
            },
        };
        let object = build_object(parts, &mut |_| {}).map_err(Error::Invalid)?;
        if mesh.vertex_colors.is_some() {
            self.inner.modes.vertex_shades = true;
        }
        self.inner.objects.push(object);
        Ok(())
    }

    /// The background colour, 0 to 1.
    ///
    /// ```
    /// use plytrace::api::{render, Camera, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// scene.set_background([1., 0.5, 0.])?;
    /// let image = render(&scene, &Options::default())?;
    /// assert!(image.rgb.chunks(3).all(|p| p[0] == 255 && p[1] > 100 && p[2] == 0));
    /// # Ok(())
    /// # }
    /// ```
    pub fn set_background(&mut self, rgb: [f64; 3]) -> Result<()> {
        check_color("background", rgb)?;
        self.inner.background = DVec3::from_array(rgb);
        Ok(())
    }

    /// The ambient light's colour, 0 to 1.
    ///
    /// ```
    /// use plytrace::api::{render, Camera, Material, MeshData, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let square = MeshData::new(
    ///     vec![[-1., 0., -1.], [1., 0., -1.], [1., 0., 1.], [-1., 0., 1.]],
    ///     vec![vec![0, 1, 2, 3]],
    /// );
    /// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// let mut white = Material::color([1., 1., 1.]);
    /// white.surface.diffuse = 0.0; // ambient only: k_a = 1 - k_d = 1
    /// scene.add_mesh("square", &square, &white)?;
    /// scene.set_ambient([0., 1., 0.])?;
    /// let image = render(&scene, &Options::default())?;
    /// assert_eq!(&image.rgb[(8 * 16 + 8) * 3..][..3], [0, 255, 0], "white seen in green light");
    /// # Ok(())
    /// # }
    /// ```
    pub fn set_ambient(&mut self, rgb: [f64; 3]) -> Result<()> {
        check_color("ambient", rgb)?;
        self.inner.ambient = DVec3::from_array(rgb);
        Ok(())
    }

    /// Levels of reflection and refraction followed (the manual's
    /// `depth`, 1 to 14).
    ///
    /// ```
    /// use plytrace::api::{Camera, Scene};
    ///
    /// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 16);
    /// assert!(scene.set_depth(3).is_ok());
    /// assert!(scene.set_depth(0).is_err() && scene.set_depth(15).is_err());
    /// ```
    pub fn set_depth(&mut self, levels: u32) -> Result<()> {
        if !(1..=14).contains(&levels) {
            return Err(invalid(&format!("depth {levels}: expected 1 to 14")));
        }
        self.inner.modes.max_level = levels;
        Ok(())
    }

    /// The image size.
    ///
    /// ```
    /// use std::path::Path;
    /// use plytrace::api::{Camera, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// assert_eq!(Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 32, 16).size(), (32, 16));
    /// let scene = Scene::from_text("resolution 64 48\n", Path::new("."))?;
    /// assert_eq!(scene.size(), (64, 48));
    /// # Ok(())
    /// # }
    /// ```
    pub fn size(&self) -> (u32, u32) {
        (self.inner.viewport.width(), self.inner.viewport.height())
    }

    /// The scene model the renderer reads, with the camera applied.
    fn model(&self) -> Result<std::borrow::Cow<'_, model::Scene>> {
        let Some((camera, w, h)) = &self.camera else {
            return Ok(std::borrow::Cow::Borrowed(&self.inner));
        };
        let mut scene = self.inner.clone();
        scene.projection = camera.matrix(f64::from(*w) / f64::from(*h))?;
        Ok(std::borrow::Cow::Owned(scene))
    }
}

/// How to render.
///
/// ```
/// use plytrace::api::{render, Antialiasing, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 640, 480);
/// let options = Options::default()
///     .with_size(16, 12)
///     .with_antialiasing(Antialiasing::Point)
///     .with_threads(1);
/// let image = render(&scene, &options)?;
/// assert_eq!((image.width, image.height), (16, 12), "the size given, not the scene's");
/// assert!(Options::default().shadows);
/// # Ok(())
/// # }
/// ```
///
/// New fields may be added: start from [`Options::default`] (or
/// [`Options::new`]) and change what you need with the `with_` methods or
/// by assigning a field.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Options {
    /// Image size overriding the scene's.
    pub size: Option<(u32, u32)>,
    /// Anti-aliasing; `None` is the best for the scene (method 4).
    pub antialiasing: Option<Antialiasing>,
    /// Shadows from the lights that cast them (the manual's `run y`).
    pub shadows: bool,
    /// Worker threads; 0 is all cores. The image does not depend on it.
    pub threads: usize,
    /// Limits on the work, as the program's `--max-*` flags.
    pub budgets: Budgets,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            size: None,
            antialiasing: None,
            shadows: true,
            threads: 0,
            budgets: Budgets::default(),
        }
    }
}

impl Options {
    /// The defaults: the scene's size and best anti-aliasing, shadows on,
    /// all cores, the default budgets.
    pub fn new() -> Self {
        Options::default()
    }

    /// These options with the image size `width` x `height`, overriding
    /// the scene's.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.size = Some((width, height));
        self
    }

    /// These options with anti-aliasing `aa`.
    pub fn with_antialiasing(mut self, aa: Antialiasing) -> Self {
        self.antialiasing = Some(aa);
        self
    }

    /// These options with shadows on or off.
    pub fn with_shadows(mut self, shadows: bool) -> Self {
        self.shadows = shadows;
        self
    }

    /// These options with `threads` worker threads (0: all cores).
    pub fn with_threads(mut self, threads: usize) -> Self {
        self.threads = threads;
        self
    }

    /// These options with the limits `budgets`.
    pub fn with_budgets(mut self, budgets: Budgets) -> Self {
        self.budgets = budgets;
        self
    }

    fn render_options(&self) -> RenderOptions {
        RenderOptions {
            size: self.size,
            shadows: self.shadows,
            aa: self.antialiasing,
            threads: self.threads,
            budgets: self.budgets,
            ..RenderOptions::default()
        }
    }
}

/// A rendered image: 8-bit RGB, rows from the top.
///
/// ```
/// use plytrace::api::{render, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 8);
/// scene.set_background([1., 1., 1.])?;
/// let image = render(&scene, &Options::default())?;
/// assert_eq!((image.width, image.height), (16, 8));
/// assert_eq!(image.rgb, vec![255; 16 * 8 * 3]);
/// assert_eq!(image.stats.polygons_tiled, 0, "nothing in the scene");
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 3` bytes.
    pub rgb: Vec<u8>,
    /// What the render did.
    pub stats: RenderStats,
}

impl Image {
    /// The image as a PNG file's bytes.
    ///
    /// ```
    /// use plytrace::api::{render, Camera, Options, Scene};
    ///
    /// # fn main() -> Result<(), plytrace::Error> {
    /// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 8);
    /// let png = render(&scene, &Options::default())?.to_png()?;
    /// assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    /// // The IHDR chunk: width and height, big-endian.
    /// assert_eq!(&png[12..24], b"IHDR\0\0\0\x10\0\0\0\x08");
    /// # Ok(())
    /// # }
    /// ```
    pub fn to_png(&self) -> Result<Vec<u8>> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder
            .write_header()
            .map_err(|e| Error::Invalid(format!("PNG: {e}")))?;
        writer
            .write_image_data(&self.rgb)
            .map_err(|e| Error::Invalid(format!("PNG: {e}")))?;
        writer
            .finish()
            .map_err(|e| Error::Invalid(format!("PNG: {e}")))?;
        Ok(out)
    }
}

/// Renders `scene` to an image in memory.
///
/// ```
/// use plytrace::api::{render, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 32, 32);
/// let image = render(&scene, &Options::default())?;
/// assert_eq!(image.rgb.len(), 32 * 32 * 3);
/// // Over the pixel budget (the program's `--max-pixels`), it is refused.
/// let mut small = Options::default();
/// small.budgets.pixels = 100;
/// assert!(render(&scene, &small).is_err());
/// # Ok(())
/// # }
/// ```
pub fn render(scene: &Scene, options: &Options) -> Result<Image> {
    let (w, h) = options.size.unwrap_or(scene.size());
    check_size(w, h)?;
    // The whole image is held: within the frame budget, before a byte.
    let need = u64::from(w) * u64::from(h) * 3;
    if need > options.budgets.frame_memory {
        return Err(Error::budget(
            &format!(
                "the image of {w} x {h} pixels in memory ({} MiB)",
                need.div_ceil(1 << 20)
            ),
            format!("{} MiB", options.budgets.frame_memory >> 20),
            "--max-frame-memory",
        ));
    }
    let mut rgb = Vec::new();
    let (mut width, mut height) = (0, 0);
    let stats = render_rows(scene, options, &mut |y, row| {
        width = (row.len() / 3) as u32;
        height = y + 1;
        rgb.extend_from_slice(row);
        Ok(())
    })?;
    Ok(Image {
        width,
        height,
        rgb,
        stats,
    })
}

/// Renders `scene` row by row: `sink` gets each row's index from the top
/// and its RGB bytes, in order, as the scan converter finishes them; the
/// whole image is never held when the scene takes the streamed path (the
/// virtual image tree).
///
/// ```
/// use plytrace::api::{render_rows, Camera, Options, Scene};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 16, 8);
/// let mut rows = Vec::new();
/// render_rows(&scene, &Options::default(), &mut |y, row| {
///     rows.push((y, row.len()));
///     Ok(())
/// })?;
/// assert_eq!(rows, (0..8).map(|y| (y, 16 * 3)).collect::<Vec<_>>());
/// # Ok(())
/// # }
/// ```
pub fn render_rows(
    scene: &Scene,
    options: &Options,
    sink: &mut dyn FnMut(u32, &[u8]) -> Result<()>,
) -> Result<RenderStats> {
    let model = scene.model()?;
    let (w, h) = options.size.unwrap_or(scene.size());
    check_size(w, h)?;
    if u64::from(w) * u64::from(h) > options.budgets.pixels {
        return Err(Error::budget(
            &format!("the image of {w} x {h} pixels"),
            options.budgets.pixels,
            "--max-pixels",
        ));
    }
    let mode = model.outmode;
    let mut bytes = Vec::new();
    let mut rows = ByteRows {
        mode,
        bytes: &mut bytes,
        sink,
    };
    match render::plan(&model, &options.render_options())? {
        render::Plan::Tree(prepared) => Ok(render::scan_into(*prepared, &mut rows)?.stats),
        render::Plan::Painted(rendered) => {
            let frame = &rendered.frame;
            for (y, row) in frame.color.chunks(frame.width.max(1) as usize).enumerate() {
                crate::raster::scan::RowSink::row(
                    &mut rows,
                    &crate::raster::scan::Row::colors(y as u32, row),
                )?;
            }
            Ok(rendered.stats)
        }
    }
}

/// Rows of colours to rows of bytes.
struct ByteRows<'a> {
    mode: model::OutMode,
    bytes: &'a mut Vec<u8>,
    sink: &'a mut dyn FnMut(u32, &[u8]) -> Result<()>,
}

impl crate::raster::scan::RowSink for ByteRows<'_> {
    fn row(&mut self, row: &crate::raster::scan::Row<'_>) -> Result<()> {
        crate::cancel::check()?;
        crate::output::rgb8_row(row.rgb, row.y, self.mode, self.bytes);
        (self.sink)(row.y, self.bytes)
    }

    fn wants_pixel_structs(&self) -> bool {
        false
    }
}

/// Renders `scene` as vector graphics (SVG, one-page PDF or TikZ): the
/// polygons of the virtual image tree, split and ordered by NNS, painted
/// back to front.
///
/// ```
/// use plytrace::api::{render_vector, Camera, Material, MeshData, Options, Scene, VectorFormat};
///
/// # fn main() -> Result<(), plytrace::Error> {
/// let triangle = MeshData::new(vec![[-1., 0., -1.], [1., 0., -1.], [0., 0., 1.]], vec![vec![0, 1, 2]]);
/// let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 32, 32);
/// scene.add_mesh("triangle", &triangle, &Material::color([1., 0., 0.]))?;
/// let svg = String::from_utf8(render_vector(&scene, &Options::default(), VectorFormat::Svg)?).unwrap();
/// assert!(svg.starts_with("<?xml") && svg.contains("<svg"));
/// let pdf = render_vector(&scene, &Options::default(), VectorFormat::Pdf)?;
/// assert!(pdf.starts_with(b"%PDF-"));
/// let tikz = render_vector(&scene, &Options::default(), VectorFormat::Tikz)?;
/// assert!(String::from_utf8_lossy(&tikz).contains("\\begin{tikzpicture}"));
/// # Ok(())
/// # }
/// ```
pub fn render_vector(scene: &Scene, options: &Options, format: VectorFormat) -> Result<Vec<u8>> {
    let (w, h) = options.size.unwrap_or(scene.size());
    check_size(w, h)?;
    let model = scene.model()?;
    let style = crate::vector::Style::Shaded;
    let input = crate::render::vector::prepare_for(&model, &options.render_options(), style)?;
    let picture = crate::vector::picture(&input, style);
    let mut out = Vec::new();
    format
        .write(&picture, &mut out)
        .map_err(|e| Error::Invalid(format!("vector output: {e}")))?;
    Ok(out)
}

fn invalid(message: &str) -> Error {
    Error::Invalid(message.to_string())
}

fn finite3(what: &str, v: [f64; 3]) -> Result<DVec3> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(DVec3::from_array(v))
    } else {
        Err(invalid(&format!("{what} is not finite: {v:?}")))
    }
}

/// Refuses an image size the program's `--size` refuses.
fn check_size(w: u32, h: u32) -> Result<()> {
    let side = |v: u32| (1..=MAX_IMAGE_SIDE).contains(&i64::from(v));
    if side(w) && side(h) && u64::from(w) * u64::from(h) <= MAX_IMAGE_PIXELS {
        return Ok(());
    }
    Err(invalid(&format!(
        "an image of {w} x {h} pixels: each side must be 1 to {MAX_IMAGE_SIDE} and the total \
         at most {MAX_IMAGE_PIXELS} pixels"
    )))
}

/// A colour's components, each from 0 to 1.
fn check_color(what: &str, rgb: [f64; 3]) -> Result<()> {
    if rgb.iter().all(|c| (0.0..=1.0).contains(c)) {
        Ok(())
    } else {
        Err(invalid(&format!(
            "{what} {rgb:?}: expected components from 0 to 1"
        )))
    }
}

fn check_range(what: &str, v: f64, lo: f64, hi: f64) -> Result<()> {
    if v.is_finite() && v > lo && v < hi {
        Ok(())
    } else {
        Err(invalid(&format!(
            "{what} {v}: expected more than {lo} and less than {hi}"
        )))
    }
}

fn check_depths(near: f64, far: f64) -> Result<()> {
    if near.is_finite() && far.is_finite() && near > 0.0 && far > near {
        Ok(())
    } else {
        Err(invalid(&format!(
            "near {near} and far {far}: expected 0 < near < far"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> MeshData {
        MeshData::new(
            vec![[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]],
            vec![vec![0, 1, 2, 3]],
        )
    }

    #[test]
    fn bad_arrays_are_refused_with_the_reason() {
        let mut m = square();
        m.vertices[2][1] = f64::NAN;
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("vertex 2 is not finite")
        );
        let mut m = square();
        m.faces[0][3] = 9;
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("names vertex 9, but there are 4")
        );
        let mut m = square();
        m.faces.push(vec![0, 1]);
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("face 1 has 2 vertices")
        );
        let mut m = square();
        m.face_colors = Some(vec![]);
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("0 colours for 1 faces")
        );
    }

    #[test]
    fn a_square_seen_from_above_fills_the_middle_in_its_colour() {
        let mut camera = Camera::looking_at([0., 0., 5.], [0., 0., 0.]);
        camera.up = [0., 1., 0.];
        let mut scene = Scene::new(camera, 32, 32);
        scene.set_ambient([1., 1., 1.]).unwrap();
        let mut red = Material::color([1., 0., 0.]);
        red.surface.diffuse = 0.0;
        scene.add_mesh("square", &square(), &red).unwrap();
        let image = render(&scene, &Options::default()).unwrap();
        let centre = ((16 * 32 + 16) * 3) as usize;
        // Ambient only: k_a = 1 - k_d = 1, the colour itself.
        assert_eq!(&image.rgb[centre..centre + 3], &[255, 0, 0]);
        assert_eq!(&image.rgb[0..3], &[0, 0, 0], "the corner is background");
        // Seen from behind, a one-sided square is culled; two-sided it shows.
        camera.eye = [0., 0., -5.];
        let mut back = Scene::new(camera, 32, 32);
        back.add_mesh("square", &square(), &red).unwrap();
        let culled = render(&back, &Options::default()).unwrap();
        assert_eq!(&culled.rgb[centre..centre + 3], &[0, 0, 0]);
        red.two_sided = true;
        let mut back = Scene::new(camera, 32, 32);
        back.add_mesh("square", &square(), &red).unwrap();
        let shown = render(&back, &Options::default()).unwrap();
        assert_ne!(&shown.rgb[centre..centre + 3], &[0, 0, 0]);
    }

    /// The unit cube, counter-clockwise faces; the top (z = +1) is face 1.
    fn cube() -> MeshData {
        MeshData::new(
            vec![
                [-1., -1., -1.],
                [1., -1., -1.],
                [1., 1., -1.],
                [-1., 1., -1.],
                [-1., -1., 1.],
                [1., -1., 1.],
                [1., 1., 1.],
                [-1., 1., 1.],
            ],
            vec![
                vec![0, 3, 2, 1],
                vec![4, 5, 6, 7],
                vec![0, 1, 5, 4],
                vec![2, 3, 7, 6],
                vec![1, 2, 6, 5],
                vec![0, 4, 7, 3],
            ],
        )
    }

    #[test]
    fn counter_clockwise_faces_face_out_and_z_is_up() {
        let mut mesh = cube();
        let mut colors = vec![[0., 0., 1.]; 6];
        colors[1] = [1., 0., 0.];
        mesh.face_colors = Some(colors);
        let mut material = Material::default();
        material.surface.diffuse = 0.0;
        let pixel = |up: [f64; 3], x: usize, y: usize| {
            let mut camera = Camera::looking_at([3., -5., 6.], [0., 0., 0.]);
            camera.up = up;
            let mut scene = Scene::new(camera, 40, 40);
            scene.add_mesh("cube", &mesh, &material).unwrap();
            let image = render(&scene, &Options::default()).unwrap();
            let i = (y * 40 + x) * 3;
            [image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]]
        };
        let red = |p: [u8; 3]| p[0] > 200 && p[1] == 0 && p[2] < 30;
        let blue = |p: [u8; 3]| p[2] > 200 && p[0] < 30 && p[1] == 0;
        // Above the centre the red top is seen; below it a blue side.
        assert!(
            red(pixel([0., 0., 1.], 20, 12)),
            "{:?}",
            pixel([0., 0., 1.], 20, 12)
        );
        assert!(
            blue(pixel([0., 0., 1.], 20, 28)),
            "{:?}",
            pixel([0., 0., 1.], 20, 28)
        );
        // Upside down, the top is below the centre.
        assert!(
            red(pixel([0., 0., -1.], 20, 28)),
            "{:?}",
            pixel([0., 0., -1.], 20, 28)
        );
    }

    #[test]
    fn a_scene_from_text_renders_like_the_program() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let text = std::fs::read_to_string(dir.join("ccube.des")).unwrap();
        let scene = Scene::from_text(&text, &dir).unwrap();
        let options = Options {
            size: Some((48, 48)),
            ..Options::default()
        };
        let image = render(&scene, &options).unwrap();
        let from_file =
            render(&Scene::from_file(&dir.join("ccube.des")).unwrap(), &options).unwrap();
        assert_eq!(image.rgb, from_file.rgb);
        assert!(image.stats.polygons_tiled > 0);
    }

    #[test]
    fn a_scene_text_refuses_what_the_same_file_refuses() {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let dir = tempfile::tempdir().unwrap();
        for (text, refused) in [
            ("defobj cube\n", true),
            ("lookat 0 0 6 0 0 0 0\ndefobj cube\ncolor 1 0 0\n", true),
            ("defobj cube\nendobj\n", false),
            // `quit` ends the input early, as in a file.
            ("defobj cube\nquit\n", false),
        ] {
            let file = dir.path().join("scene.des");
            std::fs::write(&file, text).unwrap();
            std::fs::create_dir_all(dir.path().join("det")).unwrap();
            std::fs::copy(
                examples.join("det/cube.det"),
                dir.path().join("det/cube.det"),
            )
            .unwrap();
            let from_text = Scene::from_text(text, dir.path());
            let from_file = Scene::from_file(&file);
            assert_eq!(from_text.is_err(), refused, "{text:?}");
            assert_eq!(from_file.is_err(), refused, "{text:?}");
            if let (Err(a), Err(b)) = (from_text, from_file) {
                let (a, b) = (a.diagnostic().unwrap(), b.diagnostic().unwrap());
                assert_eq!(a.message, b.message);
                assert_eq!(
                    (a.location.line, a.location.column),
                    (b.location.line, b.location.column)
                );
            }
        }
        let long = "# \n".repeat(crate::scene::interpreter::MAX_SCENE_BYTES as usize / 3 + 1);
        let e = Scene::from_text(&long, dir.path()).unwrap_err().to_string();
        assert!(e.contains("more than the 16777216 bytes"), "{e}");
    }

    #[test]
    fn lights_materials_and_colours_that_are_not_finite_are_refused() {
        let mut scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 8, 8);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut light = Light::point([0., -5., 0.], [1., 1., 1.]);
            light.range = bad;
            assert!(scene.add_light(light).is_err());
            light.range = 10.0;
            light.position[1] = bad;
            assert!(scene.add_light(light).is_err());
            light.position[1] = 0.0;
            light.color[2] = bad;
            assert!(scene.add_light(light).is_err());
            for field in 0..8 {
                let mut m = Material::default();
                let s = &mut m.surface;
                *[
                    &mut s.diffuse,
                    &mut s.specular,
                    &mut s.shininess,
                    &mut s.reflectance,
                    &mut s.transmittance,
                    &mut s.index,
                    &mut s.transparency.0,
                    &mut s.transparency.1,
                ][field] = bad;
                assert!(scene.add_mesh("m", &square(), &m).is_err(), "{field} {bad}");
            }
            assert!(scene.set_background([0., bad, 0.]).is_err());
            assert!(scene.set_ambient([bad, 0., 0.]).is_err());
        }
        assert!(scene.inner.lights.is_empty() && scene.inner.objects.is_empty());
        assert!(scene.add_mesh("m", &square(), &Material::default()).is_ok());
    }

    #[test]
    fn sizes_beyond_the_program_s_are_refused_and_frames_over_the_budget_before_rendering() {
        let scene = Scene::new(Camera::looking_at([0., -5., 0.], [0., 0., 0.]), 8, 8);
        for size in [(0, 1), (1, 0), (65537, 1), (20000, 20000)] {
            let options = Options {
                size: Some(size),
                ..Options::default()
            };
            assert!(render(&scene, &options).is_err(), "{size:?}");
            assert!(
                render_vector(&scene, &options, VectorFormat::Svg).is_err(),
                "{size:?}"
            );
        }
        let mut options = Options {
            size: Some((1024, 1024)),
            ..Options::default()
        };
        options.budgets.frame_memory = 1 << 20;
        let e = render(&scene, &options).unwrap_err().to_string();
        assert!(
            e.contains("3 MiB") && e.contains("--max-frame-memory"),
            "{e}"
        );
    }
}

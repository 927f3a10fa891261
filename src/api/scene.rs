//! The scene a caller holds: read from a scene descriptor file or built
//! in code, with its camera, lights and objects, within its budgets
//! (Garcia 1986, section 4.3: input processing; appendix B: the scene
//! language).

use super::*;

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
    pub(super) inner: model::Scene,
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
    pub(super) fn model(&self) -> Result<std::borrow::Cow<'_, model::Scene>> {
        let Some((camera, w, h)) = &self.camera else {
            return Ok(std::borrow::Cow::Borrowed(&self.inner));
        };
        let mut scene = self.inner.clone();
        scene.projection = camera.matrix(f64::from(*w) / f64::from(*h))?;
        Ok(std::borrow::Cow::Owned(scene))
    }
}

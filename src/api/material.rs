//! The surface of an object in the public face: colour and the shading
//! coefficients of the illumination model (Garcia 1986, section 4.8; the
//! scene language's surface commands, appendix B).

use super::*;

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

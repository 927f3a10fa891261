//! The lights of the public face: point, directional and ambient sources
//! as the scene language's `light` command (Garcia 1986, section 4.8 and
//! appendix B), with the shadows they cast (section 4.7).

use super::*;

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

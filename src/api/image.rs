//! A rendered image in memory: 8-bit RGB rows with the render's
//! statistics (Garcia 1986, section 5.10: the frame buffer), and its PNG
//! encoding.

use super::*;

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

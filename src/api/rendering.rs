//! Rendering a scene: to an image in memory, row by row to a sink, or to
//! vector graphics, through the pipeline of Garcia 1986, figure 3.2
//! (scene → visibility → virtual image tree → scan conversion).

use super::*;

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

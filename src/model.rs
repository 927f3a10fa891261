//! The scene model: what the scene descriptor language builds and the
//! geometry stage reads (Garcia 1986, 004 section 4.3: "a data structure is
//! created containing the object's three-dimensional bounding-box
//! description, an array of points ... and a list of all polygons").
//!
//! Everything here is in *world* coordinates: the coordinates that the
//! object's CTM at `endobj` produced. The CTM left when the scene ends is the
//! projection used to render ([`Scene::projection`]).

mod index_list;
mod points;

use std::sync::Arc;

use glam::{DVec3, DVec4};

pub use index_list::IndexList;
pub use points::{Points, PointsRef};

use crate::math::Matrix4;
use crate::precision;

/// Geometry of one object in its own coordinates, as read from a file.
/// Polygons are lists of 0-based vertex indices, clockwise seen from outside
/// (right-handed coordinates), as in a `.det` file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Vertex coordinates.
    pub vertices: Vec<DVec3>,
    /// Polygons: 0-based indices into `vertices`, clockwise from outside
    /// (a triangle's held in place, no allocation of its own).
    pub polygons: Vec<IndexList>,
}

impl Mesh {
    /// A mesh of `vertices` and `polygons` (each a list of indices into
    /// `vertices`, clockwise from outside).
    pub fn new<P: Into<IndexList>>(
        vertices: Vec<DVec3>,
        polygons: impl IntoIterator<Item = P>,
    ) -> Mesh {
        Mesh {
            vertices,
            polygons: polygons.into_iter().map(Into::into).collect(),
        }
    }
}

/// One entry of a polygon or vertex colour file: `r g b dif ref trn`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorEntry {
    /// Red, green, blue in 0..=1.
    pub color: DVec3,
    /// Diffuse coefficient.
    pub diffuse: f64,
    /// Reflection coefficient.
    pub reflectance: f64,
    /// Transmission coefficient.
    pub transmittance: f64,
}

/// The surface parameters at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Surface colour.
    pub color: Color,
    /// Diffuse coefficient kd.
    pub diffuse: f64,
    /// Specular coefficient ks.
    pub specular: f64,
    /// Shininess n.
    pub shininess: f64,
    /// Reflection coefficient kr.
    pub reflectance: f64,
    /// Transmission coefficient kt.
    pub transmittance: f64,
}

impl Material {
    /// The ambient coefficient `max(0, 1 - (kd + kr + kt))`.
    pub fn ambient_coefficient(&self) -> f64 {
        (1.0 - (self.diffuse + self.reflectance + self.transmittance)).max(0.0)
    }

    /// This material with colour and coefficients of a `.pcl`/`.vcl` entry.
    pub fn with_entry(mut self, e: &ColorEntry) -> Material {
        self.color = e.color;
        self.diffuse = e.diffuse;
        self.reflectance = e.reflectance;
        self.transmittance = e.transmittance;
        self
    }
}

/// An RGB colour, components nominally in 0..=1.
pub type Color = DVec3;

/// Surface attributes of an object (`color`, `diffuse`, ... commands).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// `color r g b` (default white).
    pub color: Color,
    /// `diffuse k` (default 0.6).
    pub diffuse: f64,
    /// `specular k` (default 0).
    pub specular: f64,
    /// `shininess n` (default 0, no highlight spread given).
    pub shininess: f64,
    /// `reflectance k` (default 0).
    pub reflectance: f64,
    /// `transmittance k` (default 0).
    pub transmittance: f64,
    /// `index n`, index of refraction (default 1).
    pub index: f64,
    /// `transparency t rolloff`: linear transparency and its roll-off.
    pub transparency: (f64, f64),
}

impl Default for Surface {
    fn default() -> Self {
        Surface {
            color: Color::ONE,
            diffuse: 0.6,
            specular: 0.0,
            shininess: 0.0,
            reflectance: 0.0,
            transmittance: 0.0,
            index: 1.0,
            transparency: (0.0, 0.0),
        }
    }
}

/// The attributes of `type polygon [open curved concave hidden ltsrc]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SurfaceType {
    /// Back faces are kept (not removed).
    pub open: bool,
    /// A curved surface modelled by polygons: vertex normals are computed.
    pub curved: bool,
    /// Not convex: may shadow itself.
    pub concave: bool,
    /// Not displayed (a template for `callobj`).
    pub hidden: bool,
    /// Represents a light source: shown in its own colour, unshaded.
    pub ltsrc: bool,
}

/// A polygon of an object, in world coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    /// 0-based indices into the object's vertices, clockwise from outside
    /// (a triangle's held in place, no allocation of its own).
    pub indices: IndexList,
    /// Plane `[A B C D]` with the unit normal `(A,B,C)` pointing outward:
    /// a point `p` is in front when `A x + B y + C z + D > 0`.
    pub plane: DVec4,
}

impl Polygon {
    /// The outward unit normal.
    pub fn normal(&self) -> DVec3 {
        self.plane.truncate()
    }
}

/// An object placed in the scene.
#[derive(Debug, Clone)]
pub struct Object {
    /// The object number (`defobj name number`, or the next free one).
    pub number: u32,
    /// The name given to `defobj`/`getobj`.
    pub name: String,
    /// Geometry in the object's own coordinates, shared by `callobj` copies.
    pub mesh: Arc<Mesh>,
    /// Polygon colours (`pcolors`), one per polygon.
    pub polygon_colors: Option<Arc<Vec<ColorEntry>>>,
    /// Vertex colours (`vcolors`), one per vertex.
    pub vertex_colors: Option<Arc<Vec<ColorEntry>>>,
    /// The CTM at `endobj`: object coordinates to world coordinates.
    pub transform: Matrix4,
    /// Vertices in world coordinates.
    pub vertices: Vec<DVec3>,
    /// Polygons with their world planes (degenerate ones already removed).
    pub polygons: Vec<Polygon>,
    /// Index in `mesh.polygons` of each entry of `polygons`.
    pub source_polygon: Vec<u32>,
    /// Vertex normals (averaged planes), for `type curved` objects.
    pub vertex_normals: Option<Vec<DVec3>>,
    /// The object-space bounding box's eight corners in world coordinates.
    pub bbox_corners: [DVec3; 8],
    /// Surface attributes.
    pub surface: Surface,
    /// Surface type attributes.
    pub surface_type: SurfaceType,
}

impl Object {
    /// The material of polygon `pi`, with its `.pcl` entry or the
    /// average of its vertices' `.vcl` entries.
    pub fn material(&self, pi: usize) -> Material {
        let s = &self.surface;
        let base = Material {
            color: s.color,
            diffuse: s.diffuse,
            specular: s.specular,
            shininess: s.shininess,
            reflectance: s.reflectance,
            transmittance: s.transmittance,
        };
        if let Some(pcl) = &self.polygon_colors {
            let source = self.source_polygon[pi] as usize;
            return base.with_entry(&pcl[source]);
        }
        if let Some(vcl) = &self.vertex_colors {
            let idx = &self.polygons[pi].indices;
            let n = idx.len() as f64;
            let mut avg = vcl[idx[0] as usize];
            let sum =
                |f: &dyn Fn(usize) -> f64| idx.iter().map(|&i| f(i as usize)).sum::<f64>() / n;
            avg.color = idx.iter().map(|&i| vcl[i as usize].color).sum::<DVec3>() / n;
            avg.diffuse = sum(&|i| vcl[i].diffuse);
            avg.reflectance = sum(&|i| vcl[i].reflectance);
            avg.transmittance = sum(&|i| vcl[i].transmittance);
            return base.with_entry(&avg);
        }
        base
    }
}

/// `light ... Point` casts shadows, `Diffuse` does not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightKind {
    /// Casts shadows.
    Point,
    /// Illuminates without shadows.
    Diffuse,
}

/// A light source, its position in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Position (transformed by the CTM when the light was read).
    pub position: DVec3,
    /// Colour.
    pub color: Color,
    /// Maximum range (k(j) of 004 section 4.8 falls to 0 there).
    pub range: f64,
    /// Point or diffuse.
    pub kind: LightKind,
}

/// The output region: pixels `left..=right`, `bottom..=top`. The image is
/// `right - left + 1` by `top - bottom + 1` pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Viewport {
    /// Leftmost pixel column.
    pub left: i64,
    /// Rightmost pixel column.
    pub right: i64,
    /// Bottom pixel row.
    pub bottom: i64,
    /// Top pixel row.
    pub top: i64,
}

impl Viewport {
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        (self.right - self.left + 1) as u32
    }
    /// Height in pixels.
    pub fn height(&self) -> u32 {
        (self.top - self.bottom + 1) as u32
    }
    /// A viewport of `w` x `h` pixels at the origin.
    pub fn of_size(w: u32, h: u32) -> Viewport {
        Viewport {
            left: 0,
            right: w as i64 - 1,
            bottom: 0,
            top: h as i64 - 1,
        }
    }
}

/// `sort btf|ftb`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SortOrder {
    /// Back to front (the default).
    #[default]
    BackToFront,
    /// Front to back.
    FrontToBack,
}

/// `outmode`: how colours are shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OutMode {
    /// Full colour (mode `c`, the default).
    #[default]
    Color,
    /// Red only, as grey (`r`).
    Red,
    /// Green only (`g`).
    Green,
    /// Blue only (`b`).
    Blue,
    /// Luminance (`y`).
    Luminance,
    /// Colours quantized to this many bits per component (`a bits`).
    Quantized(u8),
}

/// The `setmode` parameters (004 appendix, "SETMODE COMMANDS").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modes {
    /// `digit`: debugging level 0-9.
    pub debug: u8,
    /// `b`: pre-blend parent and child intensities.
    pub blend: bool,
    /// `d`: minimum screen detail size.
    pub min_detail: f64,
    /// `e`: clipping epsilon.
    pub epsilon: f64,
    /// `h`: explicit shadow shades.
    pub shadow_shades: bool,
    /// `l` (and `depth`): maximum recursion level 1-14.
    pub max_level: u32,
    /// `n`: Newell, Newell and Sancha sorting (on unless the scene or
    /// `-n off` turns it off: the simple sort of `n off` is wrong wherever
    /// polygons overlap in depth and on the screen).
    pub nns: bool,
    /// `o`: write the virtual image tree.
    pub output_tree: bool,
    /// `p`: bounding boxes only.
    pub boxes_only: bool,
    /// `s`: Phong highlight vectors.
    pub phong: bool,
    /// `v`: vertex shades (Gouraud).
    pub vertex_shades: bool,
    /// `x`: expand all objects into one composite list before sorting.
    pub expand: bool,
}

impl Default for Modes {
    fn default() -> Self {
        Modes {
            debug: 0,
            blend: false,
            min_detail: precision::DEFAULT_MIN_DETAIL,
            epsilon: precision::DEFAULT_CLIP_EPSILON,
            shadow_shades: false,
            max_level: 1,
            nns: true,
            output_tree: false,
            boxes_only: false,
            phong: false,
            vertex_shades: false,
            expand: false,
        }
    }
}

/// Default viewport of the NULL display (004 appendix, `init`).
pub const DEFAULT_VIEWPORT: Viewport = Viewport {
    left: 0,
    right: 1023,
    bottom: 0,
    top: 1023,
};

/// A complete scene, ready for the geometry stage.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Objects in definition order.
    pub objects: Vec<Object>,
    /// Lights in definition order.
    pub lights: Vec<Light>,
    /// The CTM at render time: world to homogeneous clip coordinates.
    pub projection: Matrix4,
    /// Output region.
    pub viewport: Viewport,
    /// `background r g b` (default black).
    pub background: Color,
    /// `ambient r g b` (default white).
    pub ambient: Color,
    /// `setmode` parameters.
    pub modes: Modes,
    /// `threshold`.
    pub threshold: f64,
    /// `sort`.
    pub sort_order: SortOrder,
    /// `fname`, if given.
    pub fname: Option<String>,
    /// `outmode`.
    pub outmode: OutMode,
    /// `disp on|off`.
    pub display: bool,
    /// `setmode f FILE`: the scene file named for immediate mode.
    pub scene_file: Option<String>,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            objects: Vec::new(),
            lights: Vec::new(),
            projection: crate::math::perspective(45.0, 1.0, 0.01, 10000.0),
            viewport: DEFAULT_VIEWPORT,
            background: Color::ZERO,
            ambient: Color::ONE,
            modes: Modes::default(),
            threshold: 0.0,
            sort_order: SortOrder::default(),
            fname: None,
            outmode: OutMode::default(),
            display: true,
            scene_file: None,
        }
    }
}

impl Scene {
    /// Total vertices over all objects.
    pub fn point_count(&self) -> usize {
        self.objects.iter().map(|o| o.vertices.len()).sum()
    }
    /// Total polygons over all objects.
    pub fn polygon_count(&self) -> usize {
        self.objects.iter().map(|o| o.polygons.len()).sum()
    }

    /// The size of the scene: the diagonal of the box around every vertex
    /// (1 for an empty scene). Tolerances relative to the scene use it.
    pub fn size(&self) -> f64 {
        let (lo, hi) =
            crate::math::bounds(self.objects.iter().flat_map(|o| o.vertices.iter().copied()));
        if lo.x.is_finite() {
            (hi - lo).length()
        } else {
            1.0
        }
    }
}

//! From world polygons to screen polygons (Garcia 1986, 004 sections 4.4
//! and 4.5): objects' bounding boxes are tested against the view volume
//! first (inside, outside, crossing); polygons of visible objects have back
//! faces removed (unless the object is `type open`), are clipped only when
//! their object crosses the volume, divided by w and mapped to the viewport.
//!
//! Screen coordinates: x and y in pixels with the origin at the lower left
//! corner of the image, so that pixel `(i, j)` has its sample point (its
//! centre) at `(i + 0.5, j + 0.5)`; z is the normalized depth in -1..1,
//! growing away from the eye.

use glam::{DVec3, DVec4};

use super::clip::{self, ClipVertex, Containment};
use crate::math::Matrix4;
use crate::model::{Object, Scene};

/// The vector from world point `p` towards the homogeneous eye `eye`
/// (for an eye at infinity, `w = 0`, its direction), not normalized.
pub fn towards_eye(eye: DVec4, p: DVec3) -> DVec3 {
    if eye.w != 0.0 {
        eye.truncate() / eye.w - p
    } else {
        eye.truncate()
    }
}

/// The unit direction from world point `p` towards the homogeneous eye.
pub fn direction_to_eye(eye: DVec4, p: DVec3) -> DVec3 {
    towards_eye(eye, p).normalize_or_zero()
}

/// A polygon ready for visibility and painting.
#[derive(Debug, Clone, PartialEq)]
pub struct ScreenPolygon {
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// Screen x, y in pixels (y up) and normalized depth z.
    pub points: Vec<DVec3>,
    /// World positions of the same vertices.
    pub world: Vec<DVec3>,
    /// Whether clipping changed the polygon.
    pub clipped: bool,
    /// Whether the viewer sees the polygon's back (only for `type open`).
    pub back_facing: bool,
}

impl ScreenPolygon {
    /// Smallest and largest depth of the vertices.
    pub fn z_range(&self) -> (f64, f64) {
        self.points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.z), hi.max(p.z))
            })
    }
}

/// The viewing set-up shared by all objects of one render.
#[derive(Debug, Clone, Copy)]
pub struct View {
    /// World to clip coordinates.
    pub projection: Matrix4,
    /// The eye in homogeneous world coordinates (w = 0: at infinity).
    pub eye: DVec4,
    /// Image width and height in pixels.
    pub width: f64,
    /// Image height in pixels.
    pub height: f64,
    /// Clipping epsilon (`setmode e`).
    pub epsilon: f64,
    /// Minimum screen detail in normalized units (`setmode d`).
    pub min_detail: f64,
    /// Clip to world coordinates (the inverse projection), if invertible.
    pub inverse: Option<Matrix4>,
}

impl View {
    /// The view of `scene` rendered at `width` x `height`; `None` when the
    /// scene's final CTM has no centre of projection (it is singular).
    pub fn new(scene: &Scene, width: u32, height: u32) -> Option<View> {
        Some(View {
            projection: scene.projection,
            eye: scene.projection.centre_of_projection()?,
            width: width as f64,
            height: height as f64,
            epsilon: scene.modes.epsilon,
            min_detail: scene.modes.min_detail,
            inverse: scene.projection.inverse(),
        })
    }

    /// The view of `scene` at `size` (else the scene's own viewport), or
    /// the error every renderer gives for a singular final CTM.
    pub fn for_scene(scene: &Scene, size: Option<(u32, u32)>) -> crate::error::Result<View> {
        let (width, height) = size.unwrap_or((scene.viewport.width(), scene.viewport.height()));
        View::new(scene, width, height).ok_or_else(|| {
            crate::error::Error::Invalid(
                "the final CTM is singular: it has no centre of projection to view from".into(),
            )
        })
    }

    /// Screen coordinates of world point `p` (which must be in front of the
    /// eye).
    pub fn project(&self, p: DVec3) -> DVec3 {
        self.screen_point(self.projection.transform_point4(p))
    }

    /// The world point whose screen coordinates are `s` (inverse of
    /// [`View::project`]).
    pub fn unproject(&self, s: DVec3) -> Option<DVec3> {
        let inv = self.inverse?;
        let h = inv.transform(DVec4::new(
            s.x / self.width * 2.0 - 1.0,
            s.y / self.height * 2.0 - 1.0,
            s.z,
            1.0,
        ));
        let p = h.truncate() / h.w;
        p.is_finite().then_some(p)
    }

    /// The world ray through screen point `(x, y)` (pixels), from the near
    /// plane (`t = 0`) to the far plane (`t = 1`), as origin and direction.
    pub fn ray(&self, x: f64, y: f64) -> Option<(DVec3, DVec3)> {
        let inv = self.inverse?;
        let nx = x / self.width * 2.0 - 1.0;
        let ny = y / self.height * 2.0 - 1.0;
        let near = inv.transform(DVec4::new(nx, ny, -1.0, 1.0));
        let far = inv.transform(DVec4::new(nx, ny, 1.0, 1.0));
        let (o, f) = (near.truncate() / near.w, far.truncate() / far.w);
        (o.is_finite() && f.is_finite()).then_some((o, f - o))
    }

    /// Whether the front of the plane `[A B C D]` faces the eye.
    pub fn faces_eye(&self, plane: DVec4) -> bool {
        plane.dot(self.eye) > 0.0
    }

    /// Direction from world point `p` towards the eye (unit).
    pub fn to_eye(&self, p: DVec3) -> DVec3 {
        direction_to_eye(self.eye, p)
    }

    fn screen_point(&self, c: DVec4) -> DVec3 {
        let inv = 1.0 / c.w;
        DVec3::new(
            (c.x * inv + 1.0) * 0.5 * self.width,
            (c.y * inv + 1.0) * 0.5 * self.height,
            c.z * inv,
        )
    }
}

/// Classifies an object's bounding box against the view volume.
pub fn classify_object(object: &Object, view: &View) -> Containment {
    clip::classify(
        object
            .bbox_corners
            .iter()
            .map(|c| clip::outcode(view.projection.transform_point4(*c))),
    )
}

/// Counters of the geometry stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GeometryStats {
    /// Objects culled by their bounding box.
    pub objects_culled: usize,
    /// Polygons removed as back faces.
    pub back_faces: usize,
    /// Polygons wholly outside the view volume.
    pub outside: usize,
    /// Polygons that were clipped.
    pub clipped: usize,
    /// Polygons dropped for being smaller than the minimum detail.
    pub too_small: usize,
}

impl std::ops::AddAssign for GeometryStats {
    fn add_assign(&mut self, o: GeometryStats) {
        self.objects_culled += o.objects_culled;
        self.back_faces += o.back_faces;
        self.outside += o.outside;
        self.clipped += o.clipped;
        self.too_small += o.too_small;
    }
}

/// A polygon the view keeps, as [`expand_objects_with`] hands it on: its
/// vertices after clipping, in clip and world coordinates.
#[derive(Debug, Clone, Copy)]
pub struct Kept<'a> {
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// The vertices, clipped to the view volume.
    pub vertices: &'a [ClipVertex],
    /// Whether clipping changed the polygon.
    pub clipped: bool,
    /// Whether the viewer sees the polygon's back (only for `type open`).
    pub back_facing: bool,
}

impl ScreenPolygon {
    /// The polygon `kept`, in the screen coordinates of `view`.
    pub fn new(kept: Kept<'_>, view: &View) -> ScreenPolygon {
        ScreenPolygon {
            object: kept.object,
            polygon: kept.polygon,
            points: kept
                .vertices
                .iter()
                .map(|v| view.screen_point(v.clip))
                .collect(),
            world: kept.vertices.iter().map(|v| v.world).collect(),
            clipped: kept.clipped,
            back_facing: kept.back_facing,
        }
    }
}

/// The screen polygons of each shown (not `type hidden`) object of
/// `objects`, one list an object, in order; the objects are expanded in
/// parallel (a scene of many small objects), each as [`expand_object`].
pub fn expand_objects(
    objects: &[Object],
    view: &View,
    stats: &mut GeometryStats,
) -> Vec<Vec<ScreenPolygon>> {
    expand_objects_with(objects, view, stats, |k| ScreenPolygon::new(k, view))
}

/// [`expand_objects`], each polygon kept made into a `T` by `make`: a
/// caller that needs only some of a screen polygon allocates only that.
pub fn expand_objects_with<T: Send>(
    objects: &[Object],
    view: &View,
    stats: &mut GeometryStats,
    make: impl Fn(Kept<'_>) -> T + Sync,
) -> Vec<Vec<T>> {
    use rayon::prelude::*;
    // An object a task: a few heavy objects among many light ones would
    // else share one thread's run of the iterator.
    let expanded: Vec<(Vec<T>, GeometryStats)> = (0..objects.len())
        .into_par_iter()
        .with_max_len(1)
        .filter(|&i| !objects[i].surface_type.hidden)
        .map(|i| {
            let (mut out, mut counts) = (Vec::new(), GeometryStats::default());
            expand_object_with(objects, i, view, &mut out, &mut counts, &make);
            (out, counts)
        })
        .collect();
    expanded
        .into_iter()
        .map(|(out, counts)| {
            *stats += counts;
            out
        })
        .collect()
}

/// Expands object `index` of a scene's `objects` into screen polygons
/// appended to `out`.
/// The polygons are expanded in parallel and appended in order, so the
/// thread count changes nothing.
pub fn expand_object(
    objects: &[Object],
    index: usize,
    view: &View,
    out: &mut Vec<ScreenPolygon>,
    stats: &mut GeometryStats,
) {
    expand_object_with(objects, index, view, out, stats, &|k| {
        ScreenPolygon::new(k, view)
    });
}

/// [`expand_object`], each polygon kept made into a `T` by `make`.
fn expand_object_with<T: Send>(
    objects: &[Object],
    index: usize,
    view: &View,
    out: &mut Vec<T>,
    stats: &mut GeometryStats,
    make: &(impl Fn(Kept<'_>) -> T + Sync),
) {
    use rayon::prelude::*;
    let object = &objects[index];
    let containment = classify_object(object, view);
    if containment == Containment::Outside {
        stats.objects_culled += 1;
        return;
    }
    let clip_coords: Vec<DVec4> = object
        .vertices
        .par_iter()
        .with_min_len(PARALLEL_MIN)
        .map(|v| view.projection.transform_point4(*v))
        .collect();
    let codes: Vec<u8> = if containment == Containment::Crossing {
        clip_coords.iter().map(|c| clip::outcode(*c)).collect()
    } else {
        Vec::new()
    };
    let expanded = Expansion {
        object,
        index: index as u32,
        view,
        containment,
        clip_coords: &clip_coords,
        codes: &codes,
    };
    // Back faces (usually half) are only counted. Each thread gathers a
    // polygon's vertices in one reused buffer.
    let outcomes: Vec<Outcome<T>> = object
        .polygons
        .par_iter()
        .enumerate()
        .with_min_len(PARALLEL_MIN)
        .map_init(Vec::new, |scratch, (pi, polygon)| {
            expanded.polygon(pi, polygon, scratch, make)
        })
        .flatten()
        .collect();
    stats.back_faces += object.polygons.len() - outcomes.len();
    out.reserve(
        outcomes
            .iter()
            .filter(|o| matches!(o, Outcome::Kept { .. }))
            .count(),
    );
    for outcome in outcomes {
        match outcome {
            Outcome::Outside { clipped } => {
                stats.clipped += usize::from(clipped);
                stats.outside += 1;
            }
            Outcome::TooSmall { clipped } => {
                stats.clipped += usize::from(clipped);
                stats.too_small += 1;
            }
            Outcome::Kept { made, clipped } => {
                stats.clipped += usize::from(clipped);
                out.push(made);
            }
        }
    }
}

/// The fewest polygons (or vertices) a thread takes at once.
const PARALLEL_MIN: usize = 1024;

/// What became of one polygon in [`expand_object`] that is not a back face.
enum Outcome<T> {
    Outside { clipped: bool },
    TooSmall { clipped: bool },
    Kept { made: T, clipped: bool },
}

/// One object's expansion: what each of its polygons needs.
struct Expansion<'a> {
    object: &'a Object,
    index: u32,
    view: &'a View,
    containment: Containment,
    clip_coords: &'a [DVec4],
    codes: &'a [u8],
}

impl Expansion<'_> {
    /// `None` for a back face; the vertices are gathered in `scratch`.
    fn polygon<T>(
        &self,
        pi: usize,
        polygon: &crate::model::Polygon,
        scratch: &mut Vec<ClipVertex>,
        make: &impl Fn(Kept<'_>) -> T,
    ) -> Option<Outcome<T>> {
        let (object, view) = (self.object, self.view);
        let front = view.faces_eye(polygon.plane);
        if !front && !object.surface_type.open {
            return None;
        }
        scratch.clear();
        scratch.extend(polygon.indices.iter().map(|&i| ClipVertex {
            clip: self.clip_coords[i as usize],
            world: object.vertices[i as usize],
        }));
        let mut clipped = false;
        let cut;
        let vertices: &[ClipVertex] = if self.containment == Containment::Crossing {
            match clip::classify(polygon.indices.iter().map(|&i| self.codes[i as usize])) {
                Containment::Inside => scratch,
                Containment::Outside => return Some(Outcome::Outside { clipped: false }),
                Containment::Crossing => {
                    clipped = true;
                    cut = clip::clip_polygon(scratch, view.epsilon);
                    if cut.is_empty() {
                        return Some(Outcome::Outside { clipped });
                    }
                    &cut
                }
            }
        } else {
            scratch
        };
        if is_below_detail(vertices, view) {
            return Some(Outcome::TooSmall { clipped });
        }
        let made = make(Kept {
            object: self.index,
            polygon: pi as u32,
            vertices,
            clipped,
            back_facing: !front,
        });
        Some(Outcome::Kept { made, clipped })
    }
}

fn is_below_detail(vertices: &[ClipVertex], view: &View) -> bool {
    if view.min_detail <= 0.0 {
        return false;
    }
    let (lo, hi) = crate::math::bounds(vertices.iter().map(|v| view.screen_point(v.clip)));
    // Extents in normalized units (the image spans 2).
    let dx = (hi.x - lo.x) * 2.0 / view.width;
    let dy = (hi.y - lo.y) * 2.0 / view.height;
    dx < view.min_detail && dy < view.min_detail
}

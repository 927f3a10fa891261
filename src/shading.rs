//! The illumination model of Garcia 1986 (004 section 4.8), Phong's:
//!
//! `I = ka Ia + sum_j k(j) (kd (N.L_j) + ks (N.H_j)^n)`,
//! `ka = max(0, 1 - (kd + kr + kt))`,
//! `k(j) = max(1 - |P_j - P_v| / Range_j, 0)^2`.
//!
//! Colour enters as in Phong's model: the ambient and diffuse terms are
//! multiplied by the surface colour and by the ambient or light colour, the
//! specular term by the light colour only. Lights behind the surface
//! (N.L <= 0) contribute nothing. Results are clamped to 0..1.
//! Shading is done in world space.
//!
//! Below the model, the shades of a scene's polygons: one per polygon
//! (faceted), per vertex (Gouraud, with vertex attributes interpolated
//! along the original polygon's edges), Phong highlight vectors, and the
//! transparency `k_t = k_trp (E.N)^tpwr` (004 section 4.9). They read a
//! scene's [`Materials`], resolved once per render: the tree builder,
//! `emit` and the painters never look a material up in the `Scene`.
#![doc = include_str!("shading.md")]

use glam::{DVec3, DVec4};

use crate::geometry::view::View;
use crate::model::{Color, ColorEntry, Light, Material, Object, Scene, SortOrder};

/// What the tree builder, its records and their shades read of a scene,
/// resolved once per render (004 section 4.3: the object's data
/// structure; 4.8: the surface parameters of the illumination model):
/// the built objects' world polygons, each polygon's material as a typed
/// value, the lights and the few settings these stages follow.
#[derive(Debug, Clone)]
pub struct Materials<'a> {
    /// The built objects (world vertices and polygons), in scene order.
    pub objects: &'a [Object],
    /// Per object, in the same order, its resolved surface.
    pub resolved: Vec<ObjectMaterials<'a>>,
    /// The lights, in definition order.
    pub lights: &'a [Light],
    /// `ambient r g b`.
    pub ambient: Color,
    /// `background r g b`: what the records' stream is painted over.
    pub background: Color,
    /// `setmode s`: Phong highlight vectors.
    pub phong: bool,
    /// `setmode v`: vertex shades (Gouraud).
    pub vertex_shades: bool,
    /// `setmode x`: one composite list per level.
    pub expand: bool,
    /// `sort btf|ftb`.
    pub sort_order: SortOrder,
    /// The absolute tolerance: `setmode e` times the scene's size.
    pub eps: f64,
}

/// One object's surface, resolved: per polygon its material (colour,
/// coefficients, specular and shininess for Phong), and what per-point
/// shading interpolates (004 section 4.8: "world space vertex normals are
/// carried along with each polygon").
#[derive(Debug, Clone)]
pub struct ObjectMaterials<'a> {
    /// Per polygon (index into `Object::polygons`): its material, with
    /// its `.pcl` entry or the mean of its vertices' `.vcl` entries; one
    /// for all when the object has no colour file (see
    /// [`ObjectMaterials::material`]).
    pub materials: Vec<Material>,
    /// `transparency k_trp tpwr` (004 section 4.9).
    pub transparency: (f64, f64),
    /// `index n`, the index of refraction.
    pub index: f64,
    /// `type ltsrc`: shown in its own colour, unshaded.
    pub unshaded: bool,
    /// Vertex normals for `type curved` objects.
    pub vertex_normals: Option<&'a [DVec3]>,
    /// `.vcl` vertex colours, interpolated along edges; `None` when the
    /// object has none or polygon colours override them.
    pub vertex_colors: Option<&'a [ColorEntry]>,
}

impl<'a> Materials<'a> {
    /// Resolves the materials of every polygon of `scene`, once.
    pub fn new(scene: &'a Scene) -> Materials<'a> {
        let resolved = scene.objects.iter().map(ObjectMaterials::new).collect();
        Materials {
            objects: &scene.objects,
            resolved,
            lights: &scene.lights,
            ambient: scene.ambient,
            background: scene.background,
            phong: scene.modes.phong,
            vertex_shades: scene.modes.vertex_shades,
            expand: scene.modes.expand,
            sort_order: scene.sort_order,
            eps: scene.modes.epsilon * scene.size().max(f64::MIN_POSITIVE),
        }
    }

    /// Object `o`'s geometry and resolved surface.
    fn object(&self, o: u32) -> (&'a Object, &ObjectMaterials<'a>) {
        (&self.objects[o as usize], &self.resolved[o as usize])
    }

    /// Whether object `o` is `transparency`-transparent (004 section 4.9):
    /// what lies behind it shows through.
    pub fn is_transparent(&self, o: u32) -> bool {
        self.resolved[o as usize].transparency.0 > 0.0
    }

    /// The material of polygon `polygon` of object `object`.
    pub fn material(&self, object: u32, polygon: u32) -> Material {
        self.resolved[object as usize].material(polygon as usize)
    }
}

impl<'a> ObjectMaterials<'a> {
    /// `o`'s surface, each polygon's material resolved.
    pub fn new(o: &'a Object) -> ObjectMaterials<'a> {
        // Without colour files every polygon has the object's surface:
        // one copy, not one per polygon (office2's peak memory).
        let per_polygon = o.polygon_colors.is_some() || o.vertex_colors.is_some();
        let count = if per_polygon { o.polygons.len() } else { 1 };
        ObjectMaterials {
            materials: (0..count).map(|pi| o.material(pi)).collect(),
            transparency: o.surface.transparency,
            index: o.surface.index,
            unshaded: o.surface_type.ltsrc,
            vertex_normals: o.vertex_normals.as_deref(),
            vertex_colors: match (&o.vertex_colors, &o.polygon_colors) {
                (Some(vcl), None) => Some(vcl.as_slice()),
                _ => None,
            },
        }
    }

    /// The material of polygon `pi`.
    pub fn material(&self, pi: usize) -> Material {
        match self.materials.as_slice() {
            [one] => *one,
            many => many[pi],
        }
    }
}

/// Per vertex: the shade without highlights `I_e` (3 values), then per
/// light the highlight normal vector `hltnml` (the vertex normal in a frame
/// whose z axis is the halfway vector H) and the light's highlight
/// intensity `I_L` (3 + 3 values). At a pixel, the interpolated values give
/// `I = I_e + sum I_L (h_z / |h|)^n` (004 section 4.8).
#[derive(Debug, Clone, PartialEq)]
pub struct PhongVertices {
    /// Number of highlight lights.
    pub lights: usize,
    /// Shininess `n`.
    pub shininess: f32,
    /// `stride()` values per vertex.
    pub attrs: Vec<f32>,
}

impl PhongVertices {
    /// Values per vertex.
    pub fn stride(&self) -> usize {
        3 + 6 * self.lights
    }

    /// The colour from interpolated values `v`.
    pub fn shade(&self, v: &[f32]) -> [f32; 3] {
        let mut c = [v[0], v[1], v[2]];
        for l in 0..self.lights {
            let h = &v[3 + 6 * l..6 + 6 * l];
            let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
            if len > 0.0 && h[2] > 0.0 {
                let k = (h[2] / len).powf(self.shininess);
                for (ci, i) in c.iter_mut().zip(&v[6 + 6 * l..9 + 6 * l]) {
                    *ci += i * k;
                }
            }
        }
        c.map(|x| x.clamp(0.0, 1.0))
    }
}

/// Which illumination model shades the polygons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShadingModel {
    /// Garcia's (Phong's) model of 004 section 4.8: see [`shade`].
    #[default]
    Garcia,
    /// Donovan's scattering and specular rules (000 section 6, rules (1)
    /// and (2)): see [`shade_donovan`].
    Donovan,
}

/// The range attenuation k(j) of a light at distance `d`.
pub fn range_attenuation(d: f64, range: f64) -> f64 {
    let k = (1.0 - d / range).max(0.0);
    k * k
}

/// The intensity at world point `p` with unit normal `n` (facing the
/// viewer's side that is shaded), seen from direction `to_eye` (unit).
pub fn shade(
    m: &Material,
    p: DVec3,
    n: DVec3,
    to_eye: DVec3,
    lights: &[Light],
    ambient: Color,
) -> Color {
    let mut c = m.color * ambient * m.ambient_coefficient();
    for light in lights {
        if let Some(term) = light_term(m, p, n, to_eye, light) {
            c += term;
        }
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

/// The unclamped contribution of one light to [`shade`], `None` when it
/// gives nothing.
fn light_term(m: &Material, p: DVec3, n: DVec3, to_eye: DVec3, light: &Light) -> Option<Color> {
    let to_light = light.position - p;
    let d = to_light.length();
    if d == 0.0 {
        return None;
    }
    let l = to_light / d;
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return None;
    }
    let k = range_attenuation(d, light.range);
    if k == 0.0 {
        return None;
    }
    let mut term = m.color * m.diffuse * n_dot_l;
    if m.specular > 0.0 {
        let h = (l + to_eye).normalize_or_zero();
        let n_dot_h = n.dot(h).max(0.0);
        term += DVec3::splat(m.specular * n_dot_h.powf(m.shininess));
    }
    Some(light.color * term * k)
}

/// The unclamped contribution of one light to [`shade_donovan`] (rules
/// (1) and (2)), `None` when it gives nothing.
fn light_term_donovan(
    m: &Material,
    p: DVec3,
    n: DVec3,
    to_eye: DVec3,
    light: &Light,
) -> Option<Color> {
    let theta1 = n.dot(to_eye).clamp(-1.0, 1.0).acos();
    let l = (light.position - p).try_normalize()?;
    let cos_theta = n.dot(l).clamp(-1.0, 1.0);
    if cos_theta <= 0.0 {
        return None;
    }
    let mut c = light.color * m.color * (m.diffuse * cos_theta);
    let cos_spec = (cos_theta.acos() - theta1).cos();
    if m.specular > 0.0 && cos_spec > 0.0 {
        c += light.color * (m.specular * cos_spec.powf(m.shininess));
    }
    Some(c)
}

/// The faceted shade of one polygon seen from one eye, kept as its
/// unclamped sum over all lights, so that its shade without a few lights
/// (the shade of a shadow, 004 section 4.7) costs those lights only, not
/// a new sum over all the others: with thousands of lights and a shadow
/// per light, that sum made the cost grow with the square of the light
/// count.
#[derive(Debug, Clone)]
pub struct FacetTerms<'a> {
    lights: &'a [Light],
    eye: DVec4,
    model: ShadingModel,
    material: Material,
    point: DVec3,
    normal: DVec3,
    to_eye: DVec3,
    /// `None` for `type ltsrc`: the colour itself, lights or not.
    total: Option<Color>,
}

impl<'a> FacetTerms<'a> {
    /// The terms of [`facet_shade_with_model`] with all of the scene's
    /// lights: one pass over them.
    pub fn new(
        materials: &Materials<'a>,
        eye: DVec4,
        object: u32,
        polygon: u32,
        back: bool,
        at: Option<DVec3>,
        model: ShadingModel,
    ) -> FacetTerms<'a> {
        let (object, resolved) = materials.object(object);
        let pi = polygon as usize;
        let poly = &object.polygons[pi];
        let material = resolved.material(pi);
        let point = at.unwrap_or_else(|| {
            poly.indices
                .iter()
                .map(|&i| object.vertices[i as usize])
                .sum::<DVec3>()
                / poly.indices.len() as f64
        });
        let normal = if back { -poly.normal() } else { poly.normal() };
        let to_eye = crate::geometry::view::direction_to_eye(eye, point);
        let mut terms = FacetTerms {
            lights: materials.lights,
            eye,
            model,
            material,
            point,
            normal,
            to_eye,
            total: None,
        };
        if !resolved.unshaded {
            let mut c = material.color * materials.ambient * material.ambient_coefficient();
            for light in materials.lights {
                if let Some(t) = terms.term(light) {
                    c += t;
                }
            }
            terms.total = Some(c);
        }
        terms
    }

    fn term(&self, light: &Light) -> Option<Color> {
        let (m, p, n, e) = (&self.material, self.point, self.normal, self.to_eye);
        match self.model {
            ShadingModel::Garcia => light_term(m, p, n, e, light),
            ShadingModel::Donovan => light_term_donovan(m, p, n, e, light),
        }
    }

    /// The eye (homogeneous world point) the shade is seen from.
    pub fn eye(&self) -> DVec4 {
        self.eye
    }

    /// The shade with every light.
    pub fn shade(&self) -> Color {
        self.total
            .map_or(self.material.color, |c| c.clamp(DVec3::ZERO, DVec3::ONE))
    }

    /// The shade without the lights of these indices (distinct), in the
    /// time of their number.
    pub fn without(&self, lights: &[u32]) -> Color {
        let Some(mut c) = self.total else {
            return self.material.color;
        };
        for &j in lights {
            if let Some(t) = self.lights.get(j as usize).and_then(|l| self.term(l)) {
                c -= t;
            }
        }
        c.clamp(DVec3::ZERO, DVec3::ONE)
    }
}

/// The intensity at `p` under `model` (see [`shade`] and
/// [`shade_donovan`]).
pub fn shade_with_model(
    model: ShadingModel,
    m: &Material,
    p: DVec3,
    n: DVec3,
    to_eye: DVec3,
    lights: &[Light],
    ambient: Color,
) -> Color {
    match model {
        ShadingModel::Garcia => shade(m, p, n, to_eye, lights, ambient),
        ShadingModel::Donovan => shade_donovan(m, p, n, to_eye, lights, ambient),
    }
}

/// Donovan's shader (000 section 6), per light: rule (1), scattering,
/// `I0 cos^a(theta)` with `a = 1`, and rule (2), specular reflection,
/// `I1 cos^b(theta - theta1)` with `b` the surface shininess; `theta` is
/// the angle between the normal `n` and the direction to the light,
/// `theta1` the angle between the normal and the direction to the eye.
/// `I0` is the light colour times the diffuse coefficient times the surface
/// colour ("proportional to the intensity of the light source and the
/// reflectance of the face"), `I1` the light colour times the specular
/// coefficient. Donovan's source is distant (parallel rays), so there is no
/// range attenuation; a light behind the face (`theta >= 90` degrees)
/// gives nothing, and neither does rule (2) past `|theta - theta1| >= 90`
/// degrees. The ambient term is Garcia's, `ka Ia` times the surface
/// colour. Clamped to 0..1.
pub fn shade_donovan(
    m: &Material,
    p: DVec3,
    n: DVec3,
    to_eye: DVec3,
    lights: &[Light],
    ambient: Color,
) -> Color {
    let mut c = m.color * ambient * m.ambient_coefficient();
    let theta1 = n.dot(to_eye).clamp(-1.0, 1.0).acos();
    for light in lights {
        let Some(l) = (light.position - p).try_normalize() else {
            continue;
        };
        let cos_theta = n.dot(l).clamp(-1.0, 1.0);
        if cos_theta <= 0.0 {
            continue;
        }
        // Rule (1), a = 1.
        c += light.color * m.color * (m.diffuse * cos_theta);
        // Rule (2).
        let cos_spec = (cos_theta.acos() - theta1).cos();
        if m.specular > 0.0 && cos_spec > 0.0 {
            c += light.color * (m.specular * cos_spec.powf(m.shininess));
        }
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

// ---------------------------------------------------------------------
// Shades of polygons and their vertices in a scene: faceted, Gouraud and
// Phong (004 section 4.8), transparency (004 section 4.9).
// ---------------------------------------------------------------------

/// Where world point `p` lies on the outline of polygon `pi` of `o`: the
/// nearest edge, as its two vertex indices and the parameter along it.
/// Clipping and splitting only make new vertices on edges, so this finds
/// the vertex attributes to interpolate (004 section 4.8: "world space
/// vertex normals are carried along with each polygon").
fn edge_position(o: &Object, pi: usize, p: DVec3) -> (usize, usize, f64) {
    let poly = &o.polygons[pi];
    let m = poly.indices.len();
    let mut best = (
        f64::INFINITY,
        (poly.indices[0] as usize, poly.indices[0] as usize, 0.0),
    );
    for k in 0..m {
        let (ia, ib) = (poly.indices[k] as usize, poly.indices[(k + 1) % m] as usize);
        let (a, b) = (o.vertices[ia], o.vertices[ib]);
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (a + ab * t).distance(p);
        if d < best.0 {
            best = (d, (ia, ib, t));
        }
    }
    best.1
}

/// The vertex normal at world point `p` of polygon `pi` of `o`: for `type
/// curved` objects interpolated along the nearest edge of the original
/// polygon, else the polygon's normal; turned to the viewer when `back`.
fn vertex_normal_at(o: &Object, r: &ObjectMaterials<'_>, pi: usize, back: bool, p: DVec3) -> DVec3 {
    let poly = &o.polygons[pi];
    let flat = if back { -poly.normal() } else { poly.normal() };
    let Some(normals) = r.vertex_normals else {
        return flat;
    };
    let (ia, ib, t) = edge_position(o, pi, p);
    let n = (normals[ia] * (1.0 - t) + normals[ib] * t).normalize_or_zero();
    if back { -n } else { n }
}

/// The material at world point `p` of polygon `pi`: the polygon's, or with
/// `.vcl` vertex colours the entries of the nearest edge's vertices,
/// interpolated.
fn material_at(o: &Object, r: &ObjectMaterials<'_>, pi: usize, p: DVec3) -> Material {
    let base = r.material(pi);
    let Some(vcl) = r.vertex_colors else {
        return base;
    };
    let (ia, ib, t) = edge_position(o, pi, p);
    let (a, b) = (vcl[ia], vcl[ib]);
    let lerp = |x: f64, y: f64| x + (y - x) * t;
    base.with_entry(&ColorEntry {
        color: a.color + (b.color - a.color) * t,
        diffuse: lerp(a.diffuse, b.diffuse),
        reflectance: lerp(a.reflectance, b.reflectance),
        transmittance: lerp(a.transmittance, b.transmittance),
    })
}

/// The transparency `k_t = k_trp (E.N)^tpwr` at each world point of a
/// polygon (004 section 4.9: "carried along as a per-vertex component"),
/// or `None` for an opaque object.
pub fn vertex_transparency(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
    world: &[DVec3],
) -> Option<Vec<f32>> {
    let (o, r) = materials.object(object);
    let (k, power) = r.transparency;
    if k <= 0.0 {
        return None;
    }
    Some(
        world
            .iter()
            .map(|&p| {
                let n = vertex_normal_at(o, r, polygon as usize, back, p);
                let e = crate::geometry::view::direction_to_eye(eye, p);
                let cos = e.dot(n).clamp(0.0, 1.0);
                (if power > 0.0 { k * cos.powf(power) } else { k }) as f32
            })
            .collect(),
    )
}

/// Phong polygons with highlight vectors (004 section 4.8, `setmode s
/// on`): for polygons with a specular coefficient, per vertex the shade
/// without highlights and, per light, the vertex normal rotated into a
/// frame whose z axis is the halfway vector, with the light's highlight
/// intensity; the painter interpolates them and evaluates `(h_z/|h|)^n` at
/// every pixel, so highlights inside a polygon survive. The result is
/// `offset + weight * I` (pre-blending under a parent). `None` when not
/// asked for or not specular.
#[allow(clippy::too_many_arguments)]
pub fn phong_vertices(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
    world: &[DVec3],
    offset: Color,
    weight: f64,
) -> Option<PhongVertices> {
    if !materials.phong {
        return None;
    }
    let (o, r) = materials.object(object);
    let pi = polygon as usize;
    let material = r.material(pi);
    if r.unshaded || material.specular <= 0.0 {
        return None;
    }
    let (lights, ambient) = (materials.lights, materials.ambient);
    let mut base_material = material;
    base_material.specular = 0.0;
    let mut attrs = Vec::with_capacity(world.len() * (3 + 6 * lights.len()));
    for &p in world {
        let n = vertex_normal_at(o, r, pi, back, p);
        let e = crate::geometry::view::direction_to_eye(eye, p);
        let base = offset + shade(&base_material, p, n, e, lights, ambient) * weight;
        attrs.extend(base.as_vec3().to_array());
        for light in lights {
            let to_light = light.position - p;
            let d = to_light.length();
            let l = to_light / d.max(f64::MIN_POSITIVE);
            let k = range_attenuation(d, light.range);
            let h = (l + e).normalize_or_zero();
            if n.dot(l) <= 0.0 || k == 0.0 || h == DVec3::ZERO {
                attrs.extend([0.0; 6]);
                continue;
            }
            let hlt = rotate_to_z(h, n);
            attrs.extend([hlt.x as f32, hlt.y as f32, hlt.z as f32]);
            attrs.extend(
                (light.color * (material.specular * k * weight))
                    .as_vec3()
                    .to_array(),
            );
        }
    }
    Some(PhongVertices {
        lights: lights.len(),
        shininess: material.shininess as f32,
        attrs,
    })
}

/// `v` turned by the smallest rotation that takes the unit vector `h` to
/// +z, so that nearby vertices get consistent frames and their highlight
/// vectors interpolate smoothly.
fn rotate_to_z(h: DVec3, v: DVec3) -> DVec3 {
    let axis = h.cross(DVec3::Z);
    let s = axis.length();
    let c = h.z;
    if s < 1e-12 {
        return if c > 0.0 {
            v
        } else {
            DVec3::new(v.x, -v.y, -v.z)
        };
    }
    let k = axis / s;
    // Rodrigues: v cos + (k x v) sin + k (k.v)(1 - cos).
    v * c + k.cross(v) * s + k * k.dot(v) * (1.0 - c)
}

/// Gouraud vertex shades (004 section 4.8): the illumination model at each
/// vertex of the original polygon with the vertex normal (for `type
/// curved` objects, else the polygon's own normal) and its `.vcl` colour.
/// A point of a piece that lies on an edge of the original polygon (a
/// vertex made by clipping or by the NNS splitter) gets the linear
/// interpolation of the shades at the edge's ends, as Donovan requires of
/// the face splitter (000 section 6: "compute a correct intensity value for
/// the vertex it creates"), so no seam shows along the edge; other points
/// get the model evaluated there.
pub fn vertex_shades(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
    world: &[DVec3],
) -> Vec<Color> {
    let (o, r) = materials.object(object);
    let pi = polygon as usize;
    let model_at = |p: DVec3| {
        let material = material_at(o, r, pi, p);
        if r.unshaded {
            return material.color;
        }
        let n = vertex_normal_at(o, r, pi, back, p);
        let to_eye = crate::geometry::view::direction_to_eye(eye, p);
        shade(&material, p, n, to_eye, materials.lights, materials.ambient)
    };
    world
        .iter()
        .map(|&p| {
            let (ia, ib, t) = edge_position(o, pi, p);
            let (a, b) = (o.vertices[ia], o.vertices[ib]);
            let on_edge = (a + (b - a) * t).distance(p) <= 1e-7 * a.distance(b);
            if !on_edge {
                return model_at(p);
            }
            let (sa, sb) = (model_at(a), model_at(b));
            sa + (sb - sa) * t
        })
        .collect()
}

/// The transparency `k_t = k_trp (E.N)^tpwr` of a polygon (004 section
/// 4.9) from the object's `transparency k_trp tpwr`, at its centroid; 0 for
/// opaque polygons. With `tpwr = 0` it is the linear transparency `k_trp`.
pub fn transparency_of(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
) -> f64 {
    let (o, r) = materials.object(object);
    let (k, power) = r.transparency;
    if k <= 0.0 {
        return 0.0;
    }
    let poly = &o.polygons[polygon as usize];
    let c = poly
        .indices
        .iter()
        .map(|&i| o.vertices[i as usize])
        .sum::<DVec3>()
        / poly.indices.len() as f64;
    let e = crate::geometry::view::direction_to_eye(eye, c);
    let n = if back { -poly.normal() } else { poly.normal() };
    let cos = e.dot(n).clamp(0.0, 1.0);
    if power > 0.0 { k * cos.powf(power) } else { k }
}

/// The value at screen point `(x, y)` of a convex polygon with `values` at
/// its vertices: linear along the two edges crossing row `y`, then
/// linear between them in x (004 figure 4.16). Points outside take the
/// nearest crossing's value, or the nearest vertex's.
pub fn interpolate_in_polygon(screen: &[DVec3], values: &[Color], x: f64, y: f64) -> Color {
    let n = screen.len();
    let mut crossings: Vec<(f64, Color)> = Vec::with_capacity(4);
    for k in 0..n {
        let (a, b) = (screen[k], screen[(k + 1) % n]);
        let (lo, hi) = if a.y <= b.y { (a.y, b.y) } else { (b.y, a.y) };
        if hi > lo && y >= lo && y <= hi {
            let t = (y - a.y) / (b.y - a.y);
            crossings.push((
                a.x + (b.x - a.x) * t,
                values[k] + (values[(k + 1) % n] - values[k]) * t,
            ));
        }
    }
    if crossings.is_empty() {
        let nearest = (0..n)
            .min_by(|&i, &j| {
                let di = (screen[i].x - x).powi(2) + (screen[i].y - y).powi(2);
                let dj = (screen[j].x - x).powi(2) + (screen[j].y - y).powi(2);
                di.total_cmp(&dj)
            })
            .unwrap_or(0);
        return values.get(nearest).copied().unwrap_or(Color::ZERO);
    }
    let left = crossings
        .iter()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("not empty");
    let right = crossings
        .iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .expect("not empty");
    if right.0 <= left.0 {
        return left.1;
    }
    let t = ((x - left.0) / (right.0 - left.0)).clamp(0.0, 1.0);
    left.1 + (right.1 - left.1) * t
}

/// One shade for the whole polygon (faceted): the illumination model at the
/// centroid of the world polygon, with its plane normal turned towards the
/// viewer (`back` when the viewer sees its back, for `type open`).
pub fn facet_shade(
    materials: &Materials<'_>,
    view: &View,
    object: u32,
    polygon: u32,
    back: bool,
) -> Color {
    facet_shade_from(materials, view.eye, object, polygon, back)
}

/// [`facet_shade`] seen from the homogeneous world point `eye` (for
/// fragments seen by reflection or refraction, the eye mapped back into
/// world space).
pub fn facet_shade_from(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
) -> Color {
    facet_shade_with(
        materials,
        eye,
        object,
        polygon,
        back,
        materials.lights,
        None,
    )
}

/// [`facet_shade_from`] with a given set of lights, and optionally at a
/// given world point instead of the polygon's centroid (for shadow shades,
/// 004 section 4.7: the target's shade without the shadowing light).
pub fn facet_shade_with(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
    lights: &[Light],
    at: Option<DVec3>,
) -> Color {
    facet_shade_with_model(
        materials,
        eye,
        object,
        polygon,
        back,
        lights,
        at,
        ShadingModel::Garcia,
    )
}

/// [`facet_shade_with`] under a given illumination model.
#[allow(clippy::too_many_arguments)]
pub fn facet_shade_with_model(
    materials: &Materials<'_>,
    eye: DVec4,
    object: u32,
    polygon: u32,
    back: bool,
    lights: &[Light],
    at: Option<DVec3>,
    model: ShadingModel,
) -> Color {
    let (object, resolved) = materials.object(object);
    let pi = polygon as usize;
    let polygon = &object.polygons[pi];
    let material = resolved.material(pi);
    if resolved.unshaded {
        return material.color;
    }
    let centroid = at.unwrap_or_else(|| {
        polygon
            .indices
            .iter()
            .map(|&i| object.vertices[i as usize])
            .sum::<DVec3>()
            / polygon.indices.len() as f64
    });
    let normal = if back {
        -polygon.normal()
    } else {
        polygon.normal()
    };
    let to_eye = crate::geometry::view::direction_to_eye(eye, centroid);
    shade_with_model(
        model,
        &material,
        centroid,
        normal,
        to_eye,
        lights,
        materials.ambient,
    )
}

#[cfg(test)]
mod tests;

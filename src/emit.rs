//! The virtual image tree emitted as one stream of records (Garcia 1986,
//! 004 section 4.10, figure 4.14): the only way image generation hands
//! its result downstream. The picture, the tree files and the rftb
//! programs all read what [`records`] makes.
//!
//! Shades (004 sections 4.8-4.10): pre-blended (`setmode b on`) a
//! fragment carries `I_parent + k I_own`; post-blended it carries `k I_own`
//! and the scan converter adds the parent (method 4). Faceted polygons
//! give type-1 records, Gouraud polygons (`setmode v`) type 2, Phong
//! polygons (`setmode s`) type 3, restore polygons type 0. A transparent
//! polygon (section 4.9) needs its `t`, which only the Phong record holds:
//! it is written as a Phong record, with no highlights unless it has them.

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::geometry::view::View;
use crate::image_tree::{Fragment, FragmentKind, VirtualImageTree};
use crate::model::{Color, Points, SortOrder};
use crate::shading::{
    Materials, interpolate_in_polygon, phong_vertices, transparency_of, vertex_shades,
    vertex_transparency,
};
use crate::tree::{PhongShades, Record, RecordStream, Shades};

/// Where a record came from: for id images and tests, not for files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Source {
    /// Object index in the scene.
    pub object: u32,
    /// Polygon index in the object.
    pub polygon: u32,
    /// The light whose shadow this is, for shadow records.
    pub shadow_of: Option<u32>,
}

/// How to emit: order and blending, and the screen the tree was made for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emit {
    /// Output order.
    pub order: SortOrder,
    /// Pre-blended shades.
    pub blended: bool,
    /// Screen size in pixels (to normalize coordinates).
    pub width: u32,
    /// Screen height in pixels.
    pub height: u32,
}

/// The tree (built for `view`) as a record stream, with each record's
/// source; shades come from the scene's resolved `materials`.
pub fn records(
    materials: &Materials<'_>,
    tree: &VirtualImageTree,
    how: Emit,
    view: &View,
) -> (RecordStream, Vec<Source>) {
    let order = tree.output_order(how.order);
    let gouraud = blended_vertex_shades(materials, tree, how, view);
    let (records, sources) = some_records(materials, tree, how, view, &order, &gouraud);
    (stream(materials, how, records), sources)
}

/// [`records`] from a tree that is not needed afterwards: the fragments'
/// points are freed as their records are made, a run of the output order
/// at a time, so that the tree and its records are never held whole
/// together: office2's peak memory falls by a twelfth. The first run's
/// records are kept as made (a tree of one run copies none), and the
/// last run's points go with the tree, freed on another thread while the
/// picture is scan converted.
pub fn records_freeing(
    materials: &Materials<'_>,
    mut tree: VirtualImageTree,
    how: Emit,
    view: &View,
) -> (RecordStream, Vec<Source>) {
    let order = tree.output_order(how.order);
    let gouraud = blended_vertex_shades(materials, &tree, how, view);
    let (mut records, mut sources) = (Vec::new(), Vec::new());
    let mut runs = order.chunks(FREEING_RUN).peekable();
    while let Some(run) = runs.next() {
        let (r, s) = some_records(materials, &tree, how, view, run, &gouraud);
        if records.is_empty() {
            (records, sources) = (r, s);
            records.reserve(order.len() - run.len());
            sources.reserve(order.len() - run.len());
        } else {
            records.extend(r);
            sources.extend(s);
        }
        if runs.peek().is_some() {
            for &n in run {
                tree.nodes[n].virtual_points = Points::Own(Box::default());
            }
        }
    }
    rayon::spawn(move || drop(tree));
    (stream(materials, how, records), sources)
}

/// `records` as the stream `how` asks for.
fn stream(materials: &Materials<'_>, how: Emit, records: Vec<Record>) -> RecordStream {
    RecordStream {
        records,
        background: Some(color_bytes(materials.background)),
        front_to_back: how.order == SortOrder::FrontToBack,
        blended: how.blended,
    }
}

/// Fragments whose records [`records_freeing`] makes before it frees them.
const FREEING_RUN: usize = 32768;

/// The records of the fragments `order` of `tree`, and their sources.
fn some_records(
    materials: &Materials<'_>,
    tree: &VirtualImageTree,
    how: Emit,
    view: &View,
    order: &[usize],
    gouraud: &[Option<Vec<Color>>],
) -> (Vec<Record>, Vec<Source>) {
    // Each record depends only on its fragment: in parallel, in order.
    order
        .par_iter()
        .with_min_len(512)
        .map(|&n| {
            let f = &tree.nodes[n];
            let pre = gouraud.get(n).and_then(|g| g.as_deref());
            let source = Source {
                object: f.object,
                polygon: f.polygon,
                shadow_of: match f.kind {
                    FragmentKind::Shadow { light } => Some(light),
                    _ => None,
                },
            };
            (record(materials, tree, f, how, pre, view), source)
        })
        .unzip()
}

/// One fragment's record.
fn record(
    materials: &Materials<'_>,
    tree: &VirtualImageTree,
    f: &Fragment,
    how: Emit,
    pre_gouraud: Option<&[Color]>,
    view: &View,
) -> Record {
    let level = f.level.min(31) as u16;
    let points = f
        .points(materials.objects)
        .iter()
        .map(|&v| {
            let p = view.project(v);
            // Figure 4.14's "x,y floats 0 to 1": a vertex clipped to the
            // screen's edge can land a rounding error beyond it.
            [
                crate::tree::file::unit((p.x / how.width as f64) as f32),
                crate::tree::file::unit((p.y / how.height as f64) as f32),
            ]
        })
        .collect();
    let shades = if f.kind == FragmentKind::Restore {
        Shades::Special
    } else {
        shades(
            materials,
            &Lit::new(materials, tree, f),
            how.blended,
            pre_gouraud,
            view.eye,
        )
    };
    Record {
        level,
        points,
        shades,
    }
}

/// A fragment with what shading it from its level's space takes: its
/// true world points (polygons only) and the eye that sees it.
struct Lit<'t> {
    f: &'t Fragment,
    world: Vec<DVec3>,
    eye: DVec4,
}

impl<'t> Lit<'t> {
    fn new(materials: &Materials<'_>, tree: &VirtualImageTree, f: &'t Fragment) -> Lit<'t> {
        let world = if f.kind == FragmentKind::Polygon {
            tree.world(materials.objects, f)
        } else {
            Vec::new()
        };
        Lit {
            f,
            world,
            eye: tree.eye(f),
        }
    }
}

/// A fragment's shades: `offset + weight * own`, the offset being the
/// parent's shade when pre-blending.
fn shades(
    materials: &Materials<'_>,
    lit: &Lit<'_>,
    blended: bool,
    pre_gouraud: Option<&[Color]>,
    eye: DVec4,
) -> Shades {
    let f = lit.f;
    let polygon = f.kind == FragmentKind::Polygon;
    let (offset, weight) = if blended {
        (f.blended - f.shade * f.weight, f.weight)
    } else {
        (Color::ZERO, f.weight)
    };
    if polygon
        && let Some(ph) = phong_vertices(
            materials,
            lit.eye,
            f.object,
            f.polygon,
            f.back_facing,
            &lit.world,
            offset,
            weight,
        )
    {
        let t = transparency_bytes(materials, lit, eye);
        let stride = ph.stride();
        let vertices: Vec<&[f32]> = ph.attrs.chunks(stride).collect();
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        // One highlight colour per light (figure 4.14): the vertices' mean.
        let light_colors = (0..ph.lights)
            .map(|l| {
                let mean = |c: usize| {
                    vertices.iter().map(|v| v[6 + 6 * l + c]).sum::<f32>() / vertices.len() as f32
                };
                [byte(mean(0)), byte(mean(1)), byte(mean(2))]
            })
            .collect();
        return Shades::Phong(Box::new(PhongShades {
            shininess: ph.shininess as f64,
            light_colors,
            rgbt: vertices
                .iter()
                .enumerate()
                .map(|(k, v)| [byte(v[0]), byte(v[1]), byte(v[2]), t[k % t.len()]])
                .collect(),
            normals: vertices
                .iter()
                .map(|v| {
                    (0..ph.lights)
                        .map(|l| [v[3 + 6 * l], v[4 + 6 * l], v[5 + 6 * l]])
                        .collect()
                })
                .collect(),
        }));
    }
    let colors: Vec<Color> = match (polygon && materials.vertex_shades, pre_gouraud) {
        (true, Some(pre)) => pre.to_vec(),
        (true, None) => vertex_shades(
            materials,
            lit.eye,
            f.object,
            f.polygon,
            f.back_facing,
            &lit.world,
        )
        .into_iter()
        .map(|c| offset + c * weight)
        .collect(),
        _ => vec![if blended {
            f.blended
        } else {
            f.shade * f.weight
        }],
    };
    let t = if polygon {
        transparency_bytes(materials, lit, eye)
    } else {
        vec![0]
    };
    if t.iter().any(|&v| v > 0) {
        let n = f.points(materials.objects).len();
        return Shades::Phong(Box::new(PhongShades {
            shininess: 1.0,
            light_colors: Vec::new(),
            rgbt: (0..n)
                .map(|k| {
                    let c = color_bytes(colors[k % colors.len()]);
                    [c[0], c[1], c[2], t[k % t.len()]]
                })
                .collect(),
            normals: vec![Vec::new(); n],
        }));
    }
    match colors.as_slice() {
        [one] => Shades::Faceted(color_bytes(*one)),
        many => Shades::Gouraud(many.iter().map(|c| color_bytes(*c)).collect()),
    }
}

/// The transparency of a polygon fragment as bytes: one per vertex with
/// vertex shades, else one for the polygon.
fn transparency_bytes(materials: &Materials<'_>, lit: &Lit<'_>, eye: DVec4) -> Vec<u8> {
    let f = lit.f;
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    if materials.vertex_shades
        && let Some(ts) = vertex_transparency(
            materials,
            lit.eye,
            f.object,
            f.polygon,
            f.back_facing,
            &lit.world,
        )
    {
        return ts.into_iter().map(|t| byte(t as f64)).collect();
    }
    // At level n the eye is mapped back; the view direction only matters
    // for the roll-off.
    vec![byte(transparency_of(
        materials,
        eye,
        f.object,
        f.polygon,
        f.back_facing,
    ))]
}

/// A colour, clamped, as bytes.
pub fn color_bytes(c: Color) -> [u8; 3] {
    let c = c.clamp(DVec3::ZERO, DVec3::ONE) * 255.0;
    [c.x.round() as u8, c.y.round() as u8, c.z.round() as u8]
}

/// Pre-blended Gouraud vertex shades of every polygon fragment
/// (`setmode v on`): a fragment's vertex shade is its parent's blended
/// shade at that screen point, interpolated as in 004 figure 4.16 (along
/// the two parent edges crossing the point's row, then across), plus `k`
/// times its own vertex shade. `None` for other fragments; empty when the
/// records are not pre-blended or vertex shades are off.
fn blended_vertex_shades(
    materials: &Materials<'_>,
    tree: &VirtualImageTree,
    how: Emit,
    view: &View,
) -> Vec<Option<Vec<Color>>> {
    if !how.blended || !materials.vertex_shades {
        return Vec::new();
    }
    let mut out: Vec<Option<Vec<Color>>> = vec![None; tree.nodes.len()];
    // Parents are pushed before their children.
    for n in 0..tree.nodes.len() {
        let f = &tree.nodes[n];
        if f.kind != FragmentKind::Polygon {
            continue;
        }
        let own = vertex_shades(
            materials,
            tree.eye(f),
            f.object,
            f.polygon,
            f.back_facing,
            &tree.world(materials.objects, f),
        );
        let parent = f.parent().and_then(|p| out[p].as_ref().map(|vs| (p, vs)));
        let blended = match parent {
            Some((p, parent_shades)) => {
                let outline = tree.nodes[p].screen(materials.objects, view);
                f.screen(materials.objects, view)
                    .iter()
                    .zip(&own)
                    .map(|(s, c)| {
                        interpolate_in_polygon(&outline, parent_shades, s.x, s.y) + *c * f.weight
                    })
                    .collect()
            }
            None => {
                let base = f.blended - f.shade * f.weight;
                own.iter().map(|c| base + *c * f.weight).collect()
            }
        };
        out[n] = Some(blended);
    }
    out
}

//! Vector output as a stage of the pipeline (Garcia 1986, 004 figure
//! 3.2, with the tree's records drawn as paths instead of scan converted):
//! the tree is built with NNS, emitted back to front and handed to
//! [`crate::vector`]'s writers, or to its hidden-line drawing.

use glam::DVec3;

use crate::emit::{self, Emit};
use crate::error::Result;
use crate::geometry::view::View;
use crate::image_tree::{FragmentKind, TreeOptions, VirtualImageTree};
use crate::model::{Scene, SortOrder};
use crate::output::{AtomicFile, Staged};
use crate::tree::RecordStream;
use crate::vector::{Format, Style, VectorInput, hidden_line, picture};

use super::{RenderOptions, RenderStats};

/// Builds the tree of `scene` with NNS (always) and emits it back to
/// front, pre-blended: [`prepare_for`] the shaded picture.
pub fn prepare(scene: &Scene, options: &RenderOptions) -> Result<VectorInput> {
    prepare_for(scene, options, Style::Shaded)
}

/// [`prepare`] for `style`. A hidden-line drawing needs level 1 only,
/// no shadows, and the edge flags; the others need no edge flags.
/// Shadows are cast only when a Point light can cast them.
pub fn prepare_for(scene: &Scene, options: &RenderOptions, style: Style) -> Result<VectorInput> {
    Ok(prepared(scene, options, style)?.0)
}

/// [`prepare_for`], with the tree's figures: NNS counters and warnings.
fn prepared(
    scene: &Scene,
    options: &RenderOptions,
    style: Style,
) -> Result<(VectorInput, RenderStats)> {
    let lines = style == Style::HiddenLine;
    let view = View::for_scene(scene, options.size)?;
    let (width, height) = (view.width as u32, view.height as u32);
    let materials = crate::shading::Materials::new(scene);
    let tree = crate::image_tree::build(
        &materials,
        &view,
        TreeOptions {
            max_level: if lines { 1 } else { scene.modes.max_level },
            threshold: scene.threshold,
            nns: true,
            shadows: options.shadows && !lines && crate::render::has_point_light(scene),
            refraction: options.refraction,
            explicit_shadow_shades: scene.modes.shadow_shades,
            shading: options.shading,
            budgets: options.budgets,
            cull_samples: None,
        },
    );
    // The tree builder stops early on a stop request.
    crate::cancel::check()?;
    let how = Emit {
        order: SortOrder::BackToFront,
        blended: true,
        width,
        height,
    };
    let (stream, sources) = emit::records(&materials, &tree, how, &view);
    let tree_file = scene.modes.output_tree.then(|| {
        let how = Emit {
            order: scene.sort_order,
            blended: scene.modes.blend,
            width,
            height,
        };
        emit::records(&materials, &tree, how, &view).0
    });
    let order = tree.output_order(SortOrder::BackToFront);
    let direct: Vec<bool> = order
        .iter()
        .map(|&n| {
            let f = &tree.nodes[n];
            f.level == 1 && f.kind == FragmentKind::Polygon
        })
        .collect();
    let mut record_of = vec![usize::MAX; tree.nodes.len()];
    for (k, &n) in order.iter().enumerate() {
        record_of[n] = k;
    }
    let parents = order
        .iter()
        .map(|&n| {
            tree.nodes[n]
                .parent()
                .map(|p| record_of[p])
                .filter(|&k| k != usize::MAX)
        })
        .collect();
    let original_edges = order
        .iter()
        .zip(&direct)
        .map(|(&n, &d)| {
            if d && lines {
                original_edge_flags(scene, &tree, n)
            } else {
                Vec::new()
            }
        })
        .collect();
    let stats = RenderStats {
        algorithm: Some(crate::visibility::Algorithm::Nns),
        polygons_listed: stream.records.len(),
        polygons_tiled: stream.records.len(),
        max_depth: tree.max_depth,
        geometry: tree.geometry,
        nns: tree.nns,
        pruned: tree.pruned,
        warnings: tree.warnings.clone(),
        ..Default::default()
    };
    let input = VectorInput {
        stream,
        sources,
        direct,
        parents,
        original_edges,
        width,
        height,
        tree_file,
    };
    Ok((input, stats))
}

/// Renders `scene` for a `run` into `file` (when the scene displays):
/// a vector file when `file`'s extension names a vector [`Format`], else
/// (with `hidden_line`) the hidden-line drawing as PNG or PPM, 1-pixel
/// lines anti-aliased unless `options.aa` is point sampling. Returns the
/// staged file, the tree's figures and, with `setmode o on`, the tree
/// for its files.
pub fn render_run(
    file: Option<AtomicFile>,
    scene: &Scene,
    options: &RenderOptions,
    hidden_line: bool,
) -> Result<RunOutput> {
    let style = if hidden_line {
        Style::HiddenLine
    } else {
        Style::Shaded
    };
    let t = std::time::Instant::now();
    let (mut input, mut stats) = prepared(scene, options, style)?;
    // The tree (NNS) and its records; then painting and writing.
    stats.sort_time = t.elapsed();
    let tree = input.tree_file.take();
    let Some(file) = file else {
        return Ok((None, stats, tree));
    };
    let t = std::time::Instant::now();
    let staged = match Format::from_path(file.path()) {
        Some(format) => {
            let pic = picture(&input, style);
            // The stages of `picture` give up early when a stop was
            // requested; nothing half-made is written.
            crate::cancel::check()?;
            file.write_with(|w| format.write(&pic, w))?
        }
        None => {
            let aa = options.aa != Some(crate::raster::scan::Method::Point);
            let segments = hidden_line::try_visible_edges(&input)?;
            let fb = hidden_line::rasterize(&segments, input.width, input.height, aa);
            crate::cancel::check()?;
            crate::output::stage_image(file, &fb, scene.outmode)?
        }
    };
    stats.paint_time = t.elapsed();
    Ok((Some(staged), stats, tree))
}

/// What [`render_run`] gives: the staged file, the figures, the tree.
pub type RunOutput = (Option<Staged>, RenderStats, Option<RecordStream>);

/// For each edge of fragment `n`: whether both ends lie on one edge of
/// the source polygon (in world space, to 1e-6 of the polygon's size).
fn original_edge_flags(scene: &Scene, tree: &VirtualImageTree, n: usize) -> Vec<bool> {
    let f = &tree.nodes[n];
    let object = &scene.objects[f.object as usize];
    let outline: Vec<DVec3> = object.polygons[f.polygon as usize]
        .indices
        .iter()
        .map(|&i| object.vertices[i as usize])
        .collect();
    let size = outline
        .iter()
        .map(|p| (*p - outline[0]).length())
        .fold(0.0, f64::max)
        .max(1e-300);
    let tol = 1e-6 * size;
    let on_edge = |a: DVec3, b: DVec3| {
        (0..outline.len()).any(|k| {
            let (p, q) = (outline[k], outline[(k + 1) % outline.len()]);
            distance_to_segment(a, p, q) <= tol && distance_to_segment(b, p, q) <= tol
        })
    };
    let world = tree.world(&scene.objects, f);
    let m = world.len();
    (0..m)
        .map(|k| on_edge(world[k], world[(k + 1) % m]))
        .collect()
}

fn distance_to_segment(x: DVec3, p: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((x - p).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x - (p + d * t)).length()
}

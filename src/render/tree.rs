//! The list-priority path (Garcia 1986, 004 figure 3.2): the virtual
//! image tree is built ([`crate::image_tree`]), then emitted as one stream
//! of records ([`crate::emit`]) for the scan converter, and, with `setmode
//! o`, as the tree file; exact refraction adds its ray-traced layer.

use std::time::Instant;

use crate::emit::{self, Emit, Source};
use crate::geometry::view::View;
use crate::image_tree::{Refraction, TreeOptions, VirtualImageTree};
use crate::model::{Scene, SortOrder};
use crate::raster::scan::{self, Method, ScanOptions};
use crate::raytrace::exact::ExactLayer;
use crate::shading::{Materials, ShadingModel};
use crate::threads::Pool;
use crate::tree::RecordStream;
use crate::visibility::Algorithm;

use super::{RenderOptions, RenderStats, best_method};

/// Whether `method` wants pre-blended shades (methods 1-3: no levels).
fn wants_pre_blending(method: Method) -> bool {
    matches!(method, Method::Area | Method::Mask | Method::Hybrid)
}

/// A tree ready for scan conversion: the picture's record stream (front to
/// back) and, with `setmode o on`, the file's (the scene's order and
/// blending).
pub struct Prepared {
    /// The records the picture is made from.
    pub picture: RecordStream,
    /// Each picture record's source polygon.
    pub sources: Vec<Source>,
    /// The tree as `setmode o` writes it.
    pub file: Option<RecordStream>,
    /// How to scan convert the picture.
    pub scan: ScanOptions,
    /// The profile, with `--profile`.
    pub profile: Option<crate::profile::Profile>,
    /// Figures so far.
    pub stats: RenderStats,
    /// With exact refraction: the ray-traced refracted branches, added to
    /// the picture's rows.
    pub exact: Option<crate::raytrace::exact::ExactLayer>,
}

/// Builds the virtual image tree and emits it as records.
pub fn prepare(
    scene: &Scene,
    view: &View,
    algorithm: Algorithm,
    options: &RenderOptions,
    mut stats: RenderStats,
    reuse: &super::Reuse,
    pool: &Pool,
) -> Prepared {
    let (casters, orders) = (&reuse.casters, &reuse.sort_orders);
    let t = Instant::now();
    let profile = crate::profile::Profile::new(options.profile);
    // Every polygon's material, resolved once for the tree and its records.
    let materials = Materials::new(scene);
    let (refraction, said) = refraction_model(scene, &materials, view, options.refraction);
    stats.refraction = said;
    let method = best_method(options);
    let scan = scan_options(view, options, method);
    // Hidden polygons are left out only of a picture made from samples:
    // not of the tree file (another method may read it), nor where exact
    // refraction paints its layer over the tree's fragments.
    let cull = !scene.modes.output_tree && refraction != Refraction::Exact;
    let tree_options = TreeOptions {
        max_level: scene.modes.max_level,
        threshold: scene.threshold,
        nns: algorithm == Algorithm::Nns,
        shadows: options.shadows,
        refraction,
        explicit_shadow_shades: scene.modes.shadow_shades,
        shading: options.shading,
        budgets: options.budgets,
        cull_samples: scan.sample_grid().filter(|_| cull),
    };
    let builder = Builder {
        materials: &materials,
        view,
        profile: &profile,
        casters,
        orders,
        pool,
    };
    let tree = builder.build(tree_options);
    stats.sort_time = t.elapsed();
    tree_figures(&mut stats, &tree);
    let t = Instant::now();
    let keep = refraction == Refraction::Exact;
    // `setmode o`: the tree file in the scene's order and blending.
    let file_how = (scene.modes.output_tree).then_some((scene.sort_order, scene.modes.blend));
    let (picture, sources, file, tree) = records(
        &materials, file_how, view, tree, options, method, keep, pool,
    );
    stats.shading_time = t.elapsed();
    profile.add(crate::profile::Category::Shading, t.elapsed());
    stats.polygons_listed = picture.records.len();
    stats.method = Some(method);
    let exact = tree.as_ref().and_then(|tree| {
        exact_layer(
            scene,
            view,
            tree,
            &scan,
            options,
            file.is_some(),
            &mut stats,
        )
    });
    stats.raytrace = exact.as_ref().map(|l| l.stats);
    // The tree file holds the branches the picture has.
    let file = match (file, &exact, &tree) {
        (Some(file), Some(layer), Some(tree)) => Some(
            with_traced_branches(scene, view, tree, layer, file, options).unwrap_or_else(|| {
                stats.warnings.push(linear_file_warning(options));
                let how = file_how.expect("a tree file");
                builder.linear_file(tree_options, how, &mut stats)
            }),
        ),
        (file, _, _) => file,
    };
    Prepared {
        picture,
        sources,
        file,
        scan,
        exact,
        profile: options.profile.then_some(profile),
        stats,
    }
}

/// The tree's own figures, into the render's.
fn tree_figures(stats: &mut RenderStats, tree: &VirtualImageTree) {
    stats.geometry = tree.geometry;
    stats.max_depth = tree.max_depth;
    stats.nns = tree.nns;
    stats.pruned = tree.pruned;
    stats.warnings = tree.warnings.clone();
}

/// What building a virtual image tree takes beside its options.
struct Builder<'a> {
    materials: &'a Materials<'a>,
    view: &'a View,
    profile: &'a crate::profile::Profile,
    casters: &'a crate::image_tree::CasterReuse,
    orders: &'a crate::visibility::nns::PriorOrder,
    pool: &'a Pool,
}

impl Builder<'_> {
    /// The tree of `options`, built on the run's pool.
    fn build(&self, options: TreeOptions) -> VirtualImageTree {
        self.pool.install(|| {
            crate::image_tree::build_profiled(
                self.materials,
                self.view,
                options,
                self.profile,
                self.casters,
                self.orders,
            )
        })
    }

    /// The tree file with the linear maps' refracted branches, when the
    /// traced ones do not fit: the tree built again, linearized, and
    /// emitted in the file's `(order, blended)`.
    fn linear_file(
        &self,
        options: TreeOptions,
        (order, blended): (SortOrder, bool),
        stats: &mut RenderStats,
    ) -> RecordStream {
        let linear = TreeOptions {
            refraction: Refraction::Linearized,
            ..options
        };
        let tree = self.build(linear);
        stats.warnings.extend(tree.warnings.iter().cloned());
        let how = Emit {
            order,
            blended,
            width: self.view.width as u32,
            height: self.view.height as u32,
        };
        self.pool
            .install(|| emit::records(self.materials, &tree, how, self.view).0)
    }
}

/// The picture's records and their sources, the tree file's records
/// (`setmode o`: `file_how`, its order and blending), and the tree itself
/// when `keep` (exact refraction).
#[allow(clippy::too_many_arguments)]
fn records(
    materials: &Materials<'_>,
    file_how: Option<(SortOrder, bool)>,
    view: &View,
    tree: VirtualImageTree,
    options: &RenderOptions,
    method: Method,
    keep: bool,
    pool: &Pool,
) -> (
    RecordStream,
    Vec<Source>,
    Option<RecordStream>,
    Option<VirtualImageTree>,
) {
    let emit = |order, blended| Emit {
        order,
        blended,
        width: view.width as u32,
        height: view.height as u32,
    };
    // Donovan's transparency rule (000 section 6, rule (3)) blends a
    // surface with the colour behind it, so his picture is painted back to
    // front, pre-blended (the overwriting principle of 004 section 4.10),
    // by every method (see [`crate::raster::scan`]).
    let picture_how = match options.shading {
        ShadingModel::Donovan => emit(SortOrder::BackToFront, true),
        ShadingModel::Garcia => emit(SortOrder::FrontToBack, wants_pre_blending(method)),
    };
    let file = file_how.map(|(order, blended)| {
        let how = emit(order, blended);
        pool.install(|| emit::records(materials, &tree, how, view).0)
    });
    // The tree is kept past its records only for exact refraction.
    if keep {
        let (p, s) = pool.install(|| emit::records(materials, &tree, picture_how, view));
        (p, s, file, Some(tree))
    } else {
        let (p, s) = pool.install(|| emit::records_freeing(materials, tree, picture_how, view));
        (p, s, file, None)
    }
}

/// How the picture is scan converted.
fn scan_options(view: &View, options: &RenderOptions, method: Method) -> ScanOptions {
    ScanOptions {
        width: view.width as u32,
        height: view.height as u32,
        method,
        act_lines: 16,
        paint_background: true,
        transparency: match options.shading {
            ShadingModel::Garcia => scan::TransparencyRule::Garcia,
            ShadingModel::Donovan => scan::TransparencyRule::Donovan,
        },
        threads: options.threads,
        ids: true,
        max_overdraw: options.budgets.overdraw,
    }
}

/// Exact refraction: the refracted branches ray traced before the
/// picture's scan conversion (a failure leaves them out, with a warning);
/// their colours are kept for a tree file (`for_file`).
fn exact_layer(
    scene: &Scene,
    view: &View,
    tree: &VirtualImageTree,
    scan: &ScanOptions,
    options: &RenderOptions,
    for_file: bool,
    stats: &mut RenderStats,
) -> Option<ExactLayer> {
    let how = crate::raytrace::exact::LayerOptions {
        shadows: options.shadows,
        shading: options.shading,
        max_rays: options.budgets.rays,
        keep_traced: for_file,
    };
    let made = crate::raytrace::exact::layer(scene, view, tree, scan, how);
    made.unwrap_or_else(|e| {
        stats
            .warnings
            .push(format!("exact refraction left out: {e}"));
        None
    })
}

/// The tree file `file` with the ray-traced branches of `layer` as
/// records, while they fit the tree's budget (`--max-tree-nodes`) beside
/// the tree's own fragments.
fn with_traced_branches(
    scene: &Scene,
    view: &View,
    tree: &VirtualImageTree,
    layer: &ExactLayer,
    file: RecordStream,
    options: &RenderOptions,
) -> Option<RecordStream> {
    let budget = options.budgets.tree_nodes.saturating_sub(tree.nodes.len());
    crate::raytrace::branch_records::with_traced_branches(scene, view, tree, layer, file, budget)
}

/// What a tree file says when its refracted branches are the linear
/// maps' while the picture ray traces them.
fn linear_file_warning(options: &RenderOptions) -> String {
    format!(
        "the tree file's refracted branches are the linearized matrix's (004 section 6.4.3), \
         not the picture's exact ones: written as records, one a pixel, they would pass the \
         budget of {} tree fragments (--max-tree-nodes raises it)",
        options.budgets.tree_nodes
    )
}

/// The refraction model for `scene` (resolving `auto`: exact when the
/// linearized matrix is off by more than a pixel through a transmitting
/// polygon, [`crate::raytrace::exact::linear_error`]) and, when
/// the scene refracts, the model in words for the statistics. Whether a
/// polygon transmits is read from the scene's resolved `materials`.
pub fn refraction_model(
    scene: &Scene,
    materials: &Materials<'_>,
    view: &View,
    asked: crate::image_tree::Refraction,
) -> (crate::image_tree::Refraction, Option<String>) {
    use crate::image_tree::Refraction;
    let refracts = scene.modes.max_level > 1
        && materials
            .objects
            .iter()
            .zip(&materials.resolved)
            .any(|(o, r)| {
                !o.surface_type.hidden
                    && (0..o.polygons.len()).any(|p| r.material(p).transmittance > 0.0)
            });
    if !refracts {
        return (asked, None);
    }
    let name = |r: Refraction| format!("{r:?}").to_lowercase();
    if asked != Refraction::Auto {
        return (asked, Some(format!("{} (--refraction)", name(asked))));
    }
    let error = crate::raytrace::exact::linear_error(scene, view);
    let chosen = if error > 1.0 {
        Refraction::Exact
    } else {
        Refraction::Linearized
    };
    let said = format!(
        "{} (the linearized matrix is off by up to {error:.1} pixels through the transmitting \
         polygons; exact above 1)",
        name(chosen)
    );
    (chosen, Some(said))
}

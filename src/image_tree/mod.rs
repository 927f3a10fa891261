//! The recursive visible-surface processor and the virtual image tree
//! (Garcia 1986, 004 chapter 3, figure 3.3, and sections 4.4-4.6, 4.10).
//!
//! Level 1 holds the polygons visible in the viewing volume, sorted back to
//! front. For each reflective (refractive) polygon whose accumulated
//! coefficient stays above `threshold`, and while the level is below
//! `depth`, the whole scene is mapped by the reflection (refraction) matrix
//! of the polygon's plane (004 section 4.6) and clipped to a new clipping
//! volume: the pyramid from the eye through the polygon's outline, beyond
//! its plane, inside the viewing volume (004 section 4.5, figure 4.6: in
//! screen space, the polygon extruded along z). The fragments found there
//! form the polygon's sub-tree, recursively.
//!
//! Coordinates: the clipping is done in "virtual" world coordinates, where
//! the points of a level are the world points mapped by the product `T` of
//! the matrices above it and are seen by the real eye through the real
//! projection (`CTM_n = M_r(n-1) ... M_r(1) M_v M_p`, 004 section 4.6).
//! Shading is done in true world space (004 section 4.8): the eye is
//! mapped back by `T^-1`.
//!
//! Output orders (004 section 4.10): back to front, every polygon is
//! followed by its reflected sub-tree, then (after a restore copy of the
//! polygon, when both exist) its refracted sub-tree: for a cube on a
//! mirror, `P11, P21, P22, P23, P12, P13, P14`. Front to back, sub-trees
//! come before their polygon: `P12, P13, P14, P21, P22, P23, P11`; shadow
//! polygons come between the sub-trees and their target (004 section 5.9:
//! `P12, P13, P14, P21, P22, P23, S1, S2, S3, P11`).
//! Pre-blended shades (`setmode b on`, and always for painting) are
//! `I_child = I_parent + k I_child_own`, `k` the product of the
//! coefficients on the path.
//!
//! Preconditions: planar polygons (the scene model's). The simple sort (or
//! NNS with `setmode n on`) orders each level; the simple sort's key is
//! the scene's `sort` order's (004 section 4.4): the farthest vertex for
//! `sort btf`, the nearest for `sort ftb` (a level is stored back to front
//! either way). Refraction uses the matrix
//! linearized about the ray through the polygon's centre (004 section
//! 6.4.3), or none on total internal reflection.

mod fragments;

use glam::{DVec3, DVec4};

use crate::budget::Budgets;
use crate::geometry::plane_clip::{self, ClipScratch, Clipped};
use crate::geometry::polygon;
use crate::geometry::view::{self, GeometryStats, View};
use crate::math::{self, Matrix4};
use crate::model::{Color, SortOrder};
use crate::profile::{Category, Profile};
use crate::shading::{FacetTerms, Materials, ShadingModel};
pub use crate::shadow::CasterReuse;
pub use crate::shadow::overlap::{ShadowRegion, overlap_regions};
use crate::visibility::occlusion::{self, CoverMask, Outline};
use crate::visibility::{depth_sort, nns};
pub use fragments::Fragments;
use rayon::prelude::*;

/// What a fragment of the tree is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FragmentKind {
    /// A polygon (at level 1) or a fragment mapped onto its parent.
    Polygon,
    /// The specially tagged copy of a polygon between its reflected and
    /// refracted branches (004 section 4.10).
    Restore,
    /// A shadow cast on its parent from the Point light of this index
    /// (004 section 4.7).
    Shadow {
        /// Index into `Scene::lights`.
        light: u32,
    },
}

/// How a sub-tree was mapped onto its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Branch {
    /// Level 1: seen directly.
    Direct,
    /// Seen by reflection in the parent.
    Reflected,
    /// Seen by refraction through the parent.
    Refracted,
    /// A shadow polygon on the parent.
    Shadow,
}

/// A node of the virtual image tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragment {
    /// Level in the tree, 1 at the top.
    pub level: u32,
    /// What it is.
    pub kind: FragmentKind,
    /// How it is seen.
    pub branch: Branch,
    /// Index of the object in `Scene::objects`.
    pub object: u32,
    /// Index of the polygon in the object's `polygons`.
    pub polygon: u32,
    /// Points in the virtual coordinates of its level; its screen points
    /// are their projections ([`Fragment::screen`]), made when needed.
    pub virtual_points: Box<[DVec3]>,
    /// Whether the viewer sees the polygon's back (`type open`).
    pub back_facing: bool,
    /// Its own shade (ambient, diffuse, specular).
    pub shade: Color,
    /// Its shade pre-blended with its ancestors' (`I_parent + k I_own`).
    pub blended: Color,
    /// `k`: the product of the coefficients above it (1 at level 1).
    pub weight: f64,
    /// Index of the parent fragment in [`VirtualImageTree::nodes`], or
    /// [`NO_PARENT`] ([`Fragment::parent`] reads it): 4 bytes where an
    /// `Option<usize>` took 16, for the tens of millions of fragments of
    /// a big mesh's tree.
    parent: u32,
    /// Index of its level's space in [`VirtualImageTree::spaces`]: its
    /// true world points ([`VirtualImageTree::world`]) and the eye that
    /// sees it ([`VirtualImageTree::eye`]).
    pub space: u32,
    /// A shadow polygon's lights ([`Fragment::shadowed_from`]), any other
    /// fragment's children ([`Fragment::children`]): a shadow polygon has
    /// no children and no other fragment is shadowed, so one list serves
    /// both.
    links: Box<[u32]>,
}

/// [`Fragment::parent`] of a fragment with none (level 1).
const NO_PARENT: u32 = u32::MAX;

/// Fragment index `id` as a link (parent or child): below [`NO_PARENT`].
/// A tree of 2^32 fragments would take over 500 GB, so none is that big.
fn link(id: usize) -> u32 {
    u32::try_from(id)
        .ok()
        .filter(|&v| v != NO_PARENT)
        .expect("fewer than 2^32 - 1 fragments")
}

impl Fragment {
    /// Index of the parent fragment in [`VirtualImageTree::nodes`];
    /// `None` at level 1.
    pub fn parent(&self) -> Option<usize> {
        (self.parent != NO_PARENT).then_some(self.parent as usize)
    }

    /// Children (indices in [`VirtualImageTree::nodes`]) in back-to-front
    /// order: shadow polygons, the reflected branch, then the refracted.
    pub fn children(&self) -> impl DoubleEndedIterator<Item = usize> + ExactSizeIterator + '_ {
        let kids: &[u32] = if self.is_shadow() { &[] } else { &self.links };
        kids.iter().map(|&c| c as usize)
    }

    /// For shadow polygons, every light (indices into `Scene::lights`,
    /// increasing) the region is shadowed from; the first is the one in
    /// [`FragmentKind::Shadow`]. Empty for other fragments.
    pub fn shadowed_from(&self) -> &[u32] {
        if self.is_shadow() { &self.links } else { &[] }
    }

    /// Whether it is a shadow polygon.
    fn is_shadow(&self) -> bool {
        matches!(self.kind, FragmentKind::Shadow { .. })
    }

    /// Appends `ids` to its children (not for a shadow polygon).
    fn add_children(&mut self, ids: impl IntoIterator<Item = usize>) {
        debug_assert!(!self.is_shadow(), "a shadow polygon has no children");
        let mut kids = std::mem::take(&mut self.links).into_vec();
        kids.extend(ids.into_iter().map(link));
        self.links = kids.into_boxed_slice();
    }

    /// Its screen points (x, y in pixels, y up; z normalized depth): the
    /// projections of its virtual points by the real eye.
    pub fn screen(&self, view: &View) -> Vec<DVec3> {
        self.virtual_points
            .iter()
            .map(|p| view.project(*p))
            .collect()
    }
}

/// The virtual coordinates of one traced level (004 section 4.6): how
/// its points map back to true world space, where shading is done (004
/// section 4.8). The fragments of a level share it, so they do not each
/// carry their world points and eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VirtualSpace {
    /// `T^-1`, the inverse of the product of the level's matrices; `None`
    /// at level 1 (the identity) or where `T` is singular.
    pub inverse: Option<Matrix4>,
    /// The eye in true world coordinates, as the level sees it.
    pub eye: DVec4,
}

/// The virtual image tree of a view.
#[derive(Debug, Clone, Default)]
pub struct VirtualImageTree {
    /// All fragments; `roots` and `children` index this.
    pub nodes: Fragments,
    /// The levels' spaces; [`Fragment::space`] indexes this.
    pub spaces: Vec<VirtualSpace>,
    /// Level-1 fragments, back to front.
    pub roots: Vec<usize>,
    /// Deepest level reached.
    pub max_depth: u32,
    /// Geometry counters of level 1.
    pub geometry: GeometryStats,
    /// NNS counters summed over every level sorted, when NNS sorted;
    /// `fallbacks` counts the levels that ran out of the split budget and
    /// were ordered by the simple depth sort.
    pub nns: Option<crate::visibility::nns::NnsStats>,
    /// Warnings for the user: budgets that ran out and what was done
    /// instead (one line per kind).
    pub warnings: Vec<String>,
    /// Branches (reflected or refracted sub-trees) left out because the
    /// tree reached its node budget ([`Budgets::tree_nodes`]): the
    /// lightest ones, after the `threshold` cut.
    pub pruned: usize,
    /// Polygons left out as hidden, at every level
    /// ([`TreeOptions::cull_samples`]).
    pub hidden: usize,
}

impl VirtualImageTree {
    /// Fragment `f`'s points in true world coordinates (its virtual
    /// points mapped back by `T^-1`).
    pub fn world(&self, f: &Fragment) -> Vec<DVec3> {
        match self.spaces[f.space as usize].inverse {
            Some(i) => f
                .virtual_points
                .iter()
                .map(|p| i.transform_point(*p))
                .collect(),
            None => f.virtual_points.to_vec(),
        }
    }

    /// The eye in true world coordinates, as fragment `f` sees it.
    pub fn eye(&self, f: &Fragment) -> DVec4 {
        self.spaces[f.space as usize].eye
    }

    /// The fragments in output order (004 section 4.10).
    pub fn output_order(&self, order: SortOrder) -> Vec<usize> {
        let mut out = Vec::with_capacity(self.nodes.len());
        match order {
            SortOrder::BackToFront => {
                for &r in &self.roots {
                    self.back_to_front(r, &mut out);
                }
            }
            SortOrder::FrontToBack => {
                for &r in self.roots.iter().rev() {
                    self.front_to_back(r, &mut out);
                }
            }
        }
        out
    }

    /// Back to front (004 section 4.10): the polygon, its shadow polygons
    /// (fewest lights first, so the painter leaves the most shadowed overlap
    /// regions on top), then its reflected and refracted sub-trees.
    fn back_to_front(&self, n: usize, out: &mut Vec<usize>) {
        out.push(n);
        for c in self.nodes[n].children() {
            self.back_to_front(c, out);
        }
    }

    /// Front to back (004 section 5.9, figure 5.14): the reflected and
    /// refracted sub-trees (and the restore copy between them) first, each
    /// run of a level list reversed, then the polygon's shadow polygons
    /// (reversed: the most shadowed overlap regions first), then the
    /// polygon: `P12, P13, P14, P21, P22, P23, S1, S2, S3, P11`.
    fn front_to_back(&self, n: usize, out: &mut Vec<usize>) {
        let (shadows, branches): (Vec<usize>, Vec<usize>) = self.nodes[n]
            .children()
            .partition(|&c| self.nodes[c].branch == Branch::Shadow);
        for run in self.branch_runs(&branches) {
            for &c in run.iter().rev() {
                self.front_to_back(c, out);
            }
        }
        out.extend(shadows.iter().rev());
        out.push(n);
    }

    /// Children split into runs per branch, each back to front; a restore
    /// copy starts a new run.
    fn branch_runs(&self, kids: &[usize]) -> Vec<Vec<usize>> {
        let mut runs: Vec<Vec<usize>> = Vec::new();
        for &c in kids {
            let start_new = runs.last().is_none_or(|r: &Vec<usize>| {
                self.nodes[*r.last().expect("runs are not empty")].branch != self.nodes[c].branch
                    || self.nodes[c].kind == FragmentKind::Restore
            });
            if start_new {
                runs.push(Vec::new());
            }
            runs.last_mut().expect("pushed").push(c);
        }
        runs
    }
}

/// The refraction matrix used for refractive polygons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Refraction {
    /// The renderer's choice (`render::prepare`): exact when the
    /// linearized matrix is off by more than a pixel through a
    /// transmitting polygon (at its corners or at the refracted objects'
    /// vertices, `raytrace::exact::linear_error`), else linearized. The tree builder itself treats
    /// it as linearized.
    #[default]
    Auto,
    /// `M_t` linearized exactly about the ray through the polygon's centre
    /// (the improvement of 004 section 6.4.3).
    Linearized,
    /// No refracted branches in the tree: they are ray traced per pixel
    /// and composited after scan conversion (`raytrace::exact`, the hybrid
    /// of 004 section 6.4).
    Exact,
    /// `M_to`, exact for rays parallel to the line of sight (004 section
    /// 4.6; exact under an orthographic projection).
    Orthographic,
    /// The paraxial approximation `M_tp = I + (eta - 1) L N`.
    Paraxial,
}

impl std::str::FromStr for Refraction {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "linearized" | "linearised" => Ok(Refraction::Linearized),
            "orthographic" => Ok(Refraction::Orthographic),
            "paraxial" => Ok(Refraction::Paraxial),
            "exact" => Ok(Refraction::Exact),
            "auto" => Ok(Refraction::Auto),
            _ => Err(format!(
                "unknown refraction model `{s}`; expected linearized, orthographic, paraxial, \
                 exact or auto"
            )),
        }
    }
}

/// Options of the tree builder.
#[derive(Debug, Clone, Copy)]
pub struct TreeOptions {
    /// Deepest level (`depth`, 1-14).
    pub max_level: u32,
    /// Smallest coefficient worth tracing (`threshold`).
    pub threshold: f64,
    /// Use the NNS sorter at every level.
    pub nns: bool,
    /// Cast shadows from Point lights (`run y`).
    pub shadows: bool,
    /// Which refraction matrix (004 sections 4.6 and 6.4.3).
    pub refraction: Refraction,
    /// `setmode h on`: shade every shadow polygon at its own centroid;
    /// off: all shadows of one light on one target share the target's
    /// shade without that light (004 section 4.7).
    pub explicit_shadow_shades: bool,
    /// The illumination model of the fragments' shades (Garcia's, 004
    /// section 4.8, by default; or Donovan's, 000 section 6).
    pub shading: ShadingModel,
    /// The limits: tree fragments ([`Budgets::tree_nodes`]) and NNS splits
    /// per level ([`Budgets::splits`]).
    pub budgets: Budgets,
    /// With `Some(n)`, leave out the polygons of each level whose every
    /// sample of the image's `n x n` grid per pixel is covered by opaque
    /// polygons of that level later in its order
    /// ([`crate::visibility::occlusion`]): right for a
    /// picture made from those samples only, not for exact areas, tree
    /// files or vector output, where what lies behind shows through the
    /// seams of a mesh.
    pub cull_samples: Option<u32>,
}

impl Default for TreeOptions {
    /// One level, no threshold, the simple sort, no shadows, the
    /// linearized refraction matrix, shared shadow shades, Garcia's model,
    /// the default budgets.
    fn default() -> TreeOptions {
        TreeOptions {
            max_level: 1,
            threshold: 0.0,
            nns: false,
            shadows: false,
            refraction: Refraction::default(),
            explicit_shadow_shades: false,
            shading: ShadingModel::default(),
            budgets: Budgets::default(),
            cull_samples: None,
        }
    }
}

struct Builder<'a> {
    profile: &'a Profile,
    /// Every polygon in world coordinates, for shadow casting at any level
    /// (with shadows on: built, or found unchanged from the last frame,
    /// while level 1 is found).
    casters: Option<std::sync::Arc<crate::shadow::CasterIndex>>,
    materials: &'a Materials<'a>,
    view: &'a View,
    options: TreeOptions,
    eps: f64,
    frustum: Vec<DVec4>,
    tree: VirtualImageTree,
    /// Branches found and not yet traced.
    pending: std::collections::BinaryHeap<Pending>,
    next_seq: usize,
    /// Nodes kept for restore copies still to be made.
    reserved: usize,
    /// Splits made by the first NNS sort that fell back.
    first_fallback_splits: usize,
    /// Whether the scene has fewer than [`PARALLEL_LEVEL_POLYGONS`]
    /// polygons: its levels are small, mapped on one thread and found
    /// several at once.
    small_scene: bool,
}

/// A branch waiting to be traced: the scene seen by reflection in (or
/// refraction through) fragment `parent`.
struct Pending {
    /// The product of the coefficients down to the branch.
    weight: f64,
    /// Order found, to break ties deterministically.
    seq: usize,
    parent: usize,
    branch: Branch,
    level: u32,
    /// The mapping of the branch's level.
    t: Matrix4,
    /// The parent's plane, towards the eye.
    plane: DVec4,
    /// The parent's pre-blended shade.
    blend: Color,
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for Pending {}

impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Pending {
    /// Heaviest first; among equals, the first found.
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.weight
            .total_cmp(&other.weight)
            .then(other.seq.cmp(&self.seq))
    }
}

/// A polygon found at some level, before sorting.
struct Candidate {
    object: u32,
    polygon: u32,
    points: Vec<DVec3>,
    back_facing: bool,
}

/// Builds the virtual image tree of a scene, its polygons and
/// `materials` resolved, seen through `view`.
pub fn build(materials: &Materials<'_>, view: &View, options: TreeOptions) -> VirtualImageTree {
    build_profiled(
        materials,
        view,
        options,
        &Profile::new(false),
        &CasterReuse::default(),
    )
}

/// [`build`], timing its parts into `profile` (table 6.2), with the
/// shadow casters (and the shadows on their polygons) of the previous
/// frame in `casters`, used again if the world has not changed.
pub fn build_profiled(
    materials: &Materials<'_>,
    view: &View,
    options: TreeOptions,
    profile: &Profile,
    casters: &CasterReuse,
) -> VirtualImageTree {
    let p = &view.projection;
    let (c0, c1, c2, c3) = (p.column(0), p.column(1), p.column(2), p.column(3));
    let frustum = [c3 + c0, c3 - c0, c3 + c1, c3 - c1, c3 + c2, c3 - c2]
        .into_iter()
        .filter_map(|pl| {
            let len = pl.truncate().length();
            (len > 0.0).then(|| pl / len)
        })
        .collect();
    let mut b = Builder {
        profile,
        casters: None,
        materials,
        view,
        options,
        eps: materials.eps,
        frustum,
        tree: VirtualImageTree {
            max_depth: 1,
            ..VirtualImageTree::default()
        },
        pending: std::collections::BinaryHeap::new(),
        next_seq: 0,
        reserved: 0,
        first_fallback_splits: 0,
        small_scene: materials
            .objects
            .iter()
            .map(|o| o.polygons.len())
            .sum::<usize>()
            < PARALLEL_LEVEL_POLYGONS,
    };
    // The casters' index does not depend on the view: it is built (or
    // found unchanged) while this thread finds level 1.
    let (level1, casters) = rayon::join(
        || b.level_one(),
        || {
            options.shadows.then(|| {
                let _t = profile.time(Category::Transform);
                casters.index(materials.objects, materials.lights, materials.eps)
            })
        },
    );
    b.casters = casters;
    let mut sorted = b.sort(level1);
    if let Some(n) = b.options.cull_samples {
        let hidden;
        (sorted, hidden) = b.unhidden(sorted, n);
        b.tree.hidden += hidden;
    }
    let roots = b
        .trace(
            1,
            sorted,
            None,
            &Matrix4::IDENTITY,
            Branch::Direct,
            1.0,
            Color::ZERO,
            None,
            0,
        )
        .expect("level 1 is not budgeted here");
    b.tree.roots = roots;
    b.expand();
    if let Some(n) = b.tree.nns
        && n.fallbacks > 0
    {
        b.tree
            .warnings
            .push(nns::fallback_warning(b.first_fallback_splits, n.fallbacks));
    }
    b.tree
}

impl<'a> Builder<'a> {
    /// Level 1: the geometry stage's polygons (homogeneous clipping).
    fn level_one(&mut self) -> Vec<Candidate> {
        let _t = self.profile.time(Category::Expobj);
        let lists =
            view::expand_objects(self.materials.objects, self.view, &mut self.tree.geometry);
        // Exactly as many as there are: a mesh's level 1 is millions.
        let mut level = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        level.extend(lists.into_iter().flatten().map(|p| Candidate {
            object: p.object,
            polygon: p.polygon,
            points: p.world,
            back_facing: p.back_facing,
        }));
        level
    }

    /// Lower levels: the scene mapped by `t`, clipped to `planes` (front
    /// sides kept) with the splitter. `planes[0]` is the plane of the
    /// fragment seen through.
    fn mapped_level(&self, t: &Matrix4, planes: &[DVec4]) -> Vec<Candidate> {
        let _t = self.profile.time(Category::Addobj);
        let mirrored = t.linear_determinant() < 0.0;
        let objects = self.materials.objects;
        let one = |clip: &mut ClipBuffers, (oi, object): (usize, &crate::model::Object)| {
            self.mapped_object(oi as u32, object, t, planes, mirrored, clip)
        };
        // A small scene's level is mapped on this thread: handing a few
        // hundred polygons to others costs more than it saves.
        if self.small_scene {
            let mut clip = ClipBuffers::default();
            return objects
                .iter()
                .enumerate()
                .flat_map(|o| one(&mut clip, o))
                .collect();
        }
        // Objects in parallel, appended in order: the thread count
        // changes nothing.
        let per_object: Vec<Vec<Candidate>> = objects
            .par_iter()
            .enumerate()
            .map_init(ClipBuffers::default, one)
            .collect();
        per_object.into_iter().flatten().collect()
    }

    /// The fragments of `object` (number `oi`) in the level mapped by `t`
    /// and clipped to `planes` (in `clip`'s reused buffers: most polygons
    /// come out whole or empty); `mirrored` when `t` is a reflection.
    fn mapped_object(
        &self,
        oi: u32,
        object: &crate::model::Object,
        t: &Matrix4,
        planes: &[DVec4],
        mirrored: bool,
        clip: &mut ClipBuffers,
    ) -> Vec<Candidate> {
        let mut out = Vec::new();
        if object.surface_type.hidden {
            return out;
        }
        let outside = {
            let _t = self.profile.time(Category::ChkBbox);
            let corners: Vec<DVec3> = object
                .bbox_corners
                .iter()
                .map(|c| t.transform_point(*c))
                .collect();
            planes.iter().any(|pl| {
                corners
                    .iter()
                    .all(|c| pl.truncate().dot(*c) + pl.w < -self.eps)
            })
        };
        if outside {
            return out;
        }
        let verts: Vec<DVec3> = {
            let _t = self.profile.time(Category::Transform);
            object
                .vertices
                .iter()
                .map(|v| t.transform_point(*v))
                .collect()
        };
        // Polygons in the mirror's (or refracting surface's) own plane,
        // itself included, map onto it: they are not seen through it.
        let front_plane = planes[0];
        let on_front =
            |p: &DVec3| (front_plane.truncate().dot(*p) + front_plane.w).abs() <= self.eps;
        for (pi, poly) in object.polygons.iter().enumerate() {
            let mut pts: Vec<DVec3> = poly.indices.iter().map(|&i| verts[i as usize]).collect();
            if mirrored {
                pts.reverse();
            }
            let Ok(plane) = polygon::outward_plane(&pts) else {
                continue;
            };
            if pts.iter().all(on_front) {
                continue;
            }
            let front = self.view.faces_eye(plane);
            if !front && !object.surface_type.open {
                continue;
            }
            let clipped = {
                let _t = self.profile.time(Category::Clipping);
                plane_clip::clip_to_planes(&pts, planes, self.eps, &mut clip.one, &mut clip.many)
            };
            let candidate = |points| Candidate {
                object: oi,
                polygon: pi as u32,
                points,
                back_facing: !front,
            };
            match clipped {
                Ok(Clipped::One) => out.push(candidate(clip.one.piece().to_vec())),
                Ok(Clipped::Many) => out.extend(clip.many.drain(..).map(candidate)),
                Ok(Clipped::Empty) | Err(_) => {}
            }
        }
        out
    }

    /// Orders a level's candidates back to front, and counts the sort.
    fn sort(&mut self, candidates: Vec<Candidate>) -> Vec<Candidate> {
        let (sorted, stats) = self.sorted(candidates);
        self.count_sort(stats);
        sorted
    }

    /// Adds an NNS sort's counts to the tree's.
    fn count_sort(&mut self, stats: Option<nns::NnsStats>) {
        let Some(stats) = stats else {
            return;
        };
        let total = self.tree.nns.get_or_insert_with(Default::default);
        total.faces_in += stats.faces_in;
        total.faces_out += stats.faces_out;
        total.splits += stats.splits;
        total.cycles_of_two += stats.cycles_of_two;
        total.longer_cycles += stats.longer_cycles;
        total.exact_tests += stats.exact_tests;
        total.unresolved += stats.unresolved;
        total.work += stats.work;
        if stats.fallbacks > 0 && total.fallbacks == 0 {
            self.first_fallback_splits = stats.splits;
        }
        total.fallbacks += stats.fallbacks;
    }

    /// A level's candidates back to front, with the NNS sort's counts
    /// (`None` under the depth sort).
    fn sorted(&self, candidates: Vec<Candidate>) -> (Vec<Candidate>, Option<nns::NnsStats>) {
        let _t = self.profile.time(Category::Sortply);
        if self.options.nns {
            // Which source polygons are seen from behind (`type open`);
            // none in a closed scene, where back faces are culled.
            let back: std::collections::HashMap<(u32, u32), bool> = candidates
                .iter()
                .filter(|c| c.back_facing)
                .map(|c| ((c.object, c.polygon), true))
                .collect();
            let mut faces: Vec<nns::NnsFace> = Vec::with_capacity(candidates.len());
            for c in candidates {
                let (object, polygon) = (c.object, c.polygon);
                if polygon::is_convex(&c.points) {
                    faces.push(nns::NnsFace {
                        object,
                        polygon,
                        world: c.points,
                    });
                } else {
                    faces.extend(polygon::triangulate(&c.points).into_iter().map(|t| {
                        nns::NnsFace {
                            object,
                            polygon,
                            world: t.to_vec(),
                        }
                    }));
                }
            }
            let (sorted, stats) =
                nns::sort_budgeted(faces, self.view, self.eps, self.options.budgets.splits);
            let sorted = sorted
                .into_iter()
                .map(|f| Candidate {
                    back_facing: back.contains_key(&(f.object, f.polygon)),
                    object: f.object,
                    polygon: f.polygon,
                    points: f.world,
                })
                .collect();
            return (sorted, Some(stats));
        }
        // 004 section 4.4: "the sorting order is simply determined by
        // either the minimum or maximum vertex Z-coordinate of the polygon,
        // depending on the sorting order (i.e., front-to-back or
        // back-to-front)": `sort btf` paints by the farthest vertex, far
        // first; `sort ftb` takes the nearest vertex, near first. The two
        // orders are different sorts, not one reversed. The level list is
        // kept back to front, so an ftb sort is stored reversed (and
        // emitted front to back, its own order, again).
        let order = self.materials.sort_order;
        let keys: Vec<f64> = candidates
            .iter()
            .map(|c| {
                let range = c
                    .points
                    .iter()
                    .map(|p| self.view.project(*p).z)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
                        (lo.min(z), hi.max(z))
                    });
                depth_sort::sort_key(range, order)
            })
            .collect();
        let mut slots: Vec<Option<Candidate>> = candidates.into_iter().map(Some).collect();
        let stored = |mut v: Vec<Candidate>| {
            if order == SortOrder::FrontToBack {
                v.reverse();
            }
            v
        };
        if self.materials.expand {
            // `setmode x on`: one composite list.
            let sorted = depth_sort::sorted_order(&keys)
                .into_iter()
                .map(|k| slots[k].take().expect("a permutation"))
                .collect();
            return (stored(sorted), None);
        }
        // `setmode x off` (004 section 4.4): objects one at a time, by the
        // farthest (btf) or nearest (ftb) depth of their polygons, each
        // object's polygons sorted. Grouped by object in one sort (stable:
        // each object's polygons keep their order), objects in increasing
        // index.
        let object = |k: usize| slots[k].as_ref().expect("full").object;
        let mut by_object: Vec<usize> = (0..slots.len()).collect();
        by_object.sort_by_key(|&k| object(k));
        let groups: Vec<&[usize]> = by_object
            .chunk_by(|&a, &b| object(a) == object(b))
            .collect();
        let object_keys: Vec<f64> = groups
            .iter()
            .map(|g| g.iter().map(|&k| keys[k]).fold(f64::INFINITY, f64::min))
            .collect();
        let mut out = Vec::with_capacity(slots.len());
        for gi in depth_sort::sorted_order(&object_keys) {
            let members = groups[gi];
            let member_keys: Vec<f64> = members.iter().map(|&k| keys[k]).collect();
            for m in depth_sort::sorted_order(&member_keys) {
                out.push(slots[members[m]].take().expect("each once"));
            }
        }
        (stored(out), None)
    }

    /// Adds `sorted` (the polygons of one level back to front, in virtual
    /// coordinates under `t`) as fragments and traces their sub-trees.
    /// Returns the new fragments' indices, back to front. `found` is what
    /// the first chunk needs, when it was found ahead.
    ///
    /// The shadow regions of the fragments are found in parallel a chunk
    /// at a time, the next chunk's while this thread adds the current
    /// one's fragments to the tree, in order (so the tree does not depend
    /// on the threads).
    #[allow(clippy::too_many_arguments)]
    fn trace(
        &mut self,
        level: u32,
        sorted: Vec<Candidate>,
        found: Option<PreparedChunk<'a>>,
        t: &Matrix4,
        branch: Branch,
        weight: f64,
        parent_blend: Color,
        parent: Option<usize>,
        reserve: usize,
    ) -> Option<Vec<usize>> {
        // Below level 1 the node budget is checked before anything is
        // added; `reserve` more nodes (a restore copy) must fit as well.
        if level > 1
            && self.tree.nodes.len() + self.reserved + sorted.len() + reserve
                > self.options.budgets.tree_nodes
        {
            return None;
        }
        self.tree.max_depth = self.tree.max_depth.max(level);
        let work = self.chunk_work(t);
        self.tree.spaces.push(VirtualSpace {
            inverse: t.inverse(),
            eye: work.eye,
        });
        let mut at = LevelState {
            level,
            t,
            branch,
            weight,
            parent_blend,
            parent,
            space: (self.tree.spaces.len() - 1) as u32,
            ids: Vec::new(),
        };
        let prepare = |chunk: Option<&[Candidate]>| {
            chunk.map_or_else(PreparedChunk::default, |chunk| work.prepare(chunk))
        };
        let mut chunks = into_chunks(sorted);
        let mut ready = match found {
            Some(found) => found,
            None => prepare(chunks.last().map(Vec::as_slice)),
        };
        while let Some(chunk) = chunks.pop() {
            let mut now = std::mem::take(&mut ready);
            // A full tree takes no more shadows.
            if !now.regions.is_empty() && self.tree_full() {
                self.tree.pruned += chunk.len();
                now.regions.clear();
            }
            let next = chunks.last().map(Vec::as_slice);
            let (next, ()) = rayon::join(|| prepare(next), || self.add_chunk(&mut at, chunk, now));
            ready = next;
        }
        Some(at.ids)
    }

    /// A level's `sorted` polygons (back to front) less those hidden at
    /// every sample (`n x n` per pixel) under opaque ones later in the
    /// order, and how many were left out. A level below the first lies
    /// within its parent's outline and is painted there in its own
    /// priority order, so what its own polygons hide cannot show either;
    /// leaving it out drops its shadows and branches too.
    ///
    /// A picture whose mask would pass [`occlusion::MAX_BYTES`] keeps
    /// them all.
    fn unhidden(&self, sorted: Vec<Candidate>, n: u32) -> (Vec<Candidate>, usize) {
        let view = self.view;
        let (w, h) = (view.width as u32, view.height as u32);
        if CoverMask::bytes(w, h, n) > occlusion::MAX_BYTES {
            return (sorted, 0);
        }
        let outlines: Vec<Outline> = sorted
            .par_iter()
            .map(|c| Outline {
                points: c
                    .points
                    .iter()
                    .map(|p| view.project(*p).truncate())
                    .collect(),
                opaque: !self.materials.is_transparent(c.object),
            })
            .collect();
        let hidden = occlusion::hidden(w, h, n, &outlines);
        drop(outlines);
        let kept: Vec<Candidate> = sorted
            .into_iter()
            .zip(&hidden)
            .filter_map(|(c, &h)| (!h).then_some(c))
            .collect();
        let left_out = hidden.len() - kept.len();
        (kept, left_out)
    }

    /// Whether the tree has reached its node budget.
    fn tree_full(&self) -> bool {
        self.tree.nodes.len() + self.reserved >= self.options.budgets.tree_nodes
    }

    /// Adds the fragments of `chunk` (with their shadow `regions`, if
    /// any) at level `at`, and queues their branches. Each candidate's
    /// points move into its fragment, and the chunk is freed: the level's
    /// candidates are not held beside the tree they become.
    fn add_chunk(
        &mut self,
        at: &mut LevelState<'_>,
        chunk: Vec<Candidate>,
        ready: PreparedChunk<'a>,
    ) {
        let mut regions = ready.regions.into_iter();
        for (mut c, terms) in chunk.into_iter().zip(ready.terms) {
            let own = terms.shade();
            let blended = at.parent_blend + own * at.weight;
            let id = self.push(Fragment {
                level: at.level,
                kind: FragmentKind::Polygon,
                branch: at.branch,
                object: c.object,
                polygon: c.polygon,
                // Set below, once the candidate's points are no more read.
                virtual_points: Box::default(),
                back_facing: c.back_facing,
                shade: own,
                blended,
                weight: at.weight,
                parent: at.parent.map_or(NO_PARENT, link),
                space: at.space,
                links: Box::default(),
            });
            at.ids.push(id);
            if let Some(regions) = regions.next() {
                let start = std::time::Instant::now();
                let shadows = self.shadows_on(regions, &c, &terms, at, id);
                self.profile.add(Category::Shadows, start.elapsed());
                self.tree.nodes[id].add_children(shadows);
            }
            if at.level < self.options.max_level && !c.back_facing {
                self.queue_branches(at, &c, id, blended);
            }
            self.tree.nodes[id].virtual_points = std::mem::take(&mut c.points).into_boxed_slice();
        }
    }

    /// Queues the reflected and refracted branches of fragment `id` (made
    /// from `c`, pre-blended shade `blended`) that pass the threshold.
    fn queue_branches(&mut self, at: &LevelState<'_>, c: &Candidate, id: usize, blended: Color) {
        let material = self.materials.material(c.object, c.polygon);
        let weight = at.weight;
        let threshold = self.options.threshold;
        let passes = |k: f64| k > 0.0 && weight * k > threshold;
        // Most polygons neither reflect nor refract: their plane is not
        // needed (this runs on the builder's one thread).
        let (reflects, refracts) = (passes(material.reflectance), passes(material.transmittance));
        if !reflects && !refracts {
            return;
        }
        let Some(plane) = toward_eye_plane(&c.points, self.view.eye) else {
            return;
        };
        let pending = |branch, k: f64, m: &Matrix4| Pending {
            weight: weight * k,
            seq: 0,
            parent: id,
            branch,
            level: at.level + 1,
            t: at.t.mul(m),
            plane,
            blend: blended,
        };
        if reflects {
            let m = math::reflection(plane);
            self.enqueue(pending(Branch::Reflected, material.reflectance, &m));
        }
        if refracts {
            let eta = 1.0 / self.materials.resolved[c.object as usize].index;
            if let Some(m) = self.refraction_matrix(c, plane, eta) {
                self.enqueue(pending(Branch::Refracted, material.transmittance, &m));
            }
        }
    }

    /// The refraction matrix of the options' model through the plane of
    /// `c` (`None` on total internal reflection, and for exact refraction,
    /// which is ray traced after the tree by `raytrace::exact`).
    fn refraction_matrix(&self, c: &Candidate, plane: DVec4, eta: f64) -> Option<Matrix4> {
        match self.options.refraction {
            Refraction::Linearized | Refraction::Auto => {
                let centre = c.points.iter().copied().sum::<DVec3>() / c.points.len() as f64;
                math::refraction(plane, -self.view.to_eye(centre), eta)
            }
            Refraction::Exact => None,
            Refraction::Orthographic => {
                // All rays parallel to the line of sight: the direction
                // from the eye through the view centre.
                let axis = self
                    .view
                    .ray(self.view.width / 2.0, self.view.height / 2.0)
                    .map(|(_, d)| d);
                axis.and_then(|d| math::refraction(plane, d, eta))
            }
            Refraction::Paraxial => Some(math::refraction_paraxial(plane, eta)),
        }
    }

    fn enqueue(&mut self, mut p: Pending) {
        p.seq = self.next_seq;
        self.next_seq += 1;
        self.pending.push(p);
    }

    /// Traces the pending branches, heaviest first (largest product of
    /// coefficients; among equals, in the order they were found), until
    /// the node budget: a branch whose fragments would pass it is pruned
    /// with every lighter branch still waiting, and counted in
    /// [`VirtualImageTree::pruned`]. Then each fragment's children are put
    /// in output order: shadows, the reflected branch, the restore copy
    /// (when both branches exist), the refracted branch.
    fn expand(&mut self) {
        let mut branches: std::collections::HashMap<usize, (Vec<usize>, Vec<usize>)> =
            std::collections::HashMap::new();
        let mut ahead = std::collections::HashMap::new();
        while let Some(p) = self.pending.pop() {
            if crate::cancel::requested() {
                continue;
            }
            if self.tree.pruned > 0 {
                self.tree.pruned += 1;
                continue;
            }
            let found = match ahead.remove(&p.seq) {
                Some(found) => found,
                None => self.find_ahead(&p, &mut ahead),
            };
            let Some(found) = found else {
                continue;
            };
            self.count_sort(found.stats);
            self.tree.hidden += found.hidden;
            if found.sorted.is_empty() {
                continue;
            }
            let reserve = usize::from(p.branch == Branch::Refracted);
            let Some(kids) = self.trace(
                p.level,
                found.sorted,
                found.ready,
                &p.t,
                p.branch,
                p.weight,
                p.blend,
                Some(p.parent),
                reserve,
            ) else {
                self.tree.pruned += 1;
                continue;
            };
            // A restore copy may join the refracted branch at the end.
            self.reserved += reserve;
            let entry = branches.entry(p.parent).or_default();
            if p.branch == Branch::Reflected {
                entry.0 = kids;
            } else {
                entry.1 = kids;
            }
        }
        let mut parents: Vec<usize> = branches.keys().copied().collect();
        parents.sort_unstable();
        for id in parents {
            let (reflected, refracted) = branches.remove(&id).expect("listed");
            let both = !reflected.is_empty() && !refracted.is_empty();
            self.tree.nodes[id].add_children(reflected);
            if both {
                let mut restore = self.tree.nodes[id].clone();
                restore.kind = FragmentKind::Restore;
                restore.parent = link(id);
                restore.links = Box::default();
                let r = self.push(restore);
                self.tree.nodes[id].add_children([r]);
            }
            self.tree.nodes[id].add_children(refracted);
        }
        if self.tree.pruned > 0 {
            self.tree.warnings.push(format!(
                "the virtual image tree reached its budget of {} fragments (--max-tree-nodes \
                 raises it; `threshold` cuts light branches too): the {} lightest branches \
                 were pruned",
                self.options.budgets.tree_nodes, self.tree.pruned
            ));
        }
    }

    /// The level of branch `p`, found with those of the next heaviest
    /// pending branches not yet found, in parallel; theirs go to `ahead`
    /// by their order found. They are traced in their turn as before:
    /// only what does not depend on the tree is found ahead, so the tree
    /// does not depend on the threads. A scene of [`PARALLEL_LEVEL_POLYGONS`]
    /// or more finds one level at a time (in parallel within it): several
    /// of its levels would be held at once.
    fn find_ahead(
        &mut self,
        p: &Pending,
        ahead: &mut std::collections::HashMap<usize, Option<FoundLevel<'a>>>,
    ) -> Option<FoundLevel<'a>> {
        let at_once = if self.small_scene { FIND_AHEAD } else { 1 };
        let mut next = Vec::new();
        while next.len() + 1 < at_once
            && let Some(q) = self.pending.pop()
        {
            next.push(q);
        }
        let todo: Vec<&Pending> = std::iter::once(p)
            .chain(next.iter().filter(|q| !ahead.contains_key(&q.seq)))
            .collect();
        let this: &Self = self;
        let found: Vec<Option<FoundLevel<'a>>> =
            todo.par_iter().map(|q| this.find_level(q)).collect();
        let mut found = todo.iter().map(|q| q.seq).zip(found);
        let (_, mine) = found.next().expect("p is first");
        ahead.extend(found);
        self.pending.extend(next);
        mine
    }

    /// The level of branch `p`: the scene mapped and clipped to what is
    /// seen through its parent, sorted, less what its own polygons hide
    /// ([`TreeOptions::cull_samples`]), and for a level of one chunk the
    /// chunk's shades and shadows. `None` if nothing is mapped.
    fn find_level(&self, p: &Pending) -> Option<FoundLevel<'a>> {
        let planes = self.volume(&self.tree.nodes[p.parent].virtual_points, p.plane);
        let found = self.mapped_level(&p.t, &planes);
        if found.is_empty() {
            return None;
        }
        let (sorted, stats) = self.sorted(found);
        let (sorted, hidden) = match self.options.cull_samples {
            Some(n) => self.unhidden(sorted, n),
            None => (sorted, 0),
        };
        let ready = (!sorted.is_empty() && sorted.len() <= SHADOW_CHUNK)
            .then(|| self.chunk_work(&p.t).prepare(&sorted));
        Some(FoundLevel {
            sorted,
            stats,
            ready,
            hidden,
        })
    }

    /// The eye in true world coordinates, for a level under mapping `t`.
    fn eye_under(&self, t: &Matrix4) -> DVec4 {
        t.inverse()
            .map(|inv| inv.transform(self.view.eye))
            .unwrap_or(self.view.eye)
    }

    /// What preparing the chunks of a level under mapping `t` reads.
    fn chunk_work(&self, t: &Matrix4) -> ChunkWork<'a> {
        ChunkWork {
            materials: self.materials,
            profile: self.profile,
            shading: self.options.shading,
            caster: self.caster(),
            t: *t,
            eye: self.eye_under(t),
        }
    }

    /// The shadow caster of the scene, `None` without `run y` (the index
    /// of casters is set by [`build_profiled`] with shadows on).
    fn caster(&self) -> Option<ShadowCaster<'a>> {
        let index = self.casters.clone()?;
        Some(ShadowCaster {
            materials: self.materials,
            view: self.view,
            profile: self.profile,
            eps: self.eps,
            index,
        })
    }

    /// Adds the shadow `regions` of fragment `c` (see
    /// [`Self::shadow_regions`]) under fragment `parent`, each with the
    /// target's shade without its lights, so that where the shadows of
    /// several lights overlap the region is darker than either (lifting
    /// the limit of 004 section 4.10 on "overlapped shadow regions caused
    /// by multiple light sources"). Back to front, regions of fewer lights
    /// come first.
    fn shadows_on(
        &mut self,
        regions: Vec<ShadowRegion>,
        c: &Candidate,
        terms: &FacetTerms,
        at: &LevelState<'_>,
        parent: usize,
    ) -> Vec<usize> {
        let eye_real = &terms.eye();
        // The shadows of a fragment fit in the node budget whole, or are
        // pruned like a branch.
        if !regions.is_empty()
            && self.tree.nodes.len() + self.reserved + regions.len()
                > self.options.budgets.tree_nodes
        {
            self.tree.pruned += 1;
            return Vec::new();
        }
        let inverse = self.tree.spaces[at.space as usize].inverse;
        // One pass over the lights for the target; each region then costs
        // only its own lights.
        let mut out = Vec::with_capacity(regions.len());
        for (points, lights) in regions {
            let shade = self.shadow_shade(c, eye_real, &lights, &points, inverse, terms);
            out.push(self.push(Fragment {
                level: at.level,
                kind: FragmentKind::Shadow { light: lights[0] },
                branch: Branch::Shadow,
                object: c.object,
                polygon: c.polygon,
                virtual_points: points.into_boxed_slice(),
                back_facing: c.back_facing,
                shade,
                blended: at.parent_blend + shade * at.weight,
                weight: at.weight,
                parent: link(parent),
                space: at.space,
                links: lights.into_boxed_slice(),
            }));
        }
        out
    }

    /// The target's shade without `lights` (004 section 4.7): the
    /// target's shade with all lights (`terms`) less those lights, or with
    /// `setmode h on` the same at the region's centroid mapped back to
    /// world space (one pass over the lights per region).
    fn shadow_shade(
        &self,
        c: &Candidate,
        eye_real: &DVec4,
        lights: &[u32],
        points: &[DVec3],
        inverse: Option<Matrix4>,
        terms: &FacetTerms,
    ) -> Color {
        if self.options.explicit_shadow_shades {
            let at = points.iter().copied().sum::<DVec3>() / points.len() as f64;
            let at = inverse.map_or(at, |i| i.transform_point(at));
            return FacetTerms::new(
                self.materials,
                *eye_real,
                c.object,
                c.polygon,
                c.back_facing,
                Some(at),
                self.options.shading,
            )
            .without(lights);
        }
        terms.without(lights)
    }

    fn push(&mut self, f: Fragment) -> usize {
        self.tree.nodes.push(f);
        self.tree.nodes.len() - 1
    }

    /// The clipping volume of a fragment: beyond its plane, inside the
    /// pyramid from the eye through its outline, inside the view volume.
    fn volume(&self, points: &[DVec3], toward_eye: DVec4) -> Vec<DVec4> {
        let mut planes = vec![-toward_eye];
        let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
        let eye = self.view.eye;
        for i in 0..points.len() {
            let (a, b) = (points[i], points[(i + 1) % points.len()]);
            let to_eye = crate::geometry::view::towards_eye(eye, a);
            let Some(n) = (b - a).cross(to_eye).try_normalize() else {
                continue;
            };
            let mut pl = n.extend(-n.dot(a));
            if pl.truncate().dot(centre) + pl.w < 0.0 {
                pl = -pl;
            }
            planes.push(pl);
        }
        planes.extend(self.frustum.iter().copied());
        planes
    }
}

/// What casting shadows needs of the builder, apart from its tree, so that
/// a chunk's shadows can be cast while the tree grows.
struct ShadowCaster<'a> {
    materials: &'a Materials<'a>,
    view: &'a View,
    profile: &'a Profile,
    eps: f64,
    index: std::sync::Arc<crate::shadow::CasterIndex>,
}

impl ShadowCaster<'_> {
    /// The shadow regions of fragments of a level (`chunk`, virtual
    /// coordinates under `t`), one list per fragment in their order,
    /// computed in parallel.
    ///
    /// One fragment of each polygon goes first, the largest first, each
    /// a task of its own: a big receiver (a floor under a furnished room)
    /// starts at once while the other threads take the rest, and the
    /// pieces of a polygon then find their polygon's regions kept instead
    /// of casting them again side by side.
    fn level_regions(&self, chunk: &[Candidate], t: &Matrix4) -> Vec<Vec<ShadowRegion>> {
        let start = std::time::Instant::now();
        let (mut first, rest) = first_of_each_polygon(chunk);
        let area: Vec<f64> = chunk.iter().map(|c| polygon::area(&c.points)).collect();
        first.sort_by(|&a, &b| area[b].total_cmp(&area[a]).then(a.cmp(&b)));
        let mut regions = vec![Vec::new(); chunk.len()];
        for batch in [first, rest] {
            let done: Vec<(usize, Vec<ShadowRegion>)> = batch
                .par_iter()
                .with_max_len(1)
                .map_init(crate::shadow::Scratch::default, |s, &i| {
                    if crate::cancel::requested() {
                        return (i, Vec::new());
                    }
                    (i, self.shadow_regions(&chunk[i], t, s))
                })
                .collect();
            for (i, r) in done {
                regions[i] = r;
            }
        }
        self.profile.add(Category::Shadows, start.elapsed());
        regions
    }

    /// The shadow regions on fragment `c` (virtual coordinates under `t`)
    /// from every Point light (004 section 4.7), as overlap regions (see
    /// [`overlap_regions`]): each region carries the lights it is shadowed
    /// from. Only the first [`MAX_COMBINED_LIGHTS`] lights that cast on
    /// the fragment are combined; the shadows of further lights come
    /// alone. Fragments of `type ltsrc` show their colour whatever the
    /// lights and get none.
    fn shadow_regions(
        &self,
        c: &Candidate,
        t: &Matrix4,
        scratch: &mut crate::shadow::Scratch,
    ) -> Vec<ShadowRegion> {
        if self.materials.resolved[c.object as usize].unshaded {
            return Vec::new();
        }
        let Some(plane) = toward_eye_plane(&c.points, self.view.eye) else {
            return Vec::new();
        };
        let target = crate::shadow::Target {
            object: c.object,
            polygon: c.polygon,
            points: &c.points,
            plane,
            t,
            convex: polygon::is_convex(&c.points),
        };
        let casting = crate::shadow::Casting {
            objects: self.materials.objects,
            index: &self.index,
            profile: self.profile,
            eps: self.eps,
        };
        casting.regions(&target, scratch, |target, scratch| {
            let mut per_light = Vec::new();
            for (j, light) in self.materials.lights.iter().enumerate() {
                if light.kind != crate::model::LightKind::Point {
                    continue;
                }
                let pieces = casting.pieces(target, j, light.position, scratch);
                if !pieces.is_empty() {
                    per_light.push((j as u32, pieces));
                }
            }
            let rest = per_light.split_off(per_light.len().min(MAX_COMBINED_LIGHTS));
            let mut regions =
                overlap_regions(per_light, target.plane, self.eps, MAX_OVERLAP_PIECES);
            for (j, pieces) in rest {
                regions.extend(pieces.into_iter().map(|p| (p, vec![j])));
            }
            regions
        })
    }
}

/// The positions in `chunk` of the first fragment of each polygon, and of
/// the others, in order.
fn first_of_each_polygon(chunk: &[Candidate]) -> (Vec<usize>, Vec<usize>) {
    let mut seen = std::collections::HashSet::with_capacity(chunk.len());
    (0..chunk.len()).partition(|&i| seen.insert((chunk[i].object, chunk[i].polygon)))
}

/// The shading terms of the fragments of `chunk` seen from `eye` (true
/// world coordinates), one per fragment: one computed per source polygon
/// and side (the pieces of a polygon of 200,000 vertices would each
/// average all its vertices), in parallel.
fn facet_terms<'a>(
    materials: &Materials<'a>,
    eye: DVec4,
    shading: ShadingModel,
    chunk: &[Candidate],
) -> Vec<FacetTerms<'a>> {
    let mut first = std::collections::HashMap::new();
    let mut unique = Vec::new();
    let slot: Vec<usize> = chunk
        .iter()
        .map(|c| {
            *first
                .entry((c.object, c.polygon, c.back_facing))
                .or_insert_with(|| {
                    unique.push(c);
                    unique.len() - 1
                })
        })
        .collect();
    let terms: Vec<FacetTerms<'a>> = unique
        .par_iter()
        .map(|c| {
            FacetTerms::new(
                materials,
                eye,
                c.object,
                c.polygon,
                c.back_facing,
                None,
                shading,
            )
        })
        .collect();
    slot.into_iter().map(|k| terms[k].clone()).collect()
}

/// What preparing a level's chunks reads: nothing of the tree, so a chunk
/// is prepared while the one before it is added.
struct ChunkWork<'a> {
    materials: &'a Materials<'a>,
    profile: &'a Profile,
    shading: ShadingModel,
    /// `None` without shadows.
    caster: Option<ShadowCaster<'a>>,
    /// The level's mapping.
    t: Matrix4,
    /// The eye in true world coordinates.
    eye: DVec4,
}

impl<'a> ChunkWork<'a> {
    /// What a chunk's fragments need that does not depend on the tree
    /// (shades, and shadows with a caster), found in parallel.
    fn prepare(&self, chunk: &[Candidate]) -> PreparedChunk<'a> {
        let own = || {
            let _t = self.profile.time(Category::Shading);
            facet_terms(self.materials, self.eye, self.shading, chunk)
        };
        let (terms, regions) = match &self.caster {
            Some(c) => rayon::join(own, || c.level_regions(chunk, &self.t)),
            None => (own(), Vec::new()),
        };
        PreparedChunk { terms, regions }
    }
}

/// A branch's level found ahead of its turn (see `Builder::find_ahead`).
struct FoundLevel<'a> {
    sorted: Vec<Candidate>,
    stats: Option<nns::NnsStats>,
    /// The shades and shadows of its only chunk, if it has one.
    ready: Option<PreparedChunk<'a>>,
    /// Its polygons left out as hidden (all of them when `sorted` is
    /// empty).
    hidden: usize,
}

/// How many pending branches of a small scene are found at once: a few
/// per thread keeps both busy on the hundreds of small levels of a deep
/// mirror scene.
const FIND_AHEAD: usize = 8;

/// A level's sorted candidates in chunks of [`SHADOW_CHUNK`], the last
/// chunk first (popped in order, each freed once added to the tree).
fn into_chunks(sorted: Vec<Candidate>) -> Vec<Vec<Candidate>> {
    let mut chunks = Vec::with_capacity(sorted.len().div_ceil(SHADOW_CHUNK));
    let mut rest = sorted.into_iter();
    loop {
        let chunk: Vec<Candidate> = rest.by_ref().take(SHADOW_CHUNK).collect();
        if chunk.is_empty() {
            break;
        }
        chunks.push(chunk);
    }
    chunks.reverse();
    chunks
}

/// What a chunk of a level's fragments needs that does not depend on the
/// tree, one entry per fragment (no shadow regions without `run y`).
#[derive(Default)]
struct PreparedChunk<'a> {
    terms: Vec<FacetTerms<'a>>,
    regions: Vec<Vec<ShadowRegion>>,
}

/// A level being added to the tree: what its fragments share.
struct LevelState<'t> {
    level: u32,
    /// The level's mapping.
    t: &'t Matrix4,
    branch: Branch,
    weight: f64,
    parent_blend: Color,
    parent: Option<usize>,
    /// Index of the level's space in [`VirtualImageTree::spaces`].
    space: u32,
    /// The fragments added, in order.
    ids: Vec<usize>,
}

/// Fragments whose shadows are cast in parallel at once. It bounds the
/// regions waiting to be added to the tree: with many Point lights each
/// fragment may carry up to [`MAX_OVERLAP_PIECES`] overlap regions, and
/// 4096 fragments of office2 under 50 lights held more than 5 GB.
const SHADOW_CHUNK: usize = 256;

/// At most this many lights are combined into overlap regions on one
/// target fragment (see `Builder::shadows_on`).
pub const MAX_COMBINED_LIGHTS: usize = 8;

/// At most this many overlap regions of two or more lights are made on one
/// target fragment (see [`overlap_regions`]). 4,096 left double shadows
/// one light too bright on office2's floor (726 pixels, 27/255 from the
/// ray tracer on average); the tree's node budget still bounds them all.
pub const MAX_OVERLAP_PIECES: usize = 65_536;

/// Scenes of at least this many polygons map a mirror's level on all
/// threads (see `Builder::mapped_level`).
const PARALLEL_LEVEL_POLYGONS: usize = 4096;

/// Buffers for clipping a mirror's level, reused from polygon to polygon.
#[derive(Default)]
struct ClipBuffers {
    one: ClipScratch,
    many: Vec<Vec<DVec3>>,
}

/// The plane of `points` with its unit normal towards the eye.
fn toward_eye_plane(points: &[DVec3], eye: DVec4) -> Option<DVec4> {
    let pl = polygon::newell_plane(points)?;
    let side = pl.dot(eye);
    if side == 0.0 {
        return None;
    }
    Some(if side > 0.0 { pl } else { -pl })
}

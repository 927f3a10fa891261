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
//! NNS with `setmode n on`) orders each level. Refraction uses the matrix
//! linearized about the ray through the polygon's centre (004 section
//! 6.4.3), or none on total internal reflection.

use glam::{DVec3, DVec4};

use crate::budget::Budgets;
use crate::geometry::face_splitter;
use crate::geometry::plane_clip::{self, ClipScratch, Clipped};
use crate::geometry::polygon;
use crate::geometry::view::{self, GeometryStats, View};
use crate::math::{self, Matrix4};
use crate::profile::{Category, Profile};
use crate::scene::model::{Color, Scene, SortOrder};
use crate::shading::{FacetTerms, ShadingModel, polygon_material};
use crate::visibility::{depth_sort, nns};
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
    /// Points in the virtual coordinates of its level.
    pub virtual_points: Vec<DVec3>,
    /// Screen points (x, y in pixels, y up; z normalized depth).
    pub screen: Vec<DVec3>,
    /// Whether the viewer sees the polygon's back (`type open`).
    pub back_facing: bool,
    /// Its own shade (ambient, diffuse, specular).
    pub shade: Color,
    /// Its shade pre-blended with its ancestors' (`I_parent + k I_own`).
    pub blended: Color,
    /// `k`: the product of the coefficients above it (1 at level 1).
    pub weight: f64,
    /// Index of the parent fragment in [`VirtualImageTree::nodes`].
    pub parent: Option<usize>,
    /// The same points in true world coordinates (mapped back by `T^-1`).
    pub world: Vec<DVec3>,
    /// The eye in true world coordinates, as this fragment sees it.
    pub eye: DVec4,
    /// Children in back-to-front order: shadow polygons, the reflected
    /// branch, then the refracted.
    pub children: Vec<usize>,
    /// For shadow polygons, every light (indices into `Scene::lights`,
    /// increasing) the region is shadowed from; the first is the one in
    /// [`FragmentKind::Shadow`]. Empty for other fragments.
    pub shadowed_from: Vec<u32>,
}

/// The virtual image tree of a view.
#[derive(Debug, Clone, Default)]
pub struct VirtualImageTree {
    /// All fragments; `roots` and `children` index this.
    pub nodes: Vec<Fragment>,
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
}

impl VirtualImageTree {
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
        for &c in &self.nodes[n].children {
            self.back_to_front(c, out);
        }
    }

    /// Front to back (004 section 5.9, figure 5.14): the reflected and
    /// refracted sub-trees (and the restore copy between them) first, each
    /// run of a level list reversed, then the polygon's shadow polygons
    /// (reversed: the most shadowed overlap regions first), then the
    /// polygon: `P12, P13, P14, P21, P22, P23, S1, S2, S3, P11`.
    fn front_to_back(&self, n: usize, out: &mut Vec<usize>) {
        let kids = &self.nodes[n].children;
        let (shadows, branches): (Vec<usize>, Vec<usize>) = kids
            .iter()
            .partition(|&&c| self.nodes[c].branch == Branch::Shadow);
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
    /// linearized matrix is off by more than a pixel at a transmitting
    /// polygon's corner, else linearized. The tree builder itself treats
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
        }
    }
}

struct Builder<'a> {
    profile: &'a Profile,
    /// Every polygon in world coordinates, for shadow casting at any level
    /// (built on the first shadow).
    casters: Option<std::sync::Arc<crate::shadow::CasterIndex>>,
    scene: &'a Scene,
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

/// The shades of one level's fragments ([`Builder::level_terms`]).
struct LevelShades<'a> {
    /// Per source polygon and side: its shade.
    shades: Vec<Color>,
    /// Per source polygon and side: its shading terms, when shadows are
    /// cast (empty otherwise).
    terms: Vec<FacetTerms<'a>>,
    /// Per fragment: the index of its polygon and side.
    of_fragment: Vec<u32>,
}

/// A polygon found at some level, before sorting.
struct Candidate {
    object: u32,
    polygon: u32,
    points: Vec<DVec3>,
    back_facing: bool,
}

/// Builds the virtual image tree of `scene` seen through `view`.
pub fn build(scene: &Scene, view: &View, options: TreeOptions) -> VirtualImageTree {
    build_profiled(scene, view, options, &Profile::new(false))
}

/// [`build`], timing its parts into `profile` (table 6.2).
pub fn build_profiled(
    scene: &Scene,
    view: &View,
    options: TreeOptions,
    profile: &Profile,
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
        scene,
        view,
        options,
        eps: scene.modes.epsilon * scene.size().max(f64::MIN_POSITIVE),
        frustum,
        tree: VirtualImageTree {
            max_depth: 1,
            ..VirtualImageTree::default()
        },
        pending: std::collections::BinaryHeap::new(),
        next_seq: 0,
        reserved: 0,
        first_fallback_splits: 0,
    };
    let level1 = b.level_one();
    let roots = b
        .trace(
            1,
            level1,
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
        let mut polys = Vec::new();
        for i in 0..self.scene.objects.len() {
            if !self.scene.objects[i].surface_type.hidden {
                view::expand_object(
                    self.scene,
                    i,
                    self.view,
                    &mut polys,
                    &mut self.tree.geometry,
                );
            }
        }
        polys
            .into_iter()
            .map(|p| Candidate {
                object: p.object,
                polygon: p.polygon,
                points: p.world,
                back_facing: p.back_facing,
            })
            .collect()
    }

    /// Lower levels: the scene mapped by `t`, clipped to `planes` (front
    /// sides kept) with the splitter. `planes[0]` is the plane of the
    /// fragment seen through.
    fn mapped_level(&self, t: &Matrix4, planes: &[DVec4]) -> Vec<Candidate> {
        let _t = self.profile.time(Category::Addobj);
        let mirrored = linear_determinant(t) < 0.0;
        let mut out = Vec::new();
        for (oi, object) in self.scene.objects.iter().enumerate() {
            if object.surface_type.hidden {
                continue;
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
                continue;
            }
            let verts: Vec<DVec3> = {
                let _t = self.profile.time(Category::Transform);
                object
                    .vertices
                    .iter()
                    .map(|v| t.transform_point(*v))
                    .collect()
            };
            for (pi, poly) in object.polygons.iter().enumerate() {
                let mut pts: Vec<DVec3> = poly.indices.iter().map(|&i| verts[i as usize]).collect();
                if mirrored {
                    pts.reverse();
                }
                let Ok(plane) = polygon::outward_plane(&pts) else {
                    continue;
                };
                // Polygons in the mirror's (or refracting surface's) own
                // plane, itself included, map onto it: they are not seen
                // through it.
                let front_plane = planes[0];
                if pts
                    .iter()
                    .all(|p| (front_plane.truncate().dot(*p) + front_plane.w).abs() <= self.eps)
                {
                    continue;
                }
                let front = self.view.faces_eye(plane);
                if !front && !object.surface_type.open {
                    continue;
                }
                let clipped = {
                    let _t = self.profile.time(Category::Clipping);
                    face_splitter::clip_to_planes(&pts, planes, self.eps)
                };
                let Ok(pieces) = clipped else {
                    continue;
                };
                for piece in pieces {
                    out.push(Candidate {
                        object: oi as u32,
                        polygon: pi as u32,
                        points: piece,
                        back_facing: !front,
                    });
                }
            }
        }
        out
    }

    /// Orders a level's candidates back to front.
    fn sort(&mut self, candidates: Vec<Candidate>) -> Vec<Candidate> {
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
            return sorted
                .into_iter()
                .map(|f| Candidate {
                    back_facing: back.contains_key(&(f.object, f.polygon)),
                    object: f.object,
                    polygon: f.polygon,
                    points: f.world,
                })
                .collect();
        }
        let keys: Vec<f64> = candidates
            .iter()
            .map(|c| {
                let zmax = c
                    .points
                    .iter()
                    .map(|p| self.view.project(*p).z)
                    .fold(f64::NEG_INFINITY, f64::max);
                depth_sort::sort_key((f64::NEG_INFINITY, zmax), SortOrder::BackToFront)
            })
            .collect();
        let mut slots: Vec<Option<Candidate>> = candidates.into_iter().map(Some).collect();
        if self.scene.modes.expand {
            // `setmode x on`: one composite list.
            return depth_sort::sorted_order(&keys)
                .into_iter()
                .map(|k| slots[k].take().expect("a permutation"))
                .collect();
        }
        // `setmode x off` (004 section 4.4): objects one at a time, by the
        // farthest depth of their polygons, each object's polygons sorted.
        let mut objects: Vec<u32> = slots
            .iter()
            .map(|c| c.as_ref().expect("full").object)
            .collect();
        objects.sort_unstable();
        objects.dedup();
        let object_key = |o: u32| {
            slots
                .iter()
                .zip(&keys)
                .filter(|(c, _)| c.as_ref().is_some_and(|c| c.object == o))
                .map(|(_, k)| *k)
                .fold(f64::INFINITY, f64::min)
        };
        let object_keys: Vec<f64> = objects.iter().map(|&o| object_key(o)).collect();
        let mut out = Vec::with_capacity(slots.len());
        for oi in depth_sort::sorted_order(&object_keys) {
            let o = objects[oi];
            let members: Vec<usize> = (0..slots.len())
                .filter(|&k| slots[k].as_ref().is_some_and(|c| c.object == o))
                .collect();
            let member_keys: Vec<f64> = members.iter().map(|&k| keys[k]).collect();
            for m in depth_sort::sorted_order(&member_keys) {
                out.push(slots[members[m]].take().expect("each once"));
            }
        }
        out
    }

    /// Sorts `candidates` (the polygons of one level, in virtual coordinates
    /// under `t`), adds them as fragments and traces their sub-trees.
    /// Returns the new fragments' indices, back to front.
    #[allow(clippy::too_many_arguments)]
    fn trace(
        &mut self,
        level: u32,
        candidates: Vec<Candidate>,
        t: &Matrix4,
        branch: Branch,
        weight: f64,
        parent_blend: Color,
        parent: Option<usize>,
        reserve: usize,
    ) -> Option<Vec<usize>> {
        let sorted = self.sort(candidates);
        // Below level 1 the node budget is checked before anything is
        // added; `reserve` more nodes (a restore copy) must fit as well.
        if level > 1
            && self.tree.nodes.len() + self.reserved + sorted.len() + reserve
                > self.options.budgets.tree_nodes
        {
            return None;
        }
        self.tree.max_depth = self.tree.max_depth.max(level);
        let inverse = t.inverse();
        let eye_real = inverse
            .map(|inv| inv.transform(self.view.eye))
            .unwrap_or(self.view.eye);
        let mut ids = Vec::with_capacity(sorted.len());
        // The shadow regions of the level's fragments, found in parallel
        // a chunk at a time (so that only one chunk's wait at once); the
        // fragments are added below in order.
        let mut shadow_regions = Vec::new().into_iter();
        let level_shades = self.level_terms(&sorted, eye_real);
        let (screens, worlds): (Vec<Vec<DVec3>>, Vec<Vec<DVec3>>) = sorted
            .par_iter()
            .with_min_len(PARALLEL_MIN)
            .map(|c| {
                let screen = c.points.iter().map(|p| self.view.project(*p)).collect();
                let world = match inverse {
                    Some(i) => c.points.iter().map(|p| i.transform_point(*p)).collect(),
                    None => c.points.clone(),
                };
                (screen, world)
            })
            .unzip();
        let per_fragment = level_shades.of_fragment.iter().zip(screens).zip(worlds);
        let mut sorted = sorted;
        self.tree.nodes.reserve(sorted.len());
        for (k, ((&shared, screen), world)) in per_fragment.enumerate() {
            if k % SHADOW_CHUNK == 0 {
                let chunk = &sorted[k..(k + SHADOW_CHUNK).min(sorted.len())];
                shadow_regions = self.level_shadow_regions(chunk, t).into_iter();
            }
            // The points move into the fragment (the chunk's shadow
            // regions, the last use of the candidate's, are found).
            let points = std::mem::take(&mut sorted[k].points);
            let c = &sorted[k];
            let own = level_shades.shades[shared as usize];
            let blended = parent_blend + own * weight;
            let id = self.push(Fragment {
                level,
                kind: FragmentKind::Polygon,
                branch,
                object: c.object,
                polygon: c.polygon,
                virtual_points: points,
                screen,
                back_facing: c.back_facing,
                shade: own,
                blended,
                weight,
                parent,
                world,
                eye: eye_real,
                children: Vec::new(),
                shadowed_from: Vec::new(),
            });
            ids.push(id);
            if let Some(regions) = shadow_regions.next() {
                let start = std::time::Instant::now();
                let terms = &level_shades.terms[shared as usize];
                let shadows =
                    self.shadows_on(regions, c, t, terms, weight, parent_blend, id, level);
                self.profile.add(Category::Shadows, start.elapsed());
                self.tree.nodes[id].children.extend(shadows);
            }
            if level >= self.options.max_level || c.back_facing {
                continue;
            }
            let object = &self.scene.objects[c.object as usize];
            let material = polygon_material(object, c.polygon as usize);
            let points = &self.tree.nodes[id].virtual_points;
            let Some(plane) = toward_eye_plane(points, self.view.eye) else {
                continue;
            };
            let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
            if material.reflectance > 0.0 && weight * material.reflectance > self.options.threshold
            {
                let m = math::reflection(plane);
                self.enqueue(Pending {
                    weight: weight * material.reflectance,
                    seq: 0,
                    parent: id,
                    branch: Branch::Reflected,
                    level: level + 1,
                    t: t.mul(&m),
                    plane,
                    blend: blended,
                });
            }
            if material.transmittance > 0.0
                && weight * material.transmittance > self.options.threshold
            {
                let eta = 1.0 / object.surface.index;
                let matrix = match self.options.refraction {
                    Refraction::Linearized | Refraction::Auto => {
                        math::refraction(plane, -self.view.to_eye(centre), eta)
                    }
                    // Ray traced after the tree (`raytrace::exact`).
                    Refraction::Exact => None,
                    Refraction::Orthographic => {
                        // All rays parallel to the line of sight: the
                        // direction from the eye through the view centre.
                        let axis = self
                            .view
                            .ray(self.view.width / 2.0, self.view.height / 2.0)
                            .map(|(_, d)| d);
                        axis.and_then(|d| math::refraction(plane, d, eta))
                    }
                    Refraction::Paraxial => Some(math::refraction_paraxial(plane, eta)),
                };
                if let Some(m) = matrix {
                    self.enqueue(Pending {
                        weight: weight * material.transmittance,
                        seq: 0,
                        parent: id,
                        branch: Branch::Refracted,
                        level: level + 1,
                        t: t.mul(&m),
                        plane,
                        blend: blended,
                    });
                }
            }
        }
        Some(ids)
    }

    /// The shades of a level's fragments (`sorted`), seen from `eye` (true
    /// world coordinates), computed in parallel: one per source polygon
    /// and side (the fragments of a level share the eye; the pieces of a
    /// polygon of 200,000 vertices would each average all its vertices).
    /// The shading terms are kept only when shadows need them. A function
    /// of the polygon, side and eye alone, so the thread count changes
    /// nothing.
    fn level_terms(&self, sorted: &[Candidate], eye: DVec4) -> LevelShades<'a> {
        let _t = self.profile.time(Category::Shading);
        let scene: &'a Scene = self.scene;
        let shading = self.options.shading;
        let keys: Vec<(u32, u32, bool)> = sorted
            .iter()
            .map(|c| (c.object, c.polygon, c.back_facing))
            .collect();
        // The fragments by source polygon: each polygon's terms once, and
        // the polygons (their vertices) read in memory order rather than
        // in depth order.
        let mut by_polygon: Vec<u32> = (0..keys.len() as u32).collect();
        by_polygon.par_sort_unstable_by_key(|&k| keys[k as usize]);
        let firsts: Vec<(u32, u32, bool)> = (0..by_polygon.len())
            .filter(|&i| i == 0 || keys[by_polygon[i] as usize] != keys[by_polygon[i - 1] as usize])
            .map(|i| keys[by_polygon[i] as usize])
            .collect();
        let new = |&(object, polygon, back): &(u32, u32, bool)| {
            FacetTerms::new(scene, eye, object, polygon, back, None, shading)
        };
        let (shades, terms) = if self.options.shadows {
            let terms: Vec<FacetTerms<'a>> = firsts
                .par_iter()
                .with_min_len(PARALLEL_MIN)
                .map(new)
                .collect();
            (terms.iter().map(FacetTerms::shade).collect(), terms)
        } else {
            let shades = firsts
                .par_iter()
                .with_min_len(PARALLEL_MIN)
                .map(|k| new(k).shade())
                .collect();
            (shades, Vec::new())
        };
        let mut of_fragment = vec![0u32; keys.len()];
        let mut group = 0;
        for (i, &k) in by_polygon.iter().enumerate() {
            if i > 0 && keys[k as usize] != keys[by_polygon[i - 1] as usize] {
                group += 1;
            }
            of_fragment[k as usize] = group;
        }
        LevelShades {
            shades,
            terms,
            of_fragment,
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
        while let Some(p) = self.pending.pop() {
            if crate::cancel::requested() {
                continue;
            }
            if self.tree.pruned > 0 {
                self.tree.pruned += 1;
                continue;
            }
            let planes = self.volume(&self.tree.nodes[p.parent].virtual_points, p.plane);
            let found = self.mapped_level(&p.t, &planes);
            if found.is_empty() {
                continue;
            }
            let reserve = usize::from(p.branch == Branch::Refracted);
            let Some(kids) = self.trace(
                p.level,
                found,
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
            self.tree.nodes[id].children.extend(reflected);
            if both {
                let mut restore = self.tree.nodes[id].clone();
                restore.kind = FragmentKind::Restore;
                restore.parent = Some(id);
                restore.children.clear();
                let r = self.push(restore);
                self.tree.nodes[id].children.push(r);
            }
            self.tree.nodes[id].children.extend(refracted);
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

    /// The shadow regions of fragments of a level (`sorted`, virtual
    /// coordinates under `t`), one list per fragment in their order,
    /// computed in parallel; empty without `run y`.
    fn level_shadow_regions(
        &mut self,
        sorted: &[Candidate],
        t: &Matrix4,
    ) -> Vec<Vec<(ShadowRegion, Vec<DVec3>)>> {
        if !self.options.shadows {
            return Vec::new();
        }
        // A full tree takes no more shadows: they are not even cast.
        if self.tree.nodes.len() + self.reserved >= self.options.budgets.tree_nodes {
            self.tree.pruned += sorted.len();
            return Vec::new();
        }
        let index = match &self.casters {
            Some(i) => i.clone(),
            None => {
                let _t = self.profile.time(Category::Transform);
                let i = std::sync::Arc::new(crate::shadow::CasterIndex::new(self.scene));
                self.casters = Some(i.clone());
                i
            }
        };
        let start = std::time::Instant::now();
        let this = &*self;
        let regions = sorted
            .par_iter()
            .map_init(crate::shadow::Scratch::default, |s, c| {
                if crate::cancel::requested() {
                    return Vec::new();
                }
                this.shadow_regions(&index, c, t, s)
                    .into_iter()
                    .map(|region| {
                        let screen = region.0.iter().map(|p| this.view.project(*p)).collect();
                        (region, screen)
                    })
                    .collect()
            })
            .collect();
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
        index: &crate::shadow::CasterIndex,
        c: &Candidate,
        t: &Matrix4,
        scratch: &mut crate::shadow::Scratch,
    ) -> Vec<ShadowRegion> {
        if self.scene.objects[c.object as usize].surface_type.ltsrc {
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
            scene: self.scene,
            index,
            profile: self.profile,
            eps: self.eps,
        };
        let mut per_light = Vec::new();
        for (j, light) in self.scene.lights.iter().enumerate() {
            if light.kind != crate::scene::model::LightKind::Point {
                continue;
            }
            let pieces = casting.pieces(&target, j, light.position, scratch);
            if !pieces.is_empty() {
                per_light.push((j as u32, pieces));
            }
        }
        let split = per_light.len().min(MAX_COMBINED_LIGHTS);
        let mut regions = overlap_regions(
            &per_light[..split],
            plane.truncate(),
            self.eps,
            MAX_OVERLAP_PIECES,
        );
        for (j, pieces) in &per_light[split..] {
            regions.extend(pieces.iter().map(|p| (p.clone(), vec![*j])));
        }
        regions
    }

    /// Adds the shadow `regions` of fragment `c` (see
    /// [`Self::shadow_regions`]) under fragment `parent`, each with the
    /// target's shade without its lights, so that where the shadows of
    /// several lights overlap the region is darker than either (lifting
    /// the limit of 004 section 4.10 on "overlapped shadow regions caused
    /// by multiple light sources"). Back to front, regions of fewer lights
    /// come first.
    #[allow(clippy::too_many_arguments)]
    fn shadows_on(
        &mut self,
        regions: Vec<(ShadowRegion, Vec<DVec3>)>,
        c: &Candidate,
        t: &Matrix4,
        terms: &FacetTerms,
        weight: f64,
        parent_blend: Color,
        parent: usize,
        level: u32,
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
        let inverse = t.inverse();
        // One pass over the lights for the target; each region then costs
        // only its own lights.
        let mut out = Vec::with_capacity(regions.len());
        for ((points, lights), screen) in regions {
            let shade = self.shadow_shade(c, eye_real, &lights, &points, inverse, terms);
            out.push(self.push(Fragment {
                level,
                kind: FragmentKind::Shadow { light: lights[0] },
                branch: Branch::Shadow,
                object: c.object,
                polygon: c.polygon,
                virtual_points: points,
                screen,
                back_facing: c.back_facing,
                shade,
                blended: parent_blend + shade * weight,
                weight,
                parent: Some(parent),
                world: Vec::new(),
                eye: *eye_real,
                children: Vec::new(),
                shadowed_from: lights,
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
                self.scene,
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

/// Fragments whose shadows are cast in parallel at once. It bounds the
/// regions waiting to be added to the tree: with many Point lights each
/// fragment may carry up to [`MAX_OVERLAP_PIECES`] overlap regions, and
/// 4096 fragments of office2 under 50 lights held more than 5 GB.
const SHADOW_CHUNK: usize = 256;

/// The fewest fragments a thread takes at once in a level's parallel
/// per-fragment work (shading terms, projections).
const PARALLEL_MIN: usize = 512;

/// At most this many lights are combined into overlap regions on one
/// target fragment (see [`Builder::shadows_on`]).
pub const MAX_COMBINED_LIGHTS: usize = 8;

/// At most this many overlap regions of two or more lights are made on one
/// target fragment (see [`overlap_regions`]).
pub const MAX_OVERLAP_PIECES: usize = 4096;

/// A region of a target's plane and the lights it is shadowed from.
pub type ShadowRegion = (Vec<DVec3>, Vec<u32>);

/// The shadow regions on one target plane (unit normal `normal`) from the
/// shadow pieces of several lights (`(light, pieces)`, lights in increasing
/// order, pieces in the plane): first every piece alone, then the
/// intersections of two pieces of different lights, then of three, and so
/// on (004 section 4.7 extended to overlapped shadows), each carrying its
/// light set (increasing). The painter, back to front, lets the regions of
/// more lights overwrite those of fewer. Two pieces are intersected with
/// the splitter, clipping one to the planes through the edges of the other
/// (triangulated when not convex) perpendicular to the target plane.
///
/// Past `cap` regions of two or more lights, no more intersections are
/// made: the remaining overlaps show the shade of a smaller light set (too
/// bright there), never a wrong outline.
pub fn overlap_regions(
    per_light: &[(u32, Vec<Vec<DVec3>>)],
    normal: DVec3,
    eps: f64,
    cap: usize,
) -> Vec<ShadowRegion> {
    let mut out: Vec<ShadowRegion> = per_light
        .iter()
        .flat_map(|(j, pieces)| pieces.iter().map(move |p| (p.clone(), vec![*j])))
        .collect();
    if per_light.len() < 2 {
        return out;
    }
    // Every piece's box and clipping planes, once.
    let prepared: Vec<Vec<InPlane>> = per_light
        .iter()
        .map(|(_, pieces)| pieces.iter().map(|p| InPlane::new(p, normal)).collect())
        .collect();
    let mut scratch = ClipScratch::default();
    let mut many = Vec::new();
    let mut layer: Vec<(Vec<DVec3>, Vec<u32>, usize)> = Vec::new();
    for (k, (j, pieces)) in per_light.iter().enumerate() {
        layer.extend(pieces.iter().map(|p| (p.clone(), vec![*j], k)));
    }
    let mut made = 0;
    let mut found = Vec::new();
    while !layer.is_empty() && made < cap {
        let mut next = Vec::new();
        'regions: for (points, lights, last) in &layer {
            let bounds = polygon_bounds(points);
            for (k, (j, _)) in per_light.iter().enumerate().skip(last + 1) {
                for piece in &prepared[k] {
                    found.clear();
                    piece.clip(points, bounds, eps, &mut scratch, &mut many, &mut found);
                    for region in found.drain(..) {
                        if made >= cap {
                            break 'regions;
                        }
                        made += 1;
                        let mut set = lights.clone();
                        set.push(*j);
                        next.push((region, set, k));
                    }
                }
            }
        }
        out.extend(next.iter().map(|(p, l, _)| (p.clone(), l.clone())));
        layer = next;
    }
    out
}

fn polygon_bounds(p: &[DVec3]) -> (DVec3, DVec3) {
    p.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), q| (lo.min(*q), hi.max(*q)),
    )
}

/// A polygon in a plane, ready to clip others to it: its box and, per
/// convex part, the planes perpendicular to the plane through its edges.
struct InPlane {
    bounds: (DVec3, DVec3),
    parts: Vec<Vec<DVec4>>,
}

impl InPlane {
    fn new(b: &[DVec3], normal: DVec3) -> InPlane {
        let parts = polygon::triangulate_if_needed(b)
            .into_iter()
            .map(|part| {
                let centre = part.iter().copied().sum::<DVec3>() / part.len() as f64;
                (0..part.len())
                    .filter_map(|i| {
                        let (p, q) = (part[i], part[(i + 1) % part.len()]);
                        let n = (q - p).cross(normal).try_normalize()?;
                        let pl = n.extend(-n.dot(p));
                        Some(if pl.truncate().dot(centre) + pl.w < 0.0 {
                            -pl
                        } else {
                            pl
                        })
                    })
                    .collect()
            })
            .collect();
        InPlane {
            bounds: polygon_bounds(b),
            parts,
        }
    }

    /// The pieces of `a` (box `a_bounds`) inside this polygon, into `out`;
    /// pieces of no area are dropped.
    fn clip(
        &self,
        a: &[DVec3],
        a_bounds: (DVec3, DVec3),
        eps: f64,
        scratch: &mut ClipScratch,
        many: &mut Vec<Vec<DVec3>>,
        out: &mut Vec<Vec<DVec3>>,
    ) {
        let ((alo, ahi), (blo, bhi)) = (a_bounds, self.bounds);
        if (alo - DVec3::splat(eps)).cmpgt(bhi).any() || (blo - DVec3::splat(eps)).cmpgt(ahi).any()
        {
            return;
        }
        let keep = |p: &[DVec3]| polygon::newell_vector(p.iter().copied()).length() > eps * eps;
        for planes in &self.parts {
            match plane_clip::clip_to_planes(a, planes, eps, scratch, many) {
                Ok(Clipped::One) if keep(scratch.piece()) => out.push(scratch.piece().to_vec()),
                Ok(Clipped::Many) => out.extend(many.drain(..).filter(|p| keep(p))),
                _ => {}
            }
        }
    }
}

/// The intersection of two polygons lying in one plane (unit normal
/// `normal`): `a` clipped to the planes perpendicular to it through the
/// edges of each convex part of `b`. Pieces of no area are dropped.
pub fn intersect_in_plane(a: &[DVec3], b: &[DVec3], normal: DVec3, eps: f64) -> Vec<Vec<DVec3>> {
    let mut out = Vec::new();
    InPlane::new(b, normal).clip(
        a,
        polygon_bounds(a),
        eps,
        &mut ClipScratch::default(),
        &mut Vec::new(),
        &mut out,
    );
    out
}

/// The plane of `points` with its unit normal towards the eye.
fn toward_eye_plane(points: &[DVec3], eye: DVec4) -> Option<DVec4> {
    let n = polygon::newell_vector(points.iter().copied()).try_normalize()?;
    let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let pl = n.extend(-n.dot(c));
    let side = pl.dot(eye);
    if side == 0.0 {
        return None;
    }
    Some(if side > 0.0 { pl } else { -pl })
}

fn linear_determinant(m: &Matrix4) -> f64 {
    let a = &m.m;
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

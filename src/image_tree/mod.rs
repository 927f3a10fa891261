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
//! Preconditions: planar polygons (the scene model's). NNS (the default;
//! the simple sort with `setmode n off`) orders each level back to front;
//! `sort ftb` reverses that one order, children before parents, so both
//! orders give one picture. Refraction uses the matrix
//! linearized about the ray through the polygon's centre (004 section
//! 6.4.3), or none on total internal reflection.
#![doc = include_str!("design.md")]

mod fragments;
mod levels;
mod options;
mod pipeline;
mod shadows;
mod tree;

use glam::{DVec3, DVec4};

use crate::geometry::plane_clip::{self, ClipScratch, Clipped};
use crate::geometry::polygon;
use crate::geometry::view::{self, View};
use crate::math::Matrix4;
use crate::model::{Color, Object, Points, PointsRef};
use crate::profile::{Category, Profile};
use crate::shading::Materials;
pub use crate::shadow::CasterReuse;
pub use crate::shadow::overlap::{ShadowRegion, overlap_regions};
use crate::visibility::occlusion::{self, CoverMask, Outline};
use crate::visibility::{depth_sort, nns};
pub use fragments::Fragments;
use levels::Pending;
pub use options::{Refraction, TreeOptions};
use rayon::prelude::*;
pub use shadows::{MAX_COMBINED_LIGHTS, MAX_OVERLAP_PIECES};
use shadows::{PreparedChunk, into_chunks};
pub use tree::{Branch, Fragment, FragmentKind, VirtualImageTree, VirtualSpace};
use tree::{NO_PARENT, link};

struct Builder<'a> {
    profile: &'a Profile,
    /// Every polygon in world coordinates, for shadow casting at any level
    /// (with shadows on: built, or found unchanged from the last frame,
    /// while level 1 is found).
    casters: Option<std::sync::Arc<crate::shadow::CasterIndex>>,
    /// The last frame's order of level 1's faces, where its sort starts.
    orders: &'a nns::PriorOrder,
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

/// A polygon found at some level, before sorting.
struct Candidate {
    object: u32,
    polygon: u32,
    /// Its points ([`Candidate::points`] reads them): a whole polygon of
    /// level 1 holds none of its own.
    points: Points,
    back_facing: bool,
}

impl Candidate {
    /// Its points, in the scene of `objects`.
    fn points<'a>(&'a self, objects: &'a [Object]) -> PointsRef<'a> {
        self.points.get(objects, self.object, self.polygon)
    }
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
        &nns::PriorOrder::default(),
    )
}

/// [`build`], timing its parts into `profile` (table 6.2), with the
/// shadow casters (and the shadows on their polygons) of the previous
/// frame in `casters`, used again if the world has not changed, and the
/// last frame's order of level 1's faces in `orders`, where its sort
/// starts (the tree is the same with any).
pub fn build_profiled<'a>(
    materials: &'a Materials<'a>,
    view: &'a View,
    options: TreeOptions,
    profile: &'a Profile,
    casters: &CasterReuse,
    orders: &'a nns::PriorOrder,
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
        orders,
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
    // found unchanged) while this thread finds, sorts and culls level 1.
    let asked_again = may_branch(materials, &options);
    let (sorted, casters) = rayon::join(
        || b.sorted_level_one(),
        || {
            options.shadows.then(|| {
                let _t = profile.time(Category::Transform);
                let (objects, lights) = (materials.objects, materials.lights);
                let index = casters.index(objects, lights, materials.eps, asked_again);
                // What the lights cast with is made here, once, not inside
                // the casts (see `shadow::Casting::warm`).
                let casting = crate::shadow::Casting {
                    objects,
                    index: &index,
                    profile,
                    eps: materials.eps,
                };
                casting.warm(lights);
                index
            })
        },
    );
    b.casters = casters;
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
    // The casters' shadows kept on whole polygons are many small lists:
    // freed on the pool while the tree is emitted.
    if let Some(casters) = b.casters.take() {
        rayon::spawn(move || drop(casters));
    }
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
    /// Level 1 in priority order, without the fragments the occlusion
    /// cull finds hidden at every sample.
    fn sorted_level_one(&mut self) -> Vec<Candidate> {
        let level1 = self.level_one();
        let mut sorted = self.sort(level1);
        if let Some(n) = self.options.cull_samples {
            let hidden;
            (sorted, hidden) = self.unhidden(sorted, n, 1, 1.0);
            self.tree.hidden += hidden;
        }
        sorted
    }

    /// Level 1: the geometry stage's polygons (homogeneous clipping).
    fn level_one(&mut self) -> Vec<Candidate> {
        let _t = self.profile.time(Category::Expobj);
        // World points alone: the screen's are not kept.
        let lists = view::expand_objects_with(
            self.materials.objects,
            self.view,
            &mut self.tree.geometry,
            |p| Candidate {
                object: p.object,
                polygon: p.polygon,
                points: Points::new(p.vertices.iter().map(|v| v.world), !p.clipped),
                back_facing: p.back_facing,
            },
        );
        // Exactly as many as there are: a mesh's level 1 is millions.
        let mut level = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        level.extend(lists.into_iter().flatten());
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
            let corners = object.bbox_corners.map(|c| t.transform_point(c));
            planes.iter().any(|pl| {
                corners
                    .iter()
                    .all(|c| pl.truncate().dot(*c) + pl.w < -self.eps)
            })
        };
        if outside {
            return out;
        }
        let ClipBuffers {
            one,
            many,
            verts,
            points: pts,
        } = clip;
        verts.clear();
        {
            let _t = self.profile.time(Category::Transform);
            verts.extend(object.vertices.iter().map(|v| t.transform_point(*v)));
        }
        // Polygons in the mirror's (or refracting surface's) own plane,
        // itself included, map onto it: they are not seen through it.
        let front_plane = planes[0];
        let on_front =
            |p: &DVec3| (front_plane.truncate().dot(*p) + front_plane.w).abs() <= self.eps;
        for (pi, poly) in object.polygons.iter().enumerate() {
            pts.clear();
            pts.extend(poly.indices.iter().map(|&i| verts[i as usize]));
            if mirrored {
                pts.reverse();
            }
            // The clipper would keep nothing, so the polygon's own plane
            // is not worth finding: most of a scene seen in a mirror lies
            // outside the mirror's volume.
            if plane_clip::beyond_one(pts, planes, self.eps) {
                continue;
            }
            let Ok(plane) = polygon::outward_plane(pts) else {
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
                plane_clip::clip_to_planes(pts, planes, self.eps, one, many)
            };
            let candidate = |points: Vec<DVec3>| Candidate {
                object: oi,
                polygon: pi as u32,
                points: points.into(),
                back_facing: !front,
            };
            match clipped {
                Ok(Clipped::One) => out.push(candidate(one.piece().to_vec())),
                Ok(Clipped::Many) => out.extend(many.drain(..).map(candidate)),
                Ok(Clipped::Empty) | Err(_) => {}
            }
        }
        out
    }

    /// Orders a level's candidates back to front, and counts the sort.
    fn sort(&mut self, candidates: Vec<Candidate>) -> Vec<Candidate> {
        let (sorted, stats) = self.sorted_from(candidates, Some(self.orders));
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
        self.sorted_from(candidates, None)
    }

    /// [`Self::sorted`], the NNS sort starting from the order `prior`
    /// kept (level 1's of the last frame).
    fn sorted_from(
        &self,
        candidates: Vec<Candidate>,
        prior: Option<&nns::PriorOrder>,
    ) -> (Vec<Candidate>, Option<nns::NnsStats>) {
        let _t = self.profile.time(Category::Sortply);
        if self.options.nns {
            // Which source polygons are seen from behind (`type open`);
            // none in a closed scene, where back faces are culled.
            let back: std::collections::HashMap<(u32, u32), bool> = candidates
                .iter()
                .filter(|c| c.back_facing)
                .map(|c| ((c.object, c.polygon), true))
                .collect();
            let objects = self.materials.objects;
            let mut faces: Vec<nns::NnsFace> = Vec::with_capacity(candidates.len());
            for c in candidates {
                let (object, polygon) = (c.object, c.polygon);
                let points = c.points(objects);
                if polygon::is_convex(&points) {
                    drop(points);
                    faces.push(nns::NnsFace {
                        object,
                        polygon,
                        world: c.points,
                    });
                } else {
                    faces.extend(
                        polygon::triangulate(&points)
                            .into_iter()
                            .map(|t| nns::NnsFace {
                                object,
                                polygon,
                                world: t.to_vec().into(),
                            }),
                    );
                }
            }
            let (sorted, stats) = nns::sort_in_scene(
                objects,
                faces,
                self.view,
                self.eps,
                self.options.budgets.splits,
                prior,
            );
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
        // either the minimum or maximum vertex Z-coordinate of the
        // polygon": the level is sorted by the farthest vertex, far first,
        // whatever `sort btf|ftb` says. Front to back is this order
        // reversed at output (`VirtualImageTree::output_order`, children
        // before parents): a second sort by the nearest vertex put a floor
        // before what stands on it and gave another picture.
        let keys: Vec<f64> = candidates
            .par_iter()
            .with_min_len(1024)
            .map(|c| {
                let far = c
                    .points(self.materials.objects)
                    .iter()
                    .map(|p| self.view.project(*p).z)
                    .fold(f64::NEG_INFINITY, f64::max);
                depth_sort::sort_key(far)
            })
            .collect();
        let permutation = if self.materials.expand {
            // `setmode x on`: one composite list.
            depth_sort::sorted_order(&keys)
        } else {
            object_by_object(&candidates, &keys)
        };
        let mut sorted = candidates;
        depth_sort::put_in_order(&mut sorted, permutation);
        (sorted, None)
    }

    /// Adds `sorted` (the polygons of one level back to front, in virtual
    /// coordinates under `t`) as fragments and traces their sub-trees.
    /// Returns the new fragments' indices, back to front. `found` is what
    /// the first chunk needs, when it was found ahead.
    ///
    /// The shadow regions and shades of the fragments are found on every
    /// thread, a few chunks ahead ([`pipeline`]), while this thread adds
    /// the chunks done to the tree, in order (so the tree does not depend
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
        let mut chunks = into_chunks(sorted);
        if let Some(found) = found {
            let first = chunks.pop().expect("found ahead for a level not empty");
            self.add_prepared(&mut at, first, found);
        }
        work.prepare_in_order(std::iter::from_fn(|| chunks.pop()), |chunk, ready| {
            self.add_prepared(&mut at, chunk, ready);
        });
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
    ///
    /// Leaving a hidden polygon out saves its shadows and its branches,
    /// and its shade and tiling; the cull itself costs about as much as
    /// shading and tiling the polygons it finds (office2 without shadows:
    /// 2.4 ms to leave out 1,412 of level 1's 10,641, and the render was
    /// 3 ms faster without it). So a level that casts no shadows asks only
    /// about its polygons that branch (at `level`, of weight `weight`) and
    /// what lies over them on the screen, and a level where nothing
    /// branches either is not culled.
    fn unhidden(
        &self,
        sorted: Vec<Candidate>,
        n: u32,
        level: u32,
        weight: f64,
    ) -> (Vec<Candidate>, usize) {
        let view = self.view;
        let (w, h) = (view.width as u32, view.height as u32);
        if CoverMask::bytes(w, h, n) > occlusion::MAX_BYTES {
            return (sorted, 0);
        }
        let shadows = self.casts_shadows();
        // Without shadows, the polygons that branch decide what is asked.
        let branching: Vec<usize> = if shadows {
            Vec::new()
        } else {
            (0..sorted.len())
                .filter(|&k| self.branches(&sorted[k], level, weight))
                .collect()
        };
        if !shadows && branching.is_empty() {
            return (sorted, 0);
        }
        let objects = self.materials.objects;
        let outline = |c: &Candidate| Outline {
            points: screen_points(objects, view, c).collect(),
            opaque: !self.materials.is_transparent(c.object),
        };
        let hidden = if shadows {
            let outlines: Vec<Outline> = sorted.par_iter().map(outline).collect();
            occlusion::hidden(w, h, n, &outlines)
        } else {
            let boxes = merged(
                branching
                    .iter()
                    .filter_map(|&k| screen_box(screen_points(objects, view, &sorted[k]))),
            );
            // Only the outlines asked about are made.
            let asked: Vec<usize> = match boxes {
                Some(boxes) => (0..sorted.len())
                    .into_par_iter()
                    .filter(|&k| overlaps(screen_points(objects, view, &sorted[k]), &boxes))
                    .collect(),
                // Branching polygons scattered over the picture: all.
                None => (0..sorted.len()).collect(),
            };
            let subset: Vec<Outline> = asked.par_iter().map(|&k| outline(&sorted[k])).collect();
            let mut hidden = vec![false; sorted.len()];
            for (&k, h) in asked.iter().zip(occlusion::hidden(w, h, n, &subset)) {
                hidden[k] = h;
            }
            hidden
        };
        let kept: Vec<Candidate> = sorted
            .into_iter()
            .zip(&hidden)
            .filter_map(|(c, &h)| (!h).then_some(c))
            .collect();
        let left_out = hidden.len() - kept.len();
        (kept, left_out)
    }

    /// Whether the levels' fragments cast shadows: shadows are asked for
    /// and a Point light gives them.
    fn casts_shadows(&self) -> bool {
        self.options.shadows
            && self
                .materials
                .lights
                .iter()
                .any(|l| l.kind == crate::model::LightKind::Point)
    }

    /// Whether the tree has reached its node budget.
    fn tree_full(&self) -> bool {
        self.tree.nodes.len() + self.reserved >= self.options.budgets.tree_nodes
    }

    /// Adds `chunk` as [`Self::add_chunk`], less its shadows once the tree
    /// is full.
    fn add_prepared(
        &mut self,
        at: &mut LevelState<'_>,
        chunk: Vec<Candidate>,
        mut ready: PreparedChunk<'a>,
    ) {
        if !ready.regions.is_empty() && self.tree_full() {
            self.tree.pruned += chunk.len();
            ready.regions.clear();
        }
        self.add_chunk(at, chunk, ready);
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
        for (mut c, &slot) in chunk.into_iter().zip(&ready.slots) {
            let terms = &ready.terms[slot as usize];
            let own = terms.shade();
            let blended = at.parent_blend + own * at.weight;
            let id = self.push(Fragment {
                level: at.level,
                kind: FragmentKind::Polygon,
                branch: at.branch,
                object: c.object,
                polygon: c.polygon,
                // Set below, once the candidate's points are no more read.
                virtual_points: Points::Scene,
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
                let shadows = self.shadows_on(regions, &c, terms, at, id);
                self.profile.add(Category::Shadows, start.elapsed());
                self.tree.nodes[id].add_children(shadows);
            }
            if at.level < self.options.max_level && !c.back_facing {
                self.queue_branches(at, &c, id, blended);
            }
            self.tree.nodes[id].virtual_points = std::mem::take(&mut c.points);
        }
    }

    /// The eye in true world coordinates, for a level under mapping `t`.
    fn eye_under(&self, t: &Matrix4) -> DVec4 {
        t.inverse()
            .map(|inv| inv.transform(self.view.eye))
            .unwrap_or(self.view.eye)
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

/// Scenes of at least this many polygons map a mirror's level on all
/// threads (see `Builder::mapped_level`).
const PARALLEL_LEVEL_POLYGONS: usize = 4096;

/// Buffers for clipping a mirror's level, reused from polygon to polygon.
#[derive(Default)]
struct ClipBuffers {
    one: ClipScratch,
    many: Vec<Vec<DVec3>>,
    /// An object's vertices mapped, and one polygon's points.
    verts: Vec<DVec3>,
    points: Vec<DVec3>,
}

/// Whether the tree may have levels below the first: a polygon reflects
/// or transmits more than the threshold and `maxlevel` allows a second
/// level. Their fragments ask again for the shadows of polygons seen
/// directly.
fn may_branch(materials: &Materials<'_>, options: &TreeOptions) -> bool {
    let passes = |k: f64| k > 0.0 && k > options.threshold;
    options.max_level > 1
        && materials.resolved.iter().any(|o| {
            o.materials
                .iter()
                .any(|m| passes(m.reflectance) || passes(m.transmittance))
        })
}

type ScreenBox = (glam::DVec2, glam::DVec2);

/// The screen box of `points` (NaN coordinates left out), `None` when
/// there are none.
fn screen_box(points: impl Iterator<Item = glam::DVec2>) -> Option<ScreenBox> {
    points
        .map(|p| (p, p))
        .reduce(|(lo, hi), (a, b)| (lo.min(a), hi.max(b)))
}

/// Whether two screen boxes meet.
fn meet(a: &ScreenBox, b: &ScreenBox) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// Most screen areas [`merged`] keeps apart.
const MAX_BOXES: usize = 32;

/// `boxes` with those that meet merged into their common box, until no
/// two meet: the screen areas of a level's mirrors and glasses. `None`
/// past [`MAX_BOXES`] areas apart (the time stays linear in the boxes).
fn merged(boxes: impl Iterator<Item = ScreenBox>) -> Option<Vec<ScreenBox>> {
    let mut out: Vec<ScreenBox> = Vec::new();
    for mut b in boxes {
        // Grow `b` by every area it meets, again until none is left.
        while let Some(k) = out.iter().position(|o| meet(o, &b)) {
            let o = out.swap_remove(k);
            b = (b.0.min(o.0), b.1.max(o.1));
        }
        out.push(b);
        if out.len() > MAX_BOXES {
            return None;
        }
    }
    Some(out)
}

/// `setmode x off` (004 section 4.4): objects one at a time, by the
/// farthest depth of their polygons, each object's
/// polygons sorted by their `keys`; the order of `candidates` that gives
/// it. Grouped by object in one sort (stable: each object's polygons keep
/// their order), objects in increasing index; the objects' polygons are
/// sorted in parallel.
fn object_by_object(candidates: &[Candidate], keys: &[f64]) -> Vec<usize> {
    let object = |k: usize| candidates[k].object;
    let mut by_object: Vec<usize> = (0..candidates.len()).collect();
    by_object.sort_by_key(|&k| object(k));
    let groups: Vec<&[usize]> = by_object
        .chunk_by(|&a, &b| object(a) == object(b))
        .collect();
    let object_keys: Vec<f64> = groups
        .iter()
        .map(|g| g.iter().map(|&k| keys[k]).fold(f64::INFINITY, f64::min))
        .collect();
    let in_groups: Vec<Vec<usize>> = groups
        .par_iter()
        .map(|members| {
            let member_keys: Vec<f64> = members.iter().map(|&k| keys[k]).collect();
            depth_sort::sorted_order(&member_keys)
                .into_iter()
                .map(|m| members[m])
                .collect()
        })
        .collect();
    let mut permutation = Vec::with_capacity(candidates.len());
    for gi in depth_sort::sorted_order(&object_keys) {
        permutation.extend_from_slice(&in_groups[gi]);
    }
    permutation
}

/// The screen points of candidate `c`'s outline (of the scene of
/// `objects`).
fn screen_points<'a>(
    objects: &'a [Object],
    view: &'a View,
    c: &'a Candidate,
) -> impl Iterator<Item = glam::DVec2> + 'a {
    let points = c.points(objects);
    (0..points.len()).map(move |k| view.project(points[k]).truncate())
}

/// Whether the outline of `points` has a box that meets one of `boxes`,
/// or a point that is not finite (the cull never finds it hidden); the
/// points are made once.
fn overlaps(points: impl Iterator<Item = glam::DVec2>, boxes: &[ScreenBox]) -> bool {
    let mut finite = true;
    let own = screen_box(points.inspect(|p| finite &= p.is_finite()));
    !finite || own.is_some_and(|own| boxes.iter().any(|b| meet(&own, b)))
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

#[cfg(test)]
mod tests;

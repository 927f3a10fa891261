//! The virtual image tree's data (Garcia 1986, 004 sections 4.6 and
//! 4.10): its fragments ([`Fragment`], what each is and how it is seen),
//! the virtual coordinates of each traced level ([`VirtualSpace`]), and
//! the tree ([`VirtualImageTree`]) with its output orders, back to front
//! and front to back (004 sections 4.10 and 5.9).

use glam::{DVec3, DVec4};

use super::fragments::Fragments;
use crate::geometry::view::{GeometryStats, View};
use crate::math::Matrix4;
use crate::model::{Color, Object, Points, PointsRef, SortOrder};

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
    /// Points in the virtual coordinates of its level ([`Fragment::points`]
    /// reads them): at level 1 a whole polygon's are its object's own,
    /// held as nothing. Its screen points are their projections
    /// ([`Fragment::screen`]), made when needed.
    pub virtual_points: Points,
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
    pub(super) parent: u32,
    /// Index of its level's space in [`VirtualImageTree::spaces`]: its
    /// true world points ([`VirtualImageTree::world`]) and the eye that
    /// sees it ([`VirtualImageTree::eye`]).
    pub space: u32,
    /// A shadow polygon's lights ([`Fragment::shadowed_from`]), any other
    /// fragment's children ([`Fragment::children`]): a shadow polygon has
    /// no children and no other fragment is shadowed, so one list serves
    /// both.
    pub(super) links: Box<[u32]>,
}

/// [`Fragment::parent`] of a fragment with none (level 1).
pub(super) const NO_PARENT: u32 = u32::MAX;

/// Fragment index `id` as a link (parent or child): below [`NO_PARENT`].
/// A tree of 2^32 fragments would take over 500 GB, so none is that big.
pub(super) fn link(id: usize) -> u32 {
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
    pub(super) fn add_children(&mut self, ids: impl IntoIterator<Item = usize>) {
        debug_assert!(!self.is_shadow(), "a shadow polygon has no children");
        let mut kids = std::mem::take(&mut self.links).into_vec();
        kids.extend(ids.into_iter().map(link));
        self.links = kids.into_boxed_slice();
    }

    /// Its points in the virtual coordinates of its level, in the scene
    /// of `objects` the tree was built from.
    pub fn points<'a>(&'a self, objects: &'a [Object]) -> PointsRef<'a> {
        self.virtual_points.get(objects, self.object, self.polygon)
    }

    /// Its screen points (x, y in pixels, y up; z normalized depth): the
    /// projections of its virtual points by the real eye (`objects` as
    /// for [`Fragment::points`]).
    pub fn screen(&self, objects: &[Object], view: &View) -> Vec<DVec3> {
        self.points(objects)
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
    /// tree reached its node budget
    /// ([`Budgets::tree_nodes`](crate::budget::Budgets::tree_nodes)): the
    /// lightest ones, after the `threshold` cut.
    pub pruned: usize,
    /// Polygons left out as hidden, at every level
    /// ([`TreeOptions::cull_samples`](super::TreeOptions::cull_samples)).
    pub hidden: usize,
}

impl VirtualImageTree {
    /// Fragment `f`'s points in true world coordinates (its virtual
    /// points mapped back by `T^-1`), the tree built from the scene of
    /// `objects`.
    pub fn world(&self, objects: &[Object], f: &Fragment) -> Vec<DVec3> {
        let points = f.points(objects);
        match self.spaces[f.space as usize].inverse {
            Some(i) => points.iter().map(|p| i.transform_point(*p)).collect(),
            None => points.to_vec(),
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

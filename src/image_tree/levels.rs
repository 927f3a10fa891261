//! The expansion queue of the tree's levels (Garcia 1986, 004 sections
//! 4.5-4.6): the reflected and refracted branches of each fragment that
//! pass the threshold, queued with the matrix of their level, then traced
//! heaviest first until the node budget, their levels found (mapped,
//! clipped, sorted, their first chunk's shades and shadows prepared) a
//! few at once ahead of their turn.

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use super::shadows::{PreparedChunk, SHADOW_CHUNK};
use super::tree::link;
use super::{Branch, Builder, Candidate, FragmentKind, LevelState, Refraction, toward_eye_plane};
use crate::math::{self, Matrix4};
use crate::model::{Color, Material};
use crate::visibility::nns;

/// A branch waiting to be traced: the scene seen by reflection in (or
/// refraction through) fragment `parent`.
pub(super) struct Pending {
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

impl<'a> Builder<'a> {
    /// Queues the reflected and refracted branches of fragment `id` (made
    /// from `c`, pre-blended shade `blended`) that pass the threshold.
    pub(super) fn queue_branches(
        &mut self,
        at: &LevelState<'_>,
        c: &Candidate,
        id: usize,
        blended: Color,
    ) {
        let material = self.materials.material(c.object, c.polygon);
        let weight = at.weight;
        // Most polygons neither reflect nor refract: their plane is not
        // needed (this runs on the builder's one thread).
        let (reflects, refracts) = self.passes(&material, weight);
        if !reflects && !refracts {
            return;
        }
        let Some(plane) = toward_eye_plane(&c.points(self.materials.objects), self.view.eye) else {
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

    /// Whether `material`, at a branch of weight `weight`, reflects and
    /// whether it refracts more than the threshold.
    fn passes(&self, material: &Material, weight: f64) -> (bool, bool) {
        let passes = |k: f64| k > 0.0 && weight * k > self.options.threshold;
        (passes(material.reflectance), passes(material.transmittance))
    }

    /// Whether candidate `c` of a level `level` deep, of weight `weight`,
    /// would queue a branch ([`Self::queue_branches`]), its plane aside.
    pub(super) fn branches(&self, c: &Candidate, level: u32, weight: f64) -> bool {
        let (reflects, refracts) =
            self.passes(&self.materials.material(c.object, c.polygon), weight);
        level < self.options.max_level && !c.back_facing && (reflects || refracts)
    }

    /// The refraction matrix of the options' model through the plane of
    /// `c` (`None` on total internal reflection, and for exact refraction,
    /// which is ray traced after the tree by `raytrace::exact`).
    fn refraction_matrix(&self, c: &Candidate, plane: DVec4, eta: f64) -> Option<Matrix4> {
        match self.options.refraction {
            Refraction::Linearized | Refraction::Auto => {
                let points = c.points(self.materials.objects);
                let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
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
    /// [`VirtualImageTree::pruned`](super::VirtualImageTree::pruned).
    /// Then each fragment's children are put in output order: shadows,
    /// the reflected branch, the restore copy (when both branches exist),
    /// the refracted branch.
    pub(super) fn expand(&mut self) {
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
    /// does not depend on the threads. A scene of
    /// [`PARALLEL_LEVEL_POLYGONS`](super::PARALLEL_LEVEL_POLYGONS) or more
    /// finds one level at a time (in parallel within it): several of its
    /// levels would be held at once.
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
    /// ([`TreeOptions::cull_samples`](super::TreeOptions::cull_samples)),
    /// and for a level of one chunk the chunk's shades and shadows. `None`
    /// if nothing is mapped.
    fn find_level(&self, p: &Pending) -> Option<FoundLevel<'a>> {
        let parent = &self.tree.nodes[p.parent];
        let planes = self.volume(&parent.points(self.materials.objects), p.plane);
        let found = self.mapped_level(&p.t, &planes);
        if found.is_empty() {
            return None;
        }
        let (sorted, stats) = self.sorted(found);
        let (sorted, hidden) = match self.options.cull_samples {
            Some(n) => self.unhidden(sorted, n, p.level, p.weight),
            None => (sorted, 0),
        };
        let (sorted, ready) = if !sorted.is_empty() && sorted.len() <= SHADOW_CHUNK {
            let (sorted, ready) = self.chunk_work(&p.t).prepare(sorted);
            (sorted, Some(ready))
        } else {
            (sorted, None)
        };
        Some(FoundLevel {
            sorted,
            stats,
            ready,
            hidden,
        })
    }
}

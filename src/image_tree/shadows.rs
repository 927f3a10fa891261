//! What a level's fragments need that does not depend on the tree,
//! prepared a chunk at a time in parallel while the tree grows (Garcia
//! 1986, 004 sections 4.7-4.8): their shading terms, and their shadow
//! regions from the Point lights, several lights' overlaps combined; and
//! the shadow polygons added under a fragment, each with its target's
//! shade without its lights (004 section 4.7).

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use super::tree::link;
use super::{Branch, Builder, Candidate, Fragment, FragmentKind, LevelState, toward_eye_plane};
use crate::geometry::polygon;
use crate::geometry::view::View;
use crate::math::Matrix4;
use crate::model::Color;
use crate::profile::{Category, Profile};
use crate::shading::{FacetTerms, Materials, ShadingModel};
use crate::shadow::overlap::{ShadowRegion, overlap_regions};

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
    /// Casting in the scene with this caster's index.
    fn casting(&self) -> crate::shadow::Casting<'_> {
        crate::shadow::Casting {
            objects: self.materials.objects,
            index: &self.index,
            profile: self.profile,
            eps: self.eps,
        }
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
        let points = c.points(self.materials.objects);
        let Some(plane) = toward_eye_plane(&points, self.view.eye) else {
            return Vec::new();
        };
        let target = crate::shadow::Target {
            object: c.object,
            polygon: c.polygon,
            points: &points,
            plane,
            t,
            convex: polygon::is_convex(&points),
        };
        let casting = self.casting();
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

thread_local! {
    /// Each thread's buffers for shadow volumes, kept from one fragment to
    /// the next: a fragment is a task of its own, and buffers made per
    /// task grew again from nothing for each of office2's 15,000.
    static SCRATCH: std::cell::Cell<crate::shadow::Scratch> = Default::default();
}

/// `f` with this thread's kept [`crate::shadow::Scratch`]. It is taken
/// out while `f` runs, so a task that this thread takes up while `f`
/// waits on others gets fresh buffers rather than these.
fn with_scratch<R>(f: impl FnOnce(&mut crate::shadow::Scratch) -> R) -> R {
    let mut s = SCRATCH.take();
    let r = f(&mut s);
    SCRATCH.set(s);
    r
}

/// The order in which the shadows of `chunk`'s fragments are found: the
/// first fragment of each polygon, the largest first, then the others in
/// order. A big receiver (a floor under a furnished room) starts at once
/// while the other threads take the rest, and the pieces of a polygon
/// mostly find their polygon's regions kept instead of casting them again
/// side by side.
fn shadow_order(objects: &[crate::model::Object], chunk: &[Candidate]) -> Vec<u32> {
    let mut seen = rustc_hash::FxHashSet::default();
    seen.reserve(chunk.len());
    let (mut first, rest): (Vec<u32>, Vec<u32>) = (0..chunk.len() as u32).partition(|&i| {
        let c = &chunk[i as usize];
        seen.insert((c.object, c.polygon))
    });
    let area: Vec<f64> = chunk
        .iter()
        .map(|c| polygon::area(&c.points(objects)))
        .collect();
    first.sort_by(|&a, &b| {
        area[b as usize]
            .total_cmp(&area[a as usize])
            .then(a.cmp(&b))
    });
    first.extend(rest);
    first
}

/// The shading terms of the fragments of `chunk` seen from `eye` (true
/// world coordinates): one computed per source polygon and side (the
/// pieces of a polygon of 200,000 vertices would each average all its
/// vertices), in parallel, and for each fragment the index of its terms.
fn facet_terms<'a>(
    materials: &Materials<'a>,
    eye: DVec4,
    shading: ShadingModel,
    chunk: &[Candidate],
) -> (Vec<FacetTerms<'a>>, Vec<u32>) {
    let mut first = rustc_hash::FxHashMap::default();
    first.reserve(chunk.len());
    let mut unique = Vec::new();
    let slots: Vec<u32> = chunk
        .iter()
        .map(|c| {
            *first
                .entry((c.object, c.polygon, c.back_facing))
                .or_insert_with(|| {
                    unique.push(c);
                    (unique.len() - 1) as u32
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
    (terms, slots)
}

/// What preparing a level's chunks reads: nothing of the tree, so a chunk
/// is prepared while the one before it is added.
pub(super) struct ChunkWork<'a> {
    materials: &'a Materials<'a>,
    profile: &'a Profile,
    shading: ShadingModel,
    /// `None` without shadows.
    caster: Option<ShadowCaster<'a>>,
    /// The level's mapping.
    t: Matrix4,
    /// The eye in true world coordinates.
    pub(super) eye: DVec4,
}

impl<'a> super::pipeline::Job for ChunkWork<'a> {
    type Chunk = Vec<Candidate>;
    /// The shading terms of the chunk's polygons, and each fragment's
    /// index among them.
    type Whole = (Vec<FacetTerms<'a>>, Vec<u32>);
    /// A fragment's shadow regions.
    type Item = Vec<ShadowRegion>;
    const AHEAD: usize = 2;

    fn items(&self, chunk: &Vec<Candidate>) -> usize {
        chunk.len()
    }

    fn order(&self, chunk: &Vec<Candidate>) -> Vec<u32> {
        if self.caster.is_some() {
            shadow_order(self.materials.objects, chunk)
        } else {
            Vec::new()
        }
    }

    fn whole(&self, chunk: &Vec<Candidate>) -> Self::Whole {
        let _t = self.profile.time(Category::Shading);
        facet_terms(self.materials, self.eye, self.shading, chunk)
    }

    fn item(&self, chunk: &Vec<Candidate>, i: u32) -> Vec<ShadowRegion> {
        let caster = self.caster.as_ref().expect("ordered only with a caster");
        if crate::cancel::requested() {
            return Vec::new();
        }
        let _t = self.profile.time(Category::Shadows);
        with_scratch(|s| caster.shadow_regions(&chunk[i as usize], &self.t, s))
    }
}

impl<'a> ChunkWork<'a> {
    /// Prepares the `chunks` of a level on every thread (see
    /// [`super::pipeline`]) and hands each to `add`, in order, with what
    /// its fragments need that does not depend on the tree.
    pub(super) fn prepare_in_order(
        &self,
        chunks: impl IntoIterator<Item = Vec<Candidate>>,
        mut add: impl FnMut(Vec<Candidate>, PreparedChunk<'a>),
    ) {
        let casts = self.caster.is_some();
        super::pipeline::in_order(self, chunks, |chunk, (terms, slots), items| {
            let regions = if casts {
                items.into_iter().map(Option::unwrap_or_default).collect()
            } else {
                Vec::new()
            };
            let ready = PreparedChunk {
                terms,
                slots,
                regions,
            };
            add(chunk, ready);
        });
    }

    /// What the fragments of `chunk` need that does not depend on the
    /// tree, found on every thread; and the chunk back.
    pub(super) fn prepare(&self, chunk: Vec<Candidate>) -> (Vec<Candidate>, PreparedChunk<'a>) {
        let mut out = None;
        self.prepare_in_order([chunk], |chunk, ready| out = Some((chunk, ready)));
        out.expect("one chunk in, one out")
    }
}

/// A level's sorted candidates in chunks of [`SHADOW_CHUNK`], the last
/// chunk first (popped in order, each freed once added to the tree).
pub(super) fn into_chunks(sorted: Vec<Candidate>) -> Vec<Vec<Candidate>> {
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
/// tree: the shading terms of its polygons, and for each fragment the
/// index of its terms and its shadow regions (none without `run y`).
#[derive(Default)]
pub(super) struct PreparedChunk<'a> {
    pub(super) terms: Vec<FacetTerms<'a>>,
    pub(super) slots: Vec<u32>,
    pub(super) regions: Vec<Vec<ShadowRegion>>,
}

/// Fragments of a chunk. With the pipeline's two chunks ahead
/// ([`super::pipeline::Job::AHEAD`]) and the one being added, it bounds
/// the regions waiting to be added to the tree: with many Point lights
/// each fragment may carry up to [`MAX_OVERLAP_PIECES`] overlap regions,
/// and 4096 fragments of office2 under 50 lights held more than 5 GB.
pub(super) const SHADOW_CHUNK: usize = 256;

/// At most this many lights are combined into overlap regions on one
/// target fragment (see `Builder::shadows_on`).
pub const MAX_COMBINED_LIGHTS: usize = 8;

/// At most this many overlap regions of two or more lights are made on one
/// target fragment (see [`overlap_regions`]). 4,096 left double shadows
/// one light too bright on office2's floor (726 pixels, 27/255 from the
/// ray tracer on average); the tree's node budget still bounds them all.
pub const MAX_OVERLAP_PIECES: usize = 65_536;

impl<'a> Builder<'a> {
    /// What preparing the chunks of a level under mapping `t` reads.
    pub(super) fn chunk_work(&self, t: &Matrix4) -> ChunkWork<'a> {
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
    /// of casters is set by [`build_profiled`](super::build_profiled) with
    /// shadows on).
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
    /// [`ShadowCaster::shadow_regions`]) under fragment `parent`, each with the
    /// target's shade without its lights, so that where the shadows of
    /// several lights overlap the region is darker than either (lifting
    /// the limit of 004 section 4.10 on "overlapped shadow regions caused
    /// by multiple light sources"). Back to front, regions of fewer lights
    /// come first.
    pub(super) fn shadows_on(
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
                virtual_points: points.into(),
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
}

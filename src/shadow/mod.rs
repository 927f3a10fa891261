//! Shadow polygons by projection (004 section 4.7), with the caster
//! selection of 004 sections 6.4.1-6.4.2 (a hierarchy of bounding volumes
//! instead of testing every object against every shadow volume).
//!
//! The shadow volume of a target fragment and a Point light is the convex
//! volume from the light through the fragment's outline down to its plane.
//! Casters are found per light, among only the polygons that face it (or
//! are `type open`), so back-facing casters are never fetched. They are
//! found as the light sees them ([`light_space`]): on each face of a cube
//! around the light, a hierarchy of their boxes in the face's coordinates
//! (two directions and a distance), where a volume is the box of its
//! target's picture, cut by the target's sides and plane. A volume that
//! the faces cannot take (a non-convex target, a level whose mapping does
//! not keep distances, a light past the memory bound) is mapped back to
//! the world and queried in a hierarchy of world boxes. Either way boxes
//! are tested against the volume at the nodes and again, caster by
//! caster, at the leaves, and both are built the first time they are
//! needed. A caster that survives is
//! tested vertex by vertex against the volume's planes, clipped to it in
//! reused buffers ([`plane_clip`], stopping as soon as nothing is left) and
//! projected from the light onto the target's plane. Nothing is allocated
//! per caster except the shadow pieces that are kept.
//!
//! An object that lies wholly between the light and a whole polygon, by
//! more than the tolerance, with many of its polygons found in the
//! polygon's shadow volume, is cast by its outline as the light sees it
//! instead ([`outline`]): the loops of the edges of its polygons facing
//! the light that no two of them share, projected, and united with the
//! other pieces under the non-zero rule. When the object reaches past the
//! volume's sides the polygon must be convex, and the loops are cut to
//! its outline first ([`union::union_with_loops`]). The region is the same in far fewer
//! points: office2's sculpture casts a few hundred on its floor instead of
//! ten thousand pieces, and a mesh of ten million triangles a few thousand
//! on its floor instead of five million.
//!
//! No view changes the shadows a light casts on a polygon: they are
//! computed once per polygon and light, on the whole polygon in world
//! coordinates, united ([`union`]) and kept in the index (Atherton, Weiler
//! and Greenberg's shadows as surface detail, 1978). So are the overlap
//! regions of all the lights on a polygon ([`overlap`]), once per side it
//! is seen from. A fragment at any level (a piece of its polygon, mapped
//! by the level's affine mapping) takes its polygon's regions, mapped the
//! same way and cut to its outline ([`Casting::regions`]). Fragments of
//! one polygon seen directly, in mirrors or split by the sort share one
//! casting, and an animation whose world does not change between frames
//! ([`CasterReuse`]) keeps them all.
#![doc = include_str!("design.md")]

mod casters;
mod kept;
pub mod light_space;
mod light_tree;
mod outline;
pub mod overlap;
pub mod union;

use std::hash::{BuildHasher, Hash, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use glam::{DVec3, DVec4};

use crate::geometry::plane_clip::{self, ClipScratch, Clipped};
use crate::geometry::polygon;
use crate::math::Matrix4;
use crate::model::{LightKind, Object};
use crate::profile::{Category, Profile};
use casters::{Caster, CasterRef, NONE, distinct_casters};
use kept::{Found, PieceCache};
pub use kept::{OnPolygon, WholePieces, WholeRegions, WholeShadows};
use light_tree::{LightFaces, LightTree};
use outline::Outline;
use overlap::ShadowRegion;

mod caster_index;
mod volume;

use caster_index::*;
pub use caster_index::{CasterIndex, CasterReuse};
use volume::*;

/// Buffers reused from one shadow volume to the next (one per thread).
#[derive(Default)]
pub struct Scratch {
    found: Vec<u32>,
    points: Vec<DVec3>,
    volume: Vec<DVec4>,
    world_volume: Vec<DVec4>,
    /// A mirrored target's points mapped back to the world.
    world_points: Vec<DVec3>,
    /// The sides of a target on a face of the cube around the light.
    face_sides: Vec<DVec4>,
    /// Buffers to clip a target to the faces of that cube.
    face_clip: light_space::FaceClip,
    clip: ClipScratch,
    many: Vec<Vec<DVec3>>,
    /// A whole polygon's points, while its shadows are cast.
    whole: Vec<DVec3>,
}

/// The target of a shadow query: a fragment in the virtual coordinates of
/// its level, which the mapping `t` takes the world to.
pub struct Target<'a> {
    /// The fragment's object.
    pub object: u32,
    /// The fragment's polygon.
    pub polygon: u32,
    /// Its points (virtual coordinates).
    pub points: &'a [DVec3],
    /// Its plane, towards the eye.
    pub plane: DVec4,
    /// The level's mapping from world to virtual coordinates.
    pub t: &'a Matrix4,
    /// Whether `points` make a convex polygon.
    pub convex: bool,
}

/// What shadow casting reads: the scene's objects, its casters, the
/// profile and the level's tolerance.
pub struct Casting<'a> {
    /// The scene's objects.
    pub objects: &'a [Object],
    /// Its casters.
    pub index: &'a CasterIndex,
    /// Timers of table 6.2.
    pub profile: &'a Profile,
    /// The absolute tolerance (`setmode e` times the scene's size).
    pub eps: f64,
}

impl Casting<'_> {
    /// Makes what each Point light of `lights` (the scene's) casts with
    /// before the casts ask for it: its hierarchies, whose builds run in
    /// parallel (see [`CasterIndex::warm_faces`]). Casts without it use
    /// the world hierarchy: the same shadows, found more slowly.
    pub fn warm(&self, lights: &[crate::model::Light]) {
        let tol = FACE_MARGIN * self.eps;
        for (j, light) in lights.iter().enumerate() {
            if light.kind == crate::model::LightKind::Point {
                self.index.tree(self.objects, j, light.position);
                self.index.warm_faces(self.objects, j, light.position, tol);
            }
        }
    }

    /// The casters that may meet the shadow volume `s.volume` of `target`
    /// (virtual coordinates, the light at `lv` there), into `s.found` in
    /// caster order, and whether they still need the facing test. From
    /// the light's faces ([`LightFaces`]) when the target is convex and its
    /// level's mapping keeps distances (so the tolerance is the same in
    /// the world), else from the world hierarchy, the volume mapped back.
    fn find(&self, target: &Target, j: usize, light: DVec3, skip: u32, s: &mut Scratch) -> bool {
        let (index, eps) = (self.index, self.eps);
        let t = target.t;
        let identity = *t == Matrix4::IDENTITY;
        let tol = FACE_MARGIN * eps;
        let faces = target.convex.then(|| index.faces(j, tol)).flatten();
        let mut world = std::mem::take(&mut s.world_points);
        let found = faces.and_then(|faces| {
            let points = world_points(target, identity, &mut world)?;
            // The volume reaches a tolerance beyond the target's plane,
            // and the clipper keeps what lies within another.
            let plane = if identity {
                target.plane
            } else {
                t.transpose().transform(target.plane)
            };
            let length = plane.truncate().length();
            let beyond = tol + 2.0 * eps / length;
            faces.query(points, plane / length, light, beyond, skip, s);
            Some(())
        });
        s.world_points = world;
        match found {
            Some(()) => false,
            None => self.find_in_world(target, j, light, skip, s),
        }
    }

    /// [`Self::find`] in the world hierarchy.
    fn find_in_world(
        &self,
        target: &Target,
        j: usize,
        light: DVec3,
        skip: u32,
        s: &mut Scratch,
    ) -> bool {
        let (objects, index, eps) = (self.objects, self.index, self.eps);
        let t = target.t;
        let identity = *t == Matrix4::IDENTITY;
        // The index is in world coordinates: map the volume's planes back
        // (a plane L of the virtual space is t L in world space).
        s.world_volume.clear();
        if identity {
            s.world_volume.extend_from_slice(&s.volume);
        } else {
            let tt = t.transpose();
            s.world_volume
                .extend(s.volume.iter().map(|pl| tt.transform(*pl)));
        }
        // The volume lies in the pyramid from the light to the target: its
        // box in world coordinates (an affine mapping, as mirrors make,
        // keeps the pyramid the hull of its corners), widened well beyond
        // the tolerance the clipper allows, culls the hierarchy before any
        // plane.
        let bounds = match world_corners(target, identity) {
            Some((lo, hi)) if target.convex => {
                let margin = DVec3::splat(BOX_MARGIN * eps);
                (lo.min(light) - margin, hi.max(light) + margin)
            }
            _ => (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY)),
        };
        let (tree, facing_unknown) = index.tree(objects, j, light);
        tree.query(&s.world_volume, bounds, skip, &mut s.found);
        facing_unknown
    }

    /// The shadows cast on `target` by Point light `j` at world position
    /// `light`, in the target's plane. `target` is a whole polygon in
    /// world coordinates, as [`Self::regions`] hands it (the pieces of
    /// [`Self::on_polygon`]), or a fragment under a mapping that is not
    /// affine, which casts directly ([`Self::cast`]).
    pub fn pieces(
        &self,
        target: &Target,
        j: usize,
        light: DVec3,
        s: &mut Scratch,
    ) -> Vec<Vec<DVec3>> {
        let (t, plane, eps) = (target.t, target.plane, self.eps);
        let lv = t.transform_point(light);
        // The light must be on the viewer's side of the fragment.
        if plane.truncate().dot(lv) + plane.w <= eps {
            return Vec::new();
        }
        // Only an affine mapping takes a polygon's shadows to its image's.
        if !t.is_affine() {
            return self.cast(target, j, light, s, false).0;
        }
        debug_assert!(*t == Matrix4::IDENTITY && self.maps_whole(target, 0.0));
        match self.on_polygon(target.object, target.polygon, j, light, s) {
            None => Vec::new(),
            Some(OnPolygon::Cast(pieces)) => pieces,
            Some(OnPolygon::Kept(kept)) => kept.pieces().map(<[DVec3]>::to_vec).collect(),
        }
    }

    /// The shadow regions of every light on `target` (see
    /// [`overlap::overlap_regions`]), with `compute` making the regions
    /// of a target. Under an affine mapping (a mirror's, or none) a
    /// fragment takes the regions of its whole polygon in world
    /// coordinates, seen from the same side ([`Self::whole_regions`]),
    /// mapped by the level's mapping and cut to its outline: the same
    /// region as casting on the fragment itself, since shadows on a
    /// polygon do not depend on how it is seen. The regions of a whole
    /// polygon are made once per side, whatever the fragments, mirrors
    /// and frames that show it. Other mappings cast on the fragment.
    pub fn regions(
        &self,
        target: &Target,
        s: &mut Scratch,
        compute: impl FnOnce(&Target, &mut Scratch) -> Vec<ShadowRegion>,
    ) -> Vec<ShadowRegion> {
        let t = target.t;
        if !t.is_affine() {
            return compute(target, s);
        }
        let identity = *t == Matrix4::IDENTITY;
        if identity && self.maps_whole(target, 0.0) {
            let front = self.front(target, target.plane);
            let kept = self.whole_regions(target, front, false, || compute(target, s));
            return Arc::try_unwrap(kept).map_or_else(|kept| kept.regions.clone(), |w| w.regions);
        }
        // The fragment's plane towards the eye, in world coordinates.
        let seen = if identity {
            target.plane
        } else {
            t.transpose().transform(target.plane)
        };
        // The whole polygon is made only when its regions are not kept.
        let make = |s: &mut Scratch| {
            let points: Vec<DVec3> = CasterRef::new(self.objects, target.object, target.polygon)
                .points()
                .collect();
            whole_target(target, &points, seen).map_or_else(Vec::new, |world| compute(&world, s))
        };
        let front = self.front(target, seen);
        // A piece of its polygon has siblings that will ask again.
        let whole = !identity && self.maps_whole(target, self.eps);
        let kept = self.whole_regions(target, front, !whole, || make(s));
        // Only the regions near the fragment are mapped and cut: a small
        // piece of a polygon with many regions (seen in a deep mirror)
        // meets few of them.
        let near = match world_corners(target, identity) {
            Some((lo, hi)) if !whole => {
                let margin = DVec3::splat(BOX_MARGIN * self.eps);
                (lo - margin, hi + margin)
            }
            _ => (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY)),
        };
        let mut regions = kept.near(near);
        if identity {
            return self.cut_to(regions, target, s);
        }
        map_regions(&mut regions, t);
        if whole {
            return regions;
        }
        self.cut_to(regions, target, s)
    }

    /// `regions` cut to the outline of `target`, which lies in their
    /// plane: by the splitter against the planes through its edges
    /// square to it when it is convex, else (or for a region the splitter
    /// refuses) by the boolean engine.
    fn cut_to(
        &self,
        regions: Vec<ShadowRegion>,
        target: &Target,
        s: &mut Scratch,
    ) -> Vec<ShadowRegion> {
        let _t = self.profile.time(Category::Clipping);
        let eps = self.eps;
        if target.convex {
            prism(target.points, target.plane.truncate(), &mut s.volume);
        }
        let mut out = Vec::new();
        let mut kept = Vec::new();
        for (ring, lights) in regions {
            kept.clear();
            // `None`: the fragment is concave, or the splitter refused.
            let clipped = target.convex.then(|| {
                plane_clip::clip_to_planes(&ring, &s.volume, eps, &mut s.clip, &mut s.many)
            });
            match clipped.and_then(Result::ok) {
                Some(Clipped::One) => push_kept(&mut kept, s.clip.piece(), eps),
                Some(Clipped::Many) => {
                    for piece in &s.many {
                        push_kept(&mut kept, piece, eps);
                    }
                }
                Some(Clipped::Empty) => {}
                None => {
                    for piece in union::intersection(&ring, target.points, target.plane) {
                        push_kept(&mut kept, &piece, eps);
                    }
                }
            }
            out.extend(kept.drain(..).map(|piece| (piece, lights.clone())));
        }
        out
    }

    /// Whether the side of `target`'s polygon that `seen` (a plane of it,
    /// world coordinates) faces is its front.
    fn front(&self, target: &Target, seen: DVec4) -> bool {
        let own = self.objects[target.object as usize].polygons[target.polygon as usize].plane;
        own.truncate().dot(seen.truncate()) > 0.0
    }

    /// The shadow regions of every light on `target`'s whole polygon, in
    /// world coordinates, seen from its front or back, as `make` makes
    /// them: kept, when asked for a second time (or at once for an index
    /// that keeps the first time, or when `piece`: the target is one of
    /// several pieces of its polygon), under the polygon and the side, on
    /// which alone they depend in a world that does not change.
    fn whole_regions(
        &self,
        target: &Target,
        front: bool,
        piece: bool,
        make: impl FnOnce() -> Vec<ShadowRegion>,
    ) -> Arc<WholeRegions> {
        let key = (target.object, target.polygon, u32::from(front));
        let again = match self.index.regions.get(key) {
            Found::Kept(kept) => return kept,
            Found::Again => true,
            Found::First => piece || self.index.keep_first,
        };
        let regions = Arc::new(WholeRegions::new(make()));
        if again {
            self.index.regions.put(key, &regions, regions.bytes());
        }
        regions
    }

    /// Whether `target` has its polygon's points mapped by its mapping,
    /// each within `eps`, in order (reversed under a reflection, as the
    /// mirror's level lists them). With `eps` 0 under the identity: its
    /// polygon's very points.
    fn maps_whole(&self, target: &Target, eps: f64) -> bool {
        let polygon = CasterRef::new(self.objects, target.object, target.polygon);
        let (t, eps2) = (target.t, eps * eps);
        let near = |p: DVec3, q: &DVec3| t.transform_point(p).distance_squared(*q) <= eps2;
        if polygon.polygon.indices.len() != target.points.len() {
            return false;
        }
        if t.linear_determinant() < 0.0 {
            polygon
                .points()
                .zip(target.points.iter().rev())
                .all(|(p, q)| near(p, q))
        } else {
            polygon.points().zip(target.points).all(|(p, q)| near(p, q))
        }
    }

    /// The shadows Point light `j` at `light` casts on the whole of
    /// polygon `polygon` of object `object`, in world coordinates, on its
    /// side facing the light; `None` when there are none. Kept in the
    /// index the second time they are asked for (the first, for an index
    /// that keeps the first time), while its memory bound allows; given
    /// as cast otherwise.
    pub fn on_polygon(
        &self,
        object: u32,
        polygon: u32,
        j: usize,
        light: DVec3,
        s: &mut Scratch,
    ) -> Option<OnPolygon> {
        let key = (object, polygon, j as u32);
        let again = match self.index.world.get(key) {
            Found::Kept(kept) => return kept.map(OnPolygon::Kept),
            Found::Again => true,
            Found::First => self.index.keep_first,
        };
        let o = &self.objects[object as usize];
        let p = &o.polygons[polygon as usize];
        let side = p.plane.truncate().dot(light) + p.plane.w;
        let pieces = if side.abs() <= self.eps {
            Vec::new()
        } else {
            let mut whole = std::mem::take(&mut s.whole);
            whole.clear();
            whole.extend(CasterRef::new(self.objects, object, polygon).points());
            let target = Target {
                object,
                polygon,
                points: &whole,
                plane: if side > 0.0 { p.plane } else { -p.plane },
                t: &Matrix4::IDENTITY,
                convex: polygon::is_convex(&whole),
            };
            let (pieces, loops) = self.cast(&target, j, light, s, true);
            let pieces = if loops.is_empty() {
                union::union(pieces, target.plane)
            } else {
                union::union_with_loops(pieces, loops, target.plane, target.points).unwrap_or_else(
                    || union::union(self.cast(&target, j, light, s, false).0, target.plane),
                )
            };
            s.whole = whole;
            pieces
        };
        if !again {
            return (!pieces.is_empty()).then_some(OnPolygon::Cast(pieces));
        }
        let kept = (!pieces.is_empty()).then(|| Arc::new(WholeShadows::new(&pieces)));
        let size = kept.as_ref().map_or(0, |p| p.bytes());
        self.index.world.put(key, &kept, size);
        kept.map(OnPolygon::Kept)
    }

    /// The shadows cast on `target` by Point light `j` at world position
    /// `light`, projected from the light onto the target's plane (virtual
    /// coordinates). Polygons back-facing to the light are never fetched
    /// (unless `type open`); the fragment's own object casts nothing on it
    /// unless it is `type concave`, and a polygon never on itself.
    fn cast(
        &self,
        target: &Target,
        j: usize,
        light: DVec3,
        s: &mut Scratch,
        outlines: bool,
    ) -> (Vec<Vec<DVec3>>, union::Loops) {
        let (objects, index, profile, eps) = (self.objects, self.index, self.profile, self.eps);
        let t = target.t;
        let plane = target.plane;
        let lv = t.transform_point(light);
        // The light must be on the viewer's side of the fragment.
        if plane.truncate().dot(lv) + plane.w <= eps {
            return Default::default();
        }
        volume(target.points, plane, lv, eps, &mut s.volume);
        let identity = *t == Matrix4::IDENTITY;
        let own = &objects[target.object as usize];
        // Its own object shadows a fragment only if it is `type concave`.
        let skip = if own.surface_type.concave {
            NONE
        } else {
            target.object
        };
        let facing_unknown = {
            let _t = profile.time(Category::ChkBbox);
            self.find(target, j, light, skip, s)
        };
        if facing_unknown {
            s.found.retain(|&k| {
                let c = &index.casters[k as usize];
                CasterRef::of(objects, c).faces(c.open, light)
            });
        }
        let n = plane.truncate();
        let mut out = Vec::new();
        let mut loops = union::Loops::default();
        let outlined = if outlines && identity && index.cast_outlines {
            self.outlined(target, j, light, s, &mut loops)
        } else {
            Vec::new()
        };
        for &k in &s.found {
            let caster = &index.casters[k as usize];
            // The objects cast by outlines, in order as the casters are.
            if outlined.binary_search(&caster.single_object).is_ok() {
                continue;
            }
            // A caster standing for several identical polygons casts if any
            // of them may.
            if caster.single_object == target.object
                && (!own.surface_type.concave
                    || (caster.copies == 1 && caster.polygon == target.polygon))
            {
                continue;
            }
            let from = CasterRef::of(objects, caster);
            s.points.clear();
            if identity {
                s.points.extend(from.points());
            } else {
                s.points.extend(from.points().map(|p| t.transform_point(p)));
            }
            let pts: &[DVec3] = &s.points;
            // A caster in the target's plane (a coincident copy, or a
            // neighbour of a tessellated plane) shadows nothing on it.
            if pts.iter().all(|p| (n.dot(*p) + plane.w).abs() <= eps) {
                continue;
            }
            let outside = {
                let _t = profile.time(Category::ChkPly);
                s.volume
                    .iter()
                    .any(|pl| pts.iter().all(|p| pl.truncate().dot(*p) + pl.w < 0.0))
            };
            if outside {
                continue;
            }
            let clipped = {
                let _t = profile.time(Category::Clipping);
                plane_clip::clip_to_planes(pts, &s.volume, eps, &mut s.clip, &mut s.many)
            };
            match clipped {
                Ok(Clipped::One) => push_projected(&mut out, s.clip.piece(), plane, lv, eps),
                Ok(Clipped::Many) => {
                    for piece in &s.many {
                        push_projected(&mut out, piece, plane, lv, eps);
                    }
                }
                Ok(Clipped::Empty) | Err(_) => {}
            }
        }
        (out, loops)
    }
}

/// Where one outline is kept, made by the first thread to ask for it.
type OutlineCell = Arc<OnceLock<Outline>>;

/// Found casters of one object in a row from which its outline is cast
/// instead, when the object lies between the light and the target.
const MIN_OUTLINED: usize = 32;

/// The most points an outline that must be cut to the target may have,
/// per caster of its object found: cutting a loop costs a few operations
/// a point and edge, casting a caster a clip and a projection.
const CUT_POINTS_PER_CASTER: usize = 8;

impl Casting<'_> {
    /// The objects among `s.found` (world coordinates), with at least
    /// [`MIN_OUTLINED`] casters found, that lie between the light and the
    /// target by more than the tolerance, and inside the sides of its
    /// shadow volume `s.volume` too or else beside a convex target: their
    /// outlines as light `j` sees them, projected onto the target's plane,
    /// go to `out` (to be cut to the target unless within the sides); the
    /// objects are returned in order, and their casters are left out.
    /// Every polygon of theirs that faces the light and meets the volume
    /// is found, and none is clipped by its ends, so the outline, cut to
    /// the target, covers what their pieces would.
    fn outlined(
        &self,
        target: &Target,
        j: usize,
        light: DVec3,
        s: &Scratch,
        out: &mut union::Loops,
    ) -> Vec<u32> {
        let (objects, index, eps) = (self.objects, self.index, self.eps);
        let mut chosen = Vec::new();
        let object_of = |k: &u32| index.casters[*k as usize].single_object;
        // The volume's planes: its sides, then its two ends ([`volume`]).
        let (sides, ends) = s.volume.split_at(s.volume.len() - 2);
        for run in s.found.chunk_by(|a, b| object_of(a) == object_of(b)) {
            let m = object_of(&run[0]);
            if run.len() < MIN_OUTLINED || m == NONE || m == target.object {
                continue;
            }
            let o = &objects[m as usize];
            if o.surface_type.open {
                continue;
            }
            // The corners of its box first; else each point, when the run
            // holds enough of its polygons for all those facing the light
            // to be in it (about half of a closed object's), so the test
            // costs no more than casting them would.
            let every_point = run.len() * 4 >= o.polygons.len();
            let inside = |planes: &[DVec4]| {
                let by = |p: &DVec3| planes.iter().all(|pl| pl.truncate().dot(*p) + pl.w > eps);
                o.bbox_corners.iter().all(by) || (every_point && o.vertices.iter().all(by))
            };
            if !inside(ends) {
                continue;
            }
            let within = inside(sides);
            if !within && !target.convex {
                continue;
            }
            let cell = index.outline_cell(m, j);
            let outline = cell.get_or_init(|| Outline::new(o, light));
            if !within && outline.point_count() > CUT_POINTS_PER_CASTER * run.len() {
                continue;
            }
            let to = if within {
                &mut out.within
            } else {
                &mut out.cut
            };
            for l in outline.loops() {
                let ring = l.iter().map(|&i| o.vertices[i as usize]);
                to.push(projected(ring, target.plane, light));
            }
            chosen.push(m);
        }
        chosen
    }
}

#[cfg(test)]
mod tests;

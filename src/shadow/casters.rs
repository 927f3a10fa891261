//! The casters: every displayed polygon of the scene that may cast a
//! shadow (004 section 4.7 projects each from the light), read in place
//! from the scene. Identical polygons share one caster, since they cast
//! the same shadow: the hierarchies of 004 sections 6.4.1-6.4.2
//! ([`super::light_tree`]) then hold it, and a query finds it, once.

use glam::DVec3;

use crate::model::Object;

/// A polygon that may cast a shadow, in world coordinates; identical
/// polygons (the same vertices from the same start, the same `type open`)
/// share one caster, since they cast the same shadow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Caster {
    /// The object and polygon of the first polygon it stands for (its
    /// points and plane are the scene's).
    pub(super) object: u32,
    pub(super) polygon: u32,
    /// The object of every polygon it stands for, or [`NONE`] when they
    /// come from several objects (20 bytes a caster, not the 24 of an
    /// `Option`).
    pub(super) single_object: u32,
    /// How many identical polygons it stands for.
    pub(super) copies: u32,
    pub(super) open: bool,
}

/// No caster (the end of a chain of casters with one hash).
pub(super) const NONE: u32 = u32::MAX;

/// A polygon of the scene as a caster: its points (world coordinates)
/// and plane are read from the scene, not copied.
#[derive(Clone, Copy)]
pub(super) struct CasterRef<'a> {
    vertices: &'a [DVec3],
    pub(super) polygon: &'a crate::model::Polygon,
}

impl<'a> CasterRef<'a> {
    pub(super) fn new(objects: &'a [Object], object: u32, polygon: u32) -> CasterRef<'a> {
        let o = &objects[object as usize];
        CasterRef {
            vertices: &o.vertices,
            polygon: &o.polygons[polygon as usize],
        }
    }

    pub(super) fn of(objects: &'a [Object], c: &Caster) -> CasterRef<'a> {
        CasterRef::new(objects, c.object, c.polygon)
    }

    pub(super) fn points(self) -> impl Iterator<Item = DVec3> + 'a {
        self.polygon
            .indices
            .iter()
            .map(move |&i| self.vertices[i as usize])
    }

    pub(super) fn bounds(self) -> (DVec3, DVec3) {
        self.points().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        )
    }

    /// Whether it may cast a shadow from `light`: it faces the light, or
    /// it is `type open`.
    pub(super) fn faces(self, open: bool, light: DVec3) -> bool {
        let plane = self.polygon.plane;
        open || plane.truncate().dot(light) + plane.w > 0.0
    }
}

/// Whether `a` and `b` have the same points (bit for bit).
fn same_points(a: CasterRef<'_>, b: CasterRef<'_>) -> bool {
    let bits = |p: DVec3| p.to_array().map(f64::to_bits);
    a.polygon.indices.len() == b.polygon.indices.len()
        && a.points().zip(b.points()).all(|(p, q)| bits(p) == bits(q))
}

/// A hash of a caster's points (their bits) and whether it is open.
fn caster_hash(open: bool, c: CasterRef<'_>) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::hash::DefaultHasher::new();
    open.hash(&mut h);
    for p in c.points() {
        p.to_array().map(f64::to_bits).hash(&mut h);
    }
    h.finish()
}

/// Every displayed polygon of `objects` as a caster, in order, but one
/// caster for identical polygons: 65,535 copies of one triangle would
/// each be found by every query of the others. The hashes are made and
/// sorted on all threads (a mesh of millions of polygons); only the
/// polygons of one hash are compared.
pub(super) fn distinct_casters(objects: &[Object]) -> Vec<Caster> {
    use rayon::prelude::*;
    let refs: Vec<(u32, u32)> = objects
        .iter()
        .enumerate()
        .filter(|(_, o)| !o.surface_type.hidden)
        .flat_map(|(oi, o)| (0..o.polygons.len() as u32).map(move |pi| (oi as u32, pi)))
        .collect();
    let open = |(oi, _): (u32, u32)| objects[oi as usize].surface_type.open;
    let caster = |r: (u32, u32)| CasterRef::new(objects, r.0, r.1);
    let mut by_hash: Vec<(u64, u32)> = refs
        .par_iter()
        .enumerate()
        .map(|(i, &r)| (caster_hash(open(r), caster(r)), i as u32))
        .collect();
    by_hash.par_sort_unstable();
    // The first polygon of each set of identical ones, for each polygon:
    // the earliest identical one of its hash (which is a first polygon,
    // or its own first, earlier still, would have been found).
    let mut first: Vec<u32> = (0..refs.len() as u32).collect();
    for run in by_hash.chunk_by(|a, b| a.0 == b.0).filter(|r| r.len() > 1) {
        for (k, &(_, i)) in run.iter().enumerate() {
            let (r, o) = (refs[i as usize], open(refs[i as usize]));
            let same = |&&(_, j): &&(u64, u32)| {
                let q = refs[j as usize];
                open(q) == o && same_points(caster(q), caster(r))
            };
            if let Some(&(_, j)) = run[..k].iter().find(same) {
                first[i as usize] = j;
            }
        }
    }
    drop(by_hash);
    let mut casters: Vec<Caster> = Vec::with_capacity(refs.len());
    for (i, &(object, polygon)) in refs.iter().enumerate() {
        let f = first[i] as usize;
        if f == i {
            // From here on, a first polygon's entry is where its caster is.
            first[i] = casters.len() as u32;
            casters.push(Caster {
                object,
                polygon,
                single_object: object,
                copies: 1,
                open: open((object, polygon)),
            });
        } else {
            let caster = &mut casters[first[f] as usize];
            caster.copies += 1;
            if caster.single_object != object {
                caster.single_object = NONE;
            }
        }
    }
    casters
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::tests::gallery;

    /// Identical polygons within an object, across objects, and with
    /// `type open` changed: the casters are those of a plain search of
    /// the polygons before each one (every copy of gallery's first two
    /// objects, one open, and a hidden copy that casts nothing).
    #[test]
    fn identical_polygons_share_the_first_ones_caster() {
        let mut objects = gallery().objects;
        let mut copy = objects[0].clone();
        copy.polygons.extend(objects[0].polygons.iter().cloned());
        let mut open = objects[1].clone();
        open.surface_type.open = true;
        let mut hidden = objects[1].clone();
        hidden.surface_type.hidden = true;
        objects.extend([copy, open, objects[1].clone(), hidden]);
        let mut expected: Vec<Caster> = Vec::new();
        for (oi, o) in objects
            .iter()
            .enumerate()
            .filter(|(_, o)| !o.surface_type.hidden)
        {
            let open = o.surface_type.open;
            for pi in 0..o.polygons.len() as u32 {
                let this = CasterRef::new(&objects, oi as u32, pi);
                let same = |c: &&mut Caster| {
                    c.open == open && same_points(CasterRef::of(&objects, c), this)
                };
                match expected.iter_mut().find(same) {
                    Some(c) => {
                        c.copies += 1;
                        if c.single_object != oi as u32 {
                            c.single_object = NONE;
                        }
                    }
                    None => expected.push(Caster {
                        object: oi as u32,
                        polygon: pi,
                        single_object: oi as u32,
                        copies: 1,
                        open,
                    }),
                }
            }
        }
        assert!(
            expected
                .iter()
                .any(|c| c.copies == 3 && c.single_object == NONE)
        );
        assert!(
            expected
                .iter()
                .any(|c| c.copies == 2 && c.single_object == NONE)
        );
        assert_eq!(distinct_casters(&objects), expected);
    }
}

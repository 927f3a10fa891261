//! Overlapped shadows of several lights on one target (004 section 4.7,
//! extended past the limit of section 4.10 on "overlapped shadow regions
//! caused by multiple light sources"): the shadow of each light on a
//! target's plane is intersected with those of the other lights, so that a
//! region shadowed from two lights can be shaded darker than either.
//!
//! Each light's shadow is a few outlines ([`super::union`]), and the
//! intersections are made by the same boolean engine in the target's plane,
//! one overlay per pair of light sets, however many pieces each has.

use glam::{DVec3, DVec4};

use super::union::PlaneFrame;
use crate::geometry::boolean::{self, Flat};

/// A region of a target's plane and the lights it is shadowed from.
pub type ShadowRegion = (Vec<DVec3>, Vec<u32>);

/// The shadow regions on one target plane (`plane`) from the shadow
/// pieces of several lights (`(light, pieces)`, lights in increasing
/// order, pieces in the plane): first every piece alone, then the
/// intersections of the shadows of two lights, then of three, and so on,
/// each carrying its light set (increasing). The painter, back to front,
/// lets the regions of more lights overwrite those of fewer. Regions of
/// two or more lights are simple polygons without holes.
///
/// Past `cap` regions of two or more lights, no more are made: the
/// remaining overlaps show the shade of a smaller light set (too bright
/// there), never a wrong outline.
pub fn overlap_regions(
    per_light: Vec<(u32, Vec<Vec<DVec3>>)>,
    plane: DVec4,
    eps: f64,
    cap: usize,
) -> Vec<ShadowRegion> {
    let lights: Vec<u32> = per_light.iter().map(|(j, _)| *j).collect();
    let frame = PlaneFrame::new(plane);
    let flat: Vec<Vec<Vec<Flat>>> = if lights.len() < 2 {
        Vec::new()
    } else {
        per_light
            .iter()
            .map(|(_, pieces)| pieces.iter().map(|p| frame.counter_clockwise(p)).collect())
            .collect()
    };
    let mut out: Vec<ShadowRegion> = per_light
        .into_iter()
        .flat_map(|(j, pieces)| pieces.into_iter().map(move |p| (p, vec![j])))
        .collect();
    // The light sets to intersect next: their region (outlines and holes,
    // as the engine gives them), lights, and the index of the last light.
    // A set ending with the last light has none left to meet.
    let deeper = |k: usize| k + 1 < lights.len();
    let mut layer: Vec<(Vec<Vec<Flat>>, Vec<u32>, usize)> = flat
        .iter()
        .enumerate()
        .filter(|&(k, _)| deeper(k))
        .map(|(k, c)| (c.clone(), vec![lights[k]], k))
        .collect();
    let mut made = 0;
    while !layer.is_empty() && made < cap {
        let mut next = Vec::new();
        for (region, set, last) in &layer {
            for k in last + 1..lights.len() {
                let shapes = boolean::intersection(region, &flat[k]);
                if shapes.is_empty() {
                    continue;
                }
                let mut set = set.clone();
                set.push(lights[k]);
                let (rings, region) = if deeper(k) {
                    let region = shapes.iter().flatten().cloned().collect();
                    (boolean::without_holes(shapes), Some(region))
                } else {
                    (boolean::without_holes(shapes), None)
                };
                // A region left with a degenerate hole is left out: too
                // bright there, never too dark.
                for r in rings.unwrap_or_default() {
                    let points = frame.lift_ring(r);
                    if made < cap && worth_keeping(&points, eps) {
                        made += 1;
                        out.push((points, set.clone()));
                    }
                }
                if let Some(region) = region {
                    next.push((region, set, k));
                }
            }
        }
        layer = next;
    }
    out
}

/// Whether a region has some area.
fn worth_keeping(points: &[DVec3], eps: f64) -> bool {
    crate::geometry::polygon::newell_vector(points.iter().copied()).length() > eps * eps
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::union::{
        self,
        tests::{inside, tilted},
    };
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]
        /// Random pieces of up to three lights on a random plane, each
        /// light's pieces united first as the caster gives them. At a point,
        /// the painter shows the region of most lights that holds it: that
        /// must be exactly the lights with a piece there, and no two
        /// regions of the same light set may hold it.
        #[test]
        fn the_deepest_region_at_a_point_has_exactly_its_lights(
            normal in (-1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0),
            lights in prop::collection::vec(
                prop::collection::vec((0.0f64..6.0, 0.0f64..6.0, 0.3f64..2.5, 3usize..5), 1..10),
                2..4,
            ),
            probes in prop::collection::vec((-1.0f64..8.0, -1.0f64..8.0), 64),
        ) {
            let n = DVec3::new(normal.0, normal.1, normal.2).normalize();
            let (plane, at) = tilted(n, DVec3::new(-2.0, 0.5, 1.0));
            let per_light: Vec<(u32, Vec<Vec<DVec3>>)> = lights
                .iter()
                .enumerate()
                .map(|(j, shapes)| {
                    let pieces = shapes
                        .iter()
                        .map(|&(x, y, r, k)| {
                            (0..k)
                                .map(|i| {
                                    let a = std::f64::consts::TAU * i as f64 / k as f64;
                                    at(x + r * a.cos(), y + r * a.sin())
                                })
                                .collect()
                        })
                        .collect();
                    (2 * j as u32, union::union(pieces, plane))
                })
                .collect();
            let regions = overlap_regions(per_light.clone(), plane, 1e-9, usize::MAX);
            for (x, y) in probes {
                let p = at(x, y);
                let Some(want) = per_light
                    .iter()
                    .map(|(j, pieces)| {
                        let hit: Option<Vec<bool>> =
                            pieces.iter().map(|r| inside(r, n, p, 1e-6)).collect();
                        hit.map(|h| h.iter().any(|&c| c).then_some(*j))
                    })
                    .collect::<Option<Vec<_>>>()
                else {
                    continue;
                };
                let want: Vec<u32> = want.into_iter().flatten().collect();
                let Some(holding) = regions
                    .iter()
                    .map(|(r, set)| inside(r, n, p, 1e-6).map(|c| c.then_some(set)))
                    .collect::<Option<Vec<_>>>()
                else {
                    continue;
                };
                let holding: Vec<&Vec<u32>> = holding.into_iter().flatten().collect();
                let deepest = holding.iter().map(|s| s.len()).max().unwrap_or(0);
                prop_assert_eq!(deepest, want.len());
                let top: Vec<_> = holding.iter().filter(|s| s.len() == deepest).collect();
                if deepest > 0 {
                    prop_assert_eq!(top.len(), 1, "one region per light set at a point");
                    prop_assert_eq!(top[0].as_slice(), want.as_slice());
                }
            }
        }
    }
}

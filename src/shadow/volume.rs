//! The geometry of a shadow volume (Garcia 1986, section 4.7 and figure
//! 4.11: the volume between a light and a polygon; figure 4.12: the
//! projection onto the target's plane): its planes, the target's world
//! box, and the pieces kept and projected.

use super::*;

/// The box of the target's corners in world coordinates, when its level's
/// mapping is affine and invertible.
pub(super) fn world_corners(target: &Target, identity: bool) -> Option<(DVec3, DVec3)> {
    if identity {
        return Some(bounds(target.points));
    }
    if !target.t.is_affine() {
        return None;
    }
    let inverse = target.t.inverse()?;
    let b = crate::math::bounds(target.points.iter().map(|p| inverse.transform_point(*p)));
    (b.0.is_finite() && b.1.is_finite()).then_some(b)
}

/// The target's points in world coordinates when its level's mapping
/// keeps distances (the identity, or a mirror's reflection), in `out`.
pub(super) fn world_points<'a>(
    target: &'a Target,
    identity: bool,
    out: &'a mut Vec<DVec3>,
) -> Option<&'a [DVec3]> {
    if identity {
        return Some(target.points);
    }
    if !target.t.keeps_distances() {
        return None;
    }
    let inverse = target.t.inverse()?;
    out.clear();
    out.extend(target.points.iter().map(|p| inverse.transform_point(*p)));
    Some(out)
}

/// Whether a shadow piece is worth keeping: finite and of some area.
pub(super) fn worth_keeping(piece: &[DVec3], eps: f64) -> bool {
    piece.iter().all(|p| p.is_finite())
        && polygon::newell_vector(piece.iter().copied()).length() > eps * eps
}

/// `piece` kept if [`worth_keeping`].
pub(super) fn push_kept(out: &mut Vec<Vec<DVec3>>, piece: &[DVec3], eps: f64) {
    if worth_keeping(piece, eps) {
        out.push(piece.to_vec());
    }
}

/// `piece` projected from the light `lv` onto the `target` plane, kept if
/// finite and of some area.
pub(super) fn push_projected(
    out: &mut Vec<Vec<DVec3>>,
    piece: &[DVec3],
    target: DVec4,
    lv: DVec3,
    eps: f64,
) {
    let projected = projected(piece.iter().copied(), target, lv);
    if worth_keeping(&projected, eps) {
        out.push(projected);
    }
}

/// `points` projected from the light `lv` onto the `target` plane.
pub(super) fn projected(
    points: impl Iterator<Item = DVec3>,
    target: DVec4,
    lv: DVec3,
) -> Vec<DVec3> {
    let n = target.truncate();
    points
        .map(|p| {
            let d = p - lv;
            let s = -(n.dot(lv) + target.w) / n.dot(d);
            lv + d * s
        })
        .collect()
}

/// The whole polygon of `target`, its world `points`, as a target seen
/// from the side that `seen` (a plane of it, world coordinates) faces;
/// `None` when the points have no plane. Its plane is the Newell plane of
/// the points, as a fragment seen directly computes it, so both make the
/// same regions bit for bit.
pub(super) fn whole_target<'p>(
    target: &Target<'_>,
    points: &'p [DVec3],
    seen: DVec4,
) -> Option<Target<'p>> {
    let plane = polygon::newell_plane(points)?;
    Some(Target {
        object: target.object,
        polygon: target.polygon,
        points,
        plane: if plane.truncate().dot(seen.truncate()) > 0.0 {
            plane
        } else {
            -plane
        },
        t: &Matrix4::IDENTITY,
        convex: polygon::is_convex(points),
    })
}

/// `regions` mapped by affine `t`, their outlines kept counter-clockwise
/// (reversed under a reflection).
pub(super) fn map_regions(regions: &mut [ShadowRegion], t: &Matrix4) {
    let turned = t.linear_determinant() < 0.0;
    for (ring, _) in regions {
        for p in ring.iter_mut() {
            *p = t.transform_point(*p);
        }
        if turned {
            ring.reverse();
        }
    }
}

/// The planes through the edges of convex polygon `points` square to its
/// `normal`, facing inwards: the prism over the polygon.
pub(super) fn prism(points: &[DVec3], normal: DVec3, out: &mut Vec<DVec4>) {
    out.clear();
    let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    for i in 0..points.len() {
        let (a, b) = (points[i], points[(i + 1) % points.len()]);
        let Some(n) = (b - a).cross(normal).try_normalize() else {
            continue;
        };
        let pl = n.extend(-n.dot(a));
        out.push(if pl.truncate().dot(centre) + pl.w < 0.0 {
            -pl
        } else {
            pl
        });
    }
}

/// The shadow volume of fragment `points` for a light at `lv` (virtual
/// coordinates): the planes from the light through its edges (its
/// sides), then its two ends: strictly above the target plane, below the
/// light (004 section 4.7).
pub(super) fn volume(points: &[DVec3], target: DVec4, lv: DVec3, eps: f64, out: &mut Vec<DVec4>) {
    out.clear();
    let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    for i in 0..points.len() {
        let (a, b) = (points[i], points[(i + 1) % points.len()]);
        let Some(n) = (b - a).cross(lv - a).try_normalize() else {
            continue;
        };
        let mut pl = n.extend(-n.dot(a));
        if pl.truncate().dot(centre) + pl.w < 0.0 {
            pl = -pl;
        }
        out.push(pl);
    }
    out.push(DVec4::new(target.x, target.y, target.z, target.w - eps));
    out.push((-target.truncate()).extend(target.truncate().dot(lv)));
}

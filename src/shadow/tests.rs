//! Unit tests of `shadow`.

use super::*;

/// The gallery scene (four shadow lights, mirrors) from the fixtures.
pub(super) fn gallery() -> crate::model::Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/gallery.des");
    crate::scene::load(&path).expect("the gallery fixture").0
}

/// Casting in `scene` with `index`, at the scene's tolerance.
fn casting<'a>(
    scene: &'a crate::model::Scene,
    index: &'a CasterIndex,
    profile: &'a Profile,
) -> Casting<'a> {
    let casting = Casting {
        objects: &scene.objects,
        index,
        profile,
        eps: scene.modes.epsilon * scene.size(),
    };
    casting.warm(&scene.lights);
    casting
}

/// Asserts that `a` and `b` cast the same pieces, bit for bit, on
/// every polygon of `scene` mapped by `t` (as a mirror level sees it),
/// for every light; returns how many pieces were compared.
fn same_pieces(scene: &crate::model::Scene, a: &Casting, b: &Casting, t: &Matrix4) -> usize {
    let mut s = Scratch::default();
    let mut total = 0;
    let turned = t.linear_determinant() < 0.0;
    for (oi, object) in scene.objects.iter().enumerate() {
        for (pi, poly) in object.polygons.iter().enumerate() {
            let mut points: Vec<DVec3> = CasterRef::new(&scene.objects, oi as u32, pi as u32)
                .points()
                .map(|p| t.transform_point(p))
                .collect();
            if turned {
                points.reverse();
            }
            let plane = t.inverse().unwrap().transpose().transform(poly.plane);
            let target = Target {
                object: oi as u32,
                polygon: pi as u32,
                points: &points,
                plane: plane / plane.truncate().length(),
                t,
                convex: polygon::is_convex(&points),
            };
            for (j, light) in scene.lights.iter().enumerate() {
                let x = a.pieces(&target, j, light.position, &mut s);
                let y = b.pieces(&target, j, light.position, &mut s);
                total += x.len();
                assert_eq!(x, y, "object {oi} polygon {pi} light {j} mapped by {t:?}");
            }
        }
    }
    total
}

/// How many pieces [`same_pieces`] compared between the gallery's
/// casters as built and as `change` leaves them, over the mappings
/// `ts`.
fn compare_indexes(change: impl FnOnce(&mut CasterIndex), ts: &[Matrix4]) -> usize {
    let scene = gallery();
    let plain = CasterIndex::new(&scene.objects, scene.lights.len());
    let mut changed = CasterIndex::new(&scene.objects, scene.lights.len());
    change(&mut changed);
    let profile = Profile::new(false);
    let (a, b) = (
        casting(&scene, &plain, &profile),
        casting(&scene, &changed, &profile),
    );
    ts.iter().map(|t| same_pieces(&scene, &a, &b, t)).sum()
}

/// Past the memory bound, lights share one hierarchy of all casters
/// and test facing per caster: the same shadows as their own
/// hierarchies, on every polygon of the gallery (4 lights).
#[test]
fn the_shared_hierarchy_casts_the_same_shadows() {
    let total = compare_indexes(|index| index.max_light_items = 0, &[Matrix4::IDENTITY]);
    assert!(total > 100, "only {total} shadow pieces compared");
}

/// The casters found on the faces of the cube around each light make
/// the same shadow pieces, bit for bit, as those found in the world
/// hierarchies, on every polygon of the gallery (4 lights), seen
/// directly and in a mirror (a reflection through a plane across the
/// room): the faces never miss a caster that matters.
#[test]
fn the_light_faces_cast_the_same_shadows_as_the_world_hierarchy() {
    let mirror = crate::math::reflection(DVec4::new(0.6, 0.0, 0.8, -0.5));
    let total = compare_indexes(
        |index| index.light_space = false,
        &[Matrix4::IDENTITY, mirror],
    );
    assert!(total > 200, "only {total} shadow pieces compared");
}

/// `warm` makes every Point light's faces before any cast, so the casts
/// above compare them with the world hierarchy (a cast never builds
/// them: without `warm` both sides would be the world hierarchy).
#[test]
fn warming_makes_every_point_lights_faces() {
    let scene = gallery();
    let index = CasterIndex::new(&scene.objects, scene.lights.len());
    let profile = Profile::new(false);
    let c = casting(&scene, &index, &profile);
    let tol = FACE_MARGIN * c.eps;
    let points = scene.lights.iter().enumerate();
    let points: Vec<usize> = points
        .filter(|(_, l)| l.kind == crate::model::LightKind::Point)
        .map(|(j, _)| j)
        .collect();
    assert!(
        points.len() >= 2,
        "the gallery has {} point lights",
        points.len()
    );
    for j in points {
        assert!(index.faces(j, tol).is_some(), "light {j} has no faces");
    }
}

/// The shadows of every light on every whole polygon of `scene`, cast
/// with objects inside a shadow volume by their outlines, and by their
/// polygons: the same pieces, bit for bit. Returns how many pieces
/// were compared and how many outlines were cast.
/// Twice the area of the region where `a` and `b`, shadows on a
/// polygon of `plane` (simple polygons that do not overlap), differ.
fn twice_area_between(a: &[Vec<DVec3>], b: &[Vec<DVec3>], plane: DVec4) -> f64 {
    use crate::geometry::boolean;
    let frame = union::PlaneFrame::new(plane);
    let flat = |r: &[Vec<DVec3>]| -> Vec<Vec<boolean::Flat>> {
        r.iter().map(|p| frame.counter_clockwise(p)).collect()
    };
    let (a, b) = (flat(a), flat(b));
    let area =
        |rings: &[Vec<boolean::Flat>]| rings.iter().map(|r| boolean::twice_area(r)).sum::<f64>();
    let both: f64 = boolean::intersection(&a, &b)
        .iter()
        .map(|shape| area(shape))
        .sum();
    area(&a) + area(&b) - 2.0 * both
}

/// Casts the shadows of every light on every polygon of `scene` with
/// outlines and without: the same regions, bit for bit where no
/// outline was cut, and elsewhere within a sliver of the tolerance
/// along the target's outline (the area where they differ, by the
/// boolean engine). Returns the pieces compared, the
/// outlines made, and the targets whose shadows differ in their last
/// bits (cut outlines end on the target's edges by other arithmetic
/// than clipped pieces).
fn same_with_outlines(scene: &crate::model::Scene) -> (usize, usize, usize) {
    let with = CasterIndex::new(&scene.objects, scene.lights.len());
    let without = CasterIndex {
        cast_outlines: false,
        ..CasterIndex::new(&scene.objects, scene.lights.len())
    };
    let profile = Profile::new(false);
    let (a, b) = (
        casting(scene, &with, &profile),
        casting(scene, &without, &profile),
    );
    let pieces = |c: &Casting, oi: usize, pi: usize, j: usize, s: &mut Scratch| {
        let light = scene.lights[j].position;
        match c.on_polygon(oi as u32, pi as u32, j, light, s) {
            None => Vec::new(),
            Some(OnPolygon::Cast(pieces)) => pieces,
            Some(OnPolygon::Kept(kept)) => kept.pieces().map(<[DVec3]>::to_vec).collect(),
        }
    };
    let mut s = Scratch::default();
    let (mut total, mut cut) = (0, 0);
    for (oi, object) in scene.objects.iter().enumerate() {
        for (pi, polygon) in object.polygons.iter().enumerate() {
            for j in 0..scene.lights.len() {
                let x = pieces(&a, oi, pi, j, &mut s);
                let y = pieces(&b, oi, pi, j, &mut s);
                total += x.len();
                if x == y {
                    continue;
                }
                cut += 1;
                let points: Vec<DVec3> = CasterRef::new(&scene.objects, oi as u32, pi as u32)
                    .points()
                    .collect();
                let perimeter: f64 = (0..points.len())
                    .map(|k| points[k].distance(points[(k + 1) % points.len()]))
                    .sum();
                let between = twice_area_between(&x, &y, polygon.plane) / 2.0;
                let eps = a.eps;
                assert!(
                    between.abs() <= 4.0 * eps * perimeter,
                    "object {oi} polygon {pi} light {j}: {between} apart"
                );
            }
        }
    }
    let outlines = with.outlines.lock().unwrap().len();
    assert!(without.outlines.lock().unwrap().is_empty());
    (total, outlines, cut)
}

/// A ring of `n x n` cells less its middle ([`outline::tests::ring_det`])
/// at height 1 over `floor` (an object file) at height 0, lit from
/// (0.2, 0.1, 5).
fn ring_over(floor: &str, n: usize) -> crate::model::Scene {
    outline::tests::scene(
        "light 0.2 0.1 5 1 1 1 100 Point\ndefobj floor\nendobj\ndefobj ring\nendobj\n",
        &[
            ("floor", floor.to_string()),
            ("ring", outline::tests::ring_det(n, 1.0)),
        ],
    )
}

/// Where the point `(x, y)` of the ring falls on the floor, from the
/// light through height 1 to height 0.
fn on_floor(x: f64, y: f64) -> DVec3 {
    DVec3::new(0.2 + (x - 0.2) * 1.25, 0.1 + (y - 0.1) * 1.25, 0.0)
}

/// How many of the polygons of `shadow` (on the floor) cover `p`.
fn covered(shadow: &[Vec<DVec3>], p: DVec3) -> usize {
    (shadow.iter())
        .filter(|r| union::tests::inside(r, DVec3::Z, p, 1e-9) == Some(true))
        .count()
}

/// A ring of 48 cells over a floor, inside the floor's shadow volume:
/// the floor takes the ring's outline, two loops turning opposite
/// ways, and its shadow keeps the ring's hole (the light shines
/// through onto the floor) and is the same as from the cells.
#[test]
fn an_object_inside_a_shadow_volume_casts_its_outline() {
    let floor = "title floor\ndata\n4 1\n-5 -5 0\n5 -5 0\n5 5 0\n-5 5 0\n4 4 3 2 1\n";
    let scene = ring_over(floor, 8);
    let (pieces, outlines, cut) = same_with_outlines(&scene);
    assert_eq!(outlines, 1, "the ring's outline, for the floor");
    assert_eq!(cut, 0, "the outline within the floor's volume is not cut");
    assert!(pieces > 0);
    let index = CasterIndex::new(&scene.objects, 1);
    let profile = Profile::new(false);
    let casting = casting(&scene, &index, &profile);
    let Some(OnPolygon::Cast(shadow)) =
        casting.on_polygon(0, 0, 0, scene.lights[0].position, &mut Scratch::default())
    else {
        panic!("the ring shadows the floor");
    };
    assert_eq!(covered(&shadow, on_floor(0.0, 0.0)), 0, "the hole is lit");
    let under = covered(&shadow, on_floor(0.75, 0.1));
    assert_eq!(under, 1, "under the ring is shadow");
    let beyond = covered(&shadow, on_floor(1.5, 0.0));
    assert_eq!(beyond, 0, "beyond the ring is lit");
}

/// A ring of 192 cells over a floor of two halves, reaching over both:
/// each half casts the ring's outline cut to its own outline, and
/// takes the same shadow as from the cells, with the ring's hole lit.
#[test]
fn an_object_beside_a_shadow_volume_casts_its_outline_cut() {
    let floor = "title floor\ndata\n6 2\n-5 -5 0\n0.3 -5 0\n5 -5 0\n5 5 0\n0.3 5 0\n-5 5 0\n4 5 2 1 6\n4 4 3 2 5\n";
    let scene = ring_over(floor, 16);
    let (pieces, outlines, _) = same_with_outlines(&scene);
    assert_eq!(outlines, 1, "the ring's outline, for both halves");
    assert!(pieces > 0);
    let index = CasterIndex::new(&scene.objects, 1);
    let profile = Profile::new(false);
    let casting = casting(&scene, &index, &profile);
    let light = scene.lights[0].position;
    let mut s = Scratch::default();
    let mut under = [0, 0, 0];
    for polygon in 0..2 {
        let points: Vec<DVec3> = CasterRef::new(&scene.objects, 0, polygon)
            .points()
            .collect();
        let target = Target {
            object: 0,
            polygon,
            points: &points,
            plane: scene.objects[0].polygons[polygon as usize].plane,
            t: &Matrix4::IDENTITY,
            convex: true,
        };
        let (_, loops) = casting.cast(&target, 0, light, &mut s, true);
        assert!(
            loops.within.is_empty() && !loops.cut.is_empty(),
            "half {polygon}"
        );
        let Some(OnPolygon::Cast(shadow)) = casting.on_polygon(0, polygon, 0, light, &mut s) else {
            panic!("the ring shadows half {polygon}");
        };
        let points = [(0.0, 0.0), (0.75, 0.1), (-0.75, 0.1)];
        for (k, (x, y)) in points.into_iter().enumerate() {
            under[k] += covered(&shadow, on_floor(x, y));
        }
    }
    assert_eq!(
        under,
        [0, 1, 1],
        "the hole lit, the ring's two sides shadow"
    );
}

/// Every polygon of office2, from both lights: the same shadows with
/// outlines (a sculpture of twenty pieces over the floor, rug and
/// base, books over a shelf) as from every polygon.
#[test]
fn office2_casts_the_same_shadows_by_outlines() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/office2.des");
    let scene = crate::scene::load(&path).expect("the office2 fixture").0;
    let (pieces, outlines, cut) = same_with_outlines(&scene);
    assert!(outlines >= 20, "only {outlines} outlines cast");
    assert!(pieces > 1000, "only {pieces} pieces compared");
    assert!(cut > 0, "no outline was cut");
}

/// A still keeps a polygon's regions when a piece of it asks: its
/// other pieces, and the polygon itself, find them made.
#[test]
fn the_pieces_of_a_polygon_make_its_regions_once() {
    let scene = gallery();
    let index = CasterIndex::new(&scene.objects, scene.lights.len());
    let profile = Profile::new(false);
    let casting = Casting {
        objects: &scene.objects,
        index: &index,
        profile: &profile,
        eps: scene.modes.epsilon * scene.size(),
    };
    let (oi, pi) = scene
        .objects
        .iter()
        .enumerate()
        .find_map(|(oi, o)| {
            let p = o.polygons.iter().position(|p| p.indices.len() >= 4)?;
            Some((oi as u32, p as u32))
        })
        .expect("a polygon of four points or more");
    let poly = &scene.objects[oi as usize].polygons[pi as usize];
    let whole: Vec<DVec3> = CasterRef::new(&scene.objects, oi, pi).points().collect();
    // Two pieces: a fan triangle and the rest.
    let pieces = [whole[..3].to_vec(), [&whole[..1], &whole[2..]].concat()];
    let made = std::cell::Cell::new(0);
    let mut s = Scratch::default();
    let mut ask = |points: &[DVec3]| {
        let target = Target {
            object: oi,
            polygon: pi,
            points,
            plane: poly.plane,
            t: &Matrix4::IDENTITY,
            convex: polygon::is_convex(points),
        };
        casting.regions(&target, &mut s, |_, _| {
            made.set(made.get() + 1);
            Vec::new()
        });
    };
    ask(&pieces[0]);
    ask(&pieces[1]);
    assert_eq!(made.get(), 1, "the second piece made the regions again");
    ask(&whole);
    assert_eq!(made.get(), 1, "the whole polygon found its pieces' regions");
}

/// Whether `p` lies inside `ring` (its x and y; even-odd rule).
fn inside_xy(ring: &[DVec3], p: DVec3) -> bool {
    let mut inside = false;
    for k in 0..ring.len() {
        let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// Cuts `region` (lights 0 and 2) to `fragment` in the plane z = 0
/// and checks, on a grid of probes off every edge, that each probe in
/// both is covered by exactly one piece and any other by none; returns
/// the number of pieces.
fn check_cut(region: &[(f64, f64)], fragment: &[(f64, f64)]) -> usize {
    let ring = |pts: &[(f64, f64)]| -> Vec<DVec3> {
        pts.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect()
    };
    let (region, fragment) = (ring(region), ring(fragment));
    let index = CasterIndex::new(&[], 0);
    let profile = Profile::new(false);
    let casting = Casting {
        objects: &[],
        index: &index,
        profile: &profile,
        eps: 1e-9,
    };
    let target = Target {
        object: 0,
        polygon: 0,
        points: &fragment,
        plane: DVec4::new(0.0, 0.0, 1.0, 0.0),
        t: &Matrix4::IDENTITY,
        convex: polygon::is_convex(&fragment),
    };
    let cut = casting.cut_to(
        vec![(region.clone(), vec![0, 2])],
        &target,
        &mut Scratch::default(),
    );
    for (piece, lights) in &cut {
        assert_eq!(lights, &vec![0, 2]);
        assert!(piece.iter().all(|p| p.z == 0.0));
    }
    for i in 0..60 {
        for j in 0..60 {
            let p = DVec3::new(-0.47 + i as f64 * 0.0537, -0.43 + j as f64 * 0.0541, 0.0);
            let want = inside_xy(&region, p) && inside_xy(&fragment, p);
            let got = cut.iter().filter(|(piece, _)| inside_xy(piece, p)).count();
            assert_eq!(got, usize::from(want), "probe {p}");
        }
    }
    cut.len()
}

/// A convex fragment (the splitter's prism) cutting a region shaped
/// like a gate leaves its two posts.
#[test]
fn a_convex_fragment_cuts_a_gate_into_its_posts() {
    let gate = [
        (0.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.5),
        (2.0, 0.5),
        (2.0, -1.0),
        (3.0, -1.0),
        (3.0, 2.0),
        (0.0, 2.0),
    ];
    let strip = [(-0.2, 0.0), (2.9, 0.0), (2.9, 0.4), (-0.2, 0.4)];
    assert_eq!(check_cut(&gate, &strip), 2);
}

/// A concave fragment goes to the boolean engine.
#[test]
fn a_concave_fragment_cuts_by_the_engine() {
    let ell = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let square = [(0.5, 0.5), (2.5, 0.5), (2.5, 2.5), (0.5, 2.5)];
    assert_eq!(check_cut(&square, &ell), 1);
    let strip = [(1.5, -0.3), (2.4, -0.3), (2.4, 2.4), (1.5, 2.4)];
    assert_eq!(check_cut(&ell, &strip), 1);
}

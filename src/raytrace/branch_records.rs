//! Exact refraction written into the tree file (`setmode o` with
//! `--refraction exact`, or `auto` when it picks exact): the ray-traced
//! refracted branches as records, so that the manual's scan converters
//! (rftb1-4, 004 chapter 5) draw from the file the picture plytrace drew.
//!
//! The tree built for exact refraction has no refracted branches; the
//! picture adds them after scan conversion, a ray per pixel
//! ([`crate::raytrace::exact`]). A tree file cannot hold a picture, only
//! polygons, so each site (a fragment whose refracted branch was ray
//! traced) gets, as its refracted branch, one record per pixel it meets:
//! the pixel's square cut to the site's outline, one level below the
//! site, in the pixel's ray-traced colour (`k kt L`). Method 4 then
//! blends the pieces into their parent as it blends any refracted
//! fragment (section 5.9), and a site that also reflects gets the
//! special record between its two branches (section 4.10), as the
//! linear maps give it.
//!
//! The pieces follow the file's order and blending: front to back they
//! come after the site's reflected branch and before its shadows and the
//! site itself; back to front after the site's whole sub-tree.
//! Pre-blended, a piece carries its parent's shade at its vertices (004
//! figure 4.16) plus its own.

use glam::DVec3;

use crate::geometry::view::View;
use crate::image_tree::{Branch, FragmentKind, VirtualImageTree};
use crate::model::{Color, Scene, SortOrder};
use crate::shading::interpolate_in_polygon;
use crate::tree::{Record, RecordStream, Shades};

use super::exact::{ExactLayer, is_site};

/// The records `file` (emitted from `tree`, which was built with exact
/// refraction) lacks: `layer`'s refracted branches, spliced in. `None`
/// when they would take more than `budget` records (the caller then
/// writes the linear maps' branches instead).
pub fn with_traced_branches(
    scene: &Scene,
    view: &View,
    tree: &VirtualImageTree,
    layer: &ExactLayer,
    file: RecordStream,
    budget: usize,
) -> Option<RecordStream> {
    let traced = layer.traced.as_deref()?;
    let sites: Vec<usize> = (0..tree.nodes.len())
        .filter(|&n| is_site(scene, tree, n))
        .collect();
    let pixels: usize = sites
        .iter()
        .map(|&n| pixel_box(&tree.nodes[n].screen(&scene.objects, view), view).count())
        .sum();
    if pixels > budget {
        return None;
    }
    let order = tree.output_order(if file.front_to_back {
        SortOrder::FrontToBack
    } else {
        SortOrder::BackToFront
    });
    debug_assert_eq!(order.len(), file.records.len(), "one record a fragment");
    let mut place = vec![0; tree.nodes.len()];
    for (k, &n) in order.iter().enumerate() {
        place[n] = k;
    }
    let mut inserts: Vec<(usize, Vec<Record>)> = sites
        .iter()
        .map(|&n| {
            let own = &file.records[place[n]];
            let at = insert_at(tree, n, place[n], file.front_to_back);
            let objects = &scene.objects;
            (
                at,
                branch(objects, tree, n, own, view, traced, file.blended),
            )
        })
        .collect();
    inserts.sort_by_key(|(at, _)| *at);
    Some(spliced(file, inserts))
}

/// `file` with each run of `inserts` placed before the record it names.
fn spliced(file: RecordStream, inserts: Vec<(usize, Vec<Record>)>) -> RecordStream {
    let added: usize = inserts.iter().map(|(_, r)| r.len()).sum();
    let mut records = Vec::with_capacity(file.records.len() + added);
    let mut inserts = inserts.into_iter().peekable();
    for (k, r) in file.records.into_iter().enumerate() {
        while let Some((_, run)) = inserts.next_if(|(at, _)| *at == k) {
            records.extend(run);
        }
        records.push(r);
    }
    records.extend(inserts.flat_map(|(_, run)| run));
    RecordStream { records, ..file }
}

/// Where site `n` (at `at` in the file's order) takes its refracted
/// branch: front to back, before its shadow polygons and itself (they
/// come last in its run); back to front, after its whole sub-tree.
fn insert_at(tree: &VirtualImageTree, n: usize, at: usize, front_to_back: bool) -> usize {
    if front_to_back {
        let shadows = tree.nodes[n]
            .children()
            .filter(|&c| is_shadow(tree, c))
            .count();
        at - shadows
    } else {
        at + subtree(tree, n)
    }
}

fn is_shadow(tree: &VirtualImageTree, n: usize) -> bool {
    matches!(tree.nodes[n].kind, FragmentKind::Shadow { .. })
}

/// The fragments below `n`.
fn subtree(tree: &VirtualImageTree, n: usize) -> usize {
    let mut count = 0;
    let mut stack: Vec<usize> = tree.nodes[n].children().collect();
    while let Some(c) = stack.pop() {
        count += 1;
        stack.extend(tree.nodes[c].children());
    }
    count
}

/// Site `n`'s refracted branch as records: the special record when it
/// also reflects, then its pieces. `own` is the site's record.
fn branch(
    objects: &[crate::model::Object],
    tree: &VirtualImageTree,
    n: usize,
    own: &Record,
    view: &View,
    traced: &[[f32; 3]],
    blended: bool,
) -> Vec<Record> {
    let f = &tree.nodes[n];
    let mut out = Vec::new();
    if f.children()
        .any(|c| tree.nodes[c].branch == Branch::Reflected)
    {
        out.push(Record {
            level: own.level,
            points: own.points.clone(),
            shades: Shades::Special,
        });
    }
    let outline = f.screen(objects, view);
    let (w, h) = (view.width, view.height);
    let level = (f.level + 1).min(31) as u16;
    for (col, row) in pixel_box(&outline, view) {
        let c = traced[row * w as usize + col];
        if c.iter().all(|&v| v <= 0.0) {
            continue;
        }
        let y = h - row as f64 - 1.0;
        let piece = cut_to_square(&outline, col as f64, y);
        if piece.len() < 3 || area(&piece) <= 1e-9 {
            continue;
        }
        let own_colour = DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64);
        let shades = if blended {
            pre_blended(own, &piece, w, h, own_colour)
        } else {
            Shades::Faceted(crate::emit::color_bytes(own_colour))
        };
        let points = piece
            .iter()
            .map(|p| {
                [
                    crate::tree::file::unit((p.x / w) as f32),
                    crate::tree::file::unit((p.y / h) as f32),
                ]
            })
            .collect();
        out.push(Record {
            level,
            points,
            shades,
        });
    }
    out
}

/// Pre-blended: the parent's record shades at the piece's vertices (004
/// figure 4.16), plus the piece's own colour.
fn pre_blended(parent: &Record, piece: &[DVec3], w: f64, h: f64, own: Color) -> Shades {
    let byte = |b: u8| b as f64 / 255.0;
    let rgb = |c: &[u8]| DVec3::new(byte(c[0]), byte(c[1]), byte(c[2]));
    let values: Vec<Color> = match &parent.shades {
        Shades::Faceted(c) => vec![rgb(c)],
        Shades::Gouraud(cs) => cs.iter().map(|c| rgb(c)).collect(),
        Shades::Phong(p) => p.rgbt.iter().map(|c| rgb(c)).collect(),
        Shades::Special => vec![Color::ZERO],
    };
    if let [one] = values.as_slice() {
        return Shades::Faceted(crate::emit::color_bytes(*one + own));
    }
    let screen: Vec<DVec3> = parent
        .points
        .iter()
        .map(|p| DVec3::new(p[0] as f64 * w, p[1] as f64 * h, 0.0))
        .collect();
    Shades::Gouraud(
        piece
            .iter()
            .map(|p| {
                let under = interpolate_in_polygon(&screen, &values, p.x, p.y);
                crate::emit::color_bytes(under + own)
            })
            .collect(),
    )
}

/// The pixels (column, row from the top) whose squares the box of
/// `outline` (screen points) meets.
fn pixel_box(outline: &[DVec3], view: &View) -> impl Iterator<Item = (usize, usize)> + use<> {
    let (w, h) = (view.width, view.height);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in outline {
        (lo, hi) = (lo.min(*p), hi.max(*p));
    }
    let finite = lo.is_finite() && hi.is_finite();
    let span = |a: f64, b: f64, n: f64| {
        if !finite || b <= 0.0 || a >= n {
            return 0..0;
        }
        (a.max(0.0).floor() as usize)..(b.min(n).ceil() as usize)
    };
    let cols = span(lo.x, hi.x, w);
    let rows_up = span(lo.y, hi.y, h);
    // Rows from the top: screen row `y` (from the bottom) is `h - 1 - y`.
    let rows = (h as usize - rows_up.end.min(h as usize))..(h as usize - rows_up.start);
    rows.flat_map(move |r| cols.clone().map(move |c| (c, r)))
}

/// `outline` cut to the unit square with lower left corner `(x, y)`
/// (Sutherland-Hodgman against its four sides).
fn cut_to_square(outline: &[DVec3], x: f64, y: f64) -> Vec<DVec3> {
    let sides: [(DVec3, f64); 4] = [
        (DVec3::X, x),
        (-DVec3::X, -(x + 1.0)),
        (DVec3::Y, y),
        (-DVec3::Y, -(y + 1.0)),
    ];
    let mut poly: Vec<DVec3> = outline.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
    for (n, d) in sides {
        let inside = |p: DVec3| n.dot(p) - d;
        let mut next = Vec::with_capacity(poly.len() + 2);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (inside(a), inside(b));
            if da >= 0.0 {
                next.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                next.push(a + (b - a) * (da / (da - db)));
            }
        }
        poly = next;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// The area of a screen polygon.
fn area(points: &[DVec3]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_cut_to_a_pixel_keeps_the_overlap() {
        let tri = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(0.0, 4.0, 0.0),
        ];
        // Wholly inside, on the diagonal, and outside.
        assert!((area(&cut_to_square(&tri, 0.0, 0.0)) - 1.0).abs() < 1e-12);
        assert!((area(&cut_to_square(&tri, 1.0, 2.0)) - 0.5).abs() < 1e-12);
        assert!(cut_to_square(&tri, 3.0, 3.0).len() < 3);
        // The pieces of every pixel add up to the outline's area.
        let total: f64 = (0..4)
            .flat_map(|x| (0..4).map(move |y| (x, y)))
            .map(|(x, y)| area(&cut_to_square(&tri, x as f64, y as f64)))
            .sum();
        assert!((total - 8.0).abs() < 1e-9, "{total}");
    }
}

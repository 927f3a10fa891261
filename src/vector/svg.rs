//! SVG 1.1 output, written by hand: a background rectangle, then the
//! paint items back to front (004 section 4.10's back-to-front order,
//! painted with the overwriting principle). User units are pixels of the
//! PNG, `y` down; coordinates are rounded to 0.01.

use super::gouraud::flat_pieces;
use super::{Item, Picture, Pt, push_num};

fn hex(out: &mut Vec<u8>, c: [u8; 3]) {
    const D: &[u8; 16] = b"0123456789abcdef";
    out.push(b'#');
    for v in c {
        out.push(D[(v >> 4) as usize]);
        out.push(D[(v & 15) as usize]);
    }
}

/// Path data of closed subpaths: `Mx yLx y...Z`.
pub fn path_data(out: &mut Vec<u8>, paths: &[Vec<Pt>]) {
    for p in paths {
        for (k, q) in p.iter().enumerate() {
            out.push(if k == 0 { b'M' } else { b'L' });
            push_num(out, q[0]);
            out.push(b' ');
            push_num(out, q[1]);
        }
        out.push(b'Z');
    }
}

fn fill(out: &mut Vec<u8>, paths: &[Vec<Pt>], color: [u8; 3], opacity: f32, stroke: bool) {
    out.extend_from_slice(b"<path fill=\"");
    hex(out, color);
    if opacity < 1.0 {
        out.extend_from_slice(b"\" fill-opacity=\"");
        out.extend_from_slice(format!("{:.4}", opacity).as_bytes());
    }
    if stroke {
        out.extend_from_slice(b"\" stroke=\"");
        hex(out, color);
        out.extend_from_slice(b"\" stroke-width=\"1\" stroke-linejoin=\"round");
    }
    out.extend_from_slice(b"\" d=\"");
    path_data(out, paths);
    out.extend_from_slice(b"\"/>\n");
}

/// A Gouraud run: flat pieces grouped by colour, each stroked 1 unit
/// wide in its own colour ([`super::gouraud`]). No clip path: resvg
/// rasterizes a clip mask of many abutting subpaths with the very cracks
/// the strokes remove (measured: 7 % of the sphere's pixels darkened).
fn gouraud(out: &mut Vec<u8>, triangles: &[[(Pt, [u8; 3]); 3]]) {
    out.extend_from_slice(b"<g>\n");
    for (color, paths) in pieces_by_color(triangles) {
        fill(out, &paths, color, 1.0, true);
    }
    out.extend_from_slice(b"</g>\n");
}

/// The flat pieces of a run, grouped by colour (in order of first use).
pub fn pieces_by_color(triangles: &[[(Pt, [u8; 3]); 3]]) -> Vec<([u8; 3], Vec<Vec<Pt>>)> {
    let mut index = std::collections::HashMap::new();
    let mut groups: Vec<([u8; 3], Vec<Vec<Pt>>)> = Vec::new();
    for t in triangles {
        for (tri, c) in flat_pieces(t) {
            let k = *index.entry(c).or_insert_with(|| {
                groups.push((c, Vec::new()));
                groups.len() - 1
            });
            groups[k].1.push(tri.to_vec());
        }
    }
    groups
}

/// The picture as an SVG document.
pub fn to_svg(p: &Picture) -> Vec<u8> {
    // About 14 bytes a point ("L123.45 67.8") and 64 an item: the
    // document grows once or not at all.
    let points: usize = p
        .items
        .iter()
        .map(|item| match item {
            Item::Fill { paths, .. } => paths.iter().map(Vec::len).sum(),
            Item::Gouraud { triangles, .. } => 3 * triangles.len(),
            Item::Lines { segments, .. } => 2 * segments.len(),
        })
        .sum();
    let mut out = Vec::with_capacity(256 + p.items.len() * 64 + points * 14);
    out.extend_from_slice(b"<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.extend_from_slice(b"<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"");
    push_num(&mut out, p.width);
    out.extend_from_slice(b"\" height=\"");
    push_num(&mut out, p.height);
    out.extend_from_slice(b"\" viewBox=\"0 0 ");
    push_num(&mut out, p.width);
    out.push(b' ');
    push_num(&mut out, p.height);
    out.push(b'"');
    if p.crisp {
        out.extend_from_slice(b" shape-rendering=\"crispEdges\"");
    }
    out.extend_from_slice(b">\n<rect x=\"0\" y=\"0\" width=\"");
    push_num(&mut out, p.width);
    out.extend_from_slice(b"\" height=\"");
    push_num(&mut out, p.height);
    out.extend_from_slice(b"\" fill=\"");
    hex(&mut out, p.background);
    out.extend_from_slice(b"\"/>\n");
    for item in &p.items {
        match item {
            Item::Fill {
                paths,
                color,
                opacity,
            } => fill(&mut out, paths, *color, *opacity, false),
            Item::Gouraud { triangles, .. } => gouraud(&mut out, triangles),
            Item::Lines {
                segments,
                color,
                width,
            } => {
                out.extend_from_slice(b"<path fill=\"none\" stroke=\"");
                hex(&mut out, *color);
                out.extend_from_slice(b"\" stroke-width=\"");
                push_num(&mut out, *width);
                out.extend_from_slice(b"\" stroke-linecap=\"round\" d=\"");
                for s in segments {
                    out.push(b'M');
                    push_num(&mut out, s[0][0]);
                    out.push(b' ');
                    push_num(&mut out, s[0][1]);
                    out.push(b'L');
                    push_num(&mut out, s[1][0]);
                    out.push(b' ');
                    push_num(&mut out, s[1][1]);
                }
                out.extend_from_slice(b"\"/>\n");
            }
        }
    }
    out.extend_from_slice(b"</svg>\n");
    out
}

//! Vector output: the virtual image tree as SVG, PDF or TikZ, and Brown's
//! hidden-line drawings (Garcia 1986, 004 section 4.10: one more consumer
//! of the record stream; Brown 1978, 003: face edges black, faces white).
//!
//! The picture is the tree's record stream painted back to front with
//! pre-blended shades, as the classic painter paints it (004 appendix,
//! the overwriting principle): every level, the shadows, transparency as
//! opacity. A vector painter must be exact, so visibility always comes
//! from NNS with splitting (004 section 4.4), whatever `setmode n` says.
//!
//! - [`crate::render::vector::prepare`]: the tree (NNS forced) as a back-to-front stream, with
//!   each record's source and which of its edges lie on the edges of the
//!   original polygon (for hidden lines);
//! - [`picture`]: records to paint items (filled paths, Gouraud runs,
//!   strokes), merging abutting pieces of one colour ([`merge`]) and
//!   sealing abutting faces of any colours with vertex caps ([`seal`]);
//! - [`svg`], [`pdf`], [`tikz`]: the writers; [`hidden_line`]: visible
//!   edge segments, also rasterized for PNG output.
//!
//! Framing: user units are pixels of the PNG, `x` to the right and `y`
//! down from the top left corner (SVG); PDF and TikZ flip `y` so that the
//! picture stands upright. Coordinates are rounded to 0.01 units.
//!
//! # Design notes
//!
//! `vector::prepare_for` builds the tree with NNS forced (a vector painter
//! must be exact) and emits it back to front, pre-blended, with each
//! record's `Source`; for hidden lines it stops at level 1 without shadows
//! and marks, per level-1 piece and edge, whether the edge lies on an edge
//! of the original polygon (both ends within 1e-6 of the polygon's size of
//! one original edge, in world space): NNS split lines and viewport clip
//! lines are not. `vector::picture` turns records into `Item`s (filled
//! paths, Gouraud runs, strokes), after `overlay` has inserted, behind
//! every faceted child of a shadowed ancestor, the child's intersection with
//! each shadow polygon in the shade `I_S + (I_C - I_P)` (what method 4's
//! post-blending gives, which the pre-blended painter would lose); `merge` puts consecutive-in-effect
//! records of one opaque colour into one path: a group stays open while no
//! record of another colour overlapping it (64 x 64 screen cells from
//! bounding boxes, one unit of margin) is painted; open groups are
//! pairwise disjoint, so closing order never matters. Before merging,
//! `seal` gives every vertex shared by opaque records a *cap*: the union of
//! the faces around it (one closed subpath through their far edges, filled
//! nonzero), added to the path of the first of them painted, so no
//! background shows through the anti-aliased shared edges of later faces;
//! faces near free edges (silhouettes, folds) enter a cap without a band
//! 0.4 units wide inside those edges, so outlines do not thicken; `merge`
//! carries a cap in its owner's group and drops caps over the group's own
//! records. `gouraud` cuts a
//! Gouraud triangle into `n x n` flat pieces (`n` = largest channel range
//! in levels), which SVG and TikZ stroke 1 unit wide in their colour; PDF
//! writes one type-4 shading per run. `hidden_line` cuts each flagged edge
//! by the later (front) pieces that strictly contain its points (a grid of
//! piece bounding boxes finds candidates) and rasterizes segments for PNG
//! with the exact box-filtered coverage of a 1-pixel line. Writers round
//! every coordinate to 0.01 user units; y is down in SVG and up in PDF and
//! TikZ. The binary picks vector output by the extension of `-o` and
//! writes it through the same `AtomicFile`/`Staged` commit as the PNG.

pub mod gouraud;
pub mod hidden_line;
pub mod merge;
pub mod overlay;
pub mod pdf;
pub mod seal;
pub mod svg;
pub mod tikz;

use std::path::Path;

use crate::emit::Source;
use crate::tree::{Record, RecordStream, Shades};

/// A vector format, chosen by the extension of the output file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.svg`: SVG 1.1, by hand.
    Svg,
    /// `.pdf`: one page, pdf-writer, Gouraud polygons as type-4 shadings.
    Pdf,
    /// `.tex`: one `tikzpicture` to `\input`.
    Tikz,
}

impl Format {
    /// The format `path`'s extension names, if it is a vector format.
    pub fn from_path(path: &Path) -> Option<Format> {
        let e = path.extension()?.to_str()?.to_ascii_lowercase();
        match e.as_str() {
            "svg" => Some(Format::Svg),
            "pdf" => Some(Format::Pdf),
            "tex" => Some(Format::Tikz),
            _ => None,
        }
    }

    /// Writes `picture` in this format.
    pub fn write(self, picture: &Picture, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        match self {
            Format::Svg => out.write_all(&svg::to_svg(picture)),
            Format::Pdf => out.write_all(&pdf::to_pdf(picture)),
            Format::Tikz => out.write_all(&tikz::to_tikz(picture)),
        }
    }
}

/// What the picture shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// The shaded tree, every level (the PNG's picture).
    Shaded,
    /// Brown's hidden-line drawing: white background and faces, black
    /// visible edges of the faces seen directly.
    HiddenLine,
    /// Each record filled in a false colour naming it (record index + 1
    /// as 24-bit RGB), without anti-aliasing: for tests.
    Ids,
}

/// The tree ready for vector output: a back-to-front, pre-blended record
/// stream and what each record came from.
#[derive(Debug, Clone)]
pub struct VectorInput {
    /// Back to front, pre-blended.
    pub stream: RecordStream,
    /// Each record's source polygon.
    pub sources: Vec<Source>,
    /// Per record: seen directly (level 1, a polygon, not a shadow).
    pub direct: Vec<bool>,
    /// Per record: the record of its parent fragment in the tree.
    pub parents: Vec<Option<usize>>,
    /// Per record and edge (`k` joins points `k` and `k + 1`): whether the
    /// edge lies on an edge of the original polygon (not made by NNS
    /// splitting or by clipping to the viewport). Only for direct records,
    /// and only when prepared for [`Style::HiddenLine`].
    pub original_edges: Vec<Vec<bool>>,
    /// Image width (user units).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The tree in the scene's order and blending, with `setmode o on`
    /// (the tree this picture was made from: NNS, and for hidden lines
    /// level 1 without shadows).
    pub tree_file: Option<RecordStream>,
}

/// A point in user units: `x` right, `y` down from the top left.
pub type Pt = [f64; 2];

/// The part of `poly` where `f >= 0` (Sutherland-Hodgman; for a
/// non-convex `poly` the pieces are joined along the line by edges that
/// enclose nothing).
pub(crate) fn clip_half_plane(poly: &[Pt], f: impl Fn(Pt) -> f64) -> Vec<Pt> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    for j in 0..poly.len() {
        let (p, q) = (poly[j], poly[(j + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            out.push(p);
        }
        if (fp >= 0.0) != (fq >= 0.0) {
            let t = fp / (fp - fq);
            out.push([p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]);
        }
    }
    out
}

/// A paint item, in painting order.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// Closed subpaths filled together with the nonzero rule (each
    /// counter-clockwise on screen, so overlaps stay filled).
    Fill {
        /// The subpaths.
        paths: Vec<Vec<Pt>>,
        /// Fill colour.
        color: [u8; 3],
        /// Opacity, 1 for opaque.
        opacity: f32,
    },
    /// A run of Gouraud triangles of one surface, clipped to its outline.
    Gouraud {
        /// The polygons of the run (the clip path).
        outline: Vec<Vec<Pt>>,
        /// Triangles with a colour per vertex.
        triangles: Vec<[(Pt, [u8; 3]); 3]>,
    },
    /// Strokes.
    Lines {
        /// Segments.
        segments: Vec<[Pt; 2]>,
        /// Stroke colour.
        color: [u8; 3],
        /// Stroke width in user units.
        width: f64,
    },
}

/// A whole vector picture.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// Width in user units.
    pub width: f64,
    /// Height in user units.
    pub height: f64,
    /// The background rectangle's colour.
    pub background: [u8; 3],
    /// The items, back to front.
    pub items: Vec<Item>,
    /// Paint without anti-aliasing (the id style).
    pub crisp: bool,
}

/// The picture of `input` in `style`.
pub fn picture(input: &VectorInput, style: Style) -> Picture {
    let (w, h) = (input.width as f64, input.height as f64);
    let mut pic = Picture {
        width: w,
        height: h,
        background: input.stream.background.unwrap_or([0, 0, 0]),
        items: Vec::new(),
        crisp: style == Style::Ids,
    };
    match style {
        Style::Shaded => {
            let records = overlay::with_shadow_patches(input);
            pic.items = merge::paint_items(&records, w, h);
        }
        Style::Ids => {
            pic.background = [0, 0, 0];
            let paths = input
                .stream
                .records
                .iter()
                .enumerate()
                .filter_map(|(k, r)| {
                    let id = k as u32 + 1;
                    let color = [(id >> 16) as u8, (id >> 8) as u8, id as u8];
                    (!r.is_special()).then(|| (vec![user_points(r, w, h)], color))
                });
            pic.items = paths
                .map(|(paths, color)| Item::Fill {
                    paths,
                    color,
                    opacity: 1.0,
                })
                .collect();
        }
        Style::HiddenLine => {
            pic.background = [255, 255, 255];
            let segments = hidden_line::visible_edges(input);
            if !segments.is_empty() {
                pic.items.push(Item::Lines {
                    segments,
                    color: [0, 0, 0],
                    width: 1.0,
                });
            }
        }
    }
    pic
}

/// A record's points in user units (y down), counter-clockwise on screen
/// (positive area with y down means clockwise in y-up terms; we only need
/// one consistent orientation for the nonzero rule).
pub fn user_points(r: &Record, w: f64, h: f64) -> Vec<Pt> {
    let mut pts: Vec<Pt> = r
        .points
        .iter()
        .map(|p| [p[0] as f64 * w, (1.0 - p[1] as f64) * h])
        .collect();
    if signed_area(&pts) < 0.0 {
        pts.reverse();
    }
    pts
}

/// Twice the signed area of a closed polygon.
pub fn signed_area(p: &[Pt]) -> f64 {
    crate::geometry::boolean::twice_area(p)
}

/// The record's colour per vertex and its opacity for painting over what
/// is behind: `I = I_old t + I_cur` (004 section 4.9) as
/// `I = I_old (1 - a) + a C` with `a = 1 - t`, `C = I_cur / a` (clamped).
/// Phong highlights are evaluated at the vertices. `None` for special
/// records.
pub fn vertex_paint(r: &Record) -> Option<(Vec<[u8; 3]>, f32)> {
    match &r.shades {
        Shades::Special => None,
        Shades::Faceted(c) => Some((vec![*c], 1.0)),
        Shades::Gouraud(cs) => Some((cs.clone(), 1.0)),
        Shades::Phong(ph) => {
            let t = ph.rgbt.iter().map(|v| v[3] as f32).sum::<f32>()
                / ph.rgbt.len().max(1) as f32
                / 255.0;
            let a = 1.0 - t;
            let colors = ph
                .rgbt
                .iter()
                .enumerate()
                .map(|(k, v)| {
                    std::array::from_fn(|c| {
                        let mut s = v[c] as f64 / 255.0;
                        for (l, lc) in ph.light_colors.iter().enumerate() {
                            let n = ph.normals.get(k).and_then(|ns| ns.get(l));
                            if let Some(n) = n {
                                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                                if len > 0.0 && n[2] > 0.0 {
                                    let cos = (n[2] / len) as f64;
                                    s += lc[c] as f64 / 255.0 * cos.powf(ph.shininess);
                                }
                            }
                        }
                        let s = if a > 1e-3 { s / a as f64 } else { s };
                        (s.clamp(0.0, 1.0) * 255.0).round() as u8
                    })
                })
                .collect();
            Some((colors, a.clamp(0.0, 1.0)))
        }
    }
}

/// Appends `v` rounded to 0.01, without trailing zeros.
pub fn push_num(out: &mut Vec<u8>, v: f64) {
    let i = (v * 100.0).round() as i64;
    if i < 0 {
        out.push(b'-');
    }
    let a = i.unsigned_abs();
    let (mut whole, frac) = (a / 100, a % 100);
    // The digits of the whole part, last first.
    let mut digits = [0u8; 20];
    let mut n = 0;
    loop {
        digits[n] = b'0' + (whole % 10) as u8;
        n += 1;
        whole /= 10;
        if whole == 0 {
            break;
        }
    }
    out.extend(digits[..n].iter().rev());
    if frac != 0 {
        out.push(b'.');
        out.push(b'0' + (frac / 10) as u8);
        if frac % 10 != 0 {
            out.push(b'0' + (frac % 10) as u8);
        }
    }
}

/// `v` rounded to 0.01 units.
pub fn round2(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_to_hundredths() {
        let s = |v: f64| {
            let mut o = Vec::new();
            push_num(&mut o, v);
            String::from_utf8(o).unwrap()
        };
        assert_eq!(s(12.345_6), "12.35");
        assert_eq!(s(-0.004), "0");
        assert_eq!(s(-1.5), "-1.5");
        assert_eq!(s(512.0), "512");
        assert_eq!(s(0.071), "0.07");
        assert_eq!(s(-0.3), "-0.3");
        assert_eq!(s(1234567.891), "1234567.89");
        assert_eq!(s(-100.0), "-100");
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(Format::from_path(Path::new("a.SVG")), Some(Format::Svg));
        assert_eq!(Format::from_path(Path::new("a.pdf")), Some(Format::Pdf));
        assert_eq!(Format::from_path(Path::new("a.tex")), Some(Format::Tikz));
        assert_eq!(Format::from_path(Path::new("a.png")), None);
    }
}

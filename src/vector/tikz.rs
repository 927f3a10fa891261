//! TikZ output: one `tikzpicture` to `\input` into a document that loads
//! tikz. One unit is 1 pt, `y` up (flipped from the PNG's rows), and the
//! `W x H` frame is the bounding box. Gouraud runs are flat pieces,
//! stroked in their own colour, as in SVG ([`super::gouraud`]).

use super::svg::pieces_by_color;
use super::{Item, Picture, Pt, push_num};

fn color(out: &mut Vec<u8>, c: [u8; 3]) {
    out.extend_from_slice(
        format!("{{rgb,255:red,{};green,{};blue,{}}}", c[0], c[1], c[2]).as_bytes(),
    );
}

fn point(out: &mut Vec<u8>, q: Pt, h: f64) {
    out.push(b'(');
    push_num(out, q[0]);
    out.push(b',');
    push_num(out, h - q[1]);
    out.push(b')');
}

fn paths(out: &mut Vec<u8>, ps: &[Vec<Pt>], h: f64) {
    for p in ps {
        for (k, q) in p.iter().enumerate() {
            if k > 0 {
                out.extend_from_slice(b"--");
            }
            point(out, *q, h);
        }
        out.extend_from_slice(b"--cycle\n");
    }
}

/// The picture as a TikZ picture.
pub fn to_tikz(p: &Picture) -> Vec<u8> {
    let (w, h) = (p.width, p.height);
    let mut out = Vec::new();
    out.extend_from_slice(
        b"% plytrace: \\input this into a document that loads tikz\n\
          \\begin{tikzpicture}[x=1pt,y=1pt]\n\\useasboundingbox (0,0) rectangle (",
    );
    push_num(&mut out, w);
    out.push(b',');
    push_num(&mut out, h);
    out.extend_from_slice(b");\n\\fill[fill=");
    color(&mut out, p.background);
    out.extend_from_slice(b"] (0,0) rectangle (");
    push_num(&mut out, w);
    out.push(b',');
    push_num(&mut out, h);
    out.extend_from_slice(b");\n");
    for item in &p.items {
        match item {
            Item::Fill {
                paths: ps,
                color: c,
                opacity,
            } => {
                out.extend_from_slice(b"\\fill[fill=");
                color(&mut out, *c);
                if *opacity < 1.0 {
                    out.extend_from_slice(format!(",fill opacity={:.4}", opacity).as_bytes());
                }
                out.extend_from_slice(b"] ");
                paths(&mut out, ps, h);
                out.extend_from_slice(b";\n");
            }
            Item::Gouraud { triangles, .. } => {
                out.extend_from_slice(b"\\begin{scope}\n");
                for (c, ps) in pieces_by_color(triangles) {
                    out.extend_from_slice(b"\\filldraw[line width=1pt,line join=round,fill=");
                    color(&mut out, c);
                    out.extend_from_slice(b",draw=");
                    color(&mut out, c);
                    out.extend_from_slice(b"] ");
                    paths(&mut out, &ps, h);
                    out.extend_from_slice(b";\n");
                }
                out.extend_from_slice(b"\\end{scope}\n");
            }
            Item::Lines {
                segments,
                color: c,
                width,
            } => {
                out.extend_from_slice(b"\\draw[line cap=round,line width=");
                push_num(&mut out, *width);
                out.extend_from_slice(b"pt,draw=");
                color(&mut out, *c);
                out.extend_from_slice(b"]\n");
                for s in segments {
                    point(&mut out, s[0], h);
                    out.extend_from_slice(b"--");
                    point(&mut out, s[1], h);
                    out.push(b'\n');
                }
                out.extend_from_slice(b";\n");
            }
        }
    }
    out.extend_from_slice(b"\\end{tikzpicture}\n");
    out
}

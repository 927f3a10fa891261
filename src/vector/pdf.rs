//! PDF output with pdf-writer: one page of `W x H` points (512 x 512 for
//! a 512 x 512 image), the picture upright as in the PNG (`y` flipped).
//! Flat items are filled paths; a Gouraud run is one type-4 (free-form
//! triangle mesh) shading painted with `sh` inside the run's outline as
//! clip path, so viewers interpolate the vertex shades themselves (004
//! section 4.8's interpolation is linear on a triangle). Opacity goes
//! through an ExtGState's `ca`. Coordinates are rounded to 0.01.

use pdf_writer::types::LineCapStyle;
use pdf_writer::{Content, Name, Pdf, Rect, Ref};

use super::{Item, Picture, Pt, round2};

fn unit(c: [u8; 3]) -> [f32; 3] {
    c.map(|v| v as f32 / 255.0)
}

fn path(content: &mut Content, paths: &[Vec<Pt>], h: f64) {
    for p in paths {
        for (k, q) in p.iter().enumerate() {
            let (x, y) = (round2(q[0]) as f32, round2(h - q[1]) as f32);
            if k == 0 {
                content.move_to(x, y);
            } else {
                content.line_to(x, y);
            }
        }
        content.close_path();
    }
}

/// The mesh data of a type-4 shading: per vertex a flag byte, x and y as
/// 32-bit fractions of the decode range, and r g b bytes.
fn mesh(triangles: &[[(Pt, [u8; 3]); 3]], w: f64, h: f64) -> Vec<u8> {
    let mut data = Vec::with_capacity(triangles.len() * 3 * 12);
    let q =
        |v: f64, size: f64| ((round2(v) / size).clamp(0.0, 1.0) * u32::MAX as f64).round() as u32;
    for t in triangles {
        for (p, c) in t {
            data.push(0);
            data.extend_from_slice(&q(p[0], w).to_be_bytes());
            data.extend_from_slice(&q(h - p[1], h).to_be_bytes());
            data.extend_from_slice(c);
        }
    }
    data
}

/// A page's content and the resources it names: the Gouraud runs'
/// shadings (name, object, mesh data) and the opacities' graphics states
/// (name, object, alpha).
struct Page {
    content: Content,
    shadings: Vec<(String, Ref, Vec<u8>)>,
    states: Vec<(String, Ref, f32)>,
    /// The next free object number.
    next: i32,
}

impl Page {
    fn alloc(&mut self) -> Ref {
        let r = Ref::new(self.next);
        self.next += 1;
        r
    }

    /// Paints one item of a picture `w x h`.
    fn item(&mut self, item: &Item, w: f64, h: f64) {
        match item {
            Item::Fill {
                paths,
                color,
                opacity,
            } => {
                let c = unit(*color);
                if *opacity < 1.0 {
                    let name = format!("G{}", self.states.len() + 1);
                    self.content.save_state();
                    self.content.set_parameters(Name(name.as_bytes()));
                    let id = self.alloc();
                    self.states.push((name, id, *opacity));
                }
                self.content.set_fill_rgb(c[0], c[1], c[2]);
                path(&mut self.content, paths, h);
                self.content.fill_nonzero();
                if *opacity < 1.0 {
                    self.content.restore_state();
                }
            }
            Item::Gouraud { outline, triangles } => {
                let name = format!("S{}", self.shadings.len() + 1);
                let content = &mut self.content;
                content.save_state();
                path(content, outline, h);
                content.clip_nonzero();
                content.end_path();
                content.shading(Name(name.as_bytes()));
                content.restore_state();
                let id = self.alloc();
                self.shadings.push((name, id, mesh(triangles, w, h)));
            }
            Item::Lines {
                segments,
                color,
                width,
            } => {
                let c = unit(*color);
                let content = &mut self.content;
                content.set_stroke_rgb(c[0], c[1], c[2]);
                content.set_line_width(*width as f32);
                content.set_line_cap(LineCapStyle::RoundCap);
                for s in segments {
                    content.move_to(round2(s[0][0]) as f32, round2(h - s[0][1]) as f32);
                    content.line_to(round2(s[1][0]) as f32, round2(h - s[1][1]) as f32);
                }
                content.stroke();
            }
        }
    }
}

/// The picture as a one-page PDF.
pub fn to_pdf(p: &Picture) -> Vec<u8> {
    let (w, h) = (p.width, p.height);
    let mut pdf = Pdf::new();
    let (catalog, tree, page_id, content_id) = (Ref::new(1), Ref::new(2), Ref::new(3), Ref::new(4));
    let mut page = Page {
        content: Content::new(),
        shadings: Vec::new(),
        states: Vec::new(),
        next: 5,
    };
    let bg = unit(p.background);
    page.content.set_fill_rgb(bg[0], bg[1], bg[2]);
    path(
        &mut page.content,
        &[vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]],
        h,
    );
    page.content.fill_nonzero();
    for item in &p.items {
        page.item(item, w, h);
    }
    pdf.catalog(catalog).pages(tree);
    pdf.pages(tree).kids([page_id]).count(1);
    {
        let mut writer = pdf.page(page_id);
        writer.media_box(Rect::new(0.0, 0.0, w as f32, h as f32));
        writer.parent(tree);
        writer.contents(content_id);
        let mut res = writer.resources();
        {
            let mut sh = res.shadings();
            for (name, id, _) in &page.shadings {
                sh.pair(Name(name.as_bytes()), *id);
            }
        }
        {
            let mut gs = res.ext_g_states();
            for (name, id, _) in &page.states {
                gs.pair(Name(name.as_bytes()), *id);
            }
        }
    }
    resources(&mut pdf, &page, w, h);
    let bytes = page.content.finish();
    pdf.stream(content_id, &bytes);
    pdf.finish()
}

/// The objects a page's resources name: its graphics states and its
/// type-4 shadings.
fn resources(pdf: &mut Pdf, page: &Page, w: f64, h: f64) {
    for (_, id, alpha) in &page.states {
        pdf.ext_graphics(*id).non_stroking_alpha(*alpha);
    }
    for (_, id, data) in &page.shadings {
        let mut s = pdf.stream_shading(*id, data);
        s.shading_type(pdf_writer::writers::StreamShadingType::FreeformGouraud);
        s.color_space().device_rgb();
        s.bits_per_coordinate(32)
            .bits_per_component(8)
            .bits_per_flag(8)
            .decode([0.0, w as f32, 0.0, h as f32, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
    }
}

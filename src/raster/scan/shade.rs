//! Records prepared for tiling and the shader-interpolator of 004 section
//! 5.5/5.6: vertex attributes (Gouraud `r g b`, Phong `r g b t` and
//! highlight normals, figure 5.3) are interpolated along the edges to the
//! row (Garcia's first step), then across the row (second step), and
//! evaluated at the pixel centre clamped into the polygon's span. A Phong
//! shade is `rgb + sum_L hltclr_L (n_z / |n|)^hilite`, clamped to 0..1
//! (004 section 4.8).

use glam::DVec2;

use super::edge::Edge;
use crate::error::{Error, Result};
use crate::tree::{Record, Shades};

/// Most highlight lights per Phong record (Garcia's "up to sixteen").
pub(crate) const MAX_LIGHTS: usize = 16;

/// A colour and a transparency (0 opaque, 1 fully transparent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Shade {
    /// Colour, 0 to 1.
    pub rgb: [f32; 3],
    /// Transparency `k_t`, 0 to 1.
    pub t: f32,
}

/// The interpolated attributes of one point (figure 5.3's edge structure
/// without the increments).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Attr {
    /// Shade without highlights and transparency.
    pub rgbt: [f32; 4],
    /// Highlight normals, the first `lights` used.
    pub normals: [[f32; 3]; MAX_LIGHTS],
}

impl Attr {
    /// The shade and transparency `t` of the way to `other`.
    #[inline]
    fn lerp_rgbt(&self, other: &Attr, t: f32) -> [f32; 4] {
        std::array::from_fn(|k| self.rgbt[k] + (other.rgbt[k] - self.rgbt[k]) * t)
    }

    fn lerp(&self, other: &Attr, t: f32, lights: usize) -> Attr {
        let mut out = *self;
        out.rgbt = self.lerp_rgbt(other, t);
        for l in 0..lights {
            for k in 0..3 {
                let (a, b) = (self.normals[l][k], other.normals[l][k]);
                out.normals[l][k] = a + (b - a) * t;
            }
        }
        out
    }
}

/// Phong highlight parameters of a record.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Highlights {
    pub shininess: f32,
    pub colors: Vec<[f32; 3]>,
}

/// How a record is shaded.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Shading {
    /// Special (restore) record: no shade.
    Special,
    /// One shade everywhere.
    Flat(Shade),
    /// Per-vertex attributes, with optional highlights.
    Interpolated(Vec<Attr>, Option<Highlights>),
}

/// A record in pixel coordinates (y up), ready for the tiler.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Prepared {
    pub points: Vec<DVec2>,
    pub shading: Shading,
    pub level: u16,
    pub ymin: f64,
    pub ymax: f64,
}

fn byte(v: u8) -> f32 {
    v as f32 / 255.0
}

fn attr(rgb: [u8; 3], t: u8) -> Attr {
    Attr {
        rgbt: [byte(rgb[0]), byte(rgb[1]), byte(rgb[2]), byte(t)],
        normals: [[0.0; 3]; MAX_LIGHTS],
    }
}

fn invalid(index: usize, what: &str) -> Error {
    Error::Invalid(format!("record {}: {what}", index + 1))
}

/// What [`prepare`] refuses in record `index`, found without preparing
/// it: the same error, for a record outside the rows being converted.
pub(crate) fn validate(rec: &Record, index: usize, width: u32, height: u32) -> Result<()> {
    let n = rec.points.len();
    let finite = rec.points.iter().all(|p| {
        (p[0] as f64 * width as f64).is_finite() && (p[1] as f64 * height as f64).is_finite()
    });
    if !finite {
        return Err(invalid(index, "a vertex is not a finite number"));
    }
    match &rec.shades {
        Shades::Gouraud(cs) if cs.len() != n => {
            Err(invalid(index, "Gouraud shades are not one per vertex"))
        }
        Shades::Phong(p) if p.light_colors.len() > MAX_LIGHTS => {
            Err(invalid(index, "more than 16 highlight lights"))
        }
        Shades::Phong(p)
            if p.rgbt.len() != n
                || p.normals.len() != n
                || p.normals.iter().any(|v| v.len() != p.light_colors.len()) =>
        {
            Err(invalid(
                index,
                "Phong values are not one per vertex and light",
            ))
        }
        _ => Ok(()),
    }
}

/// The rows from the bottom, as [`Prepared::ymin`] and [`Prepared::ymax`]
/// would say, of record `rec` in an image `height` rows high.
pub(crate) fn y_range(rec: &Record, height: u32) -> (f64, f64) {
    rec.points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let y = p[1] as f64 * height as f64;
            (lo.min(y), hi.max(y))
        })
}

/// Prepares a record that [`validate`] accepts for an image of `width` x
/// `height` pixels.
pub(crate) fn prepare(rec: &Record, width: u32, height: u32) -> Prepared {
    let n = rec.points.len();
    let points: Vec<DVec2> = rec
        .points
        .iter()
        .map(|p| DVec2::new(p[0] as f64 * width as f64, p[1] as f64 * height as f64))
        .collect();
    let shading = match &rec.shades {
        Shades::Special => Shading::Special,
        Shades::Faceted(c) => Shading::Flat(Shade {
            rgb: c.map(byte),
            t: 0.0,
        }),
        Shades::Gouraud(cs) => {
            Shading::Interpolated(cs.iter().map(|c| attr(*c, 0)).collect(), None)
        }
        Shades::Phong(p) => {
            let lights = p.light_colors.len();
            let attrs = (0..n)
                .map(|k| {
                    let c = p.rgbt[k];
                    let mut a = attr([c[0], c[1], c[2]], c[3]);
                    a.normals[..lights].copy_from_slice(&p.normals[k]);
                    a
                })
                .collect();
            let hl = (lights > 0).then(|| Highlights {
                shininess: p.shininess as f32,
                colors: p.light_colors.iter().map(|c| c.map(byte)).collect(),
            });
            Shading::Interpolated(attrs, hl)
        }
    };
    let (ymin, ymax) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    Prepared {
        points,
        shading,
        level: rec.level,
        ymin,
        ymax,
    }
}

/// Garcia's second step for one row: the polygon's spans on the line
/// `y_eval` with the attributes at their ends, then values across.
#[derive(Debug, Default)]
pub(crate) struct RowShader {
    ends: Vec<(f64, Attr)>,
}

impl RowShader {
    /// Interpolates along the active `edges` of `poly` to the row `j`'s
    /// centre line clamped into the polygon's y-range (the first step).
    pub fn setup(&mut self, poly: &Prepared, j: u32, edges: &[Edge]) {
        self.ends.clear();
        let Shading::Interpolated(attrs, hl) = &poly.shading else {
            return;
        };
        let lights = hl.as_ref().map_or(0, |h| h.colors.len());
        let y = (j as f64 + 0.5).clamp(poly.ymin, poly.ymax);
        let at_top = y >= poly.ymax;
        for e in edges {
            let (pp, qq) = (e.lo, e.hi);
            let inside = if at_top {
                pp.y < y && y <= qq.y
            } else {
                pp.y <= y && y < qq.y
            };
            if inside {
                let t = (y - pp.y) / (qq.y - pp.y);
                let x = pp.x + t * (qq.x - pp.x);
                let (a, b) = (&attrs[e.lo_vertex as usize], &attrs[e.hi_vertex as usize]);
                self.ends.push((x, a.lerp(b, t as f32, lights)));
            }
        }
        self.ends.sort_by(|a, b| a.0.total_cmp(&b.0));
    }

    /// The shade of `poly` at pixel column `i` of the row set up last.
    pub fn shade(&self, poly: &Prepared, i: u32) -> Shade {
        match &poly.shading {
            Shading::Special => Shade {
                rgb: [0.0; 3],
                t: 0.0,
            },
            Shading::Flat(s) => *s,
            Shading::Interpolated(attrs, None) => {
                // No highlights: the shade alone is interpolated.
                let rgbt = match self.span_at(i as f64 + 0.5) {
                    Some((a0, a1, t)) => a0.lerp_rgbt(a1, t),
                    None => attrs[0].rgbt,
                };
                finish(rgbt)
            }
            Shading::Interpolated(attrs, hl) => {
                let lights = hl.as_ref().map_or(0, |h| h.colors.len());
                let v = self.value_at(i as f64 + 0.5, lights).unwrap_or(attrs[0]);
                evaluate(&v, hl.as_ref())
            }
        }
    }

    /// The attributes at `x`, in the span holding it or else the nearest.
    fn value_at(&self, x: f64, lights: usize) -> Option<Attr> {
        let (a0, a1, t) = self.span_at(x)?;
        Some(a0.lerp(a1, t, lights))
    }

    /// The ends of the span holding `x`, or else the nearest, and where
    /// `x` lies between them (0 to 1).
    fn span_at(&self, x: f64) -> Option<(&Attr, &Attr, f32)> {
        let mut best: Option<(f64, &[(f64, Attr)])> = None;
        for pair in self.ends.chunks_exact(2) {
            let d = if x < pair[0].0 {
                pair[0].0 - x
            } else if x >= pair[1].0 {
                x - pair[1].0
            } else {
                -1.0
            };
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, pair));
            }
        }
        let (_, pair) = best?;
        let ((x0, a0), (x1, a1)) = (&pair[0], &pair[1]);
        let t = if x1 > x0 {
            ((x - x0) / (x1 - x0)).clamp(0.0, 1.0)
        } else {
            0.0
        } as f32;
        Some((a0, a1, t))
    }
}

/// The shade of interpolated attributes `v`.
fn evaluate(v: &Attr, hl: Option<&Highlights>) -> Shade {
    let mut c = [v.rgbt[0], v.rgbt[1], v.rgbt[2]];
    if let Some(h) = hl {
        for (l, color) in h.colors.iter().enumerate() {
            let n = v.normals[l];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if len > 0.0 && n[2] > 0.0 {
                let k = (n[2] / len).powf(h.shininess);
                for (ci, i) in c.iter_mut().zip(color) {
                    *ci += i * k;
                }
            }
        }
    }
    finish([c[0], c[1], c[2], v.rgbt[3]])
}

/// A shade from a colour and transparency, clamped to 0..1.
#[inline]
fn finish(rgbt: [f32; 4]) -> Shade {
    Shade {
        rgb: [rgbt[0], rgbt[1], rgbt[2]].map(|x| x.clamp(0.0, 1.0)),
        t: rgbt[3].clamp(0.0, 1.0),
    }
}

//! Virtual image tree files (Garcia 1986, 004 section 4.10, figure 4.14):
//! the polygons of the tree in output order, each with its level, as
//! *Special* (type 0: the restore polygon between a reflected and a
//! refracted branch), *Faceted* (type 1: one shade) or *Gouraud* (type 2:
//! a shade per vertex) records. Written with `setmode o on`.
//!
//! Binary form (little-endian), `FNAME.out`:
//!
//! ```text
//! magic    4 bytes  "VIT1"
//! version  u16      1
//! width    u32      image width the tree was made for
//! height   u32      image height
//! order    u8       0 back to front, 1 front to back
//! blended  u8       1 if shades are pre-blended (setmode b on)
//! count    u32      number of records
//! record:  type u8 (b'0' special, b'1' faceted, b'2' gouraud)
//!          level u16, nvtx u16
//!          faceted: r g b (u8 each), then nvtx x (x f32, y f32)
//!          special: nvtx x (x f32, y f32)
//!          gouraud: nvtx x (x f32, y f32, r g b u8)
//!          phong (type b'3'): hilite f64, nlt u16, nlt x (r g b u8),
//!                 then nvtx x (x f32, y f32, r g b t u8, nlt x (nx ny nz f32))
//! ```
//!
//! x and y are normalized screen coordinates, 0 to 1 from the lower left
//! corner, as the figure says. The text form, `FNAME.txt`, has the same
//! content one record per line (`faceted LEVEL NVTX R G B X Y ...`), with
//! numbers printed so that they read back to the same bits.

use std::fmt::Write as _;

use crate::error::{Error, Location, Result};

/// A record's type (figure 4.14).
#[derive(Debug, Clone, PartialEq)]
pub enum Shades {
    /// Type 0: no shade (the restore polygon).
    Special,
    /// Type 1: one shade.
    Faceted([u8; 3]),
    /// Type 2: one shade per vertex.
    Gouraud(Vec<[u8; 3]>),
    /// Type 3: Phong, with highlight vectors per vertex and light.
    Phong(PhongShades),
}

/// The Phong parameters of figure 4.14: `<hilite> <nlt> <hltclr>` and, per
/// vertex, `<r g b t>` and `nlt` highlight normal vectors.
#[derive(Debug, Clone, PartialEq)]
pub struct PhongShades {
    /// Shininess of the surface (`hilite`, a double).
    pub shininess: f64,
    /// The highlight colour of each light (`hltclr`).
    pub light_colors: Vec<[u8; 3]>,
    /// Per vertex: shade without highlights and transparency.
    pub rgbt: Vec<[u8; 4]>,
    /// Per vertex, per light: the highlight normal vector (`hltnmals`).
    pub normals: Vec<Vec<[f32; 3]>>,
}

/// One polygon of the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Tree level, from 1.
    pub level: u16,
    /// Vertices, normalized screen coordinates.
    pub points: Vec<[f32; 2]>,
    /// Its shades.
    pub shades: Shades,
}

/// A whole tree file.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeFile {
    /// Image width the tree was made for.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Front to back (else back to front).
    pub front_to_back: bool,
    /// Shades pre-blended.
    pub blended: bool,
    /// Records in output order.
    pub records: Vec<Record>,
}

const MAGIC: &[u8; 4] = b"VIT1";
const VERSION: u16 = 1;

impl TreeFile {
    /// The binary form.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&self.width.to_le_bytes());
        b.extend_from_slice(&self.height.to_le_bytes());
        b.push(self.front_to_back as u8);
        b.push(self.blended as u8);
        b.extend_from_slice(&(self.records.len() as u32).to_le_bytes());
        for r in &self.records {
            b.push(match r.shades {
                Shades::Special => b'0',
                Shades::Faceted(_) => b'1',
                Shades::Gouraud(_) => b'2',
                Shades::Phong(_) => b'3',
            });
            b.extend_from_slice(&r.level.to_le_bytes());
            b.extend_from_slice(&(r.points.len() as u16).to_le_bytes());
            if let Shades::Faceted(c) = &r.shades {
                b.extend_from_slice(c);
            }
            if let Shades::Phong(ph) = &r.shades {
                b.extend_from_slice(&ph.shininess.to_le_bytes());
                b.extend_from_slice(&(ph.light_colors.len() as u16).to_le_bytes());
                for c in &ph.light_colors {
                    b.extend_from_slice(c);
                }
            }
            for (k, p) in r.points.iter().enumerate() {
                b.extend_from_slice(&p[0].to_le_bytes());
                b.extend_from_slice(&p[1].to_le_bytes());
                if let Shades::Gouraud(cs) = &r.shades {
                    b.extend_from_slice(&cs[k]);
                }
                if let Shades::Phong(ph) = &r.shades {
                    b.extend_from_slice(&ph.rgbt[k]);
                    for n in &ph.normals[k] {
                        for v in n {
                            b.extend_from_slice(&v.to_le_bytes());
                        }
                    }
                }
            }
        }
        b
    }

    /// Reads the binary form; `file` names it in errors.
    pub fn from_bytes(bytes: &[u8], file: &std::path::Path) -> Result<TreeFile> {
        let mut r = Reader { bytes, at: 0, file };
        if r.take(4)? != MAGIC {
            return Err(r.error("not a virtual image tree file (expected the magic `VIT1`)"));
        }
        let version = r.u16()?;
        if version != VERSION {
            return Err(r.error(format!(
                "version {version}; this program reads version {VERSION}"
            )));
        }
        let width = r.u32()?;
        let height = r.u32()?;
        let order = r.u8()?;
        let blended = r.u8()?;
        if order > 1 || blended > 1 {
            return Err(r.error("order and blended flags must be 0 or 1"));
        }
        let count = r.u32()?;
        // Each record takes at least 5 bytes: do not trust the count.
        let mut records = Vec::with_capacity((count as usize).min(bytes.len() / 5));
        for _ in 0..count {
            let kind = r.u8()?;
            let level = r.u16()?;
            let n = r.u16()? as usize;
            let faceted = if kind == b'1' {
                let c = r.take(3)?;
                Some([c[0], c[1], c[2]])
            } else {
                None
            };
            if !matches!(kind, b'0' | b'1' | b'2' | b'3') {
                return Err(r.error(format!("unknown record type {kind}")));
            }
            let mut phong = if kind == b'3' {
                let shininess = f64::from_le_bytes(r.take(8)?.try_into().expect("8 bytes"));
                if !shininess.is_finite() {
                    return Err(r.error("non-finite shininess"));
                }
                let nlt = r.u16()? as usize;
                let mut light_colors = Vec::with_capacity(nlt.min(bytes.len() / 3));
                for _ in 0..nlt {
                    let c = r.take(3)?;
                    light_colors.push([c[0], c[1], c[2]]);
                }
                Some(PhongShades {
                    shininess,
                    light_colors,
                    rgbt: Vec::new(),
                    normals: Vec::new(),
                })
            } else {
                None
            };
            let mut points = Vec::with_capacity(n.min(bytes.len() / 8));
            let mut colors = Vec::new();
            for _ in 0..n {
                let x = r.f32()?;
                let y = r.f32()?;
                if !(x.is_finite() && y.is_finite()) {
                    return Err(r.error("non-finite vertex coordinate"));
                }
                points.push([x, y]);
                if kind == b'2' {
                    let c = r.take(3)?;
                    colors.push([c[0], c[1], c[2]]);
                }
                if let Some(ph) = &mut phong {
                    let c = r.take(4)?;
                    ph.rgbt.push([c[0], c[1], c[2], c[3]]);
                    let mut ns = Vec::with_capacity(ph.light_colors.len());
                    for _ in 0..ph.light_colors.len() {
                        let n = [r.f32()?, r.f32()?, r.f32()?];
                        if !n.iter().all(|v| v.is_finite()) {
                            return Err(r.error("non-finite highlight vector"));
                        }
                        ns.push(n);
                    }
                    ph.normals.push(ns);
                }
            }
            let shades = match kind {
                b'0' => Shades::Special,
                b'1' => Shades::Faceted(faceted.expect("read above")),
                b'3' => Shades::Phong(phong.expect("read above")),
                _ => Shades::Gouraud(colors),
            };
            records.push(Record {
                level,
                points,
                shades,
            });
        }
        if r.at != bytes.len() {
            return Err(r.error("unexpected bytes after the last record"));
        }
        Ok(TreeFile {
            width,
            height,
            front_to_back: order == 1,
            blended: blended == 1,
            records,
        })
    }

    /// The text form.
    pub fn to_text(&self) -> String {
        let mut s = String::from("# plytrace virtual image tree, version 1 (004 figure 4.14)\n");
        let _ = writeln!(s, "resolution {} {}", self.width, self.height);
        let _ = writeln!(
            s,
            "order {}",
            if self.front_to_back { "ftb" } else { "btf" }
        );
        let _ = writeln!(s, "blended {}", if self.blended { "on" } else { "off" });
        for r in &self.records {
            let n = r.points.len();
            match &r.shades {
                Shades::Special => {
                    let _ = write!(s, "special {} {n}", r.level);
                }
                Shades::Faceted(c) => {
                    let _ = write!(s, "faceted {} {n} {} {} {}", r.level, c[0], c[1], c[2]);
                }
                Shades::Gouraud(_) => {
                    let _ = write!(s, "gouraud {} {n}", r.level);
                }
                Shades::Phong(ph) => {
                    let _ = write!(
                        s,
                        "phong {} {n} {} {}",
                        r.level,
                        ph.shininess,
                        ph.light_colors.len()
                    );
                    for c in &ph.light_colors {
                        let _ = write!(s, " {} {} {}", c[0], c[1], c[2]);
                    }
                }
            }
            for (k, p) in r.points.iter().enumerate() {
                let _ = write!(s, " {} {}", p[0], p[1]);
                if let Shades::Gouraud(cs) = &r.shades {
                    let _ = write!(s, " {} {} {}", cs[k][0], cs[k][1], cs[k][2]);
                }
                if let Shades::Phong(ph) = &r.shades {
                    let c = ph.rgbt[k];
                    let _ = write!(s, " {} {} {} {}", c[0], c[1], c[2], c[3]);
                    for v in &ph.normals[k] {
                        let _ = write!(s, " {} {} {}", v[0], v[1], v[2]);
                    }
                }
            }
            s.push('\n');
        }
        s
    }

    /// Reads the text form.
    pub fn from_text(text: &str, file: &std::path::Path) -> Result<TreeFile> {
        let mut tree = TreeFile {
            width: 0,
            height: 0,
            front_to_back: false,
            blended: false,
            records: Vec::new(),
        };
        for (ln, line) in text.lines().enumerate() {
            let line_no = ln + 1;
            let words: Vec<&str> = line.split_whitespace().collect();
            if words.is_empty() || words[0].starts_with('#') {
                continue;
            }
            let err = |msg: String| Error::at(Location::new(file, line_no, 1), msg);
            let num = |i: usize| -> Result<&str> {
                words
                    .get(i)
                    .copied()
                    .ok_or_else(|| err(format!("`{}` line ends early", words[0])))
            };
            match words[0] {
                "resolution" => {
                    tree.width = num(1)?
                        .parse()
                        .map_err(|_| err("expected a width".into()))?;
                    tree.height = num(2)?
                        .parse()
                        .map_err(|_| err("expected a height".into()))?;
                }
                "order" => tree.front_to_back = num(1)? == "ftb",
                "blended" => tree.blended = num(1)? == "on",
                "phong" => tree.records.push(phong_record(&words, &err)?),
                kind @ ("special" | "faceted" | "gouraud") => {
                    let level: u16 = num(1)?
                        .parse()
                        .map_err(|_| err("expected a level".into()))?;
                    let n: usize = num(2)?
                        .parse()
                        .map_err(|_| err("expected a vertex count".into()))?;
                    let mut at = 3;
                    let faceted = if kind == "faceted" {
                        at += 3;
                        Some([
                            word::<u8>(&words, 3, "a colour byte", &err)?,
                            word::<u8>(&words, 4, "a colour byte", &err)?,
                            word::<u8>(&words, 5, "a colour byte", &err)?,
                        ])
                    } else {
                        None
                    };
                    let per = if kind == "gouraud" { 5 } else { 2 };
                    if words.len() != at + n * per {
                        return Err(err(format!(
                            "expected {} words for {n} vertices, found {}",
                            at + n * per,
                            words.len()
                        )));
                    }
                    let mut points = Vec::with_capacity(n);
                    let mut colors = Vec::new();
                    for _ in 0..n {
                        points.push([finite(&words, at, &err)?, finite(&words, at + 1, &err)?]);
                        if kind == "gouraud" {
                            colors.push([
                                word::<u8>(&words, at + 2, "a colour byte", &err)?,
                                word::<u8>(&words, at + 3, "a colour byte", &err)?,
                                word::<u8>(&words, at + 4, "a colour byte", &err)?,
                            ]);
                        }
                        at += per;
                    }
                    let shades = match kind {
                        "special" => Shades::Special,
                        "faceted" => Shades::Faceted(faceted.expect("read above")),
                        _ => Shades::Gouraud(colors),
                    };
                    tree.records.push(Record {
                        level,
                        points,
                        shades,
                    });
                }
                other => return Err(err(format!("unknown record `{other}`"))),
            }
        }
        Ok(tree)
    }
}

/// Word `i` of a text record parsed as `T`, or an error saying `what`.
fn word<T: std::str::FromStr>(
    words: &[&str],
    i: usize,
    what: &str,
    err: &dyn Fn(String) -> Error,
) -> Result<T> {
    let w = words
        .get(i)
        .ok_or_else(|| err(format!("the line ends before {what} (word {})", i + 1)))?;
    w.parse()
        .map_err(|_| err(format!("expected {what} at word {}, found `{w}`", i + 1)))
}

/// A finite `f32` at word `i`.
fn finite(words: &[&str], i: usize, err: &dyn Fn(String) -> Error) -> Result<f32> {
    let v: f32 = word(words, i, "a number", err)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(format!("non-finite number at word {}", i + 1)))
    }
}

/// A `phong LEVEL NVTX HILITE NLT (R G B)*NLT (X Y R G B T (NX NY NZ)*NLT)*NVTX`
/// line of the text form.
fn phong_record(words: &[&str], err: &dyn Fn(String) -> Error) -> Result<Record> {
    let num = |i: usize| -> Result<&str> {
        words
            .get(i)
            .copied()
            .ok_or_else(|| err("`phong` line ends early".into()))
    };
    let level: u16 = num(1)?
        .parse()
        .map_err(|_| err("expected a level".into()))?;
    let n: usize = num(2)?
        .parse()
        .map_err(|_| err("expected a vertex count".into()))?;
    let shininess: f64 = num(3)?
        .parse()
        .map_err(|_| err("expected a shininess".into()))?;
    let nlt: usize = num(4)?
        .parse()
        .map_err(|_| err("expected a light count".into()))?;
    if !shininess.is_finite() {
        return Err(err("non-finite shininess".into()));
    }
    let per = 6 + 3 * nlt;
    let head = 5 + 3 * nlt;
    if n.checked_mul(per).and_then(|v| v.checked_add(head)) != Some(words.len()) {
        return Err(err(format!(
            "expected {} words per vertex after {head}, found {} words",
            per,
            words.len()
        )));
    }
    let light_colors = (0..nlt)
        .map(|l| {
            Ok([
                word::<u8>(words, 5 + 3 * l, "a colour byte", &err)?,
                word::<u8>(words, 6 + 3 * l, "a colour byte", &err)?,
                word::<u8>(words, 7 + 3 * l, "a colour byte", &err)?,
            ])
        })
        .collect::<Result<Vec<_>>>()?;
    let (mut points, mut rgbt, mut normals) = (Vec::new(), Vec::new(), Vec::new());
    for v in 0..n {
        let at = head + v * per;
        points.push([finite(words, at, &err)?, finite(words, at + 1, &err)?]);
        rgbt.push([
            word::<u8>(words, at + 2, "a colour byte", &err)?,
            word::<u8>(words, at + 3, "a colour byte", &err)?,
            word::<u8>(words, at + 4, "a colour byte", &err)?,
            word::<u8>(words, at + 5, "a colour byte", &err)?,
        ]);
        normals.push(
            (0..nlt)
                .map(|l| {
                    let b = at + 6 + 3 * l;
                    Ok([
                        finite(words, b, &err)?,
                        finite(words, b + 1, &err)?,
                        finite(words, b + 2, &err)?,
                    ])
                })
                .collect::<Result<Vec<_>>>()?,
        );
    }
    Ok(Record {
        level,
        points,
        shades: Shades::Phong(PhongShades {
            shininess,
            light_colors,
            rgbt,
            normals,
        }),
    })
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    file: &'a std::path::Path,
}

impl Reader<'_> {
    fn error(&self, msg: impl Into<String>) -> Error {
        Error::at(
            Location::file(self.file),
            format!("byte {}: {}", self.at, msg.into()),
        )
    }
    fn take(&mut self, n: usize) -> Result<&[u8]> {
        if self.bytes.len() - self.at < n {
            return Err(self.error(format!("file ends early (expected {n} more bytes)")));
        }
        self.at += n;
        Ok(&self.bytes[self.at - n..self.at])
    }
    fn u8(&mut self) -> Result<u8> {
        Ok(self.take(1)?[0])
    }
    fn u16(&mut self) -> Result<u16> {
        Ok(u16::from_le_bytes(
            self.take(2)?.try_into().expect("2 bytes"),
        ))
    }
    fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }
    fn f32(&mut self) -> Result<f32> {
        Ok(f32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::path::Path;

    fn sample() -> TreeFile {
        TreeFile {
            width: 512,
            height: 480,
            front_to_back: false,
            blended: true,
            records: vec![
                Record {
                    level: 1,
                    points: vec![[0.1, 0.2], [0.5, 0.25], [0.3, 0.9]],
                    shades: Shades::Faceted([10, 200, 30]),
                },
                Record {
                    level: 2,
                    points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0 / 3.0, 0.7]],
                    shades: Shades::Gouraud(vec![[1, 2, 3], [4, 5, 6], [7, 8, 9], [255, 0, 128]]),
                },
                Record {
                    level: 1,
                    points: vec![[0.1, 0.2], [0.5, 0.25], [0.3, 0.9]],
                    shades: Shades::Special,
                },
                Record {
                    level: 3,
                    points: vec![[0.1, 0.2], [0.5, 0.25], [0.3, 0.9]],
                    shades: Shades::Phong(PhongShades {
                        shininess: 120.5,
                        light_colors: vec![[255, 250, 240], [10, 20, 30]],
                        rgbt: vec![[1, 2, 3, 0], [4, 5, 6, 128], [7, 8, 9, 255]],
                        normals: vec![
                            vec![[0.1, 0.2, 0.97], [0.0, 0.0, 1.0]],
                            vec![[-0.3, 0.1, 0.9], [0.2, -0.2, 0.95]],
                            vec![[0.0, 0.5, 0.8], [1.0 / 3.0, 0.1, 0.5]],
                        ],
                    }),
                },
            ],
        }
    }

    #[test]
    fn both_forms_round_trip() {
        let t = sample();
        assert_eq!(
            TreeFile::from_bytes(&t.to_bytes(), Path::new("t.out")).unwrap(),
            t
        );
        assert_eq!(
            TreeFile::from_text(&t.to_text(), Path::new("t.txt")).unwrap(),
            t
        );
    }

    #[test]
    fn hostile_binary_is_a_clean_error() {
        let bytes = sample().to_bytes();
        for cut in 0..bytes.len() {
            assert!(
                TreeFile::from_bytes(&bytes[..cut], Path::new("t.out")).is_err(),
                "cut {cut}"
            );
        }
        let mut huge = bytes[..17].to_vec();
        huge.extend_from_slice(&u32::MAX.to_le_bytes());
        assert!(TreeFile::from_bytes(&huge, Path::new("t.out")).is_err());
        let mut bad = bytes.clone();
        bad[0] = b'X';
        assert!(TreeFile::from_bytes(&bad, Path::new("t.out")).is_err());
    }

    #[test]
    fn bad_text_names_line_and_word() {
        let text = "resolution 4 4\nfaceted 1 3 1 2 3 0 0 1 0 x 1\n";
        let e = TreeFile::from_text(text, Path::new("t.txt"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.txt:2:1:") && e.contains("word 11") && e.contains("`x`"),
            "{e}"
        );
        let e = TreeFile::from_text("phong 1 1 2.0 1 255 255\n", Path::new("t.txt"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.txt:1:1:"), "{e}");
    }

    proptest! {
        #[test]
        fn random_trees_round_trip(
            recs in prop::collection::vec((1u16..15, prop::collection::vec((0f32..1.0, 0f32..1.0), 3..8), 0u8..3, any::<u8>()), 0..20)
        ) {
            let records = recs.into_iter().map(|(level, pts, kind, c)| {
                let points: Vec<[f32; 2]> = pts.into_iter().map(|(x, y)| [x, y]).collect();
                let shades = match kind {
                    0 => Shades::Special,
                    1 => Shades::Faceted([c, c / 2, 255 - c]),
                    _ => Shades::Gouraud(points.iter().map(|_| [c, 1, 2]).collect()),
                };
                Record { level, points, shades }
            }).collect();
            let t = TreeFile { width: 64, height: 32, front_to_back: true, blended: false, records };
            prop_assert_eq!(TreeFile::from_bytes(&t.to_bytes(), Path::new("x")).unwrap(), t.clone());
            prop_assert_eq!(TreeFile::from_text(&t.to_text(), Path::new("x")).unwrap(), t);
        }
    }
}

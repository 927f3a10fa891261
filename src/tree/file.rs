//! Virtual image tree files (Garcia 1986, 004 section 4.10, figure 4.14,
//! and the plytrace and rftb manual pages): a [`RecordStream`] written as
//! `FNAME.out` (binary) and `FNAME.txt` (text).
//!
//! The binary form is nothing but figure 4.14's records, one after the
//! other, little-endian, with no header:
//!
//! ```text
//! record:  type u8 (b'0' special, b'1' faceted, b'2' gouraud, b'3' phong)
//!          level u16, nvtx u16
//!          special: nvtx x (x f32, y f32)
//!          faceted: r g b (u8 each), then nvtx x (x f32, y f32)
//!          gouraud: nvtx x (x f32, y f32, r g b u8)
//!          phong:   hilite f64, nlt u16, nlt x (r g b u8),
//!                   then nvtx x (x f32, y f32, r g b t u8, nlt x (nx ny nz f32))
//! ```
//!
//! x and y are normalized screen coordinates, 0 to 1 from the lower left
//! corner, as the figure says ("x,y floats 0 to 1"), so one file renders
//! at any resolution. They are snapped into [0, 1] ([`fn@unit`]) in one
//! place, where plytrace makes them (`crate::emit`): a vertex clipped to
//! the screen's edge can come out a rounding error beyond it (`-1.1e-16`,
//! or `-0`), which the figure does not allow. Both forms then write the
//! same bits, and the tree in memory is the tree in the files.
//!
//! The background polygon. The rftb manual page's `-B` paints "a
//! background polygon, with color specified in the input data file": it is
//! a record at level 0 (tree levels run from 1 to 31), the unit square
//! `(0,0) (0,1) (1,1) (1,0)` in the background colour. Its place says the
//! order, its type the blending mode, so that rftb can refuse a tree made
//! for another method:
//!
//! - first record: back to front; last record: front to back;
//! - type 1 (faceted): pre-blended shades (`setmode b on`); type 2
//!   (Gouraud, four equal shades): post-blended.
//!
//! A file without a level-0 record is read as front to back with
//! post-blended shades and no background. The text form, `FNAME.txt`, has
//! the same records one per line (`faceted LEVEL NVTX R G B X Y ...`), the
//! background record among them, with numbers printed so that they read
//! back to the same bits.

use std::fmt::Write as _;

use crate::error::{Error, Location, Result};
use crate::tree::record::{PhongShades, Record, RecordStream, Shades};

/// The corners of the background record, clockwise from the lower left.
const UNIT_SQUARE: [[f32; 2]; 4] = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];

/// A coordinate snapped into figure 4.14's range, 0 to 1: below 0
/// (negative zero included) is 0, above 1 is 1. Only a rounding error is
/// expected beyond the range, the clipper having cut everything to the
/// screen. A NaN is kept (a tree holds none; the readers refuse one).
/// `crate::emit` applies it to every coordinate it makes.
pub fn unit(v: f32) -> f32 {
    if v.is_nan() {
        v
    } else if v > 0.0 {
        v.min(1.0)
    } else {
        0.0
    }
}

impl RecordStream {
    /// The records as written: the background record (if any) first for
    /// back to front, last for front to back.
    pub fn file_records(&self) -> Vec<std::borrow::Cow<'_, Record>> {
        use std::borrow::Cow;
        let mut out: Vec<Cow<'_, Record>> = self.records.iter().map(Cow::Borrowed).collect();
        if let Some(c) = self.background {
            let shades = if self.blended {
                Shades::Faceted(c)
            } else {
                Shades::Gouraud(vec![c; 4])
            };
            let bg = Cow::Owned(Record {
                level: 0,
                points: UNIT_SQUARE.to_vec(),
                shades,
            });
            if self.front_to_back {
                out.push(bg);
            } else {
                out.insert(0, bg);
            }
        }
        out
    }

    /// The stream read back from `records` as they stand in a file: the
    /// level-0 background record is taken out and gives the order and the
    /// blending mode.
    fn from_file_records(mut records: Vec<Record>, file: &std::path::Path) -> Result<RecordStream> {
        let err = |msg: String| Error::at(Location::file(file), msg);
        for (i, r) in records.iter().enumerate() {
            if r.level > 31 {
                return Err(err(format!(
                    "record {}: level {}; levels run from 1 to 31 (0 for the background)",
                    i + 1,
                    r.level
                )));
            }
            if r.points.len() < 3 {
                return Err(err(format!(
                    "record {}: {} vertices; a polygon has at least 3",
                    i + 1,
                    r.points.len()
                )));
            }
        }
        let zeros: Vec<usize> = (0..records.len())
            .filter(|&i| records[i].level == 0)
            .collect();
        let mut stream = RecordStream {
            records: Vec::new(),
            background: None,
            front_to_back: true,
            blended: false,
        };
        match zeros.as_slice() {
            [] => {}
            [i] if *i == 0 || *i + 1 == records.len() => {
                let bg = records.remove(*i);
                if bg.points.len() != 4 {
                    return Err(err(format!(
                        "record {}: the level-0 background record has {} vertices, not 4",
                        i + 1,
                        bg.points.len()
                    )));
                }
                let (color, blended) = match &bg.shades {
                    Shades::Faceted(c) => (*c, true),
                    Shades::Gouraud(cs) if cs.iter().all(|c| *c == cs[0]) => (cs[0], false),
                    _ => {
                        return Err(err(format!(
                            "record {}: the level-0 background record must be faceted or \
                             Gouraud with one colour",
                            i + 1
                        )));
                    }
                };
                stream.background = Some(color);
                stream.blended = blended;
                // A lone record is both first and last: front to back.
                stream.front_to_back = *i != 0 || records.is_empty();
            }
            _ => {
                return Err(err(format!(
                    "record {}: level 0 is only for the background record, first or last",
                    zeros
                        .iter()
                        .find(|&&i| i != 0 && i + 1 != records.len())
                        .unwrap_or(&zeros[zeros.len() - 1])
                        + 1
                )));
            }
        }
        stream.records = records;
        Ok(stream)
    }

    /// The binary form.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = Vec::new();
        for r in self.file_records() {
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
    pub fn from_bytes(bytes: &[u8], file: &std::path::Path) -> Result<RecordStream> {
        let mut r = Reader { bytes, at: 0, file };
        // Each record takes at least 5 bytes.
        let mut records = Vec::with_capacity((bytes.len() / 5).min(1 << 16));
        while r.at < bytes.len() {
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
                return Err(r.error(format!(
                    "not a virtual image tree record: type byte {kind} (expected '0' to '3')"
                )));
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
                b'3' => Shades::Phong(Box::new(phong.expect("read above"))),
                _ => Shades::Gouraud(colors),
            };
            records.push(Record {
                level,
                points,
                shades,
            });
        }
        RecordStream::from_file_records(records, file)
    }

    /// The text form.
    pub fn to_text(&self) -> String {
        let mut s = String::from(
            "# plytrace virtual image tree (004 figure 4.14); level 0 is the background\n",
        );
        for r in self.file_records() {
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
    pub fn from_text(text: &str, file: &std::path::Path) -> Result<RecordStream> {
        let mut records = Vec::new();
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
                "phong" => records.push(phong_record(&words, &err)?),
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
                    let expected = n.checked_mul(per).and_then(|v| v.checked_add(at));
                    if expected != Some(words.len()) {
                        return Err(err(format!(
                            "expected {} words for {n} vertices, found {}",
                            expected.map_or("too many".to_string(), |e| e.to_string()),
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
                    records.push(Record {
                        level,
                        points,
                        shades,
                    });
                }
                other => return Err(err(format!("unknown record `{other}`"))),
            }
        }
        RecordStream::from_file_records(records, file)
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
        shades: Shades::Phong(Box::new(PhongShades {
            shininess,
            light_colors,
            rgbt,
            normals,
        })),
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

    fn sample() -> RecordStream {
        RecordStream {
            background: Some([3, 4, 5]),
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
                    shades: Shades::Phong(Box::new(PhongShades {
                        shininess: 120.5,
                        light_colors: vec![[255, 250, 240], [10, 20, 30]],
                        rgbt: vec![[1, 2, 3, 0], [4, 5, 6, 128], [7, 8, 9, 255]],
                        normals: vec![
                            vec![[0.1, 0.2, 0.97], [0.0, 0.0, 1.0]],
                            vec![[-0.3, 0.1, 0.9], [0.2, -0.2, 0.95]],
                            vec![[0.0, 0.5, 0.8], [1.0 / 3.0, 0.1, 0.5]],
                        ],
                    })),
                },
            ],
        }
    }

    #[test]
    fn both_forms_round_trip() {
        let t = sample();
        assert_eq!(
            RecordStream::from_bytes(&t.to_bytes(), Path::new("t.out")).unwrap(),
            t
        );
        assert_eq!(
            RecordStream::from_text(&t.to_text(), Path::new("t.txt")).unwrap(),
            t
        );
    }

    #[test]
    fn hostile_binary_is_a_clean_error() {
        let bytes = sample().to_bytes();
        let whole = sample();
        for cut in 0..bytes.len() {
            // A cut between records is a shorter tree; any other is an error.
            if let Ok(t) = RecordStream::from_bytes(&bytes[..cut], Path::new("t.out")) {
                let n = t.records.len();
                assert_eq!(t.records[..], whole.records[..n], "cut {cut}");
            }
        }
        let mut huge = bytes[..5].to_vec();
        huge.extend_from_slice(&u16::MAX.to_le_bytes());
        assert!(RecordStream::from_bytes(&huge, Path::new("t.out")).is_err());
        let mut bad = bytes.clone();
        bad[0] = b'X';
        assert!(RecordStream::from_bytes(&bad, Path::new("t.out")).is_err());
    }

    #[test]
    fn a_background_record_in_the_middle_is_an_error() {
        let mut t = sample();
        t.front_to_back = true;
        let mut bytes = t.to_bytes();
        // Put a second copy of the records after the background record.
        bytes.extend_from_slice(
            &RecordStream {
                background: None,
                ..sample()
            }
            .to_bytes(),
        );
        let e = RecordStream::from_bytes(&bytes, Path::new("t.out"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("level 0 is only for the background"), "{e}");
        let e = RecordStream::from_text("faceted 1 99999999999999999 1 2 3\n", Path::new("t.txt"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.txt:1:1:"), "{e}");
    }

    #[test]
    fn bad_text_names_line_and_word() {
        let text = "# a comment\nfaceted 1 3 1 2 3 0 0 1 0 x 1\n";
        let e = RecordStream::from_text(text, Path::new("t.txt"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.txt:2:1:") && e.contains("word 11") && e.contains("`x`"),
            "{e}"
        );
        let e = RecordStream::from_text("phong 1 1 2.0 1 255 255\n", Path::new("t.txt"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.txt:1:1:"), "{e}");
    }

    proptest! {
        #[test]
        fn random_trees_round_trip(
            recs in prop::collection::vec((1u16..15, prop::collection::vec((0f32..1.0, 0f32..1.0), 3..8), 0u8..3, any::<u8>()), 0..20), ftb in any::<bool>(), blended in any::<bool>()
        ) {
            let records: Vec<Record> = recs.into_iter().map(|(level, pts, kind, c)| {
                let points: Vec<[f32; 2]> = pts.into_iter().map(|(x, y)| [x, y]).collect();
                let shades = match kind {
                    0 => Shades::Special,
                    1 => Shades::Faceted([c, c / 2, 255 - c]),
                    _ => Shades::Gouraud(points.iter().map(|_| [c, 1, 2]).collect()),
                };
                Record { level, points, shades }
            }).collect();
            let front_to_back = ftb || records.is_empty();
            let t = RecordStream { background: Some([9, 8, 7]), front_to_back, blended, records };
            prop_assert_eq!(RecordStream::from_bytes(&t.to_bytes(), Path::new("x")).unwrap(), t.clone());
            prop_assert_eq!(RecordStream::from_text(&t.to_text(), Path::new("x")).unwrap(), t);
        }

        /// Figure 4.14: "x,y floats 0 to 1". Coordinates snapped by
        /// [`unit`] lie within [0, 1], with no negative zero, and both
        /// forms write them bit for bit; those already within are kept.
        #[test]
        fn snapped_coordinates_are_within_0_and_1_in_both_forms(
            pts in prop::collection::vec(
                prop_oneof![
                    -1e-6f32..1.0 + 1e-6,
                    Just(-0.0f32),
                    Just(-1.110_223e-16f32),
                    Just(1.000_000_1f32),
                    0f32..=1.0,
                ],
                6..16,
            ),
            ftb in any::<bool>(),
        ) {
            let points: Vec<[f32; 2]> =
                pts.chunks_exact(2).map(|p| [unit(p[0]), unit(p[1])]).collect();
            let t = RecordStream {
                records: vec![Record { level: 1, points, shades: Shades::Faceted([1, 2, 3]) }],
                background: Some([0, 0, 0]),
                front_to_back: ftb,
                blended: true,
            };
            let bin = RecordStream::from_bytes(&t.to_bytes(), Path::new("x")).unwrap();
            let txt = RecordStream::from_text(&t.to_text(), Path::new("x")).unwrap();
            prop_assert_eq!(&bin, &t);
            prop_assert_eq!(&txt, &t);
            for (got, was) in bin.records[0].points.iter().flatten().zip(pts.iter()) {
                prop_assert!((0.0..=1.0).contains(got) && got.is_sign_positive(), "{got:e}");
                if (0.0..=1.0).contains(was) && was.is_sign_positive() {
                    prop_assert_eq!(got.to_bits(), was.to_bits());
                }
            }
        }
    }

    #[test]
    fn unit_snaps_into_0_and_1() {
        assert_eq!(unit(-1.110_223e-16).to_bits(), 0f32.to_bits());
        assert_eq!(unit(-0.0).to_bits(), 0f32.to_bits());
        assert_eq!(unit(0.25), 0.25);
        assert_eq!(unit(1.000_000_1), 1.0);
        assert!(unit(f32::NAN).is_nan());
    }
}

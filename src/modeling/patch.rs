//! Bicubic patches (Firebaugh 001, chapter 8): Bezier patches (equation
//! 8.6) and Hermite patches (equations 8.16-8.18), read from patch files,
//! tessellated, and checked for C0 and C1 continuity across shared edges.
//!
//! File layouts (whitespace separated; `#` starts a comment):
//!
//! * Bezier (`.bpt`): the patch count, then per patch a line `3 3` and 16
//!   points `x y z`, the control points row by row `P00 P01 ... P33`.
//!   `P(s, t) = sum_ij B_i(s) B_j(t) P_ij`: `s` runs along the first index.
//! * Hermite: the patch count, then per patch 16 points, the geometry
//!   matrix of 8.18 row by row: `P00 P01 Pt00 Pt01 / P10 P11 Pt10 Pt11 /
//!   Ps00 Ps01 Pst00 Pst01 / Ps10 Ps11 Pst10 Pst11`.
//!
//! Tessellation samples `nu + 1` by `nv + 1` points per patch with their
//! exact normals `dP/ds x dP/dt`, splits each cell into two triangles, and
//! joins the patches' coincident points. A surface that closes up is
//! oriented outward; one that does not is open (two-sided).

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::{Generated, solid};
use crate::budget::Budgets;
use crate::error::{Error, Location};
use crate::model::Mesh;

/// The two patch forms.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// Bezier control points (eq. 8.6).
    Bezier,
    /// Hermite geometry matrix (eq. 8.18).
    Hermite,
}

/// A bicubic patch as its Bezier control points `P[i][j]` (`i` along `s`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// Control points, row `i` (along `s`), column `j` (along `t`).
    pub p: [[DVec3; 4]; 4],
}

/// The Bernstein polynomials of degree 3 and their derivatives at `u`.
fn bernstein(u: f64) -> ([f64; 4], [f64; 4]) {
    let v = 1.0 - u;
    (
        [v * v * v, 3.0 * u * v * v, 3.0 * u * u * v, u * u * u],
        [
            -3.0 * v * v,
            3.0 * v * v - 6.0 * u * v,
            6.0 * u * v - 3.0 * u * u,
            3.0 * u * u,
        ],
    )
}

impl Patch {
    /// The Bezier form of a Hermite geometry matrix `g` (eq. 8.18): per
    /// curve `B0 = P0, B1 = P0 + P0'/3, B2 = P1 - P1'/3, B3 = P1`, applied
    /// along both parameters (`M G M^T`).
    pub fn from_hermite(g: &[[DVec3; 4]; 4]) -> Patch {
        const M: [[f64; 4]; 4] = [
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 1.0 / 3.0, 0.0],
            [0.0, 1.0, 0.0, -1.0 / 3.0],
            [0.0, 1.0, 0.0, 0.0],
        ];
        let mut mg = [[DVec3::ZERO; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                mg[i][j] = (0..4).map(|k| g[k][j] * M[i][k]).sum();
            }
        }
        let mut p = [[DVec3::ZERO; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                p[i][j] = (0..4).map(|k| mg[i][k] * M[j][k]).sum();
            }
        }
        Patch { p }
    }

    /// `P(s, t)` and its partial derivatives along `s` and `t`.
    pub fn eval(&self, s: f64, t: f64) -> (DVec3, DVec3, DVec3) {
        let (bs, ds) = bernstein(s);
        let (bt, dt) = bernstein(t);
        let (mut p, mut ps, mut pt) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for i in 0..4 {
            for j in 0..4 {
                let c = self.p[i][j];
                p += c * (bs[i] * bt[j]);
                ps += c * (ds[i] * bt[j]);
                pt += c * (bs[i] * dt[j]);
            }
        }
        (p, ps, pt)
    }

    /// The unit normal `dP/ds x dP/dt` at `(s, t)`; where it vanishes (a
    /// collapsed edge) the normal a little inside the patch.
    pub fn normal(&self, s: f64, t: f64) -> DVec3 {
        let (_, ps, pt) = self.eval(s, t);
        if let Some(n) = ps.cross(pt).try_normalize() {
            return n;
        }
        let h = 1e-6;
        let (s2, t2) = (
            s + if s > 0.5 { -h } else { h },
            t + if t > 0.5 { -h } else { h },
        );
        let (_, ps, pt) = self.eval(s2, t2);
        ps.cross(pt).normalize_or_zero()
    }
}

/// A patch file's patches, as Bezier patches.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchSet {
    /// The patches.
    pub patches: Vec<Patch>,
}

/// A token of a patch file with its position.
struct Tok<'a> {
    text: &'a str,
    line: usize,
    column: usize,
}

fn tokens(text: &str) -> Vec<Tok<'_>> {
    let mut out = Vec::new();
    for (l, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        let mut rest = line;
        // Characters before `rest`, counted as we go: counting from the
        // line's start for every token is quadratic on a one-line file.
        let mut column = 0;
        while let Some(start) = rest.find(|c: char| !c.is_whitespace()) {
            column += rest[..start].chars().count();
            let from = &rest[start..];
            let len = from.find(char::is_whitespace).unwrap_or(from.len());
            out.push(Tok {
                text: &from[..len],
                line: l + 1,
                column: column + 1,
            });
            column += from[..len].chars().count();
            rest = &from[len..];
        }
    }
    out
}

/// The largest patch file read.
pub const MAX_PATCH_FILE_BYTES: u64 = 256 << 20;

/// Reads the patch count of `path` and refuses (through `budget`, given
/// the count) before the points are read, then reads the patches.
pub fn read(
    path: &Path,
    form: Form,
    budget: impl FnOnce(usize) -> Result<(), Error>,
) -> Result<PatchSet, Error> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.len() > MAX_PATCH_FILE_BYTES {
        return Err(Error::at(
            Location::file(path),
            format!("a patch file larger than {MAX_PATCH_FILE_BYTES} bytes"),
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse(&text, path, form, budget)
}

/// Parses the text of a patch file (see [`read`]).
pub fn parse(
    text: &str,
    path: &Path,
    form: Form,
    budget: impl FnOnce(usize) -> Result<(), Error>,
) -> Result<PatchSet, Error> {
    let toks = tokens(text);
    let at = |t: &Tok| Location::new(path, t.line, t.column);
    let end = || {
        let lines = text.lines().count();
        Location::new(path, lines.max(1), 1)
    };
    let Some(first) = toks.first() else {
        return Err(Error::at(
            end(),
            "an empty patch file: expected the patch count",
        ));
    };
    let count: usize = first.text.parse().ok().filter(|&n| n > 0).ok_or_else(|| {
        Error::at(
            at(first),
            format!(
                "expected the patch count (a whole number of at least 1), found `{}`",
                crate::error::printable(first.text, 40)
            ),
        )
    })?;
    budget(count)?;
    let per_patch = if form == Form::Bezier { 2 + 48 } else { 48 };
    let want = count.checked_mul(per_patch).and_then(|n| n.checked_add(1));
    if want != Some(toks.len()) {
        let found = toks.len() - 1;
        let points = |n: usize| n / 3;
        let msg = match form {
            Form::Bezier => format!(
                "{count} Bezier patches need {count} lines `3 3` and {} points (16 per patch); the file has {found} numbers after the count instead of {}",
                count * 16,
                count * per_patch
            ),
            Form::Hermite => format!(
                "{count} Hermite patches need {} points (16 per patch); the file has {} points ({found} numbers) after the count",
                count * 16,
                points(found)
            ),
        };
        let loc = if toks.len() > want.unwrap_or(usize::MAX) {
            at(&toks[want.unwrap_or(0)])
        } else {
            end()
        };
        return Err(Error::at(loc, msg));
    }
    let mut patches = Vec::with_capacity(count);
    let mut k = 1;
    for n in 0..count {
        patches.push(read_patch(&toks, &mut k, n, form, path)?);
    }
    Ok(PatchSet { patches })
}

/// Patch `n` (from 0) of a patch file, from its token `*k` on: for Bezier
/// the degrees `3 3`, then 16 points; `*k` is left past it.
fn read_patch(
    toks: &[Tok],
    k: &mut usize,
    n: usize,
    form: Form,
    path: &Path,
) -> Result<Patch, Error> {
    let at = |t: &Tok| Location::new(path, t.line, t.column);
    if form == Form::Bezier {
        for _ in 0..2 {
            let t = &toks[*k];
            if t.text != "3" {
                return Err(Error::at(
                    at(t),
                    format!(
                        "patch {}: expected the degrees `3 3` (bicubic), found `{}`",
                        n + 1,
                        crate::error::printable(t.text, 40)
                    ),
                ));
            }
            *k += 1;
        }
    }
    let mut g = [[DVec3::ZERO; 4]; 4];
    for row in g.iter_mut() {
        for p in row.iter_mut() {
            let mut c = [0.0; 3];
            for x in c.iter_mut() {
                let t = &toks[*k];
                *x = t
                    .text
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        Error::at(
                            at(t),
                            format!(
                                "patch {}: expected a finite coordinate, found `{}`",
                                n + 1,
                                crate::error::printable(t.text, 40)
                            ),
                        )
                    })?;
                *k += 1;
            }
            *p = DVec3::from_array(c);
        }
    }
    Ok(match form {
        Form::Bezier => Patch { p: g },
        Form::Hermite => Patch::from_hermite(&g),
    })
}

/// Triangles of `count` patches at `nu` x `nv`: `2 nu nv` each.
pub fn face_count(count: usize, nu: usize, nv: usize) -> Option<usize> {
    count.checked_mul(nu)?.checked_mul(nv)?.checked_mul(2)
}

/// Tessellates the patches (`nu`, `nv` steps of `s`, `t`) into triangles
/// with exact normals, joining coincident points of adjacent patches.
pub fn tessellate(set: &PatchSet, nu: usize, nv: usize) -> Generated {
    let mut vertices: Vec<DVec3> = Vec::new();
    let mut normal_sums: Vec<DVec3> = Vec::new();
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut polygons = Vec::new();
    let scale = set
        .patches
        .iter()
        .flat_map(|p| p.p.iter().flatten())
        .fold(0.0f64, |m, v| m.max(v.abs().max_element()))
        .max(f64::MIN_POSITIVE);
    // Points closer than 1e-9 of the size are one point.
    let quantum = scale * 1e-9;
    for patch in &set.patches {
        let mut ids = Vec::with_capacity((nu + 1) * (nv + 1));
        for i in 0..=nu {
            for j in 0..=nv {
                let (s, t) = (i as f64 / nu as f64, j as f64 / nv as f64);
                let (p, _, _) = patch.eval(s, t);
                let key = (p / quantum)
                    .round()
                    .to_array()
                    .map(|c| (c + 0.0).to_bits());
                let n = patch.normal(s, t);
                let id = *index.entry(key).or_insert_with(|| {
                    vertices.push(p);
                    normal_sums.push(DVec3::ZERO);
                    (vertices.len() - 1) as u32
                });
                normal_sums[id as usize] += n;
                ids.push(id);
            }
        }
        let at = |i: usize, j: usize| ids[i * (nv + 1) + j];
        for i in 0..nu {
            for j in 0..nv {
                // (s, t) is counter-clockwise about dP/ds x dP/dt: clockwise
                // seen from that side is (s0,t0), (s0,t1), (s1,t1), (s1,t0).
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                for tri in [[a, b, c], [a, c, d]] {
                    if tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] {
                        polygons.push(tri.to_vec());
                    }
                }
            }
        }
    }
    let mut normals: Vec<DVec3> = normal_sums
        .iter()
        .map(|n| n.normalize_or(DVec3::Z))
        .collect();
    let mut mesh = Mesh::new(vertices, polygons);
    let closed = solid::is_closed(&mesh);
    if closed {
        solid::orient_outward(&mut mesh, Some(&mut normals));
    }
    Generated {
        mesh,
        normals: Some(normals),
        open: !closed,
    }
}

/// Continuity across one shared patch edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Join {
    /// The two patches (0-based).
    pub patches: (usize, usize),
    /// Largest distance between the two boundary curves (C0: 0).
    pub c0_gap: f64,
    /// Largest difference of the cross-boundary derivatives, the second
    /// patch's taken outward from the first (C1: 0).
    pub c1_gap: f64,
    /// Largest angle (radians) between the cross-boundary derivatives
    /// (G1, tangent-plane continuity: 0).
    pub g1_angle: f64,
}

/// What [`continuity`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuityReport {
    /// Every pair of patches whose edges share both end points.
    pub joins: Vec<Join>,
}

impl ContinuityReport {
    /// Whether every join is C0 within `tol` (relative to the surface's size).
    pub fn c0(&self, tol: f64) -> bool {
        self.joins.iter().all(|j| j.c0_gap <= tol)
    }
    /// Whether every join is C1 within `tol`.
    pub fn c1(&self, tol: f64) -> bool {
        self.joins.iter().all(|j| j.c1_gap <= tol)
    }
}

/// The four boundary edges of a patch as (parameter point on the edge at
/// `u`, derivative across the edge pointing out of the patch).
fn edge(p: &Patch, e: usize, u: f64) -> (DVec3, DVec3) {
    let (s, t, sign_s, sign_t) = match e {
        0 => (0.0, u, -1.0, 0.0),
        1 => (1.0, u, 1.0, 0.0),
        2 => (u, 0.0, 0.0, -1.0),
        _ => (u, 1.0, 0.0, 1.0),
    };
    let (q, ps, pt) = p.eval(s, t);
    (q, ps * sign_s + pt * sign_t)
}

/// Checks C0 and C1 continuity between every two patches that share an
/// edge (same end points, in either direction), sampling 9 points along
/// it. A gap is measured relative to the surface's size. Unbounded; see
/// [`continuity_within`].
pub fn continuity(set: &PatchSet) -> ContinuityReport {
    match continuity_within(set, u64::MAX) {
        Ok(r) => r,
        Err(_) => ContinuityReport { joins: Vec::new() },
    }
}

/// Why [`continuity_within`] stopped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ContinuityStop {
    /// More than the allowed edge pairs share their end points (patches
    /// piled on one another): the count when it stopped.
    Pairs(u64),
    /// Ctrl-C.
    Cancelled,
}

/// [`continuity`], comparing only edges whose end points meet (found
/// through a grid of cells of the tolerance, not over all pairs of
/// patches) and at most `max_pairs` edge pairs.
pub fn continuity_within(
    set: &PatchSet,
    max_pairs: u64,
) -> Result<ContinuityReport, ContinuityStop> {
    let size = set
        .patches
        .iter()
        .flat_map(|p| p.p.iter().flatten())
        .fold(0.0f64, |m, v| m.max(v.length()))
        .max(f64::MIN_POSITIVE);
    let tol = 1e-9 * size;
    let close = |a: DVec3, b: DVec3| a.distance(b) <= tol;
    // The end points of every edge, and a grid of the first ones.
    let ends: Vec<[(DVec3, DVec3); 4]> = set
        .patches
        .iter()
        .map(|p| std::array::from_fn(|e| (edge(p, e, 0.0).0, edge(p, e, 1.0).0)))
        .collect();
    let cell = |p: DVec3| (p / tol).floor().to_array().map(|c| c as i64);
    let mut grid: HashMap<[i64; 3], Vec<(u32, u8, bool)>> = HashMap::new();
    for (b, e) in ends.iter().enumerate() {
        for (eb, &(b0, b1)) in e.iter().enumerate() {
            grid.entry(cell(b0))
                .or_default()
                .push((b as u32, eb as u8, false));
            grid.entry(cell(b1))
                .or_default()
                .push((b as u32, eb as u8, true));
        }
    }
    let mut pairs = 0u64;
    let mut found: Vec<(usize, usize, usize, usize, bool)> = Vec::new();
    let mut near = Vec::new();
    for (a, ea_ends) in ends.iter().enumerate() {
        if a % 1024 == 0 && crate::cancel::requested() {
            return Err(ContinuityStop::Cancelled);
        }
        for (ea, &(a0, a1)) in ea_ends.iter().enumerate() {
            // Edges with an end point near a0: a shared edge has one.
            near.clear();
            let c = cell(a0);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                            near.extend(list.iter().filter(|(b, _, _)| *b as usize > a));
                        }
                    }
                }
            }
            near.sort_unstable();
            near.dedup_by_key(|(b, eb, _)| (*b, *eb));
            pairs = pairs.saturating_add(near.len() as u64);
            if pairs > max_pairs {
                return Err(ContinuityStop::Pairs(pairs));
            }
            for &(b, eb, _) in near.iter() {
                let (b0, b1) = ends[b as usize][eb as usize];
                let reversed = if close(a0, b0) && close(a1, b1) {
                    false
                } else if close(a0, b1) && close(a1, b0) {
                    true
                } else {
                    continue;
                };
                found.push((a, b as usize, ea, eb as usize, reversed));
            }
        }
    }
    // The order of a scan over all pairs: by patches, then edges.
    found.sort_unstable();
    let mut joins = Vec::with_capacity(found.len());
    for (k, &(a, b, ea, eb, reversed)) in found.iter().enumerate() {
        if k % 4096 == 0 && crate::cancel::requested() {
            return Err(ContinuityStop::Cancelled);
        }
        let (pa, pb) = (&set.patches[a], &set.patches[b]);
        let (mut c0, mut c1, mut g1) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..=8 {
            let u = k as f64 / 8.0;
            let (qa, da) = edge(pa, ea, u);
            let (qb, db) = edge(pb, eb, if reversed { 1.0 - u } else { u });
            c0 = c0.max(qa.distance(qb) / size);
            // Outward from a is inward to b.
            c1 = c1.max((da + db).length() / size);
            g1 = g1.max(da.angle_between(-db));
        }
        joins.push(Join {
            patches: (a, b),
            c0_gap: c0,
            c1_gap: c1,
            g1_angle: g1,
        });
    }
    Ok(ContinuityReport { joins })
}

/// `plytrace continuity FILE [bezier|hermite]`: reads a patch file (the
/// form from the word, else `.hpt` is Hermite and anything else Bezier)
/// and reports, per shared edge and overall, C0 and C1 continuity (gaps
/// relative to the surface's size, within `1e-9`) and the G1 angle.
pub fn continuity_report(path: &Path, form: Option<&str>) -> Result<String, Error> {
    continuity_report_within(path, form, &Budgets::default())
}

/// [`continuity_report`] under `budgets`: the patch count under
/// [`Budgets::polygons`] (`--max-polygons`), the edge pairs compared
/// under [`Budgets::pair_tests`] (`--max-pair-tests`).
pub fn continuity_report_within(
    path: &Path,
    form: Option<&str>,
    budgets: &Budgets,
) -> Result<String, Error> {
    let form = match form.map(str::to_ascii_lowercase).as_deref() {
        Some("bezier") => Form::Bezier,
        Some("hermite") => Form::Hermite,
        Some(other) => {
            return Err(Error::at(
                Location::file("<command line>"),
                format!(
                    "expected `bezier` or `hermite`, found `{}`",
                    crate::error::printable(other, 40)
                ),
            ));
        }
        None if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("hpt")) =>
        {
            Form::Hermite
        }
        None => Form::Bezier,
    };
    let set = read(path, form, |count| {
        if count > budgets.polygons {
            return Err(Error::at(
                Location::file(path),
                Budgets::exceeded(
                    &format!("{count} patches"),
                    budgets.polygons,
                    "--max-polygons",
                ),
            ));
        }
        Ok(())
    })?;
    let r = continuity_within(&set, budgets.pair_tests).map_err(|stop| match stop {
        ContinuityStop::Cancelled => Error::Cancelled,
        ContinuityStop::Pairs(n) => Error::at(
            Location::file(path),
            Budgets::exceeded(
                &format!("the patch edges sharing end points ({n} pairs and more)"),
                budgets.pair_tests,
                "--max-pair-tests",
            ),
        ),
    })?;
    let tol = 1e-9;
    let yes = |b: bool| if b { "yes" } else { "NO" };
    let mut out = format!(
        "{}: {} {} patches, {} shared edges\n",
        path.display(),
        set.patches.len(),
        if form == Form::Bezier {
            "Bezier"
        } else {
            "Hermite"
        },
        r.joins.len()
    );
    for j in &r.joins {
        out += &format!(
            "  patches {} and {}: C0 {} (gap {:.2e}), C1 {} (derivative gap {:.2e}), G1 angle {:.4} deg\n",
            j.patches.0 + 1,
            j.patches.1 + 1,
            yes(j.c0_gap <= tol),
            j.c0_gap,
            yes(j.c1_gap <= tol),
            j.c1_gap,
            j.g1_angle.to_degrees()
        );
    }
    out += &format!(
        "C0 everywhere: {}\nC1 everywhere: {}",
        yes(r.c0(tol)),
        yes(r.c1(tol))
    );
    Ok(out)
}

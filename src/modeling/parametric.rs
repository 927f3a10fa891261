//! Parametric solids of Firebaugh's chapter 8 (001): the sphere of
//! equations 8.2-8.3, the cylinder, and superquadrics with scale factors
//! (equations 8.19 and 8.22) and their exact normals (equation 8.23).
//!
//! The surface is sampled on a grid of `nu` steps of the longitude `s`
//! (0..2 pi about z) and `nv` steps of the latitude `t` (-pi/2..pi/2).
//! The two poles are single vertices; the seam `s = 2 pi` reuses the
//! vertices of `s = 0`. Polygons are clockwise seen from outside.

use std::f64::consts::{FRAC_PI_2, TAU};

use glam::DVec3;

use super::Generated;
use crate::model::Mesh;

/// `sign(x) |x|^e`: the signed power that keeps equation 8.19 real for
/// negative sines and cosines (Firebaugh's replacement after figure 8.9).
/// At `x = 0` it is 0 for every exponent: for `e <= 0` that is the mean of
/// the two one-sided limits (`+inf` and `-inf`, or `+1` and `-1`), which
/// keeps the normals of 8.23 finite where it is singular.
pub fn spow(x: f64, e: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x.signum() * x.abs().powf(e)
    }
}

/// A superquadric (eq. 8.22): exponents `e1` (latitude), `e2`
/// (longitude) and scale factors `a`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Superquadric {
    /// Shape exponent of the latitude `t`.
    pub e1: f64,
    /// Shape exponent of the longitude `s`.
    pub e2: f64,
    /// Scale factors `(ax, ay, az)`.
    pub a: DVec3,
}

impl Superquadric {
    /// The unit sphere: `e1 = e2 = 1`, unit scale.
    pub const SPHERE: Superquadric = Superquadric {
        e1: 1.0,
        e2: 1.0,
        a: DVec3::ONE,
    };

    /// `P(s, t)` of equation 8.22.
    pub fn point(&self, s: f64, t: f64) -> DVec3 {
        let (ct, st) = cos_sin(t);
        let (cs, ss) = cos_sin(s);
        let r = spow(ct, self.e1);
        DVec3::new(
            self.a.x * r * spow(cs, self.e2),
            self.a.y * r * spow(ss, self.e2),
            self.a.z * spow(st, self.e1),
        )
    }

    /// The outward unit normal `N(s, t)` of equation 8.23; at its
    /// singularities the limit of [`spow`], always finite.
    pub fn normal(&self, s: f64, t: f64) -> DVec3 {
        let (ct, st) = cos_sin(t);
        let (cs, ss) = cos_sin(s);
        let r = spow(ct, 2.0 - self.e1);
        let n = DVec3::new(
            r * spow(cs, 2.0 - self.e2) / self.a.x,
            r * spow(ss, 2.0 - self.e2) / self.a.y,
            spow(st, 2.0 - self.e1) / self.a.z,
        );
        n.try_normalize()
            .unwrap_or(if t >= 0.0 { DVec3::Z } else { -DVec3::Z })
    }

    /// The enclosed volume, `2 ax ay az e1 e2 B(e1/2 + 1, e1) B(e2/2, e2/2)`.
    pub fn volume(&self) -> f64 {
        let beta = |a: f64, b: f64| (ln_gamma(a) + ln_gamma(b) - ln_gamma(a + b)).exp();
        2.0 * self.a.x
            * self.a.y
            * self.a.z
            * self.e1
            * self.e2
            * beta(self.e1 / 2.0 + 1.0, self.e1)
            * beta(self.e2 / 2.0, self.e2 / 2.0)
    }
}

/// `ln Gamma(x)` for `x > 0` (Lanczos, g = 7, 9 terms; about 1e-15).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * TAU.ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Cosine and sine, exactly 0 and +-1 at the multiples of pi/2 that the
/// grid hits (so poles and axis points are exact and the normals' limits
/// apply there).
fn cos_sin(angle: f64) -> (f64, f64) {
    let quarter = angle / FRAC_PI_2;
    let k = quarter.round();
    if (quarter - k).abs() < 1e-12 {
        match (k as i64).rem_euclid(4) {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        }
    } else {
        (angle.cos(), angle.sin())
    }
}

/// Polygons of a `nu` x `nv` latitude-longitude grid: `nu * nv` when the
/// quads are kept whole, `2 nu (nv - 1)` triangles otherwise. `None` on
/// overflow.
pub fn grid_face_count(nu: usize, nv: usize, quads: bool) -> Option<usize> {
    if quads {
        nu.checked_mul(nv)
    } else {
        nu.checked_mul(nv.checked_sub(1)?)?.checked_mul(2)
    }
}

/// The grid of `surface` (`nu >= 3`, `nv >= 2`): poles, rings of
/// latitude, quads (planar on surfaces of revolution) or triangles.
fn grid(
    nu: usize,
    nv: usize,
    quads: bool,
    point: impl Fn(f64, f64) -> DVec3,
    normal: impl Fn(f64, f64) -> DVec3,
) -> Generated {
    let s_at = |i: usize| TAU * i as f64 / nu as f64;
    let t_at = |j: usize| -FRAC_PI_2 + std::f64::consts::PI * j as f64 / nv as f64;
    let mut vertices = Vec::with_capacity(nu * (nv - 1) + 2);
    let mut normals = Vec::with_capacity(vertices.capacity());
    vertices.push(point(0.0, -FRAC_PI_2));
    normals.push(normal(0.0, -FRAC_PI_2));
    for j in 1..nv {
        for i in 0..nu {
            vertices.push(point(s_at(i), t_at(j)));
            normals.push(normal(s_at(i), t_at(j)));
        }
    }
    vertices.push(point(0.0, FRAC_PI_2));
    normals.push(normal(0.0, FRAC_PI_2));
    let (south, north) = (0u32, (vertices.len() - 1) as u32);
    // Ring j (1..nv), column i (mod nu).
    let at = |i: usize, j: usize| -> u32 {
        if j == 0 {
            south
        } else if j == nv {
            north
        } else {
            (1 + (j - 1) * nu + i % nu) as u32
        }
    };
    let mut polygons = Vec::with_capacity(grid_face_count(nu, nv, quads).unwrap_or(0));
    for j in 0..nv {
        for i in 0..nu {
            // s runs counter-clockwise about z, t upward: (s, t) order is
            // counter-clockwise from outside, so each cell is listed
            // (s0,t0), (s0,t1), (s1,t1), (s1,t0).
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            if j == 0 {
                polygons.push(vec![a, b, c]);
            } else if j == nv - 1 {
                polygons.push(vec![a, b, d]);
            } else if quads {
                polygons.push(vec![a, b, c, d]);
            } else {
                polygons.push(vec![a, b, c]);
                polygons.push(vec![a, c, d]);
            }
        }
    }
    Generated {
        mesh: Mesh::new(vertices, polygons),
        normals: Some(normals),
        open: false,
    }
}

/// `sphere NU NV`: the unit sphere (eq. 8.19 with `e1 = e2 = 1`), its
/// cells planar quads and the polar caps triangles: `nu * nv` polygons.
pub fn sphere(nu: usize, nv: usize) -> Generated {
    let q = Superquadric::SPHERE;
    grid(nu, nv, true, |s, t| q.point(s, t), |s, t| q.point(s, t))
}

/// Polygons of `superquadric ... NU NV`: `2 nu (nv - 1)` triangles.
pub fn superquadric_face_count(nu: usize, nv: usize) -> Option<usize> {
    grid_face_count(nu, nv, false)
}

/// `superquadric E1 E2 NU NV [AX AY AZ]`: triangles with the normals of
/// eq. 8.23.
pub fn superquadric(q: &Superquadric, nu: usize, nv: usize) -> Generated {
    grid(nu, nv, false, |s, t| q.point(s, t), |s, t| q.normal(s, t))
}

/// Polygons of `cylinder NU`: `nu` sides and, when capped, two caps.
pub fn cylinder_face_count(nu: usize, capped: bool) -> Option<usize> {
    nu.checked_add(if capped { 2 } else { 0 })
}

/// `cylinder NU [capped|open]`: radius 1 about z, `z` from -1 to 1. The
/// caps' rims repeat the side's vertices with normals along z; an open
/// cylinder is two-sided.
pub fn cylinder(nu: usize, capped: bool) -> Generated {
    let ring = |z: f64| {
        (0..nu)
            .map(move |i| cos_sin(TAU * i as f64 / nu as f64))
            .map(move |(c, s)| DVec3::new(c, s, z))
    };
    let mut vertices: Vec<DVec3> = ring(-1.0).chain(ring(1.0)).collect();
    let mut normals: Vec<DVec3> = vertices.iter().map(|v| DVec3::new(v.x, v.y, 0.0)).collect();
    let n = nu as u32;
    let mut polygons: Vec<Vec<u32>> = (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            vec![i, n + i, n + j, j]
        })
        .collect();
    if capped {
        let base = vertices.len() as u32;
        vertices.extend(ring(-1.0).chain(ring(1.0)));
        normals.extend(std::iter::repeat_n(-DVec3::Z, nu));
        normals.extend(std::iter::repeat_n(DVec3::Z, nu));
        // Bottom seen from below (outside): counter-clockwise from above.
        polygons.push((0..n).map(|i| base + i).collect());
        polygons.push((0..n).rev().map(|i| base + n + i).collect());
    }
    Generated {
        mesh: Mesh::new(vertices, polygons),
        normals: Some(normals),
        open: !capped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_gamma_matches_known_values() {
        assert!((ln_gamma(1.0)).abs() < 1e-14);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-13);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        assert!((Superquadric::SPHERE.volume() - 4.0 / 3.0 * std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn signed_power_is_odd() {
        assert_eq!(spow(-8.0, 1.0 / 3.0), -2.0);
        assert_eq!(spow(0.0, -1.0), 0.0);
    }
}

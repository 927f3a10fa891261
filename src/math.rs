//! 4x4 homogeneous matrices with the conventions of the plytrace manual page
//! (Garcia 1986, 004_340543b92e50b70d.txt, appendix), which are IRIS GL's.
//!
//! * Points are **row vectors**: `P' = P * M`.
//! * Every modelling command *pre-multiplies* the current matrix:
//!   `CTM <- M * CTM`, so the transformation given last acts on the points
//!   first.
//! * Angles are in degrees, rotations follow the right-hand rule.
//! * Projections (`perspective`, `ortho`, `ortho2`, `window`) map the
//!   viewing volume onto the standard view box `-w <= x, y, z <= w`, with the
//!   eye looking down the negative z axis and z growing away from the eye
//!   after projection (004 section 4.5).
//!
//! This module depends on nothing else in the crate.
//!
//! # A worked example: a corner of the manual's cut cube
//!
//! `ccube.des` says, after `resolution` and `perspective 45 1 0.01 1000`:
//!
//! ```text
//! pushmatrix ; ident ; polarview 7 0 75 0 ; translate 0 0 -1
//! defobj cutcube ; translate 0 0 1.05 ; rotate 30 z ; endobj
//! ```
//!
//! At `endobj` the CTM is `Rz(30) * T(0,0,1.05) * T(0,0,-1) * PV` where `PV` is
//! the polarview. The object vertex `(1, -1, -1)` goes:
//!
//! 1. `rotate 30 z` (given last, acts first): `(cos30 + sin30, sin30 - cos30, -1)`
//!    = `(1.3660, -0.3660, -1)`;
//! 2. `translate 0 0 1.05`: `(1.3660, -0.3660, 0.05)`;
//! 3. `translate 0 0 -1` (the view): `(1.3660, -0.3660, -0.95)`;
//! 4. polarview: `rotate(-azim=0, z)` does nothing; `rotate(-75, x)` gives
//!    `y' = y cos(-75) - z sin(-75) = -0.0947 - 0.9176 = -1.0123`,
//!    `z' = y sin(-75) + z cos(-75) = 0.3535 - 0.2459 = 0.1077`;
//!    `rotate(-twist=0, z)` nothing; `translate(0,0,-7)`: z = -6.8923.
//!
//! So its world (here: eye) position is `(1.3660, -1.0123, -6.8923)`, which
//! `ccube_vertex_hand_worked` in `tests/scene_language.rs` checks. `popmatrix`
//! restores the perspective, which becomes the projection; the eye is its
//! centre of projection, the origin. The world z axis (up) is turned into
//! `(0, sin 75, cos 75)`: the view is from 15 degrees above the horizon, from
//! the -y side, with the Point light at `(-4, -2, 6)` to the front left.

use glam::{DVec3, DVec4};

/// A 4x4 matrix applied to row vectors (`P * M`); `m[row][column]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Matrix4 {
    /// Entries by row, then column.
    pub m: [[f64; 4]; 4],
}

impl Default for Matrix4 {
    fn default() -> Self {
        Matrix4::IDENTITY
    }
}

impl Matrix4 {
    /// The identity.
    pub const IDENTITY: Matrix4 = Matrix4 {
        m: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
    };

    /// A matrix from its rows.
    pub const fn from_rows(m: [[f64; 4]; 4]) -> Self {
        Matrix4 { m }
    }

    /// The product `self * rhs`: applied to a row vector, `self` acts first.
    pub fn mul(&self, rhs: &Matrix4) -> Matrix4 {
        let mut out = [[0.0; 4]; 4];
        for (r, row) in out.iter_mut().enumerate() {
            for (c, cell) in row.iter_mut().enumerate() {
                *cell = (0..4).map(|k| self.m[r][k] * rhs.m[k][c]).sum();
            }
        }
        Matrix4 { m: out }
    }

    /// `P * self` for a homogeneous row vector.
    pub fn transform(&self, p: DVec4) -> DVec4 {
        let v = [p.x, p.y, p.z, p.w];
        let col = |c: usize| (0..4).map(|k| v[k] * self.m[k][c]).sum::<f64>();
        DVec4::new(col(0), col(1), col(2), col(3))
    }

    /// `[x y z 1] * self`, without the division by w.
    pub fn transform_point4(&self, p: DVec3) -> DVec4 {
        self.transform(p.extend(1.0))
    }

    /// `[x y z 1] * self` divided by w (for affine matrices w stays 1).
    pub fn transform_point(&self, p: DVec3) -> DVec3 {
        let h = self.transform_point4(p);
        h.truncate() / h.w
    }

    /// `[x y z 0] * self`: a direction, unaffected by translation.
    pub fn transform_vector(&self, v: DVec3) -> DVec3 {
        self.transform(v.extend(0.0)).truncate()
    }

    /// The transpose.
    pub fn transpose(&self) -> Matrix4 {
        let mut out = [[0.0; 4]; 4];
        for (r, row) in out.iter_mut().enumerate() {
            for (c, cell) in row.iter_mut().enumerate() {
                *cell = self.m[c][r];
            }
        }
        Matrix4 { m: out }
    }

    /// Column `c` as a vector.
    pub fn column(&self, c: usize) -> DVec4 {
        DVec4::new(self.m[0][c], self.m[1][c], self.m[2][c], self.m[3][c])
    }

    /// The determinant of the linear part (the upper 3 x 3): negative
    /// for a mapping that turns orientation over, as a reflection does.
    pub fn linear_determinant(&self) -> f64 {
        let a = &self.m;
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    }

    /// Whether it is affine: its last column is 0, 0, 0, 1 (no
    /// perspective division).
    pub fn is_affine(&self) -> bool {
        let m = &self.m;
        m[0][3] == 0.0 && m[1][3] == 0.0 && m[2][3] == 0.0 && m[3][3] == 1.0
    }

    /// Whether it is affine and keeps distances (a rotation, a
    /// reflection, a translation): its linear part's rows are orthonormal,
    /// within `1e-9`.
    pub fn keeps_distances(&self) -> bool {
        let m = &self.m;
        let row = |i: usize| DVec3::new(m[i][0], m[i][1], m[i][2]);
        self.is_affine()
            && (0..3).all(|i| {
                (0..3).all(|k| {
                    let want = if i == k { 1.0 } else { 0.0 };
                    (row(i).dot(row(k)) - want).abs() <= 1e-9
                })
            })
    }

    /// The determinant.
    pub fn determinant(&self) -> f64 {
        let m = &self.m;
        let minor = |r0: usize, r1: usize, c0: usize, c1: usize| {
            m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
        };
        let s0 = minor(0, 1, 0, 1);
        let s1 = minor(0, 1, 0, 2);
        let s2 = minor(0, 1, 0, 3);
        let s3 = minor(0, 1, 1, 2);
        let s4 = minor(0, 1, 1, 3);
        let s5 = minor(0, 1, 2, 3);
        let c5 = minor(2, 3, 2, 3);
        let c4 = minor(2, 3, 1, 3);
        let c3 = minor(2, 3, 1, 2);
        let c2 = minor(2, 3, 0, 3);
        let c1 = minor(2, 3, 0, 2);
        let c0 = minor(2, 3, 0, 1);
        s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0
    }

    /// The inverse, by Gauss-Jordan elimination with partial pivoting;
    /// `None` when the matrix is singular (or too close to it to invert).
    pub fn inverse(&self) -> Option<Matrix4> {
        let mut a = self.m;
        let mut inv = Matrix4::IDENTITY.m;
        let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        if scale == 0.0 || !scale.is_finite() {
            return None;
        }
        for col in 0..4 {
            let pivot = (col..4).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
            if a[pivot][col].abs() <= 1e-14 * scale {
                return None;
            }
            a.swap(col, pivot);
            inv.swap(col, pivot);
            let p = a[col][col];
            for k in 0..4 {
                a[col][k] /= p;
                inv[col][k] /= p;
            }
            for r in 0..4 {
                if r != col {
                    let f = a[r][col];
                    if f != 0.0 {
                        for k in 0..4 {
                            a[r][k] -= f * a[col][k];
                            inv[r][k] -= f * inv[col][k];
                        }
                    }
                }
            }
        }
        Some(Matrix4 { m: inv })
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.m.iter().flatten().all(|v| v.is_finite())
    }

    /// The homogeneous point `E` (up to scale) that the matrix sends to
    /// `x = y = w = 0`: the centre of projection of a projection matrix, in
    /// the coordinates the matrix is applied to. `w = 0` means an eye at
    /// infinity (orthographic). The sign is chosen so that `E` lies on the
    /// near side (its projected z is negative). `None` when the matrix has no
    /// single such point (it is not a projection of rank 3 or more).
    pub fn centre_of_projection(&self) -> Option<DVec4> {
        // E is orthogonal to columns 0, 1 and 3: the 4D cross product.
        let a = self.column(0);
        let b = self.column(1);
        let c = self.column(3);
        let det3 = |r: [usize; 3]| {
            let g = |v: DVec4, i: usize| v.to_array()[i];
            let (i, j, k) = (r[0], r[1], r[2]);
            g(a, i) * (g(b, j) * g(c, k) - g(b, k) * g(c, j))
                - g(a, j) * (g(b, i) * g(c, k) - g(b, k) * g(c, i))
                + g(a, k) * (g(b, i) * g(c, j) - g(b, j) * g(c, i))
        };
        let e = DVec4::new(
            det3([1, 2, 3]),
            -det3([0, 2, 3]),
            det3([0, 1, 3]),
            -det3([0, 1, 2]),
        );
        let scale = e.abs().max_element();
        if !scale.is_finite() || scale <= 0.0 || scale.is_nan() {
            return None;
        }
        let mut e = e / scale;
        if self.transform(e).z > 0.0 {
            e = -e;
        }
        Some(e)
    }
}

fn radians(deg: f64) -> f64 {
    deg.to_radians()
}

/// `translate tx ty tz`.
pub fn translate(t: DVec3) -> Matrix4 {
    let mut m = Matrix4::IDENTITY;
    m.m[3] = [t.x, t.y, t.z, 1.0];
    m
}

/// `scale sx sy sz`.
pub fn scale(s: DVec3) -> Matrix4 {
    let mut m = Matrix4::IDENTITY;
    m.m[0][0] = s.x;
    m.m[1][1] = s.y;
    m.m[2][2] = s.z;
    m
}

/// An axis of `rotate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// The x axis.
    X,
    /// The y axis.
    Y,
    /// The z axis.
    Z,
}

/// `rotate angle axis`: right-handed rotation by `degrees` about `axis`.
/// For z: `x' = x cos - y sin`, `y' = x sin + y cos`.
pub fn rotate(degrees: f64, axis: Axis) -> Matrix4 {
    let (s, c) = radians(degrees).sin_cos();
    let mut m = Matrix4::IDENTITY;
    let (i, j) = match axis {
        Axis::X => (1, 2),
        Axis::Y => (2, 0),
        Axis::Z => (0, 1),
    };
    // Row vectors: row i is the image of axis i.
    m.m[i][i] = c;
    m.m[i][j] = s;
    m.m[j][i] = -s;
    m.m[j][j] = c;
    m
}

/// `polarview dist azim inc twist`, IRIS GL's: the product of
/// `translate(0,0,-dist)`, `rotate(-twist,z)`, `rotate(-inc,x)`,
/// `rotate(-azim,z)` given in that order, so azimuth acts first.
pub fn polarview(dist: f64, azim: f64, inc: f64, twist: f64) -> Matrix4 {
    rotate(-azim, Axis::Z)
        .mul(&rotate(-inc, Axis::X))
        .mul(&rotate(-twist, Axis::Z))
        .mul(&translate(DVec3::new(0.0, 0.0, -dist)))
}

/// `lookat vx vy vz px py pz twist`: eye at `v` looking at `p`, world +y
/// kept up on the screen (IRIS GL), then `rotate(-twist, z)` in eye space.
/// When the line of sight is vertical (parallel to y) the world -z (looking
/// up) or +z (looking down) axis is taken as up instead. `None` if `v == p`.
pub fn lookat(v: DVec3, p: DVec3, twist: f64) -> Option<Matrix4> {
    let f = (p - v).try_normalize()?;
    let up = if f.cross(DVec3::Y).length() < 1e-9 {
        if f.y > 0.0 { -DVec3::Z } else { DVec3::Z }
    } else {
        DVec3::Y
    };
    look_along(v, f, up, twist)
}

/// [`lookat`] with another world direction kept up on the screen: `None`
/// if `v == p`, or if the line of sight is parallel to `up`.
pub fn lookat_up(v: DVec3, p: DVec3, up: DVec3, twist: f64) -> Option<Matrix4> {
    let f = (p - v).try_normalize()?;
    let up = up.try_normalize()?;
    if f.cross(up).length() < 1e-9 {
        return None;
    }
    look_along(v, f, up, twist)
}

/// The view from `v` along the unit direction `f`, `up` (not parallel to
/// `f`) up on the screen, then `rotate(-twist, z)`.
fn look_along(v: DVec3, f: DVec3, up: DVec3, twist: f64) -> Option<Matrix4> {
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    // Rows of the rotation part are the images of the world axes: the world
    // point q goes to (s.(q-v), u.(q-v), -f.(q-v)).
    let rot = Matrix4::from_rows([
        [s.x, u.x, -f.x, 0.0],
        [s.y, u.y, -f.y, 0.0],
        [s.z, u.z, -f.z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    Some(translate(-v).mul(&rot).mul(&rotate(-twist, Axis::Z)))
}

/// `perspective fovy aspect near far` (fovy in degrees). Eye space
/// `z = -near` goes to z = -1, `z = -far` to z = +1; `w = -z`.
pub fn perspective(fovy: f64, aspect: f64, near: f64, far: f64) -> Matrix4 {
    let f = 1.0 / (radians(fovy) / 2.0).tan();
    let d = far - near;
    Matrix4::from_rows([
        [f / aspect, 0.0, 0.0, 0.0],
        [0.0, f, 0.0, 0.0],
        [0.0, 0.0, -(far + near) / d, -1.0],
        [0.0, 0.0, -2.0 * far * near / d, 0.0],
    ])
}

/// `window left right bottom top near far`: a perspective frustum whose
/// near rectangle is given (OpenGL's glFrustum).
pub fn window(l: f64, r: f64, b: f64, t: f64, n: f64, f: f64) -> Matrix4 {
    Matrix4::from_rows([
        [2.0 * n / (r - l), 0.0, 0.0, 0.0],
        [0.0, 2.0 * n / (t - b), 0.0, 0.0],
        [
            (r + l) / (r - l),
            (t + b) / (t - b),
            -(f + n) / (f - n),
            -1.0,
        ],
        [0.0, 0.0, -2.0 * f * n / (f - n), 0.0],
    ])
}

/// `ortho left right bottom top near far`.
pub fn ortho(l: f64, r: f64, b: f64, t: f64, n: f64, f: f64) -> Matrix4 {
    Matrix4::from_rows([
        [2.0 / (r - l), 0.0, 0.0, 0.0],
        [0.0, 2.0 / (t - b), 0.0, 0.0],
        [0.0, 0.0, -2.0 / (f - n), 0.0],
        [
            -(r + l) / (r - l),
            -(t + b) / (t - b),
            -(f + n) / (f - n),
            1.0,
        ],
    ])
}

/// `ortho2 left right bottom top`: IRIS GL's, `ortho` with near -1 and far 1,
/// so depth is kept as `-z` (larger z is nearer the eye, as for the others).
pub fn ortho2(l: f64, r: f64, b: f64, t: f64) -> Matrix4 {
    ortho(l, r, b, t, -1.0, 1.0)
}

/// `I + k L N` for the plane `L = [A B C D]` (unit normal) and
/// `N = [A B C 0]`: the common form of 004 section 4.6's matrices.
fn plane_outer(plane: DVec4, k: f64) -> Matrix4 {
    let l = plane.to_array();
    let n = [plane.x, plane.y, plane.z, 0.0];
    let mut m = Matrix4::IDENTITY;
    for (i, row) in m.m.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell += k * l[i] * n[j];
        }
    }
    m
}

/// Planar reflection `M_r = I - 2 L N` (Garcia 1986, 004 section 4.6): maps
/// a point to its mirror image in the plane `L` (unit normal).
pub fn reflection(plane: DVec4) -> Matrix4 {
    plane_outer(plane, -2.0)
}

/// Paraxial refraction `M_tp = I + (eta - 1) L N` (004 section 4.6):
/// points beyond the plane appear at `eta` times their distance, `eta` the
/// relative index (that of the eye's side over that of the far side).
/// `M_tp(eta = -1)` is the reflection.
pub fn refraction_paraxial(plane: DVec4, eta: f64) -> Matrix4 {
    plane_outer(plane, eta - 1.0)
}

/// Refraction exact for every ray of direction `view` (unit, from the eye
/// towards the plane): `M_t = I - alpha L [V - (N.V) N]` with
/// `alpha = 1/cos t1 - eta/cos t2` (004 section 4.6). With `view` the
/// orthographic viewing direction this is `M_to`; with the direction of
/// the ray through a polygon's centre it is the linearization of 004
/// section 6.4.3, exact for that ray. `plane` has its unit normal towards
/// the eye. `None` on total internal reflection (no refracted ray) or a
/// ray parallel to the plane.
pub fn refraction(plane: DVec4, view: DVec3, eta: f64) -> Option<Matrix4> {
    let n = plane.truncate();
    let v = view.normalize();
    let beta = -n.dot(v);
    if beta <= 0.0 {
        return None;
    }
    let cos2_sq = 1.0 - eta * eta * (1.0 - beta * beta);
    if cos2_sq <= 0.0 {
        return None;
    }
    let alpha = 1.0 / beta - eta / cos2_sq.sqrt();
    let s = v - n * n.dot(v);
    let l = plane.to_array();
    let srow = [s.x, s.y, s.z, 0.0];
    let mut m = Matrix4::IDENTITY;
    for (i, row) in m.m.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell -= alpha * l[i] * srow[j];
        }
    }
    Some(m)
}

/// Calls `f(word, mask)` for each 64-bit word of a bit set that holds bits
/// `i0..i1`, with the mask of those bits in it: the one walk of the
/// scan converter's sample masks and the hidden-polygon cull's.
pub fn for_bit_words(i0: u32, i1: u32, mut f: impl FnMut(usize, u64)) {
    let mut i = i0;
    while i < i1 {
        let (w, b) = ((i / 64) as usize, i % 64);
        let n = (i1 - i).min(64 - b);
        let m = if n == 64 {
            u64::MAX
        } else {
            ((1u64 << n) - 1) << b
        };
        f(w, m);
        i += n;
    }
}

/// The box around `points`: its lowest and highest corners (infinite and
/// inverted when there are none).
pub fn bounds(points: impl IntoIterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.into_iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn rotate_z_by_90_takes_x_to_y() {
        let p = rotate(90.0, Axis::Z).transform_point(DVec3::X);
        assert!(close(p, DVec3::Y), "{p}");
        let p = rotate(90.0, Axis::X).transform_point(DVec3::Y);
        assert!(close(p, DVec3::Z), "{p}");
        let p = rotate(90.0, Axis::Y).transform_point(DVec3::Z);
        assert!(close(p, DVec3::X), "{p}");
    }

    #[test]
    fn premultiplied_transform_given_last_acts_first() {
        // CTM <- T; CTM <- R * CTM: rotate first, then translate.
        let ctm = rotate(90.0, Axis::Z).mul(&translate(DVec3::new(10.0, 0.0, 0.0)));
        let p = ctm.transform_point(DVec3::X);
        assert!(close(p, DVec3::new(10.0, 1.0, 0.0)), "{p}");
    }

    #[test]
    fn polarview_hand_worked() {
        // polarview 7 0 75 0: eye 7 units away, 15 degrees above the horizon,
        // on the -y side of the origin. World up (0,0,1) goes to
        // (0, sin 75, cos 75) before the translation by -7 in z.
        let m = polarview(7.0, 0.0, 75.0, 0.0);
        let up = m.transform_vector(DVec3::Z);
        let (s, c) = 75f64.to_radians().sin_cos();
        assert!(close(up, DVec3::new(0.0, s, c)), "{up}");
        let origin = m.transform_point(DVec3::ZERO);
        assert!(close(origin, DVec3::new(0.0, 0.0, -7.0)), "{origin}");
        // The eye sits at world (0, -7 sin 75, 7 cos 75).
        let eye = DVec3::new(0.0, -7.0 * s, 7.0 * c);
        assert!(close(m.transform_point(eye), DVec3::ZERO));
        // azim 90 puts the eye on the +x side: the world point (7,0,0) with
        // inc 90 (horizontal view) lands on the eye.
        let m = polarview(7.0, 90.0, 90.0, 0.0);
        assert!(close(
            m.transform_point(DVec3::new(7.0, 0.0, 0.0)),
            DVec3::ZERO
        ));
    }

    #[test]
    fn perspective_maps_near_and_far_to_unit_depths() {
        let m = perspective(90.0, 2.0, 1.0, 10.0);
        let near = m.transform_point(DVec3::new(2.0, 1.0, -1.0));
        assert!(close(near, DVec3::new(1.0, 1.0, -1.0)), "{near}");
        let far = m.transform_point(DVec3::new(0.0, 0.0, -10.0));
        assert!((far.z - 1.0).abs() < 1e-12);
    }

    #[test]
    fn window_equals_perspective_for_symmetric_frustum() {
        let t = (22.5f64).to_radians().tan() * 0.5;
        let a = window(-t * 1.5, t * 1.5, -t, t, 0.5, 50.0);
        let b = perspective(45.0, 1.5, 0.5, 50.0);
        for r in 0..4 {
            for c in 0..4 {
                assert!((a.m[r][c] - b.m[r][c]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn ortho_maps_box_to_unit_cube() {
        let m = ortho(-2.0, 4.0, -1.0, 1.0, 1.0, 3.0);
        let p = m.transform_point(DVec3::new(4.0, -1.0, -3.0));
        assert!(close(p, DVec3::new(1.0, -1.0, 1.0)), "{p}");
    }

    #[test]
    fn centre_of_projection_of_perspective_is_origin() {
        let e = perspective(45.0, 1.0, 0.01, 1000.0)
            .centre_of_projection()
            .unwrap();
        assert!(e.x.abs() < 1e-12 && e.y.abs() < 1e-12 && e.z.abs() < 1e-12);
        assert!(e.w > 0.0);
        // Orthographic: at infinity towards +z (the viewer looks down -z).
        let e = ortho(-1.0, 1.0, -1.0, 1.0, 1.0, 5.0)
            .centre_of_projection()
            .unwrap();
        assert!(e.w.abs() < 1e-12 && e.z > 0.0, "{e}");
        // A viewing transform followed by a perspective: the eye in world space.
        let view = polarview(7.0, 0.0, 75.0, 0.0);
        let e = view
            .mul(&perspective(45.0, 1.0, 0.01, 1000.0))
            .centre_of_projection()
            .unwrap();
        let e = e.truncate() / e.w;
        let (s, c) = 75f64.to_radians().sin_cos();
        assert!(
            (e - DVec3::new(0.0, -7.0 * s, 7.0 * c)).length() < 1e-9,
            "{e}"
        );
    }

    #[test]
    fn lookat_puts_reference_point_on_negative_z() {
        let v = DVec3::new(3.0, 4.0, 5.0);
        let p = DVec3::new(-1.0, 2.0, 0.5);
        let m = lookat(v, p, 0.0).unwrap();
        assert!(close(m.transform_point(v), DVec3::ZERO));
        let q = m.transform_point(p);
        assert!(q.x.abs() < 1e-12 && q.y.abs() < 1e-12 && q.z < 0.0, "{q}");
        assert!((q.z + (p - v).length()).abs() < 1e-12);
        // World +y stays up on the screen.
        assert!(m.transform_vector(DVec3::Y).y > 0.0);
        assert!(lookat(v, v, 0.0).is_none());
    }

    #[test]
    fn inverse_undoes_the_matrix() {
        let m = polarview(7.0, 20.0, 75.0, 5.0).mul(&perspective(45.0, 1.3, 0.1, 100.0));
        let i = m.inverse().unwrap();
        let p = m.mul(&i);
        for r in 0..4 {
            for c in 0..4 {
                let want = if r == c { 1.0 } else { 0.0 };
                assert!((p.m[r][c] - want).abs() < 1e-12, "{r} {c} {}", p.m[r][c]);
            }
        }
        assert!(scale(DVec3::new(1.0, 0.0, 1.0)).inverse().is_none());
    }

    #[test]
    fn reflection_is_an_involution_with_determinant_minus_one() {
        let n = DVec3::new(1.0, -2.0, 0.5).normalize();
        let plane = n.extend(-0.7);
        let m = reflection(plane);
        let mm = m.mul(&m);
        for r in 0..4 {
            for c in 0..4 {
                let want = if r == c { 1.0 } else { 0.0 };
                assert!((mm.m[r][c] - want).abs() < 1e-12);
            }
        }
        assert!((m.determinant() + 1.0).abs() < 1e-12);
        // Equal to the paraxial refraction at eta = -1.
        assert_eq!(m, refraction_paraxial(plane, -1.0));
        // A point and its image are symmetric about the plane.
        let p = DVec3::new(0.3, 2.0, -1.0);
        let q = m.transform_point(p);
        let (dp, dq) = (n.dot(p) - 0.7, n.dot(q) - 0.7);
        assert!((dp + dq).abs() < 1e-12);
        assert!(((q - p).normalize().cross(n)).length() < 1e-12);
    }

    #[test]
    fn mirror_image_lies_on_the_reflected_ray() {
        // The eye at the origin looks at a mirror z = -5 (normal +z towards
        // the eye). A point seen in the mirror lands where the mirrored ray
        // goes: the virtual point is on the straight line from the eye
        // through the hit point.
        let plane = DVec4::new(0.0, 0.0, 1.0, 5.0);
        let hit = DVec3::new(1.0, 0.5, -5.0);
        let d = hit.normalize();
        let r = d - 2.0 * d.dot(DVec3::Z) * DVec3::Z;
        let real = hit + r * 3.0;
        let virtual_point = reflection(plane).transform_point(real);
        assert!((virtual_point.normalize() - d).length() < 1e-12);
    }

    #[test]
    fn refraction_obeys_snell_at_its_linearization_angle() {
        // Water surface z = 0 seen from above (normal +z towards the eye),
        // eta = 1 / 1.33; rays of direction v.
        let plane = DVec4::new(0.0, 0.0, 1.0, 0.0);
        let eta = 1.0 / 1.33;
        for angle in [0.0f64, 10.0, 35.0, 60.0] {
            let a = angle.to_radians();
            let v = DVec3::new(a.sin(), 0.0, -a.cos());
            let m = refraction(plane, v, eta).unwrap();
            // Snell: the refracted direction t for incidence v.
            let n = DVec3::Z;
            let cos1 = -n.dot(v);
            let cos2 = (1.0 - eta * eta * (1.0 - cos1 * cos1)).sqrt();
            let t = eta * v + (eta * cos1 - cos2) * n;
            assert!((eta * (1.0 - cos1 * cos1).sqrt() - (1.0 - cos2 * cos2).sqrt()).abs() < 1e-12);
            // A point on the refracted ray maps to a point on the straight
            // continuation of the incident ray.
            let x = DVec3::new(0.4, -0.2, 0.0);
            let real = x + t * 2.5;
            let seen = m.transform_point(real);
            assert!(
                ((seen - x).normalize() - v).length() < 1e-9,
                "angle {angle}: {seen}"
            );
        }
        // At normal incidence rays go straight through: no displacement
        // across the line of sight (the paraxial matrix scales depth
        // instead, which does not move the point on the screen).
        let exact = refraction(plane, -DVec3::Z, eta).unwrap();
        let para = refraction_paraxial(plane, eta);
        let p = DVec3::new(0.3, 0.1, -2.0);
        let (e, q) = (exact.transform_point(p), para.transform_point(p));
        assert!((e.truncate() - p.truncate()).length() < 1e-12);
        assert!((q.truncate() - p.truncate()).length() < 1e-12 && (q.z - eta * p.z).abs() < 1e-12);
        // Total internal reflection: from water (eta 1.33) at 60 degrees.
        let v = DVec3::new(60f64.to_radians().sin(), 0.0, -60f64.to_radians().cos());
        assert!(refraction(plane, v, 1.33).is_none());
    }

    #[test]
    fn determinant_of_rotation_and_scale() {
        assert!((rotate(33.0, Axis::Y).determinant() - 1.0).abs() < 1e-12);
        assert!((scale(DVec3::new(2.0, 3.0, -1.0)).determinant() + 6.0).abs() < 1e-12);
    }

    /// The linear part's determinant ignores the translation: a mirror's
    /// reflection (through a plane off the origin) is -1, a move 1.
    #[test]
    fn linear_determinant_ignores_translation() {
        let mirror = reflection(DVec4::new(0.0, 0.6, 0.8, -3.0));
        assert!((mirror.linear_determinant() + 1.0).abs() < 1e-12);
        let moved = translate(DVec3::new(5.0, -2.0, 7.0)).mul(&scale(DVec3::new(2.0, 3.0, -1.0)));
        assert!((moved.linear_determinant() + 6.0).abs() < 1e-12);
        assert!((translate(DVec3::ONE).linear_determinant() - 1.0).abs() < 1e-12);
    }

    /// Mirrors and moves keep distances; a scale, a refraction (which
    /// stretches along the normal) and a projection do not.
    #[test]
    fn only_rigid_mappings_keep_distances() {
        let mirror = reflection(DVec4::new(0.0, 0.6, 0.8, -3.0));
        let moved = translate(DVec3::new(5.0, -2.0, 7.0)).mul(&mirror);
        assert!(Matrix4::IDENTITY.keeps_distances() && mirror.keeps_distances());
        assert!(moved.keeps_distances());
        assert!(!scale(DVec3::new(1.0, 1.0, -1.01)).keeps_distances());
        let water = DVec4::new(0.0, 0.0, 1.0, 0.0);
        let bent = refraction(water, DVec3::new(0.3, 0.0, -1.0), 1.0 / 1.33).unwrap();
        assert!(!bent.keeps_distances());
        let mut projective = Matrix4::IDENTITY;
        projective.m[2][3] = -1.0;
        assert!(!projective.keeps_distances());
    }
}

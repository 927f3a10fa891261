//! Viewing and transforms (Garcia 1986, 004 section 4.3 and appendix B,
//! the plytrace manual page): `ident`, `lookat`, `ortho`, `ortho2`,
//! `perspective`, `polarview`, `rotate`, `scale`, `translate`, `window`
//! on the current transformation matrix (CTM), `pushmatrix` and
//! `popmatrix` on its 16-deep stack, and the image size (`resolution`,
//! `viewport`). A transform pre-multiplies the CTM, a projection loads
//! it (IRIS GL semantics, see [`crate::math`]).

use glam::DVec3;

use crate::error::Result;
use crate::math::{self, Matrix4};
use crate::model::Viewport;
use crate::scene::arguments::{Context, Spanned};
use crate::scene::interpreter::{
    Interpreter, MATRIX_STACK_DEPTH, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE,
};
use crate::scene::lexer::Token;

/// Near and far of `ortho2`'s box: so far apart that nothing is clipped
/// in z.
pub const ORTHO2_DEPTH: f64 = 1e30;

/// `ortho2 left right bottom top`: a 2-D orthographic projection. The
/// manual (004 appendix) says "for 3-D coordinates, the z values are
/// unaffected by this transformation": nothing is clipped in z, so near and
/// far are at -/+[`ORTHO2_DEPTH`] (depth is kept as `-z`, scaled, so that
/// the order of depths is that of [`math::ortho`]).
pub fn ortho2(l: f64, r: f64, b: f64, t: f64) -> Matrix4 {
    math::ortho(l, r, b, t, -ORTHO2_DEPTH, ORTHO2_DEPTH)
}

impl Interpreter {
    /// `pushmatrix` (and `defobj`): a copy of the CTM on the stack.
    pub(in crate::scene) fn push(&mut self, ctx: &Context, cmd: &Token) -> Result<()> {
        if self.stack.len() >= MATRIX_STACK_DEPTH {
            return Err(ctx.error(
                cmd,
                format!("matrix stack overflow: more than {MATRIX_STACK_DEPTH} matrices pushed (each open `defobj` holds one)"),
            ));
        }
        self.stack.push(self.ctm);
        Ok(())
    }

    /// `popmatrix`: never below the matrix an open `defobj` saved.
    pub(in crate::scene) fn popmatrix(&mut self, ctx: &Context, cmd: &Token) -> Result<()> {
        let floor = self.active.as_ref().map_or(0, |o| o.stack_depth);
        if self.stack.len() <= floor {
            let why = if floor > 0 {
                "matrix stack underflow: this would pop the matrix `defobj` saved"
            } else {
                "matrix stack underflow: `popmatrix` without a matching `pushmatrix`"
            };
            return Err(ctx.error(cmd, why));
        }
        if let Some(m) = self.stack.pop() {
            self.ctm = m;
        }
        Ok(())
    }

    /// A transform: `m` times the CTM.
    pub(in crate::scene) fn premultiply(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        m: Matrix4,
    ) -> Result<()> {
        self.load(ctx, cmd, m.mul(&self.ctm))
    }

    /// A projection: `m` becomes the CTM, if it is finite.
    pub(in crate::scene) fn load(&mut self, ctx: &Context, cmd: &Token, m: Matrix4) -> Result<()> {
        if !m.is_finite() {
            return Err(ctx.error(
                cmd,
                "the transformation matrix would overflow (non-finite entries)",
            ));
        }
        self.ctm = m;
        Ok(())
    }

    /// `lookat vx vy vz px py pz twist`.
    pub(in crate::scene) fn lookat(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        eye: DVec3,
        center: DVec3,
        twist: f64,
    ) -> Result<()> {
        let m = math::lookat(eye, center, twist)
            .ok_or_else(|| ctx.error(cmd, "viewpoint and reference point coincide"))?;
        self.premultiply(ctx, cmd, m)
    }

    /// `perspective fovy aspect near far`.
    pub(in crate::scene) fn perspective(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        [fovy, aspect, near, far]: &[Spanned<f64>; 4],
    ) -> Result<()> {
        if !(fovy.value > 0.0 && fovy.value < 180.0) {
            return Err(ctx.error(
                &fovy.token,
                "expected a field of view between 0 and 180 degrees",
            ));
        }
        if aspect.value <= 0.0 {
            return Err(ctx.error(&aspect.token, "expected a positive aspect ratio"));
        }
        if near.value <= 0.0 {
            return Err(ctx.error(&near.token, "expected a positive near distance"));
        }
        if far.value <= near.value {
            return Err(ctx.error(
                &far.token,
                "expected a far distance beyond the near distance",
            ));
        }
        let m = math::perspective(fovy.value, aspect.value, near.value, far.value);
        self.load(ctx, cmd, m)
    }

    /// `window left right bottom top near far`.
    pub(in crate::scene) fn window(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        v: &[f64; 6],
    ) -> Result<()> {
        if v[4] <= 0.0 || v[5] <= v[4] {
            return Err(ctx.error(cmd, "expected 0 < near < far"));
        }
        self.load(ctx, cmd, math::window(v[0], v[1], v[2], v[3], v[4], v[5]))
    }

    /// `resolution hres vres`: the viewport centred on 1024 x 1024, and a
    /// perspective of 45 degrees.
    pub(in crate::scene) fn resolution(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        h: i64,
        v: i64,
    ) -> Result<()> {
        check_pixels(ctx, cmd, h, v)?;
        let left = (1024 - h) / 2;
        let bottom = (1024 - v) / 2;
        self.scene.viewport = Viewport {
            left,
            right: left + h - 1,
            bottom,
            top: bottom + v - 1,
        };
        self.load(
            ctx,
            cmd,
            math::perspective(45.0, h as f64 / v as f64, 0.01, 10000.0),
        )
    }

    /// `viewport left right bottom top`.
    pub(in crate::scene) fn viewport(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        [left, right, bottom, top]: &[Spanned<i64>; 4],
    ) -> Result<()> {
        if right.value < left.value {
            return Err(ctx.error(&right.token, "expected right >= left"));
        }
        if top.value < bottom.value {
            return Err(ctx.error(&top.token, "expected top >= bottom"));
        }
        let (w, h) = (right.value - left.value + 1, top.value - bottom.value + 1);
        check_pixels(ctx, cmd, w, h)?;
        self.scene.viewport = Viewport {
            left: left.value,
            right: right.value,
            bottom: bottom.value,
            top: top.value,
        };
        Ok(())
    }
}

/// Refuses an image of `w` x `h` pixels beyond the limits.
fn check_pixels(ctx: &Context, cmd: &Token, w: i64, h: i64) -> Result<()> {
    if w < 1
        || h < 1
        || w > MAX_IMAGE_SIDE
        || h > MAX_IMAGE_SIDE
        || (w as u64) * (h as u64) > MAX_IMAGE_PIXELS
    {
        return Err(ctx.error(
            cmd,
            format!("image of {w} x {h} pixels: each side must be 1 to {MAX_IMAGE_SIDE} and the total at most {MAX_IMAGE_PIXELS} pixels"),
        ));
    }
    Ok(())
}

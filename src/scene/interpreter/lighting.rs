//! Lights and modes (Garcia 1986, 004 appendix B, the plytrace manual
//! page; lights and shadows of sections 4.7-4.8): `light` adds a light
//! placed by the CTM, `threshold` and the scene-wide settings, and
//! `setmode`, whose modes are the command line's flags of the same letters
//! (a flag given there is forced: applied again after every statement).

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::error::Result;
use crate::model::{Color, Light, LightKind, Modes};
use crate::scene::arguments::{Context, Spanned};
use crate::scene::command::ModeSetting;
use crate::scene::interpreter::Interpreter;
use crate::scene::lexer::{Statement, Token};
use crate::scene::parse;

impl ModeSetting {
    /// Sets the mode in `modes` (or, for `f`, the scene file name).
    pub(in crate::scene) fn apply(&self, modes: &mut Modes, scene_file: &mut Option<String>) {
        use ModeSetting as M;
        match self {
            M::Debug(level) => modes.debug = *level,
            M::Blend(on) => modes.blend = *on,
            M::MinDetail(d) => modes.min_detail = *d,
            M::Epsilon(e) => modes.epsilon = *e,
            M::SceneFile(name) => *scene_file = Some(name.clone()),
            M::ShadowShades(on) => modes.shadow_shades = *on,
            M::MaxLevel(level) => modes.max_level = *level,
            M::Nns(on) => modes.nns = *on,
            M::OutputTree(on) => modes.output_tree = *on,
            M::BoxesOnly(on) => modes.boxes_only = *on,
            M::Phong(on) => modes.phong = *on,
            M::VertexShades(on) => modes.vertex_shades = *on,
            M::Expand(on) => modes.expand = *on,
        }
    }
}

impl Interpreter {
    /// `setmode mode [value]`.
    pub(in crate::scene) fn setmode(&mut self, mode: &ModeSetting) {
        mode.apply(&mut self.scene.modes, &mut self.scene.scene_file);
    }

    /// Forces a `setmode` value given on the command line (`-n on`): it is
    /// applied now and again after every statement, so it overrides the
    /// scene file. `letter` is the mode letter or a digit. An empty (or
    /// blank) `value` is the bare form, `setmode v` (004 appendix B:
    /// `setmode <mode> [<on, off>]`, the value optional), which turns an
    /// on/off mode on: `force_mode('v', "")` is `-v` alone. Modes that
    /// take a number or a name (`d`, `e`, `l`, `f`) still need one.
    pub fn force_mode(&mut self, letter: char, value: &str) -> Result<()> {
        let value = value.trim();
        let token = |text: String, column| Token {
            text,
            line: 1,
            column,
        };
        let mut stmt: Statement = vec![
            token("setmode".into(), 1),
            token(letter.to_string(), 9),
            token(value.into(), 11),
        ];
        if letter.is_ascii_digit() || value.is_empty() {
            stmt.truncate(2);
        }
        let text = stmt
            .iter()
            .map(|t| t.text.as_str())
            .collect::<Vec<_>>()
            .join(" ");
        let ctx = Context {
            file: Path::new("<command line>"),
            dir: PathBuf::from("."),
            source: &text,
        };
        let mode = parse::parse_setmode(&ctx, &stmt)?;
        self.setmode(&mode);
        self.overrides.push((letter, value.to_string()));
        Ok(())
    }

    /// The modes forced on the command line, applied again.
    pub(in crate::scene) fn apply_overrides(&mut self) {
        let overrides = std::mem::take(&mut self.overrides);
        for (letter, value) in &overrides {
            // Already validated by force_mode.
            let _ = self.force_mode(*letter, value);
        }
        self.overrides = overrides;
    }

    /// `light x y z r g b range [Point|Diffuse]`: the position transformed
    /// by the CTM.
    pub(in crate::scene) fn light(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        position: DVec3,
        color: &Spanned<Color>,
        range: &Spanned<f64>,
        kind: LightKind,
    ) -> Result<()> {
        let position = self.ctm.transform_point(position);
        if color.value.min_element() < 0.0 {
            return Err(ctx.error(&color.token, "light colour components must not be negative"));
        }
        if range.value <= 0.0 {
            return Err(ctx.error(&range.token, "expected a positive light range"));
        }
        if !position.is_finite() {
            return Err(ctx.error(cmd, "the light's position is not finite after transformation by the CTM (a projection is still on the CTM, or a number overflowed)"));
        }
        self.scene.lights.push(Light {
            position,
            color: color.value,
            range: range.value,
            kind,
        });
        Ok(())
    }

    /// `threshold k`, 0 or more.
    pub(in crate::scene) fn threshold(&mut self, ctx: &Context, t: &Spanned<f64>) -> Result<()> {
        if t.value < 0.0 {
            return Err(ctx.error(&t.token, "expected a threshold of 0 or more"));
        }
        self.scene.threshold = t.value;
        Ok(())
    }
}

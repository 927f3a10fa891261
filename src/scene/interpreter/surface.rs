//! Surface attributes (Garcia 1986, 004 appendix B, the plytrace manual
//! page; the illumination model of section 4.8): `color`, `diffuse`,
//! `specular`, `shininess`, `reflectance`, `transmittance`, `index`,
//! `transparency` and `type` set the active object's attributes inside
//! `defobj` ... `endobj` and the global ones (given to new objects)
//! outside; `pcolors` and `vcolors` name an object's colour files.

use crate::error::Result;
use crate::model::{Surface, SurfaceType};
use crate::scene::arguments::{Context, Spanned};
use crate::scene::commands::Verb;
use crate::scene::interpreter::Interpreter;
use crate::scene::lexer::Token;

impl Interpreter {
    /// The attributes a surface command sets: the active object's, else
    /// the globals.
    pub(in crate::scene) fn surface_mut(&mut self) -> &mut Surface {
        match &mut self.active {
            Some(o) => &mut o.surface,
            None => &mut self.globals,
        }
    }

    /// `index n`, positive.
    pub(in crate::scene) fn index(&mut self, ctx: &Context, n: &Spanned<f64>) -> Result<()> {
        if n.value <= 0.0 {
            return Err(ctx.error(&n.token, "expected a positive index of refraction"));
        }
        self.surface_mut().index = n.value;
        Ok(())
    }

    /// `shininess n`, 0 or more.
    pub(in crate::scene) fn shininess(&mut self, ctx: &Context, n: &Spanned<f64>) -> Result<()> {
        if n.value < 0.0 {
            return Err(ctx.error(&n.token, "expected a shininess of 0 or more"));
        }
        self.surface_mut().shininess = n.value;
        Ok(())
    }

    /// `transparency t [rolloff]`, the roll-off 0 or more (0 if not given).
    pub(in crate::scene) fn transparency(
        &mut self,
        ctx: &Context,
        t: f64,
        rolloff: Option<&Spanned<f64>>,
    ) -> Result<()> {
        let rolloff = match rolloff {
            Some(r) if r.value < 0.0 => {
                return Err(ctx.error(&r.token, "expected a roll-off of 0 or more"));
            }
            Some(r) => r.value,
            None => 0.0,
        };
        self.surface_mut().transparency = (t, rolloff);
        Ok(())
    }

    /// `type polygon [...]`.
    pub(in crate::scene) fn surface_type(&mut self, t: SurfaceType) {
        match &mut self.active {
            Some(o) => o.surface_type = t,
            None => self.global_type = t,
        }
    }

    /// `pcolors file` or `vcolors file` (`verb` says which): the active
    /// object's colour file, read at `endobj`.
    pub(in crate::scene) fn color_file(
        &mut self,
        ctx: &Context,
        cmd: &Token,
        verb: Verb,
        file: &Spanned<String>,
    ) -> Result<()> {
        let loc = ctx.location(&file.token);
        let Some(active) = &mut self.active else {
            return Err(ctx.error(
                cmd,
                format!("`{}` outside an object definition", verb.name()),
            ));
        };
        let entry = Some((file.value.clone(), loc));
        if verb == Verb::Pcolors {
            active.pcolors = entry;
        } else {
            active.vcolors = entry;
        }
        Ok(())
    }
}

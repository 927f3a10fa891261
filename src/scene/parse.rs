//! The parser of the scene descriptor language (Garcia 1986, 004 appendix
//! B, the plytrace manual page: "commands are recognized by the first
//! sequence of unique characters"): a statement's command word is looked
//! up in the table ([`super::commands`]), then its arguments are counted
//! and read into the [`Command`] of that word, in one pass; every problem
//! is named with its file, line and column and what was expected.

use glam::{DVec2, DVec3};

use super::arguments::{Args, Context, Spanned};
use super::command::{Command, CsgOperands, ModeSetting, Parsed, PatchFile, RadialCommand};
use super::commands::{self, Lookup, Verb};
use super::lexer::{Statement, Token};
use crate::error::{Error, Location, MAX_SHOWN_TOKEN, Result, printable};
use crate::math::Axis;
use crate::model::{Color, LightKind, OutMode, SortOrder, SurfaceType};
use crate::modeling::Primitive;
use crate::modeling::geodesic::{Division, Radial};
use crate::modeling::parametric::Superquadric;
use crate::modeling::sweep::{self, Profile};

/// Largest image side accepted, and largest pixel count: a guard against
/// hostile sizes, not a format limit.
pub const MAX_IMAGE_SIDE: i64 = 1 << 16;

/// Parses every statement of a text (the check before it runs), into a
/// list made at its size; each statement's command word is moved into its
/// parse, not copied.
pub(super) fn parse_all(ctx: &Context, statements: Vec<Statement>) -> Result<Vec<Parsed>> {
    let mut parsed = Vec::with_capacity(statements.len());
    for stmt in statements {
        let command = command(ctx, &stmt)?;
        let word = stmt
            .into_iter()
            .next()
            .expect("a parsed statement has its word");
        parsed.push(Parsed { word, command });
    }
    Ok(parsed)
}

/// The command of one statement, from its word and arguments.
fn command(ctx: &Context, stmt: &[Token]) -> Result<Command> {
    let Some((word, args)) = stmt.split_first() else {
        return Err(Error::at(Location::file(ctx.file), "empty statement"));
    };
    let a = Args {
        ctx,
        cmd: word,
        args,
        spec: lookup(ctx, word)?,
    };
    arguments(&a)
}

/// Parses `setmode mode [value]` given as words (a mode forced on the
/// command line).
pub(super) fn parse_setmode(ctx: &Context, stmt: &[Token]) -> Result<ModeSetting> {
    let a = Args {
        ctx,
        cmd: &stmt[0],
        args: &stmt[1..],
        spec: Verb::Setmode.spec(),
    };
    setmode(&a)
}

/// The table's command for `word`; unknown and ambiguous words fail.
fn lookup(ctx: &Context, word: &Token) -> Result<&'static commands::CommandSpec> {
    let shown = printable(&word.text, MAX_SHOWN_TOKEN);
    match commands::lookup(&word.text) {
        Lookup::Found(spec) => Ok(spec),
        Lookup::Unknown(suggestion) => {
            let hint = suggestion
                .map(|s| format!("; did you mean `{s}`?"))
                .unwrap_or_else(|| "; `plytrace --help` lists the commands".into());
            Err(ctx.error(word, format!("unknown command `{shown}`{hint}")))
        }
        Lookup::Ambiguous(names) => Err(ctx.error(
            word,
            format!(
                "ambiguous command `{shown}`: it could be {}",
                names.join(", ")
            ),
        )),
    }
}

/// The command of `a.spec` with its arguments read.
fn arguments(a: &Args) -> Result<Command> {
    use Command as C;
    Ok(match a.spec.verb {
        Verb::Ident => nothing(a, C::Ident)?,
        Verb::Lookat => {
            a.count(7, 7)?;
            let [ex, ey, ez, cx, cy, cz, twist] = a.numbers()?;
            C::Lookat {
                eye: DVec3::new(ex, ey, ez),
                center: DVec3::new(cx, cy, cz),
                twist,
            }
        }
        Verb::Ortho => C::Ortho(volume(a)?),
        Verb::Ortho2 => C::Ortho2(volume(a)?),
        Verb::Perspective => C::Perspective(spanned_numbers(a)?),
        Verb::Polarview => C::Polarview(numbers(a)?),
        Verb::Popmatrix => nothing(a, C::Popmatrix)?,
        Verb::Pushmatrix => nothing(a, C::Pushmatrix)?,
        Verb::Resolution => {
            a.count(2, 2)?;
            let h = a.integer(0, 1, MAX_IMAGE_SIDE)?;
            C::Resolution {
                h,
                v: a.integer(1, 1, MAX_IMAGE_SIDE)?,
            }
        }
        Verb::Rotate => {
            a.count(2, 2)?;
            let angle = a.number(0)?;
            C::Rotate {
                angle,
                axis: axis(a, 1)?,
            }
        }
        Verb::Scale => C::Scale(vector(a)?),
        Verb::Translate => C::Translate(vector(a)?),
        Verb::Viewport => C::Viewport(viewport(a)?),
        Verb::Window => C::Window(volume(a)?),
        Verb::Callobj => {
            a.count(1, 1)?;
            C::Callobj(a.spanned(0, a.object_ref(0)?))
        }
        Verb::Defobj => defobj(a)?,
        Verb::Delobj => {
            a.count(1, usize::MAX)?;
            let refs = (0..a.args.len()).map(|i| Ok(a.spanned(i, a.object_ref(i)?)));
            C::Delobj(refs.collect::<Result<_>>()?)
        }
        Verb::Endobj => nothing(a, C::Endobj)?,
        Verb::Getobj => C::Getobj(word(a)?),
        Verb::Geodesic => geodesic(a)?,
        Verb::Radial => C::Radial(radial(a)?),
        Verb::Sphere | Verb::Cylinder | Verb::Superquadric => primitive(a)?,
        Verb::Bezier => C::Bezier(patch_file(a)?),
        Verb::Hermite => C::Hermite(patch_file(a)?),
        Verb::Lathe | Verb::Extrude => sweep(a)?,
        Verb::Union => C::Union(csg_operands(a)?),
        Verb::Intersection => C::Intersection(csg_operands(a)?),
        Verb::Difference => C::Difference(csg_operands(a)?),
        Verb::Color => C::Color(color(a)?),
        Verb::Diffuse => C::Diffuse(unit(a)?),
        Verb::Specular => C::Specular(unit(a)?),
        Verb::Reflectance => C::Reflectance(unit(a)?),
        Verb::Transmittance => C::Transmittance(unit(a)?),
        Verb::Index => C::Index(number(a)?),
        Verb::Shininess => C::Shininess(number(a)?),
        Verb::Transparency => transparency(a)?,
        Verb::Type => C::Type(surface_type(a)?),
        Verb::Pcolors => C::Pcolors(spanned_word(a)?),
        Verb::Vcolors => C::Vcolors(spanned_word(a)?),
        Verb::Ambient => C::Ambient(color(a)?),
        Verb::Background => C::Background(color(a)?),
        Verb::Light => light(a)?,
        Verb::Nolight => nothing(a, C::Nolight)?,
        Verb::Depth => {
            a.count(1, 1)?;
            C::Depth(a.integer(0, 1, 14)? as u32)
        }
        Verb::Setmode => C::Setmode(setmode(a)?),
        Verb::Threshold => C::Threshold(number(a)?),
        Verb::Outmode => C::Outmode(outmode(a)?),
        Verb::Sort => C::Sort(sort_order(a)?),
        Verb::Call => C::Call(spanned_word(a)?),
        Verb::Get => C::Get(spanned_word(a)?),
        Verb::DetDir => C::DetDir(word(a)?),
        Verb::Fname => C::Fname(word(a)?),
        Verb::Init => nothing(a, C::Init)?,
        Verb::Run => C::Run {
            shadows: run_shadows(a)?,
        },
        Verb::Clear => nothing(a, C::Clear)?,
        Verb::Wait => nothing(a, C::Wait)?,
        Verb::Disp => {
            a.count(0, 1)?;
            C::Disp(a.args.is_empty() || a.on_off(0)?)
        }
        Verb::Quit => nothing(a, C::Quit)?,
    })
}

/// A command without arguments.
fn nothing(a: &Args, command: Command) -> Result<Command> {
    a.count(0, 0)?;
    Ok(command)
}

/// The one argument, a word.
fn word(a: &Args) -> Result<String> {
    a.count(1, 1)?;
    Ok(a.text(0))
}

/// The one argument, a word, with where it is.
fn spanned_word(a: &Args) -> Result<Spanned<String>> {
    a.count(1, 1)?;
    Ok(a.spanned(0, a.text(0)))
}

/// The one argument, a number, with where it is.
fn number(a: &Args) -> Result<Spanned<f64>> {
    a.count(1, 1)?;
    Ok(a.spanned(0, a.number(0)?))
}

/// The one argument, a number from 0 to 1.
fn unit(a: &Args) -> Result<f64> {
    a.count(1, 1)?;
    a.unit(0)
}

/// `r g b`, each from 0 to 1.
fn color(a: &Args) -> Result<Color> {
    a.count(3, 3)?;
    a.color(0)
}

/// `x y z`.
fn vector(a: &Args) -> Result<DVec3> {
    a.count(3, 3)?;
    a.vec3(0)
}

/// Exactly `N` numbers.
fn numbers<const N: usize>(a: &Args) -> Result<[f64; N]> {
    a.count(N, N)?;
    a.numbers()
}

/// Exactly `N` numbers, with where each is.
fn spanned_numbers<const N: usize>(a: &Args) -> Result<[Spanned<f64>; N]> {
    let v: [f64; N] = numbers(a)?;
    Ok(std::array::from_fn(|i| a.spanned(i, v[i])))
}

/// The sides of a viewing volume: `N` numbers, each pair distinct.
fn volume<const N: usize>(a: &Args) -> Result<[f64; N]> {
    let v = numbers(a)?;
    a.distinct_pairs(&v)?;
    Ok(v)
}

/// `viewport left right bottom top`, whole numbers.
fn viewport(a: &Args) -> Result<[Spanned<i64>; 4]> {
    a.count(4, 4)?;
    let mut v = [0; 4];
    for (i, x) in v.iter_mut().enumerate() {
        *x = a.integer(i, -MAX_IMAGE_SIDE, MAX_IMAGE_SIDE)?;
    }
    Ok(std::array::from_fn(|i| a.spanned(i, v[i])))
}

/// `defobj name [number]`.
fn defobj(a: &Args) -> Result<Command> {
    a.count(1, 2)?;
    let number = if a.args.len() == 2 {
        Some(a.spanned(1, a.integer(1, 0, u32::MAX as i64)? as u32))
    } else {
        None
    };
    Ok(Command::Defobj {
        name: a.text(0),
        number,
    })
}

/// `transparency t [rolloff]`.
fn transparency(a: &Args) -> Result<Command> {
    a.count(1, 2)?;
    let t = a.unit(0)?;
    let rolloff = if a.args.len() == 2 {
        Some(a.spanned(1, a.number(1)?))
    } else {
        None
    };
    Ok(Command::Transparency { t, rolloff })
}

/// `light x y z r g b range [Point|Diffuse]`.
fn light(a: &Args) -> Result<Command> {
    a.count(7, 8)?;
    let [x, y, z, r, g, b, range] = a.numbers()?;
    Ok(Command::Light {
        position: DVec3::new(x, y, z),
        color: a.spanned(3, DVec3::new(r, g, b)),
        range: a.spanned(6, range),
        kind: light_kind(a)?,
    })
}

/// `geodesic n [equal|angle]`.
fn geodesic(a: &Args) -> Result<Command> {
    a.count(1, 2)?;
    let n = a.integer(0, 1, 1024)? as usize;
    let division = match a.args.get(1).map(|t| t.text.to_ascii_lowercase()) {
        None => Division::EqualAngle,
        Some(d) if d == "equal" => Division::Equal,
        Some(d) if d == "angle" => Division::EqualAngle,
        Some(_) => return Err(a.ctx.error(&a.args[1], "expected `equal` or `angle`")),
    };
    Ok(Command::Geodesic { n, division })
}

/// `radial sphere|ellipsoid a b c|bumps amp freq|lobes amp k` or
/// `radial rotate angle x|y|z`.
fn radial(a: &Args) -> Result<RadialCommand> {
    let (ctx, args) = (a.ctx, a.args);
    a.count(1, 4)?;
    let kind = args[0].text.to_ascii_lowercase();
    if kind == "rotate" {
        a.count(3, 3)?;
        let angle = a.number(1)?;
        let axis = match axis(a, 2)? {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        };
        return Ok(RadialCommand::Rotate(angle, axis));
    }
    let (radial, want) = match kind.as_str() {
        "sphere" => (Radial::Sphere, 1),
        "ellipsoid" => {
            a.count(4, 4)?;
            let v = a.vec3(1)?;
            if v.min_element() <= 0.0 {
                return Err(ctx.error(&args[1], "expected positive semi-axes"));
            }
            (Radial::Ellipsoid(v.x, v.y, v.z), 4)
        }
        "bumps" | "lobes" => {
            a.count(3, 3)?;
            let (amp, f) = (a.number(1)?, a.number(2)?);
            if kind == "bumps" {
                (Radial::Bumps(amp, f), 3)
            } else {
                (Radial::Lobes(amp, f), 3)
            }
        }
        _ => {
            return Err(ctx.error(
                &args[0],
                "expected a radial function: sphere, ellipsoid, bumps or lobes, or `rotate`",
            ));
        }
    };
    a.count(want, want)?;
    Ok(RadialCommand::Function(radial))
}

/// The largest step count accepted before the polygon budget is asked.
const MAX_STEPS: i64 = u32::MAX as i64;

/// Argument `i`, a step count of at least `min`.
fn steps(a: &Args, i: usize, min: i64) -> Result<usize> {
    a.integer(i, min, MAX_STEPS).map(|v| v as usize)
}

/// Argument `i`, a positive number (`what` names it in the message).
fn positive(a: &Args, i: usize, what: &str) -> Result<f64> {
    let v = a.number(i)?;
    if v <= 0.0 {
        return Err(a.ctx.error(
            &a.args[i],
            format!("`{}`: {what} must be positive, found {v}", a.spec.name),
        ));
    }
    Ok(v)
}

/// `sphere NU NV`, `cylinder NU [capped|open]`, `superquadric E1 E2 NU NV
/// [AX AY AZ]`.
fn primitive(a: &Args) -> Result<Command> {
    Ok(match a.spec.verb {
        Verb::Sphere => {
            a.count(2, 2)?;
            let nu = steps(a, 0, 3)?;
            Command::Sphere(Primitive::Sphere {
                nu,
                nv: steps(a, 1, 2)?,
            })
        }
        Verb::Cylinder => {
            a.count(1, 2)?;
            let nu = steps(a, 0, 3)?;
            let capped = match a.args.get(1).map(|t| t.text.to_ascii_lowercase()) {
                None => true,
                Some(w) if w == "capped" => true,
                Some(w) if w == "open" => false,
                Some(_) => return Err(a.ctx.error(&a.args[1], "expected `capped` or `open`")),
            };
            Command::Cylinder(Primitive::Cylinder { nu, capped })
        }
        _ => Command::Superquadric(superquadric(a)?),
    })
}

/// `superquadric E1 E2 NU NV [AX AY AZ]`.
fn superquadric(a: &Args) -> Result<Primitive> {
    a.count(4, 7)?;
    if a.args.len() != 4 && a.args.len() != 7 {
        return Err(a.ctx.error(
            &a.args[4],
            "`superquadric` takes all three scale factors AX AY AZ or none",
        ));
    }
    let (e1, e2) = (positive(a, 0, "E1")?, positive(a, 1, "E2")?);
    let (nu, nv) = (steps(a, 2, 3)?, steps(a, 3, 2)?);
    let s = if a.args.len() == 7 {
        DVec3::new(
            positive(a, 4, "AX")?,
            positive(a, 5, "AY")?,
            positive(a, 6, "AZ")?,
        )
    } else {
        DVec3::ONE
    };
    Ok(Primitive::Superquadric {
        q: Superquadric { e1, e2, a: s },
        nu,
        nv,
    })
}

/// `bezier|hermite FILE NU NV`.
fn patch_file(a: &Args) -> Result<PatchFile> {
    a.count(3, 3)?;
    Ok(PatchFile {
        file: a.text(0),
        nu: steps(a, 1, 3)?,
        nv: steps(a, 2, 2)?,
    })
}

/// The coordinate pairs from argument `from` on.
fn pairs(a: &Args, from: usize) -> Result<Vec<DVec2>> {
    if !(a.args.len() - from).is_multiple_of(2) {
        return Err(a.ctx.error(
            &a.args[a.args.len() - 1],
            format!(
                "`{}` expects coordinate pairs ({}); this one has no partner",
                a.spec.name, a.spec.usage
            ),
        ));
    }
    (from..a.args.len())
        .step_by(2)
        .map(|i| Ok(DVec2::new(a.number(i)?, a.number(i + 1)?)))
        .collect()
}

/// `lathe N r1 z1 ... rk zk` and `extrude DEPTH x1 y1 ... xk yk`. An
/// outline too long to check simple within the default pair budget is
/// checked when the command runs ([`Command::Lathe`]).
fn sweep(a: &Args) -> Result<Command> {
    if a.spec.verb == Verb::Lathe {
        a.count(5, usize::MAX)?;
        let n = steps(a, 0, 3)?;
        let points = pairs(a, 1)?;
        Profile::new_within(points.clone(), None).map_err(|e| a.ctx.error(a.cmd, e))?;
        Ok(Command::Lathe { n, points })
    } else {
        a.count(7, usize::MAX)?;
        let depth = positive(a, 0, "DEPTH")?;
        let points = pairs(a, 1)?;
        sweep::extrude_outline_within(points.clone(), None).map_err(|e| a.ctx.error(a.cmd, e))?;
        Ok(Command::Extrude { depth, points })
    }
}

/// `union|intersection|difference A B`.
fn csg_operands(a: &Args) -> Result<CsgOperands> {
    a.count(2, 2)?;
    let operand = |i: usize| (a.args[i].text.to_lowercase(), a.ctx.location(&a.args[i]));
    Ok(CsgOperands {
        a: operand(0),
        b: operand(1),
    })
}

/// The optional `Point|Diffuse` of `light` (any prefix).
fn light_kind(a: &Args) -> Result<LightKind> {
    match a.args.get(7).map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(LightKind::Point),
        Some(k) if !k.is_empty() && "point".starts_with(&k) => Ok(LightKind::Point),
        Some(k) if !k.is_empty() && "diffuse".starts_with(&k) => Ok(LightKind::Diffuse),
        Some(_) => Err(a.ctx.error(&a.args[7], "expected `Point` or `Diffuse`")),
    }
}

/// `outmode c|r|g|b|y|a bits`.
fn outmode(a: &Args) -> Result<OutMode> {
    let (ctx, args) = (a.ctx, a.args);
    a.count(1, 2)?;
    let mode = args[0].text.to_ascii_lowercase();
    if args.len() == 2 && mode != "a" {
        return Err(ctx.error(&args[1], "only outmode `a` takes a second argument"));
    }
    Ok(match mode.as_str() {
        "c" => OutMode::Color,
        "r" => OutMode::Red,
        "g" => OutMode::Green,
        "b" => OutMode::Blue,
        "y" => OutMode::Luminance,
        "a" => {
            if args.len() != 2 {
                return Err(ctx.error(a.cmd, "outmode `a` needs the bits per colour (1-8)"));
            }
            OutMode::Quantized(a.integer(1, 1, 8)? as u8)
        }
        _ => {
            return Err(ctx.error(&args[0], "expected an output mode: c, r, g, b, y or a"));
        }
    })
}

/// The axis letter of `rotate`.
fn axis(a: &Args, i: usize) -> Result<Axis> {
    match a.args[i].text.to_ascii_lowercase().as_str() {
        "x" => Ok(Axis::X),
        "y" => Ok(Axis::Y),
        "z" => Ok(Axis::Z),
        _ => Err(a.ctx.error(&a.args[i], "expected an axis: x, y or z")),
    }
}

/// `run [y]`: whether shadows are wanted.
fn run_shadows(a: &Args) -> Result<bool> {
    a.count(0, 1)?;
    match a.args.first().map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(false),
        Some(y) if y == "y" || y == "yes" => Ok(true),
        Some(n) if n == "n" || n == "no" => Ok(false),
        Some(_) => Err(a.ctx.error(&a.args[0], "expected `y` (shadows) or nothing")),
    }
}

/// `sort [btf|ftb]`.
fn sort_order(a: &Args) -> Result<SortOrder> {
    a.count(0, 1)?;
    match a.args.first().map(|t| t.text.to_ascii_lowercase()) {
        None => Ok(SortOrder::BackToFront),
        Some(s) if s == "btf" => Ok(SortOrder::BackToFront),
        Some(s) if s == "ftb" => Ok(SortOrder::FrontToBack),
        Some(_) => Err(a.ctx.error(&a.args[0], "expected `btf` or `ftb`")),
    }
}

/// `type polygon [open curved concave hidden ltsrc]`.
fn surface_type(a: &Args) -> Result<SurfaceType> {
    a.count(1, usize::MAX)?;
    let mut t = SurfaceType::default();
    for (i, word) in a.args.iter().enumerate() {
        match word.text.to_ascii_lowercase().as_str() {
            "polygon" if i == 0 => {}
            "open" => t.open = true,
            "curved" => t.curved = true,
            "concave" => t.concave = true,
            "hidden" => t.hidden = true,
            "ltsrc" => t.ltsrc = true,
            _ if i == 0 => {
                return Err(a
                    .ctx
                    .error(word, "expected `polygon`, the only surface type"));
            }
            _ => {
                return Err(a.ctx.error(
                    word,
                    "expected a type attribute: open, curved, concave, hidden or ltsrc",
                ));
            }
        }
    }
    Ok(t)
}

/// `setmode mode [value]`. A mode that is on or off is on when no value
/// is given (004 appendix: `setmode <mode> [<on, off>]`).
fn setmode(a: &Args) -> Result<ModeSetting> {
    let (ctx, args) = (a.ctx, a.args);
    a.count(1, 2)?;
    let letter_token = &args[0];
    let letter = letter_token.text.to_ascii_lowercase();
    let mut chars = letter.chars();
    let (Some(l), None) = (chars.next(), chars.next()) else {
        return Err(ctx.error(
            letter_token,
            format!(
                "expected a mode letter (b d e f h l n o p s v x) or a digit, found `{}`",
                printable(&letter_token.text, MAX_SHOWN_TOKEN)
            ),
        ));
    };
    if l.is_ascii_digit() {
        a.count(1, 1)?;
        return Ok(ModeSetting::Debug(l as u8 - b'0'));
    }
    if args.len() < 2 && matches!(l, 'd' | 'e' | 'l' | 'f') {
        return Err(ctx.error(letter_token, format!("mode `{l}` needs a value")));
    }
    let flag = || -> Result<bool> {
        if args.len() > 1 {
            a.on_off(1)
        } else {
            Ok(true)
        }
    };
    use ModeSetting as M;
    Ok(match l {
        'b' => M::Blend(flag()?),
        'd' => M::MinDetail(mode_value(a, |d| d >= 0.0, "a detail size of 0 or more")?),
        'e' => M::Epsilon(mode_value(
            a,
            |e| e > 0.0 && e < 1.0,
            "an epsilon between 0 and 1",
        )?),
        'f' => M::SceneFile(a.text(1)),
        'h' => M::ShadowShades(flag()?),
        'l' => M::MaxLevel(a.integer(1, 1, 14)? as u32),
        'n' => M::Nns(flag()?),
        'o' => M::OutputTree(flag()?),
        'p' => M::BoxesOnly(flag()?),
        's' => M::Phong(flag()?),
        'v' => M::VertexShades(flag()?),
        'x' => M::Expand(flag()?),
        'i' => {
            return Err(ctx.error(
                letter_token,
                format!("mode `{l}` can only be given on the command line (-{l})"),
            ));
        }
        _ => {
            return Err(ctx.error(
                letter_token,
                format!(
                    "unknown mode `{}`: expected b, d, e, f, h, l, n, o, p, s, v, x or a digit",
                    printable(&l.to_string(), 4)
                ),
            ));
        }
    })
}

/// The number of `setmode d|e`, which must pass `ok` (`expected` says
/// what it must be).
fn mode_value(a: &Args, ok: impl Fn(f64) -> bool, expected: &str) -> Result<f64> {
    let v = a.number(1)?;
    if !ok(v) {
        return Err(a.ctx.error(&a.args[1], format!("expected {expected}")));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    //! One table for the parser and `help`: every command of the table
    //! has help text, parses to the [`Command`] variant of its own verb,
    //! and keeps every abbreviation the manual's rule gives it.

    use std::path::{Path, PathBuf};

    use super::*;
    use crate::scene::commands::{ADDED, COMMANDS, MANUAL};

    /// Valid arguments for each command (a new command must add its own:
    /// the match is exhaustive).
    fn sample(verb: Verb) -> &'static str {
        match verb {
            Verb::Ambient | Verb::Background | Verb::Color => "0.1 0.2 0.3",
            Verb::Bezier | Verb::Hermite => "wave.bpt 8 8",
            Verb::Call | Verb::Get => "scene.des",
            Verb::Callobj => "3",
            Verb::Cylinder => "32 open",
            Verb::Defobj => "cube 3",
            Verb::Delobj => "3 cube",
            Verb::Depth => "2",
            Verb::DetDir => "det",
            Verb::Difference | Verb::Intersection | Verb::Union => "a b",
            Verb::Diffuse | Verb::Reflectance | Verb::Specular | Verb::Transmittance => "0.5",
            Verb::Disp => "off",
            Verb::Extrude => "0.5 0 0 1 0 1 1",
            Verb::Fname => "picture",
            Verb::Geodesic => "4 equal",
            Verb::Getobj => "cube",
            Verb::Index | Verb::Shininess | Verb::Threshold => "1.5",
            Verb::Lathe => "24 0 0 1 0 1 2 0 2",
            Verb::Light => "1 2 3 1 1 1 10 diffuse",
            Verb::Lookat => "0 0 5 0 0 0 0",
            Verb::Ortho | Verb::Window => "-1 1 -1 1 1 10",
            Verb::Ortho2 | Verb::Viewport => "0 511 0 511",
            Verb::Outmode => "a 4",
            Verb::Pcolors | Verb::Vcolors => "cube",
            Verb::Perspective | Verb::Polarview => "45 1 1 100",
            Verb::Radial => "bumps 0.1 3",
            Verb::Resolution => "512 256",
            Verb::Rotate => "30 y",
            Verb::Run => "y",
            Verb::Scale | Verb::Translate => "1 2 3",
            Verb::Setmode => "v on",
            Verb::Sort => "ftb",
            Verb::Sphere => "24 12",
            Verb::Superquadric => "0.5 1 24 12 1 1 2",
            Verb::Transparency => "0.5 1",
            Verb::Type => "polygon open curved",
            Verb::Clear
            | Verb::Endobj
            | Verb::Ident
            | Verb::Init
            | Verb::Nolight
            | Verb::Popmatrix
            | Verb::Pushmatrix
            | Verb::Quit
            | Verb::Wait => "",
        }
    }

    /// `text` parsed as one statement.
    fn parse_line(text: &str) -> Result<Parsed> {
        let file = Path::new("t.des");
        let statements = crate::scene::lexer::lex(text, file)?;
        let ctx = Context {
            file,
            dir: PathBuf::from("."),
            source: text,
        };
        let first = statements.into_iter().take(1).collect();
        Ok(parse_all(&ctx, first)?.remove(0))
    }

    /// What the manual's rule (the module comment of
    /// [`crate::scene::commands`]) makes of `word`, computed from the
    /// table: an exact name; else a prefix unique among the manual's
    /// commands, even if an added command shares it; else ambiguous among
    /// several manual commands; else the same among the added commands.
    /// `Err` holds the candidates of an ambiguous word.
    fn by_the_rule(word: &str) -> std::result::Result<&'static str, Vec<&'static str>> {
        if let Some(c) = COMMANDS.iter().find(|c| c.name == word) {
            return Ok(c.name);
        }
        let starting = |names: &[&'static str]| -> Vec<&'static str> {
            names
                .iter()
                .copied()
                .filter(|n| n.starts_with(word))
                .collect()
        };
        let manual = starting(MANUAL);
        let among = if manual.is_empty() {
            starting(ADDED)
        } else {
            manual
        };
        match among.as_slice() {
            [one] => Ok(one),
            _ => Err(among),
        }
    }

    #[test]
    fn every_command_has_help_and_usage_text() {
        for c in COMMANDS {
            assert!(!c.help.trim().is_empty(), "`{}` has no help", c.name);
            assert_eq!(c.help, c.help.trim(), "`{}`", c.name);
            assert_eq!(c.usage, c.usage.trim(), "`{}`", c.name);
            assert!(
                c.name
                    .bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_'),
                "`{}`",
                c.name
            );
            assert_eq!(c.verb.name(), c.name);
        }
    }

    /// Every entry of the table parses, by its full name, to the variant
    /// of its own verb, and every verb is reached: no entry without a
    /// variant, no variant without an entry.
    #[test]
    fn every_command_parses_to_its_own_variant() {
        let mut reached = Vec::new();
        for c in COMMANDS {
            let line = format!("{} {}", c.name, sample(c.verb));
            let parsed = parse_line(&line).unwrap_or_else(|e| panic!("`{line}`: {e}"));
            assert_eq!(parsed.command.verb(), c.verb, "`{line}`");
            assert_eq!(parsed.word.text, c.name);
            reached.push(parsed.command.verb());
        }
        assert_eq!(reached, Verb::ALL);
    }

    /// Every prefix of every command resolves as the manual's rule says:
    /// the manual's commands keep every prefix unique among them (`b` is
    /// `background`, not `bezier`), a prefix of several manual commands is
    /// ambiguous, and the added commands have the rest. The parser reads
    /// the statement as that command, in any case.
    #[test]
    fn every_prefix_resolves_as_the_manual_rule_says() {
        let (mut found, mut ambiguous) = (0, 0);
        for c in COMMANDS {
            for k in 1..=c.name.len() {
                let prefix = &c.name[..k];
                for word in [prefix.to_string(), prefix.to_uppercase()] {
                    match (by_the_rule(prefix), commands::lookup(&word)) {
                        (Ok(name), Lookup::Found(spec)) => {
                            assert_eq!(spec.name, name, "`{word}`");
                            let line = format!("{word} {}", sample(spec.verb));
                            let parsed = parse_line(&line).unwrap_or_else(|e| panic!("{e}"));
                            assert_eq!(parsed.command.verb(), spec.verb, "`{line}`");
                            found += 1;
                        }
                        (Err(names), Lookup::Ambiguous(got)) => {
                            assert_eq!(got, names, "`{word}`");
                            let e = parse_line(&word).unwrap_err().to_string();
                            assert!(e.contains("ambiguous command"), "{e}");
                            ambiguous += 1;
                        }
                        (want, got) => panic!("`{word}`: the rule says {want:?}, found {got:?}"),
                    }
                }
            }
        }
        assert!(found > 600 && ambiguous > 50, "{found} {ambiguous}");
        for (word, name) in [
            ("b", "background"),
            ("e", "endobj"),
            ("dif", "diffuse"),
            ("sp", "specular"),
            ("be", "bezier"),
            ("sph", "sphere"),
            ("u", "union"),
            ("ortho", "ortho"),
            ("call", "call"),
        ] {
            assert_eq!(by_the_rule(word), Ok(name), "`{word}`");
        }
        assert_eq!(by_the_rule("po"), Err(vec!["polarview", "popmatrix"]));
    }
}

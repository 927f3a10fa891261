//! The statements of the scene descriptor language as types (Garcia 1986,
//! 004 appendix B, the plytrace manual page; the modeling commands of
//! Firebaugh's chapter 8 and Brown's geodesics added).
//!
//! [`super::parse`] turns a statement's words into a [`Command`] in one
//! pass, its arguments read into the typed values here and checked as far
//! as they can be without the interpreter's state. A whole file is parsed
//! before its first statement runs. What can only be checked against the
//! interpreter's state (an object number in use, a field of view, the
//! polygon budget) is checked when the command runs, by the handlers of
//! [`super::interpreter`].

use glam::{DVec2, DVec3};

use super::arguments::{ObjectRef, Spanned};
use super::commands::Verb;
use super::lexer::Token;
use crate::error::Location;
use crate::math::Axis;
use crate::model::{Color, LightKind, OutMode, SortOrder, SurfaceType};
use crate::modeling::Primitive;
use crate::modeling::geodesic::{Division, Radial};

/// A statement: one variant per command of the table, with its arguments
/// read and checked as far as they can be without the interpreter's state.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Command {
    // Viewing and transforms.
    /// `ident`.
    Ident,
    /// `lookat vx vy vz px py pz twist`.
    Lookat {
        eye: DVec3,
        center: DVec3,
        twist: f64,
    },
    /// `ortho left right bottom top near far`.
    Ortho([f64; 6]),
    /// `ortho2 left right bottom top`.
    Ortho2([f64; 4]),
    /// `perspective fovy aspect near far`.
    Perspective([Spanned<f64>; 4]),
    /// `polarview dist azim inc twist`.
    Polarview([f64; 4]),
    /// `popmatrix`.
    Popmatrix,
    /// `pushmatrix`.
    Pushmatrix,
    /// `resolution hres vres`.
    Resolution { h: i64, v: i64 },
    /// `rotate angle x|y|z`.
    Rotate { angle: f64, axis: Axis },
    /// `scale sx sy sz`.
    Scale(DVec3),
    /// `translate tx ty tz`.
    Translate(DVec3),
    /// `viewport left right bottom top`.
    Viewport([Spanned<i64>; 4]),
    /// `window left right bottom top near far`.
    Window([f64; 6]),

    // Objects and modeling.
    /// `callobj obj-number` (or name).
    Callobj(Spanned<ObjectRef>),
    /// `defobj name [number]`; the name as written.
    Defobj {
        name: String,
        number: Option<Spanned<u32>>,
    },
    /// `delobj number...` (or names).
    Delobj(Vec<Spanned<ObjectRef>>),
    /// `endobj`.
    Endobj,
    /// `getobj name`; the name as written.
    Getobj(String),
    /// `geodesic n [equal|angle]`.
    Geodesic { n: usize, division: Division },
    /// `radial ...`.
    Radial(RadialCommand),
    /// `sphere NU NV`, `cylinder NU [capped|open]` and `superquadric E1 E2
    /// NU NV [AX AY AZ]`: their primitive.
    Sphere(Primitive),
    /// See [`Command::Sphere`].
    Cylinder(Primitive),
    /// See [`Command::Sphere`].
    Superquadric(Primitive),
    /// `bezier FILE NU NV`.
    Bezier(PatchFile),
    /// `hermite FILE NU NV`.
    Hermite(PatchFile),
    /// `lathe N r1 z1 ... rk zk`: the profile as written (checked simple
    /// again within the pair budget when it runs).
    Lathe { n: usize, points: Vec<DVec2> },
    /// `extrude DEPTH x1 y1 ... xk yk`, the outline as written.
    Extrude { depth: f64, points: Vec<DVec2> },
    /// `union A B`.
    Union(CsgOperands),
    /// `intersection A B`.
    Intersection(CsgOperands),
    /// `difference A B`.
    Difference(CsgOperands),

    // Surfaces.
    /// `color r g b`.
    Color(Color),
    /// `diffuse k`.
    Diffuse(f64),
    /// `specular k`.
    Specular(f64),
    /// `reflectance k`.
    Reflectance(f64),
    /// `transmittance k`.
    Transmittance(f64),
    /// `index n`.
    Index(Spanned<f64>),
    /// `shininess n`.
    Shininess(Spanned<f64>),
    /// `transparency t [rolloff]`.
    Transparency {
        t: f64,
        rolloff: Option<Spanned<f64>>,
    },
    /// `type polygon [open curved concave hidden ltsrc]`.
    Type(SurfaceType),
    /// `pcolors file`.
    Pcolors(Spanned<String>),
    /// `vcolors file`.
    Vcolors(Spanned<String>),

    // Lights and modes.
    /// `ambient r g b`.
    Ambient(Color),
    /// `background r g b`.
    Background(Color),
    /// `light x y z r g b range [Point|Diffuse]`; the position before the
    /// CTM.
    Light {
        position: DVec3,
        color: Spanned<Color>,
        range: Spanned<f64>,
        kind: LightKind,
    },
    /// `nolight`.
    Nolight,
    /// `depth 1-14`.
    Depth(u32),
    /// `setmode mode [value]`.
    Setmode(ModeSetting),
    /// `threshold k`.
    Threshold(Spanned<f64>),
    /// `outmode c|r|g|b|y|a bits`.
    Outmode(OutMode),
    /// `sort [btf|ftb]`.
    Sort(SortOrder),

    // Files and runs.
    /// `call file`.
    Call(Spanned<String>),
    /// `get file`.
    Get(Spanned<String>),
    /// `det_dir path`.
    DetDir(String),
    /// `fname name`.
    Fname(String),
    /// `init`.
    Init,
    /// `run [y]`.
    Run { shadows: bool },
    /// `clear`.
    Clear,
    /// `wait`.
    Wait,
    /// `disp [on|off]`.
    Disp(bool),
    /// `quit`.
    Quit,
}

/// A parsed statement: the command and its word as written.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Parsed {
    /// The command word (an abbreviation, in any case).
    pub word: Token,
    pub command: Command,
}

/// `bezier|hermite FILE NU NV`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct PatchFile {
    /// The file, in the detail directory.
    pub file: String,
    pub nu: usize,
    pub nv: usize,
}

/// The operands of `union|intersection|difference A B`, the names
/// case-folded.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CsgOperands {
    pub a: (String, Location),
    pub b: (String, Location),
}

/// What a `radial` statement says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum RadialCommand {
    /// The function.
    Function(Radial),
    /// `radial rotate ANGLE x|y|z`: turn it (degrees, axis 0-2).
    Rotate(f64, usize),
}

/// `setmode mode [value]`: one run-time mode set.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum ModeSetting {
    /// A digit: the debugging level.
    Debug(u8),
    Blend(bool),
    MinDetail(f64),
    Epsilon(f64),
    /// `f`: the scene file name.
    SceneFile(String),
    ShadowShades(bool),
    MaxLevel(u32),
    Nns(bool),
    OutputTree(bool),
    BoxesOnly(bool),
    Phong(bool),
    VertexShades(bool),
    Expand(bool),
}

impl Command {
    /// The command's word in the table.
    pub fn verb(&self) -> Verb {
        use Command as C;
        match self {
            C::Ident => Verb::Ident,
            C::Lookat { .. } => Verb::Lookat,
            C::Ortho(_) => Verb::Ortho,
            C::Ortho2(_) => Verb::Ortho2,
            C::Perspective(_) => Verb::Perspective,
            C::Polarview(_) => Verb::Polarview,
            C::Popmatrix => Verb::Popmatrix,
            C::Pushmatrix => Verb::Pushmatrix,
            C::Resolution { .. } => Verb::Resolution,
            C::Rotate { .. } => Verb::Rotate,
            C::Scale(_) => Verb::Scale,
            C::Translate(_) => Verb::Translate,
            C::Viewport(_) => Verb::Viewport,
            C::Window(_) => Verb::Window,
            C::Callobj(_) => Verb::Callobj,
            C::Defobj { .. } => Verb::Defobj,
            C::Delobj(_) => Verb::Delobj,
            C::Endobj => Verb::Endobj,
            C::Getobj(_) => Verb::Getobj,
            C::Geodesic { .. } => Verb::Geodesic,
            C::Radial(_) => Verb::Radial,
            C::Sphere(_) => Verb::Sphere,
            C::Cylinder(_) => Verb::Cylinder,
            C::Superquadric(_) => Verb::Superquadric,
            C::Bezier(_) => Verb::Bezier,
            C::Hermite(_) => Verb::Hermite,
            C::Lathe { .. } => Verb::Lathe,
            C::Extrude { .. } => Verb::Extrude,
            C::Union(_) => Verb::Union,
            C::Intersection(_) => Verb::Intersection,
            C::Difference(_) => Verb::Difference,
            C::Color(_) => Verb::Color,
            C::Diffuse(_) => Verb::Diffuse,
            C::Specular(_) => Verb::Specular,
            C::Reflectance(_) => Verb::Reflectance,
            C::Transmittance(_) => Verb::Transmittance,
            C::Index(_) => Verb::Index,
            C::Shininess(_) => Verb::Shininess,
            C::Transparency { .. } => Verb::Transparency,
            C::Type(_) => Verb::Type,
            C::Pcolors(_) => Verb::Pcolors,
            C::Vcolors(_) => Verb::Vcolors,
            C::Ambient(_) => Verb::Ambient,
            C::Background(_) => Verb::Background,
            C::Light { .. } => Verb::Light,
            C::Nolight => Verb::Nolight,
            C::Depth(_) => Verb::Depth,
            C::Setmode(_) => Verb::Setmode,
            C::Threshold(_) => Verb::Threshold,
            C::Outmode(_) => Verb::Outmode,
            C::Sort(_) => Verb::Sort,
            C::Call(_) => Verb::Call,
            C::Get(_) => Verb::Get,
            C::DetDir(_) => Verb::DetDir,
            C::Fname(_) => Verb::Fname,
            C::Init => Verb::Init,
            C::Run { .. } => Verb::Run,
            C::Clear => Verb::Clear,
            C::Wait => Verb::Wait,
            C::Disp(_) => Verb::Disp,
            C::Quit => Verb::Quit,
        }
    }

    /// Whether the command sets a surface attribute (an error in a CSG
    /// block, whose result keeps its operands' surfaces).
    pub fn sets_surface(&self) -> bool {
        use Command as C;
        matches!(
            self,
            C::Color(_)
                | C::Diffuse(_)
                | C::Specular(_)
                | C::Shininess(_)
                | C::Reflectance(_)
                | C::Transmittance(_)
                | C::Index(_)
                | C::Transparency { .. }
                | C::Type(_)
                | C::Pcolors(_)
                | C::Vcolors(_)
        )
    }

    /// Whether the command, inside a definition, gives the object its
    /// polygons (copied or generated), so that no object file is read.
    pub fn makes_object(&self) -> bool {
        use Command as C;
        matches!(
            self,
            C::Callobj(_)
                | C::Geodesic { .. }
                | C::Sphere(_)
                | C::Cylinder(_)
                | C::Superquadric(_)
                | C::Bezier(_)
                | C::Hermite(_)
                | C::Lathe { .. }
                | C::Extrude { .. }
                | C::Union(_)
                | C::Intersection(_)
                | C::Difference(_)
        )
    }
}

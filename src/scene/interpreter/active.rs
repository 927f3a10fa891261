//! The object being defined, between `defobj` and `endobj` (Garcia 1986,
//! 004 appendix B, DEFOBJ): its surface, its colour files, and a modeling
//! command recorded to be built at `endobj` (Firebaugh 001 chapter 8).

use std::path::PathBuf;

use crate::error::Location;
use crate::model::{Surface, SurfaceType};
use crate::modeling::Primitive;
use crate::modeling::csg;
use crate::modeling::geodesic::{Division, Radial};
use crate::modeling::patch::Form;
use crate::scene::command::{CsgOperands, PatchFile};

/// An object between `defobj` and `endobj`.
#[derive(Debug, Clone)]
pub(in crate::scene) struct ActiveObject {
    /// The name, case-folded (004 appendix: input is converted to lower
    /// case).
    pub name: String,
    /// The name as written, tried first for the geometry file.
    pub written: String,
    pub number: Option<u32>,
    pub surface: Surface,
    pub surface_type: SurfaceType,
    pub copy_of: Option<(u32, Location)>,
    pub geodesic: Option<(usize, Division, Location)>,
    pub radial: Option<(Radial, Location)>,
    /// `radial rotate`: the turn of the radial function (003 section 2).
    pub turn: Option<(glam::DMat3, Location)>,
    /// A Firebaugh generator (`sphere`, ..., `union`) and where it is.
    pub generator: Option<(Pending, Location)>,
    /// The first surface command of the block (an error in a CSG block).
    pub surface_cmd: Option<Location>,
    pub pcolors: Option<(String, Location)>,
    pub vcolors: Option<(String, Location)>,
    pub stack_depth: usize,
    pub location: Location,
    pub det_base: PathBuf,
}

/// A generator command read inside `defobj`, built at `endobj`.
#[derive(Debug, Clone)]
pub(in crate::scene) enum Pending {
    /// A primitive with its parameters checked.
    Primitive(Primitive),
    /// `bezier|hermite FILE NU NV`.
    Patches {
        form: Form,
        file: String,
        nu: usize,
        nv: usize,
    },
    /// `union|intersection|difference A B`, the names case-folded.
    Csg {
        op: csg::Op,
        a: (String, Location),
        b: (String, Location),
    },
}

impl Pending {
    /// `bezier|hermite FILE NU NV`.
    pub(in crate::scene) fn patches(form: Form, f: &PatchFile) -> Pending {
        Pending::Patches {
            form,
            file: f.file.clone(),
            nu: f.nu,
            nv: f.nv,
        }
    }

    /// `union|intersection|difference A B`.
    pub(in crate::scene) fn csg(op: csg::Op, operands: &CsgOperands) -> Pending {
        Pending::Csg {
            op,
            a: operands.a.clone(),
            b: operands.b.clone(),
        }
    }
}

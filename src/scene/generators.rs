//! The generator commands of Firebaugh's chapter 8 (001) inside `defobj`
//! ... `endobj`: `sphere`, `cylinder`, `superquadric`, `bezier`,
//! `hermite`, `lathe`, `extrude`, and the CSG commands `union`,
//! `intersection`, `difference` (see [`crate::modeling`]).
//!
//! A child of the interpreter: it parses the commands with the
//! interpreter's argument readers and builds the object at `endobj`.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use super::*;
use crate::modeling::parametric::Superquadric;
use crate::modeling::patch::{self, Form};
use crate::modeling::sweep::{self, Profile};
use crate::modeling::{Generated, Primitive, csg, solid};

/// The generator commands, by name.
pub(super) const GENERATORS: &[&str] = &[
    "sphere",
    "cylinder",
    "superquadric",
    "bezier",
    "hermite",
    "lathe",
    "extrude",
    "union",
    "intersection",
    "difference",
];

/// The commands that set surface attributes: an error in a CSG block.
pub(super) const SURFACE_COMMANDS: &[&str] = &[
    "color",
    "diffuse",
    "specular",
    "shininess",
    "reflectance",
    "transmittance",
    "index",
    "transparency",
    "type",
    "pcolors",
    "vcolors",
];

/// A generator command read inside `defobj`, built at `endobj`.
#[derive(Debug, Clone)]
pub(super) enum Pending {
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

/// The largest step count accepted before the polygon budget is asked.
const MAX_STEPS: i64 = u32::MAX as i64;

/// Parses a generator command (its name is `a.spec.name`).
///
/// This is the pre-pass over a whole file: an outline too long to check
/// simple within the default pair budget is left to [`parse_within`].
pub(super) fn parse(a: &Args) -> Result<Pending> {
    parse_within(a, None)
}

/// [`parse`] checking outlines simple within `pair_tests` edge pairs
/// (`None`: the pre-pass).
pub(super) fn parse_within(a: &Args, pair_tests: Option<u64>) -> Result<Pending> {
    let name = a.spec.name;
    let steps = |i: usize, min: i64| a.integer(i, min, MAX_STEPS).map(|v| v as usize);
    let positive = |i: usize, what: &str| -> Result<f64> {
        let v = a.number(i)?;
        if v <= 0.0 {
            return Err(a.ctx.error(
                &a.args[i],
                format!("`{name}`: {what} must be positive, found {v}"),
            ));
        }
        Ok(v)
    };
    let pairs = |from: usize| -> Result<Vec<DVec2>> {
        if !(a.args.len() - from).is_multiple_of(2) {
            return Err(a.ctx.error(
                &a.args[a.args.len() - 1],
                format!(
                    "`{name}` expects coordinate pairs ({}); this one has no partner",
                    a.spec.usage
                ),
            ));
        }
        (from..a.args.len())
            .step_by(2)
            .map(|i| Ok(DVec2::new(a.number(i)?, a.number(i + 1)?)))
            .collect()
    };
    let primitive = match name {
        "sphere" => {
            a.count(2, 2)?;
            Primitive::Sphere {
                nu: steps(0, 3)?,
                nv: steps(1, 2)?,
            }
        }
        "cylinder" => {
            a.count(1, 2)?;
            let nu = steps(0, 3)?;
            let capped = match a.args.get(1).map(|t| t.text.to_ascii_lowercase()) {
                None => true,
                Some(w) if w == "capped" => true,
                Some(w) if w == "open" => false,
                Some(_) => return Err(a.ctx.error(&a.args[1], "expected `capped` or `open`")),
            };
            Primitive::Cylinder { nu, capped }
        }
        "superquadric" => {
            a.count(4, 7)?;
            if a.args.len() != 4 && a.args.len() != 7 {
                return Err(a.ctx.error(
                    &a.args[4],
                    "`superquadric` takes all three scale factors AX AY AZ or none",
                ));
            }
            let (e1, e2) = (positive(0, "E1")?, positive(1, "E2")?);
            let (nu, nv) = (steps(2, 3)?, steps(3, 2)?);
            let s = if a.args.len() == 7 {
                DVec3::new(positive(4, "AX")?, positive(5, "AY")?, positive(6, "AZ")?)
            } else {
                DVec3::ONE
            };
            Primitive::Superquadric {
                q: Superquadric { e1, e2, a: s },
                nu,
                nv,
            }
        }
        "bezier" | "hermite" => {
            a.count(3, 3)?;
            return Ok(Pending::Patches {
                form: if name == "bezier" {
                    Form::Bezier
                } else {
                    Form::Hermite
                },
                file: a.args[0].text.clone(),
                nu: steps(1, 3)?,
                nv: steps(2, 2)?,
            });
        }
        "lathe" => {
            a.count(5, usize::MAX)?;
            let n = steps(0, 3)?;
            let profile =
                Profile::new_within(pairs(1)?, pair_tests).map_err(|e| a.ctx.error(a.cmd, e))?;
            Primitive::Lathe { profile, n }
        }
        "extrude" => {
            a.count(7, usize::MAX)?;
            let depth = positive(0, "DEPTH")?;
            let outline = sweep::extrude_outline_within(pairs(1)?, pair_tests)
                .map_err(|e| a.ctx.error(a.cmd, e))?;
            Primitive::Extrude { outline, depth }
        }
        _ => {
            a.count(2, 2)?;
            let op = match name {
                "union" => csg::Op::Union,
                "intersection" => csg::Op::Intersection,
                _ => csg::Op::Difference,
            };
            let operand = |i: usize| (a.args[i].text.to_lowercase(), a.ctx.location(&a.args[i]));
            return Ok(Pending::Csg {
                op,
                a: operand(0),
                b: operand(1),
            });
        }
    };
    Ok(Pending::Primitive(primitive))
}

/// The normals of an object transformed by `m` (row vectors: the inverse
/// transpose of its linear part); `None` if `m` is singular.
fn transform_normals(normals: &[DVec3], m: &Matrix4) -> Option<Vec<DVec3>> {
    let it = m.inverse()?.transpose();
    Some(
        normals
            .iter()
            .map(|n| it.transform_vector(*n).normalize_or_zero())
            .collect(),
    )
}

/// What `endobj` of a generated object needs besides the block.
pub(super) struct Ending<'a> {
    pub ctx: &'a Context<'a>,
    pub cmd: &'a Token,
    /// The CTM at `endobj`.
    pub transform: Matrix4,
    /// The CTM at `defobj` (the one `endobj` restores).
    pub saved: Matrix4,
}

impl Interpreter {
    /// Records a generator command in the active object.
    pub(super) fn add_generator(&mut self, a: &Args) -> Result<()> {
        let pending = parse_within(a, Some(self.budgets.pair_tests))?;
        let loc = a.ctx.location(a.cmd);
        let Some(active) = &mut self.active else {
            return Err(a.ctx.error(
                a.cmd,
                format!("`{}` outside an object definition", a.spec.name),
            ));
        };
        if let Some((_, first)) = &active.generator {
            return Err(a.ctx.error(
                a.cmd,
                format!("an object has one generator; this one already has one at {first}"),
            ));
        }
        if active.geodesic.is_some() {
            return Err(a.ctx.error(
                a.cmd,
                "an object has one generator; this one has a `geodesic`",
            ));
        }
        if matches!(pending, Pending::Csg { .. })
            && let Some(at) = &active.surface_cmd
        {
            return Err(surface_in_csg(at));
        }
        active.generator = Some((pending, loc));
        Ok(())
    }

    /// `endobj` of an object with a generator.
    pub(super) fn end_generated(
        &mut self,
        active: ActiveObject,
        pending: Pending,
        loc: Location,
        end: Ending,
    ) -> Result<()> {
        if active.geodesic.is_some() || active.copy_of.is_some() {
            return Err(Error::at(
                loc,
                "an object has one source of polygons: a generator, a `geodesic` or `callobj`",
            ));
        }
        let generated = match pending {
            Pending::Primitive(p) => {
                let faces = p.face_count().unwrap_or(usize::MAX);
                self.check_polygons(faces, &loc, &format!("this generator ({faces} polygons)"))?;
                let (vertices, corners) = p
                    .vertex_and_corner_counts()
                    .unwrap_or((usize::MAX, usize::MAX));
                self.check_model_memory(vertices, faces, corners, &loc)?;
                p.build()
            }
            Pending::Patches { form, file, nu, nv } => {
                self.read_patches(&active, form, &file, nu, nv, &loc)?
            }
            Pending::Csg { op, a, b } => return self.end_csg(active, op, a, b, loc, end),
        };
        let mut surface_type = active.surface_type;
        surface_type.open |= generated.open;
        surface_type.curved = generated.curved();
        let number = active.number.unwrap_or_else(|| self.next_free_number());
        let Generated { mesh, normals, .. } = generated;
        self.push_object(
            &active,
            end,
            number,
            mesh,
            normals,
            active.surface,
            surface_type,
            None,
        )
    }

    /// Reads a patch file from the detail directory and tessellates it.
    fn read_patches(
        &self,
        active: &ActiveObject,
        form: Form,
        file: &str,
        nu: usize,
        nv: usize,
        loc: &Location,
    ) -> Result<Generated> {
        let Some(path) = self
            .det_dirs(active)
            .into_iter()
            .map(|d| d.join(file))
            .find(|p| p.is_file())
        else {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "patch file `{}` not found in the detail directory",
                    printable(file, MAX_SHOWN_PATH)
                ),
            ));
        };
        let budget = |count: usize| {
            let faces = patch::face_count(count, nu, nv).unwrap_or(usize::MAX);
            self.check_polygons(
                faces,
                loc,
                &format!("{count} patches at {nu} x {nv} ({faces} triangles)"),
            )?;
            let vertices = count
                .checked_mul(nu.saturating_add(1))
                .and_then(|v| v.checked_mul(nv.saturating_add(1)))
                .unwrap_or(usize::MAX);
            self.check_model_memory(vertices, faces, faces.saturating_mul(3), loc)
        };
        let set = patch::read(&path, form, budget).map_err(|e| match e {
            Error::Input(mut d) => {
                d.included_from.push(loc.clone());
                Error::Input(d)
            }
            other => other,
        })?;
        Ok(patch::tessellate(&set, nu, nv))
    }

    /// Refuses a generated object whose `vertices`, `polygons` and
    /// `corners` would hold more than [`Budgets::model_memory`], before
    /// it is built.
    fn check_model_memory(
        &self,
        vertices: usize,
        polygons: usize,
        corners: usize,
        loc: &Location,
    ) -> Result<()> {
        let need = crate::modeling::model_bytes(vertices, polygons, corners);
        let limit = self.budgets.model_memory;
        if need <= limit {
            return Ok(());
        }
        Err(Error::at(
            loc.clone(),
            Budgets::exceeded(
                &format!(
                    "this generator's {vertices} vertices and {polygons} polygons ({} MiB)",
                    need.div_ceil(1 << 20)
                ),
                format!("{} MiB", limit >> 20),
                "--max-model-memory",
            ),
        ))
    }

    /// Builds and adds the object (transform, exact normals, budget).
    #[allow(clippy::too_many_arguments)]
    fn push_object(
        &mut self,
        active: &ActiveObject,
        end: Ending,
        number: u32,
        mesh: Mesh,
        normals: Option<Vec<DVec3>>,
        surface: Surface,
        surface_type: SurfaceType,
        polygon_colors: Option<Arc<Vec<ColorEntry>>>,
    ) -> Result<()> {
        let Ending {
            ctx,
            cmd,
            transform,
            ..
        } = end;
        let mut object = build_object(
            ObjectParts {
                number,
                name: active.name.clone(),
                mesh: Arc::new(mesh),
                polygon_colors,
                vertex_colors: None,
                transform,
                surface,
                surface_type,
            },
            &mut |msg| {
                let kind = warning_kind(&msg);
                self.warn(kind, Diagnostic::new(ctx.location(cmd), msg));
            },
        )
        .map_err(|msg| ctx.error(cmd, msg))?;
        if let Some(exact) = normals
            .as_deref()
            .and_then(|n| transform_normals(n, &transform))
        {
            object.vertex_normals = Some(exact);
        }
        self.check_polygons(
            object.polygons.len(),
            &active.location,
            &format!(
                "object `{}` ({} polygons)",
                printable(&active.written, MAX_SHOWN_TOKEN),
                object.polygons.len()
            ),
        )?;
        self.polygons += object.polygons.len();
        self.scene.objects.push(object);
        Ok(())
    }

    /// The operand of a CSG command: the last object of that name, closed.
    fn csg_operand(&self, name: &str, loc: &Location) -> Result<usize> {
        let Some(i) = self.scene.objects.iter().rposition(|o| o.name == name) else {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "no object `{}` is defined (a CSG operand is an object defined earlier)",
                    printable(name, MAX_SHOWN_TOKEN)
                ),
            ));
        };
        let o = &self.scene.objects[i];
        let polys: Vec<Vec<u32>> = o.polygons.iter().map(|p| p.indices.clone()).collect();
        if o.surface_type.open || polys.is_empty() {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "CSG operand `{}` is not a closed solid (it is open, or has no polygons)",
                    printable(name, MAX_SHOWN_TOKEN)
                ),
            ));
        }
        if let Err(why) = solid::check_closed(&solid::weld_exact(&o.vertices), &polys) {
            return Err(Error::at(
                loc.clone(),
                format!(
                    "CSG operand `{}` is not a closed solid: {why}",
                    printable(name, MAX_SHOWN_TOKEN)
                ),
            ));
        }
        Ok(i)
    }

    /// `endobj` of a CSG block: the operands combined where they stand.
    fn end_csg(
        &mut self,
        active: ActiveObject,
        op: csg::Op,
        (a, aloc): (String, Location),
        (b, bloc): (String, Location),
        loc: Location,
        end: Ending,
    ) -> Result<()> {
        if let Some(at) = &active.surface_cmd {
            return Err(surface_in_csg(at));
        }
        let ia = self.csg_operand(&a, &aloc)?;
        let ib = self.csg_operand(&b, &bloc)?;
        if ia == ib {
            return Err(Error::at(bloc, "the two CSG operands are the same object"));
        }
        let mut entries = Vec::new();
        let fa = operand_faces(&self.scene.objects[ia], &mut entries);
        let fb = operand_faces(&self.scene.objects[ib], &mut entries);
        let (oa, ob) = (&self.scene.objects[ia], &self.scene.objects[ib]);
        let with_normals = oa.vertex_normals.is_some() || ob.vertex_normals.is_some();
        let surface = oa.surface;
        let differs = |x: &Surface, y: &Surface| {
            x.specular != y.specular
                || x.shininess != y.shininess
                || x.index != y.index
                || x.transparency != y.transparency
        };
        if differs(&oa.surface, &ob.surface) {
            self.warn(
                "csg",
                Diagnostic::new(
                    loc.clone(),
                    format!("warning: the CSG operands differ in specular, shininess, index or transparency; the result takes `{a}`'s (colour, diffuse, reflectance and transmittance are kept per face)"),
                ),
            );
        }
        let (na, nb) = (self.scene.objects[ia].number, self.scene.objects[ib].number);
        let result =
            csg::combine_within(fa, fb, op, self.budgets.pair_tests).map_err(
                |stop| match stop {
                    csg::Stop::Cancelled => Error::Cancelled,
                    csg::Stop::Pairs(n) => Error::at(
                        loc.clone(),
                        Budgets::exceeded(
                            &format!("combining `{a}` and `{b}` ({n} face pair tests and more)"),
                            self.budgets.pair_tests,
                            "--max-pair-tests",
                        ),
                    ),
                },
            )?;
        let (mesh, normals, attrs) = csg::to_mesh(&result.faces, with_normals);
        let s = result.stats;
        let closed = solid::check_closed(&solid::weld_exact(&mesh.vertices), &mesh.polygons);
        let what = format!(
            "{} of `{a}` and `{b}`: {} input faces kept, {} split, {} removed; {} faces",
            match op {
                csg::Op::Union => "union",
                csg::Op::Intersection => "intersection",
                csg::Op::Difference => "difference",
            },
            s.kept,
            s.split,
            s.removed,
            mesh.polygons.len(),
        );
        // A result as asked is no warning: its figures are a note; a
        // result that is not closed is a real problem.
        match closed {
            Ok(()) => self.note(Diagnostic::new(loc.clone(), what)),
            Err(why) => self.warn(
                "csg",
                Diagnostic::new(
                    loc.clone(),
                    format!("warning: {what} (the result is not closed: {why})"),
                ),
            ),
        }
        // The operands are consumed.
        self.scene
            .objects
            .retain(|o| o.number != na && o.number != nb);
        self.polygons = self.scene.polygon_count();
        self.check_polygons(
            mesh.polygons.len(),
            &loc,
            &format!("the CSG result ({} faces)", mesh.polygons.len()),
        )?;
        // Only the transforms written inside the block: undo the CTM of
        // `defobj`, which placed the operands already.
        let block = if end.transform == end.saved {
            Matrix4::IDENTITY
        } else {
            let Some(inv) = end.saved.inverse() else {
                return Err(Error::at(
                    loc,
                    "the transforms inside this CSG block cannot be applied: the CTM at `defobj` is singular",
                ));
            };
            inv.mul(&end.transform)
        };
        let colors: Vec<ColorEntry> = attrs.iter().map(|&i| entries[i as usize]).collect();
        let surface_type = SurfaceType {
            open: false,
            curved: with_normals,
            concave: true,
            ..active.surface_type
        };
        let number = active.number.unwrap_or_else(|| self.next_free_number());
        let end = Ending {
            transform: block,
            ..end
        };
        self.push_object(
            &active,
            end,
            number,
            mesh,
            normals,
            surface,
            surface_type,
            Some(Arc::new(colors)),
        )
    }
}

fn surface_in_csg(at: &Location) -> Error {
    Error::at(
        at.clone(),
        "a surface command inside a CSG block: the result keeps the surfaces of its operands, face by face",
    )
}

/// An object's world polygons as CSG faces; each face's material is
/// appended to `entries` and its index is the face's attribute.
fn operand_faces(o: &Object, entries: &mut Vec<ColorEntry>) -> Vec<csg::Face> {
    o.polygons
        .iter()
        .enumerate()
        .map(|(pi, p)| {
            let m = o.material(pi);
            entries.push(ColorEntry {
                color: m.color,
                diffuse: m.diffuse,
                reflectance: m.reflectance,
                transmittance: m.transmittance,
            });
            let points = p.indices.iter().map(|&i| o.vertices[i as usize]).collect();
            let normals = match &o.vertex_normals {
                Some(n) => p.indices.iter().map(|&i| n[i as usize]).collect(),
                None => vec![p.normal(); p.indices.len()],
            };
            csg::Face {
                points,
                normals,
                attr: (entries.len() - 1) as u32,
            }
        })
        .collect()
}
